// The shvol program as a user runs it: exit codes, one-line errors, no half-written output.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "shvol/io/checkpoint.h"
#include "shvol/io/exr.h"
#include "shvol/io/phase_spec.h"
#include "shvol/io/scene_loader.h"
#include "shvol/io/vdb.h"
#include "shvol/surfaces/surface_scene.h"
#include "shvol/surfaces/triangle_mesh.h"
#include "test_util.h"

namespace shvol {

namespace fs = std::filesystem;

namespace {

struct Result {
    int code;
    std::string out, err;
};

/// The batch's warning of z-tests of runs below 64 spp (warnOfUnreliableZTest), for `runs` runs
/// of which `run` has the fewest samples, `fewest`.
std::string unreliableZTestWarning(const std::string& sweep, int runs, int fewest,
                                   const std::string& run) {
    return "shvol: warning: " + sweep + ": metrics: ztest of " + std::to_string(runs) + " run" +
           (runs == 1 ? "" : "s") +
           " with fewer than 64 samples per pixel (the fewest: " + std::to_string(fewest) +
           ", run " + run +
           "): standard errors from so few samples are unreliable, and unbiased runs fail the "
           "z-test there; it needs 64 spp or more, and a few hundred where samples have heavy "
           "tails (README, metrics)\n";
}

class Cli : public testing::Test {
  protected:
    void SetUp() override {
        // (With the process id: two test runs on one machine, a CI clone's and a working tree's,
        // shared the directory of each test, and one's batch found the other's lock in it.)
        dir_ = fs::path(testing::TempDir()) /
               ("shvol_cli_" +
                std::string(testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
                std::to_string(::getpid()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        // matplotlib (shvol report) warns on stderr where it cannot write its cache under HOME,
        // which the tests of report's exact messages took for report's (helper 154): its own
        // directory in the build tree (one in /tmp for every user of the machine was another's
        // once made; helper 156), unless the caller gave one.
        if (const char* given = std::getenv("MPLCONFIGDIR"); !given || !*given)
            ::setenv("MPLCONFIGDIR", SHVOL_TEST_MPLCONFIG, 1);
    }
    // sun.exr and smooth.exr, 64 × 32: an even sky of 1 whose row 1 is at 100 (a sun), and rows at
    // 1 + y (RenderWarnsOfNeeOffUnderASun gives the sun's figures).
    void writeSunAndSmoothSkies() const {
        Image sun(64, 32), smooth(64, 32);
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 64; ++x) {
                sun.set(x, y, Spectrum::Constant(y == 1 ? 100.f : 1.f));
                smooth.set(x, y, Spectrum::Constant(1.f + y));
            }
        writeExr(path("sun.exr"), sun);
        writeExr(path("smooth.exr"), smooth);
    }
    // A passed test's files go (a failed one's stay, to be looked at).
    void TearDown() override {
        std::error_code ignored;
        if (!HasFailure()) fs::remove_all(dir_, ignored);
    }
    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    void write(const std::string& name, const std::string& text) const {
        std::ofstream(path(name)) << text;
    }
    Result run(const std::string& args) const {
        return runCommand(std::string(SHVOL_BINARY) + " " + args);
    }
    // A shell command line (e.g. mpirun … shvol …), its output captured.
    Result runCommand(const std::string& command) const {
        const std::string out = path("so.txt"), err = path("se.txt");
        const int status =
            std::system((command + " >" + out + " 2>" + err + " </dev/null").c_str());
        return {WEXITSTATUS(status), test::fileBytes(out), test::fileBytes(err)};
    }
    // s.json: the homogeneous sphere with the phase table t.csv, a file its render reads.
    void writeTabulatedScene() const {
        write("t.csv", "angle_deg,value\n0,2\n180,1\n");
        write("s.json", scene(R"({"type": "homogeneous", "sigma_t": 2, "albedo": 0.8,
                                  "shape": {"type": "sphere"},
                                  "phase": {"type": "tabulated", "file": "t.csv"}})"));
    }
    // A bad scene must fail with exit code 1, exactly one line on stderr containing `expected`, and
    // leave no output (nor temporaries) behind.
    void expectOneLineError(const std::string& scene, const std::string& expected) const {
        const Result r = run("render " + path(scene) + " -o " + path("out.exr") + " --quiet");
        EXPECT_EQ(r.code, 1) << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_NE(r.err.find(expected), std::string::npos) << "stderr: " << r.err;
        EXPECT_EQ(r.err.rfind("shvol: error: ", 0), 0u) << r.err;
        for (const auto& e : fs::directory_iterator(dir_)) {
            const std::string n = e.path().filename().string();
            EXPECT_TRUE(n.find("out") == std::string::npos) << "left behind: " << n;
        }
    }
    /// `shvol bench s.json --accuracy` with the test directory as its cache, and `options`.
    std::string benchAccuracy(const std::string& options) const {
        return "bench " + path("s.json") + " --accuracy " + options + " --cache " + path("");
    }
    /// The bench references cached in the test directory.
    int cachedReferences() const {
        int n = 0;
        for (const auto& e : fs::directory_iterator(dir_))
            n += e.path().filename().string().rfind("shvol_bench_reference_", 0) == 0;
        return n;
    }
    /// An albedo-1 furnace that max_depth 64 cuts 0.08% of the paths of: 0.9992 for 1, where its
    /// noise is about 0.0001 (helper 82).
    static std::string thinFurnace(const std::string& environment = "") {
        return R"({"camera": {"resolution": [16, 16], "position": [0, -4, 0], "fov": 30},
                   "render": {"spp": 256}, "environment": {"type": "constant", "radiance": 1)" +
               environment + R"(}, "media": [{"type": "homogeneous", "sigma_t": 5, "albedo": 1,
                   "phase": {"type": "hg", "g": 0}, "shape": {"type": "sphere"}}]})";
    }
    static std::string scene(const std::string& media, const std::string& extra = "") {
        return R"({"camera": {"resolution": [8, 6], "position": [0, -3, 0]},
                   "render": {"spp": 2}, "environment": {"type": "constant", "radiance": 1})" +
               extra + R"(, "media": [)" + media + "]}";
    }
    fs::path dir_;
};

/// How many times `needle` occurs in `text`.
size_t occurrences(const std::string& text, const std::string& needle) {
    size_t n = 0;
    for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1))
        ++n;
    return n;
}

const std::string Homogeneous =
    R"({"type": "homogeneous", "sigma_t": 2, "albedo": 0.8, "shape": {"type": "sphere"}})";

/// The density lookups, majorant segments and regular-tracking cells per path (the last three
/// columns) of the bench table row named `name` in `out`; empty if there is no such row.
std::vector<double> benchCounts(const std::string& out, const std::string& name) {
    const size_t at = out.find("| " + name + " | ");
    if (at == std::string::npos) return {};
    std::vector<double> cells;
    const size_t from = at + name.size() + 4;  // past "| name |"
    std::stringstream line(out.substr(from, out.find('\n', at) - from));
    for (std::string cell; std::getline(line, cell, '|');)
        if (cell.find_first_not_of(' ') != std::string::npos) cells.push_back(std::stod(cell));
    if (cells.size() < 3) return {};
    return {cells[cells.size() - 3], cells[cells.size() - 2], cells.back()};
}

/// Shell text to follow a command started with `&`: sends SIGNAL (`sig`, number `number`) once
/// the process catches it (its bit in SigCgt of /proc/PID/status; a fixed sleep could come before
/// the handler on a loaded machine, and the signal's default action gives the same exit code),
/// `settle` seconds after that, then waits for it, its exit code the command's. The process must
/// have left the shell's image first: a background job is a fork of the shell until it execs, and
/// the shell catches SIGINT itself, so on a loaded machine the signal went to the fork, which then
/// exec'd a render that never saw it (Cli.SignalsStopTheRadianceCacheFill completed, 1 run in a
/// few under load). The image is read before and after the mask, and must be the same both times:
/// read once after it, the mask could be the shell fork's and the image the program it exec'd
/// meanwhile (`env`, which then took the signal's default action: the same test failed in 6 ms
/// with no output, 2 runs in about 45 beside the slab test).
std::string killOnceCaught(const std::string& sig, int number, const std::string& settle = "0") {
    const std::string bit = std::to_string(1ull << (number - 1));
    return " & p=$!; s=$(readlink /proc/$$/exe); for i in $(seq 1000); do "
           "e=$(readlink /proc/$p/exe); m=$(sed -n 's/^SigCgt:\\t//p' /proc/$p/status); "
           "[ \"$e\" != \"$s\" ] && [ \"$(readlink /proc/$p/exe)\" = \"$e\" ] && "
           "[ $(( 0x$m & " +
           bit + " )) -ne 0 ] && break; sleep 0.01; done; sleep " + settle + "; kill -" + sig +
           " $p; wait $p";
}

}  // namespace

namespace {
/// The warning of two surfaces closer than a tenth of the ray offset ε allows, gap ≤ ε, with ε
/// from the surfaces' extent: `pair` is "a and b are G apart[ (the closest of N such pairs)]".
std::string gapWarning(const std::string& file, const std::string& pair, const std::string& eps) {
    return "shvol: warning: " + file + ": " + pair + ", and the ray offset is " + eps +
           " (2^-16 of the surfaces' extent): rays leaving one skip more than a tenth of the gap "
           "(all of it: they see past each other), and light between them is unreliable; make "
           "the surfaces' extent smaller, which sets the offset, or the gap wider\n";
}
}  // namespace

TEST_F(Cli, HelpAndVersion) {
    Result r = run("--help");
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.out.find("render"), std::string::npos);
    EXPECT_NE(r.out.find("make-medium"), std::string::npos);
    r = run("--version");
    EXPECT_EQ(r.code, 0);
    EXPECT_EQ(r.out.rfind("shvol ", 0), 0u);
    for (const char* sub : {"render", "make-medium", "make-sky", "bench"}) {
        r = run(std::string(sub) + " --help");
        EXPECT_EQ(r.code, 0) << sub;
        EXPECT_NE(r.out.find("Usage"), std::string::npos) << sub;
    }
}

// Command-line mistakes follow the same contract as every other error: one line, exit code 1.
TEST_F(Cli, UsageErrorsAreOneLine) {
    write("s.json", scene(Homogeneous));
    for (const std::string& args :
         std::vector<std::string>{"render", "render " + path("s.json") + " --spp 0",
                                  "render " + path("s.json") + " --bogus", "frobnicate",
                                  "phase fit", "phase fit hg --order 0"}) {
        const Result r = run(args);
        EXPECT_EQ(r.code, 1) << args;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << args << ": " << r.err;
        EXPECT_EQ(r.err.rfind("shvol: error: ", 0), 0u) << r.err;
    }
}

// An integer option's value is the decimal one that was checked: CLI11 converted it with base 0,
// so zero-padded numbers were octal (--seed 010 rendered seed 8; helper 152).
TEST_F(Cli, ZeroPaddedIntegersAreDecimal) {
    write("s.json", scene(Homogeneous));
    const Result r = run("render " + path("s.json") + " -o " + path("z.exr") +
                         " --spp 1 --seed 010 --threads 03 --quiet");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto stats = nlohmann::json::parse(std::ifstream(path("z.stats.json")));
    EXPECT_EQ(stats["seed"], 10);
    EXPECT_EQ(stats["threads"], 3);
    EXPECT_EQ(run("render " + path("s.json") + " -o " + path("z.exr") + " --seed 08 --quiet").code,
              0);
}

// Number options say their real range in one short line; a wrong subcommand is named as such,
// also with --help.
TEST_F(Cli, NumberOptionsAndSubcommandsSayWhatIsWrong) {
    write("s.json", scene(Homogeneous));
    struct Case {
        std::string args, message;
    };
    const Case cases[] = {
        {"render " + path("s.json") + " --spp 0",
         "--spp: must be an integer in [1, 16777216], got 0"},
        {"render " + path("s.json") + " --spp 2,",
         "--spp: expected an integer in [1, 16777216], got \"\""},
        {"make-medium cloud -o " + path("m.vdb") + " --grid ''", "--grid: a grid needs a name"},
        {"render " + path("s.json") + " --spp abc",
         "--spp: expected an integer in [1, 16777216], got \"abc\""},
        // Blanks around a number are refused on either side (" 4" was read as 4, "4 " not).
        {"render " + path("s.json") + " --spp ' 4'",
         "--spp: expected an integer in [1, 16777216], got \" 4\""},
        {"render " + path("s.json") + " --spp '4, 16'",
         "--spp: expected an integer in [1, 16777216], got \" 16\""},
        {"render " + path("s.json") + " --time-limit ' 5'",
         "--time-limit: expected a decimal number, got \" 5\""},
        // Decimal numbers only, as whole numbers and phase specifications have them ("0x10"
        // was 16), and none that reads as 0 when it is not (1e-400; helper 130).
        {"make-sky -o " + path("k.exr") + " --sun-elevation 0x10",
         "--sun-elevation: expected a decimal number, got \"0x10\""},
        {"render " + path("s.json") + " --time-limit 1e400",
         "--time-limit: \"1e400\" is beyond the range of a double (±1.8e308)"},
        {"render " + path("s.json") + " --time-limit inf",
         "--time-limit: expected a decimal number, got \"inf\""},
        {"render " + path("s.json") + " --time-limit 1e-400",
         "--time-limit: \"1e-400\" is below the smallest double (4.9e-324) and would read as 0"},
        // --spp and --seed are applied after every --set: one that sets the same key too would
        // have had no effect, yet be listed among the stats' overrides.
        {"render " + path("s.json") + " --spp 2 --set render.spp=3",
         "--spp: --set render.spp=3 sets the same value; give it once"},
        {"render " + path("s.json") + " --set media[0].albedo=0.5 --set render.seed=3 --seed 7",
         "--seed: --set render.seed=3 sets the same value; give it once"},
        {"render " + path("s.json") + " --spp 2 --set 'render={\"spp\": 3}'",
         "--spp: --set render={\"spp\": 3} sets the same value; give it once"},
        {"render " + path("s.json") + " --spp 16,4",
         "--spp: sample counts must increase, got 16,4"},
        {"render " + path("s.json") + " --spp 2 --spp 4", "--spp: given 2 times; give it once"},
        // A width is a decimal integer (as a number, "0x10" was 16 and "8.5" CLI11's "Could not
        // convert"), and empty names named no file.
        {"make-sky -o " + path("k.exr") + " --width 8.5",
         "--width: expected an integer in [8, 16384], got \"8.5\""},
        {"make-sky -o " + path("k.exr") + " --width 0x10",
         "--width: expected an integer in [8, 16384], got \"0x10\""},
        {"render ''", "scene: an empty name"},
        {"diff " + path("s.json") + " ''", "reference: an empty name"},
        {"tonemap '' -o " + path("t.png"), "image: an empty name"},
        {"phase sample hg:g=0.5 --out ''", "--output: an empty name"},
        {"batch ''", "sweep: an empty name"},
        {"report ''", "dir: an empty name"},
        // Found as the command runs, not as the options are read: the same form.
        {"render " + path("s.json") + " --spp 1 --variance -o " + path("v.exr"),
         "--variance: a standard error needs at least 2 samples per pixel"},
        {"phase fit hg:g=0.5 --order 4 --tolerance 1e-3",
         "--tolerance: only valid with --order auto (got --order 4)"},
        {"phase sample hg:g=0.6 --order 8 --sampler general --depth 22 --out " + path("m.csv"),
         "--depth: the general sampler supports depths up to 10"},
        {"phase sample hg:g=0.999 --sampler general --out " + path("m.csv"),
         "--sampler: the general sampler supports orders up to 128, and the automatic order of "
         "hg:g=0.999 is 256; give --order 128 or less"},
        {"phase sample '{\"type\": \"hg\", \"g\": 0.5, \"order\": 200}' --sampler general --out " +
             path("m.csv"),
         "--sampler: the general sampler supports orders up to 128, and the spec's order is 200; "
         "give --order 128 or less (see"},
        {"render " + path("s.json") + " --seed -1",
         "--seed: must be an integer in [0, 9007199254740992], got -1"},
        {"render " + path("s.json") + " --threads -2",
         "--threads: must be an integer in [0, 4096], got -2"},
        {"bench " + path("s.json") + " --repeats 0",
         "--repeats: must be an integer in [1, 1000], got 0"},
        {"make-medium cloud -o " + path("m.vdb") + " --resolution 2",
         "--resolution: must be an integer in [4, 1024], got 2"},
        {"frobnicate x.json", "unknown subcommand \"frobnicate\"; expected one of render,"},
        {"batch " + path("none.json"), path("none.json") + ": no such file"},
        {"render " + path("s.json") + " -o " + path("m.png"),
         "render writes OpenEXR (shvol tonemap makes a PNG); name the file .exr"},
        {"make-medium cloud -o " + path("m.vdb") + " --coverage -2",
         "--coverage: must be in [-1, 1], got -2"},
        {"make-medium cloud -o " + path("m.vdb") + " --resolution 16 --coverage -1",
         "the grid would be empty"},
        {"frobnicate --help", "unknown subcommand \"frobnicate\""},
        // One level down too (it said "A subcommand is required", one being given).
        {"phase hg:g=0.9", "unknown subcommand \"hg:g=0.9\" of phase; expected one of fit, sample"},
        // A typo is named, as a scene key's is (helper 84).
        {"rendr x.json",
         "unknown subcommand \"rendr\"; did you mean \"render\"? expected one of "
         "render,"},
        {"phase smaple",
         "unknown subcommand \"smaple\" of phase; did you mean \"sample\"? "
         "expected one of fit, sample"},
        // Seeds are range-checked everywhere, not wrapped modulo 2^64.
        {"make-medium cloud -o " + path("m.vdb") + " --seed -1",
         "--seed: must be an integer in [0, 9007199254740992], got -1"},
        {"make-medium plume -o " + path("m.vdb") + " --seed 18446744073709551616", "--seed: "},
        {"phase sample hg:g=0.5 --out " + path("m.csv") + " --seed -1",
         "--seed: must be an integer in [0, 9007199254740992], got -1"},
        {"make-medium cloud -o " + path("m.txt"), "make-medium writes OpenVDB; name the file .vdb"},
        {"make-sky -o " + path("m.png"), "make-sky writes OpenEXR; name the file .exr"},
        {"phase sample hg:g=0.5 -o " + path("m.txt"),
         "phase sample writes CSV; name the file .csv"},
        {"phase sample hg:g=0.5 --sampler analytic --depth 8 -o " + path("m.csv"),
         "--depth: not with --sampler analytic: it samples no SH fit"},
        {"phase sample '{\"type\": \"hg\", \"g\": 0.5, \"sampling\": \"sh\"}' --sampler "
         "analytic -o " +
             path("m.csv"),
         "--sampler: analytic samples the phase function itself, and the spec asks for "
         "\"sampling\": \"sh\""},
        {"make-medium sphere -o " + path("m.vdb") + " --grid \"$(printf 'x\\ny')\"",
         "--grid: a control character in the grid name"},
        // CLI11's own words, as shvol's (they listed the arguments backwards, and started with
        // a capital; helper 77).
        {"render x.json --outptu y.exr",
         "unexpected arguments (an unknown option, or a value no option takes): --outptu y.exr"},
        {"render x.json --outptu",
         "an unexpected argument (an unknown option, or a value no option takes): --outptu"},
        {"phase", "shvol: error: a subcommand is required (see --help)"},
        // ... and the converse: fitted in silence against the spec's word (helper 77)
        {"phase fit '{\"type\": \"hg\", \"g\": 0.5, \"sampling\": \"analytic\", "
         "\"order\": 4}'",
         "sampling: the spec asks for \"analytic\", and this command fits an SH sampler"},
        {"make-sky -o " + path("m.exr") + " --width 9",
         "--width: must be even (the height is width/2), got 9"},
        // A bare extension is no name, for every command that writes one.
        {"make-medium cloud -o " + path(".vdb"), "the output needs a name before .vdb"},
        {"make-sky -o " + path(".EXR"), "the output needs a name before .exr"},
        {"tonemap " + path("s.json") + " -o " + path(".png"),
         "the output needs a name before .png"},
    };
    for (const Case& c : cases) {
        const Result r = run(c.args);
        EXPECT_EQ(r.code, 1) << c.args;
        EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << ": " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_LT(r.err.size(), 200u) << r.err;
        // An option's error points to the help, as README says (--spp's list is checked as the
        // option is read, as the others are).
        if (c.message.rfind("--", 0) == 0)
            EXPECT_EQ(r.err.substr(r.err.size() - std::min<size_t>(r.err.size(), 13)),
                      "(see --help)\n")
                << r.err;
    }
    for (const char* file : {"m.vdb", "m.png", "m.csv", "m.txt"})
        EXPECT_FALSE(fs::exists(path(file))) << file;
}

// bench without a scene finds the default scene also when run outside the repository (ctest runs
// in build/, where there is no media/ folder).
TEST_F(Cli, BenchFindsTheDefaultScene) {
    const Result r = run("bench --spp 1 --set camera.resolution=[8,6]");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("media/default.json (1 spp)"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find("majorant grid / global majorant"), std::string::npos) << r.out;
    // The floor: the scene without its media does no tracking.
    const size_t floor = r.out.find("| without media, 1 thread | ");
    ASSERT_NE(floor, std::string::npos) << r.out;
    const std::string row = r.out.substr(floor, r.out.find('\n', floor) - floor);
    EXPECT_NE(row.find(" | 0.00 | 0.00 |"), std::string::npos) << row;
    EXPECT_NE(r.out.find("time above the floor (1 thread): "), std::string::npos) << r.out;
    // 8×6 pixels at 1 spp render in well under a millisecond: timing noise, said (helper 84).
    EXPECT_NE(r.err.find(" of 8 configurations rendered in under 10 ms"), std::string::npos)
        << r.err;
    // Bricks and OpenVDB give the same densities, so a configuration tracks the same collisions
    // and segments with either: the last three columns (lookups, segments and cells per path)
    // agree.
    auto counts = [&](const std::string& name) { return benchCounts(r.out, name); };
    ASSERT_EQ(counts("defaults, 1 thread").size(), 3u) << r.out;
    EXPECT_EQ(counts("global majorant, OpenVDB lookups, 1 thread"),
              counts("global majorant, 1 thread"));
    EXPECT_EQ(counts("OpenVDB lookups, 1 thread"), counts("defaults, 1 thread"));
    EXPECT_NE(counts("global majorant, 1 thread"), counts("defaults, 1 thread"));
    EXPECT_NE(r.out.find("majorant grid / global majorant, both with OpenVDB lookups (1 thread): "),
              std::string::npos)
        << r.out;
    // The default cloud never prefers regular tracking (no cells crossed): that ratio was timing
    // noise printed as a speed-up (helper 77); bricks against OpenVDB, the same work by
    // design, keep theirs.
    ASSERT_EQ(counts("defaults, 1 thread")[2], 0.0) << r.out;
    EXPECT_NE(r.out.find("regular tracking where preferred / tentative collisions only (1 "
                         "thread): n/a (unused here: equal images and counts per path)\n"),
              std::string::npos)
        << r.out;
    EXPECT_EQ(r.out.find("bricks / OpenVDB lookups (1 thread): n/a"), std::string::npos) << r.out;
    // A bad value fails before anything is measured or printed.
    const Result bad = run("bench --spp 1 --set camera.resolution=[8,6] --set camera.fov=0");
    EXPECT_EQ(bad.code, 1);
    EXPECT_EQ(bad.out, "");
    EXPECT_NE(bad.err.find("camera.fov: value 0 out of range"), std::string::npos) << bad.err;
    // So does a --set of what the bench sets itself: the sample count (replaced by --spp without
    // a word) and the keys its rows vary (both sides of a ratio were one configuration).
    for (const auto& [set, message] : std::vector<std::pair<std::string, std::string>>{
             {"render.spp=1",
              "--set: render.spp=1: the bench renders at --spp; give the sample "
              "count there (see --help)\n"},
             {"media[0].majorant_grid=false",
              "--set: media[0].majorant_grid=false: the bench varies majorant_grid itself "
              "(README.md, \"bench\"); leave it to the scene (see --help)\n"},
             {"'media=[{\"type\": \"homogeneous\", \"lookup\": \"openvdb\"}]'",
              "--set: media=[{\"type\": \"homogeneous\", \"lookup\": \"openvdb\"}]: the bench "
              "varies lookup itself (README.md, \"bench\"); leave it to the scene (see "
              "--help)\n"}}) {
        const Result r2 = run("bench --spp 1 --set camera.resolution=[8,6] --set " + set);
        EXPECT_EQ(r2.code, 1) << set;
        EXPECT_EQ(r2.out, "");
        EXPECT_EQ(r2.err, "shvol: error: " + message);
    }
}

// With more than one round, each same-run ratio shows the range of its round-by-round ratios,
// which holds the best-of ratio printed before it; one round prints the ratio alone.
TEST_F(Cli, BenchRatiosShowTheirRounds) {
    const Result r = run("bench --spp 1 --repeats 3 --set camera.resolution=[8,6]");
    ASSERT_EQ(r.code, 0) << r.err;
    for (const char* what :
         {"bricks / OpenVDB lookups (1 thread): ", "majorant grid / global majorant (1 thread): ",
          "2 threads / 1 thread: "}) {
        const size_t at = r.out.find(what);
        ASSERT_NE(at, std::string::npos) << what << "\n" << r.out;
        double best = 0, lo = 0, hi = 0;
        ASSERT_EQ(std::sscanf(r.out.c_str() + at + std::strlen(what), "%lfx (rounds %lf-%lfx)",
                              &best, &lo, &hi),
                  3)
            << r.out.substr(at, 120);
        EXPECT_GT(lo, 0) << what;
        EXPECT_LE(lo, best) << what;
        EXPECT_LE(best, hi) << what;
    }
    const Result one = run("bench --spp 1 --set camera.resolution=[8,6]");
    ASSERT_EQ(one.code, 0) << one.err;
    EXPECT_EQ(one.out.find("(rounds "), std::string::npos) << one.out;
}

// bench --cell-sweep renders the default scene with majorant cells of 1, 2, 4, 8 and 16 voxels
// and fits ns per path over them; without a VDB medium there is nothing to sweep.
TEST_F(Cli, BenchCellSweepFitsTheCostPerPath) {
    Result r = run("bench --spp 1 --cell-sweep --set camera.resolution=[8,6]");
    ASSERT_EQ(r.code, 0) << r.err;
    std::vector<std::vector<double>> rows;
    for (const char* cells : {"1 voxel", "2 voxels", "4 voxels", "8 voxels", "16 voxels"}) {
        rows.push_back(
            benchCounts(r.out, std::string("majorant cells of ") + cells + ", 1 thread"));
        ASSERT_EQ(rows.back().size(), 3u) << cells << "\n" << r.out;
    }
    // Finer cells: more segments per path (several times as many from 16 to 2 voxels).
    EXPECT_GT(rows[1][1], 2 * rows[4][1]) << r.out;
    EXPECT_GT(rows[0][1], rows[1][1]) << r.out;
    EXPECT_NE(r.out.find("ns per path fitted over the cell sizes (1 thread): "), std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("most any majorant structure can buy over the global majorant"),
              std::string::npos)
        << r.out;

    write("s.json", scene(Homogeneous));
    r = run("bench " + path("s.json") + " --spp 1 --cell-sweep");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("no VDB medium: no majorant cell sweep"), std::string::npos) << r.out;
    // Nor the VDB configurations, the same render as the defaults: their ratios were noise
    // (helper 72: "majorant grid / global majorant 0.69x").
    EXPECT_NE(r.out.find("no VDB medium: no lookup, tracking or majorant configurations"),
              std::string::npos)
        << r.out;
    EXPECT_EQ(r.out.find("global majorant"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("2 threads / 1 thread: "), std::string::npos) << r.out;

    // One tile over 4096³ voxels: every asked cell is doubled to 32 voxels (at most 2^22 cells),
    // and the rows say so; with one cell size there is nothing to fit.
    write("tile.json", R"({"camera": {"resolution": [4, 3]},
        "media": [{"type": "vdb", "file": ")" SHVOL_SOURCE_DIR R"(/tests/fuzz/vdb/root_tile.vdb",
                   "density_scale": 0.001}]})");
    r = run("bench " + path("tile.json") + " --spp 1 --cell-sweep");
    ASSERT_EQ(r.code, 0) << r.err;
    for (int cell : {1, 2, 4, 8, 16})
        EXPECT_EQ(benchCounts(r.out, "majorant cells of 32 voxels (" + std::to_string(cell) +
                                         " asked; at most 2^22 cells), 1 thread")
                      .size(),
                  3u)
            << cell << "\n"
            << r.out;
    EXPECT_NE(r.out.find("the cell sizes do not separate lookups from segments: no fit"),
              std::string::npos)
        << r.out;
}

// bench --accuracy renders the reference once (cached under the cache directory) and reports
// the time to an RMSE for the renderer before issue 11 and now; the second run uses the cache.
TEST_F(Cli, BenchAccuracyCachesItsReference) {
    write("s.json", scene(Homogeneous));
    const std::string args = benchAccuracy("--spp 2 --reference-spp 64 --epsilon 0.01");
    Result r = run(args);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("reference: rendering 64 spp"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("warning: --reference-spp"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find("| now (defaults), 2 threads |"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("time to equal RMSE, before / now: "), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("ns per density lookup"), std::string::npos) << r.out;
    EXPECT_EQ(cachedReferences(), 1);
    r = run(args);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("(cached)"), std::string::npos) << r.err;
    // A damaged cached reference is said and rendered again (it failed the bench after the
    // timings); so is one of another size.
    std::string cached;
    for (const auto& e : fs::directory_iterator(path("")))
        if (e.path().filename().string().rfind("shvol_bench_reference_", 0) == 0)
            cached = e.path().string();
    for (const bool damaged : {true, false}) {
        if (damaged)
            fs::resize_file(cached, fs::file_size(cached) / 2);
        else
            writeExr(cached, Image(3, 2));
        r = run(args);
        ASSERT_EQ(r.code, 0) << r.err;
        EXPECT_NE(r.err.find("shvol: warning: " + cached +
                             (damaged ? ": " : ": 3 x 2 pixels, not the scene's\n")),
                  std::string::npos)
            << r.err;
        EXPECT_NE(r.err.find("shvol: the cached reference is rendered again\n  reference: "
                             "rendering 64 spp"),
                  std::string::npos)
            << r.err;
        EXPECT_EQ(readExr(cached).width, 8);
    }

    // A missing cache directory is made; one that cannot be is refused before anything renders.
    const std::string small = "bench " + path("s.json") + " --accuracy --spp 1 --reference-spp 4";
    r = run(small + " --cache " + path("new/deeper"));
    ASSERT_EQ(r.code, 0) << r.err;
    // A reference of fewer than 10 times the samples is warned of, as a batch's is (helper 130);
    // 64 against 2 spp was not.
    EXPECT_NE(r.err.find("shvol: warning: --reference-spp 4: fewer than 10 times --spp (1): the "
                         "reference's own noise adds about 25% to each renderer's MSE"),
              std::string::npos)
        << r.err;
    EXPECT_TRUE(fs::is_directory(path("new/deeper")));
    r = run(small + " --cache " + path("s.json/sub"));
    EXPECT_EQ(r.code, 1);
    // (One line: the bench's heading came first.)
    EXPECT_EQ(r.err, "shvol: error: --cache: " + path("s.json/sub") +
                         ": cannot make the directory (Not a directory) (see --help)\n");
    // An empty name is refused, as every other option's is (it was the current directory,
    // where the reference was then written; helper 116).
    r = run(small + " --cache ''");
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err, "shvol: error: --cache: an empty name (see --help)\n");
    // A scene the reference matches exactly (no medium under a constant sky) has no time to
    // compare: said, not printed as NaN.
    write("empty.json", R"({"camera": {"resolution": [4, 4]}, "render": {"spp": 1},
        "environment": {"type": "constant", "radiance": 1}})");
    r = run("bench " + path("empty.json") + " --accuracy --spp 1 --reference-spp 1 --cache " +
            path("cache"));
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("time to equal RMSE, before / now: n/a (an RMSE of 0 against the "
                         "reference)"),
              std::string::npos)
        << r.out;
    EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;
    // Without --accuracy its options are refused, not ignored.
    for (const char* option : {"--cache ", "--reference-spp 4", "--epsilon 0.1"}) {
        r = run("bench " + path("s.json") + " --spp 1 " + option +
                (std::string(option) == "--cache " ? path("unused") : ""));
        EXPECT_EQ(r.code, 1) << option;
        EXPECT_NE(r.err.find(" requires --accuracy"), std::string::npos) << r.err;
        EXPECT_FALSE(fs::exists(path("unused")));
    }
}

// The cached reference is keyed by the contents of the files the scene names too: a .vdb
// rewritten under the same name renders a new reference, not the stale one.
TEST_F(Cli, BenchAccuracyReferenceFollowsTheVdbContents) {
    VdbGridSpec s;
    s.resolution = 8;
    s.density = [](const Vec3& p) { return p.norm() < 0.4 ? 1.f : 0.f; };
    writeVdb(path("m.vdb"), {s});
    write("s.json", scene(R"({"type": "vdb", "file": "m.vdb"})"));
    const std::string args = benchAccuracy("--spp 1 --reference-spp 16 --epsilon 0.1");
    Result r = run(args);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("reference: rendering 16 spp"), std::string::npos) << r.err;
    s.density = [](const Vec3& p) { return p.norm() < 0.4 ? 3.f : 0.f; };
    writeVdb(path("m.vdb"), {s});
    r = run(args);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("reference: rendering 16 spp"), std::string::npos) << r.err;
    EXPECT_EQ(cachedReferences(), 2);
}

// --help shows the defaults.
TEST_F(Cli, HelpShowsDefaults) {
    const Result m = run("make-medium --help");
    EXPECT_NE(m.out.find("--resolution INT:integer in [4, 1024]=96"), std::string::npos) << m.out;
    const Result b = run("bench --help");
    EXPECT_NE(b.out.find("--spp INT:integer in [1, 16777216]=4"), std::string::npos) << b.out;
    const Result r = run("render --help");
    EXPECT_NE(r.out.find("--threads INT:integer in [0, 4096]=0"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("=the scene's render.spp"), std::string::npos) << r.out;
    // --depth names the general sampler's depths only where --sampler offers it (helper 122).
    const Result fit = run("phase fit --help"), sample = run("phase sample --help");
    EXPECT_NE(fit.out.find("=the spec's sh_depth, else 16\n"), std::string::npos) << fit.out;
    EXPECT_EQ(fit.out.find("general"), std::string::npos) << fit.out;
    EXPECT_NE(sample.out.find("=the spec's sh_depth, else 16 (general: 10)"), std::string::npos)
        << sample.out;
}

// Numbers beyond double range are malformed input, not internal errors.
TEST_F(Cli, NumberOverflowIsAnInputError) {
    // The place is the number's, not that of an earlier string with the same text.
    write("big.json", "{\"note\": \"fov 1e999\", \"1e999\": 0,\n \"camera\":\n  {\"fov\": 1e999}}");
    expectOneLineError("big.json", path("big.json") + ": line 3, column 11: malformed JSON: " +
                                       "number overflow parsing '1e999'");
    write("s.json", scene(Homogeneous));
    const Result r = run("render " + path("s.json") + " -o " + path("out.exr") +
                         " --set camera.fov=1e999 --quiet");
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err,
              "shvol: error: " + path("s.json") +
                  ": --set camera.fov=1e999: number beyond the range of a double (±1.8e308)\n");
    // ... also with --spp, whose check of the --set options read the value first (and named no
    // file).
    EXPECT_EQ(run("render " + path("s.json") + " -o " + path("out.exr") +
                  " --set camera.fov=1e999 --spp 2 --quiet")
                  .err,
              r.err);
    // The weight's second moment over 100 bounces, where it overflows a double, as a power of 10.
    const Result q = run("phase fit hg:g=0.999999");
    EXPECT_EQ(q.code, 0) << q.err;
    EXPECT_NE(q.out.find("(evaluate exact; ^100 = 10^"), std::string::npos) << q.out;
    // A spec of several lines stays in its comment line (its second line broke the output).
    write("spec.txt", "{\"type\": \"hg\",\n\"g\": 0.5}");
    const Result m = run("phase fit \"$(cat " + path("spec.txt") + ")\" --order 3");
    EXPECT_EQ(m.code, 0) << m.err;
    EXPECT_EQ(m.out.rfind("# zonal SH fit of {\"type\": \"hg\",\\u000a\"g\": 0.5}: ", 0), 0u)
        << m.out;
    EXPECT_EQ(q.out.find("inf"), std::string::npos) << q.out;
    const Result p = run("phase fit hg:g=1e999 --order 4");
    EXPECT_EQ(p.code, 1);
    EXPECT_NE(p.err.find("phase spec \"hg:g=1e999\": g: number beyond the range of a double"),
              std::string::npos)
        << p.err;
}

TEST_F(Cli, PhaseFitAndSample) {
    Result r = run("phase fit hg:g=0.6 --order 5 --window none --json");
    ASSERT_EQ(r.code, 0) << r.err;
    auto fit = nlohmann::json::parse(r.out);
    for (int l = 0; l < 5; ++l)
        EXPECT_NEAR(fit["coefficients"][l].get<double>(),
                    std::pow(0.6, l) * std::sqrt((2 * l + 1) / (4 * M_PI)), 1e-12);
    EXPECT_EQ(fit["evaluate"], "sh");
    EXPECT_EQ(fit["weight_second_moment"], 1.0);
    EXPECT_GT(fit["weight_second_moment_exact"].get<double>(), 1.0);
    EXPECT_TRUE(fit["before_window"].contains("energy_fraction"));
    EXPECT_TRUE(fit["after_window"].contains("relative_l2_error"));
    r = run("phase sample hg:g=0.6 --order 8 --count 100 --out " + path("s.csv"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("weight p/pdf: mean 1,"), std::string::npos) << r.err;  // exactly 1
    std::ifstream f(path("s.csv"));
    std::string line;
    int rows = 0;
    std::getline(f, line);
    EXPECT_EQ(line, "x,y,z,pdf,weight");
    while (std::getline(f, line)) {
        double x, y, z, pdf, w;
        ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%lf", &x, &y, &z, &pdf, &w), 5)
            << line;
        EXPECT_NEAR(x * x + y * y + z * z, 1.0, 1e-12);
        EXPECT_GT(pdf, 0);
        EXPECT_DOUBLE_EQ(w, 1.0);
        ++rows;
    }
    EXPECT_EQ(rows, 100);
    // The general sampler reports its weights, and none of the zonal sampler's figures.
    r = run("phase sample hg:g=0.5 --order 16 --sampler general --count 100 --out " +
            path("g.csv"));
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("weight p/pdf: mean "), std::string::npos) << r.err;
    for (const char* absent : {"nan", "quadrature"})
        EXPECT_EQ(r.err.find(absent), std::string::npos) << r.err;
    // Its weights keep their mean of 1 where the warp never goes: a uniform share covers the
    // function there. Evaluated exactly, where the fit rings below 0 (the mean was 0.977, 5.9
    // standard errors low; helper 55); as the fit, in the fine bins of the zonal sampler's table
    // within coarse cells the warp's table clamps to 0 (0.9895, 5.6 standard errors low; helper
    // 110).
    for (const std::string& spec :
         {"hg:g=0.9 --order 4 --evaluate exact", "hg:g=0.999 --order 128 --evaluate sh"}) {
        r = run("phase sample " + spec + " --sampler general --count 400000 --out " +
                path("g.csv"));
        ASSERT_EQ(r.code, 0) << r.err;
        double mean = 0, variance = 0;
        ASSERT_EQ(std::sscanf(r.err.c_str() + r.err.find("mean "), "mean %lf, variance %lf", &mean,
                              &variance),
                  2)
            << r.err;
        EXPECT_LT(std::abs(mean - 1), 3 * std::sqrt(variance / 400000)) << spec << ": " << r.err;
        EXPECT_NE(r.err.find("defensive share 0.02"), std::string::npos) << r.err;
    }
    r = run("phase sample hg:g=0.6 --order 200 --sampler general --count 10 --out " +
            path("g200.csv"));
    EXPECT_EQ(r.code, 1);
    EXPECT_FALSE(fs::exists(path("g200.csv")));
    r = run("phase sample hg:g=0.6 --order 8 --sampler general --depth 22 --out " +
            path("g200.csv"));
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("--depth: the general sampler supports depths up to 10"),
              std::string::npos)
        << r.err;
}

// The weights' variance that phase sample prints is theirs, as the file's weights give it by two
// passes: Cornette-Shanks at g = 0.999999 has weights within 5e-5 of 1, whose variance,
// 2.2e-14, Σw²/n − mean² printed as 0 (helper 164).
TEST_F(Cli, PhaseSampleStatesItsWeightsVariance) {
    const Result r =
        run("phase sample cornette_shanks:g=0.999999 --sampler analytic --count "
            "100000 -o " +
            path("cs.csv"));
    ASSERT_EQ(r.code, 0) << r.err;
    const size_t at = r.err.find(", variance ");
    ASSERT_NE(at, std::string::npos) << r.err;
    const double said = std::stod(r.err.substr(at + 11));
    std::ifstream f(path("cs.csv"));
    std::string line;
    std::getline(f, line);
    std::vector<double> w;
    while (std::getline(f, line)) w.push_back(std::stod(line.substr(line.rfind(',') + 1)));
    ASSERT_EQ(w.size(), 100000u);
    double mean = 0, var = 0;
    for (const double x : w) mean += x / double(w.size());
    for (const double x : w) var += (x - mean) * (x - mean) / double(w.size());
    EXPECT_GT(var, 1e-15);
    EXPECT_NEAR(said, var, 1e-5 * var);
}

// The analytic samplers (what "sampling": "analytic" renders) can be checked from outside: HG's
// samples have E[μ] = g and Var[μ] = (1 − g²)/3 (its Legendre moments E[P_l(μ)] = g^l), and
// weight 1 each. (phase sample drew from SH fits only: helper 62's F5.)
TEST_F(Cli, PhaseSampleDrawsFromTheAnalyticSampler) {
    for (const double g : {0.9, -0.5, 0.999}) {
        const int n = 200000;
        const Result r =
            run("phase sample hg:g=" + std::to_string(g) + " --sampler analytic --count " +
                std::to_string(n) + " -o " + path("a.csv"));
        ASSERT_EQ(r.code, 0) << r.err;
        EXPECT_NE(r.err.find("weight p/pdf: mean 1, variance 0, max 1"), std::string::npos)
            << r.err;
        std::ifstream f(path("a.csv"));
        std::string line;
        std::getline(f, line);
        double sum = 0, sumP2 = 0;
        int rows = 0;
        while (std::getline(f, line)) {
            double x, y, z, pdf, w;
            ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%lf", &x, &y, &z, &pdf, &w), 5);
            const double hg = (1 - g * g) / (4 * M_PI * std::pow(1 + g * g - 2 * g * z, 1.5));
            ASSERT_NEAR(pdf, hg, 1e-9 * hg) << line;
            sum += z, sumP2 += 1.5 * z * z - 0.5, ++rows;
        }
        ASSERT_EQ(rows, n);
        EXPECT_NEAR(sum / n, g, 5 * std::sqrt((1 - g * g) / 3 / n)) << g;
        // E[P_2(μ)] = g², so Var[μ] = (1 − g²)/3 (only the mean was checked: helper 118); P_2 ∈
        // [−1/2, 1], so its variance E[P_2²] − g⁴ is at most 1 − g⁴.
        EXPECT_NEAR(sumP2 / n, g * g, 5 * std::sqrt((1 - g * g * g * g) / n)) << g;
    }
}

// The SH keys of a JSON spec are used; an option replaces only the key it names.
TEST_F(Cli, PhaseToolsUseTheSpecsKeys) {
    const std::string spec =
        R"('{"type": "hg", "g": 0.6, "sampling": "sh", "order": 5, "window": "none", )"
        R"("evaluate": "exact", "sh_depth": 8}')";
    auto fit = nlohmann::json::parse(run("phase fit " + spec + " --json").out);
    EXPECT_EQ(fit["order"], 5);
    EXPECT_EQ(fit["window"], "none");
    EXPECT_EQ(fit["evaluate"], "exact");
    EXPECT_EQ(fit["sh_depth"], 8);
    fit = nlohmann::json::parse(run("phase fit " + spec + " --order 7 --json").out);
    EXPECT_EQ(fit["order"], 7);
    EXPECT_EQ(fit["window"], "none");
    EXPECT_EQ(fit["sh_depth"], 8);
    // --tolerance with a fixed order is the options' error, not the spec's; --order N replaces
    // the spec's "order": "auto" together with its tolerance.
    Result r = run("phase fit " + spec + " --tolerance 1e-3");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("--tolerance: only valid with --order auto (the spec's order is 5)"),
              std::string::npos)
        << r.err;
    r = run("phase fit hg:g=0.5 --order 4 --tolerance 1e-3");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("--tolerance: only valid with --order auto (got --order 4)"),
              std::string::npos)
        << r.err;
    const std::string autoSpec =
        R"('{"type": "hg", "g": 0.5, "sampling": "sh", "order": "auto", "tolerance": 1e-4}')";
    r = run("phase fit " + autoSpec + " --order 5 --json");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["order"], 5);
    // The general sampler takes the spec's sh_depth as --depth (it used its own 10 instead).
    const std::string general = " --sampler general --count 2000 --out ";
    ASSERT_EQ(run("phase sample " + spec + " --depth 8" + general + path("a.csv")).code, 0);
    ASSERT_EQ(run("phase sample " + spec + general + path("b.csv")).code, 0);
    ASSERT_EQ(run("phase sample hg:g=0.6 --order 5 --window none --evaluate exact" + general +
                  path("c.csv"))
                  .code,
              0);
    EXPECT_EQ(test::fileBytes(path("a.csv")), test::fileBytes(path("b.csv")));
    EXPECT_NE(test::fileBytes(path("a.csv")), test::fileBytes(path("c.csv")));  // depth 10
    r = run(R"(phase sample '{"type": "hg", "g": 0.5, "sampling": "sh", "sh_depth": 12}')" +
            general + path("d.csv"));
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("--sampler: the general sampler supports depths up to 10, and the "
                         "spec's sh_depth is 12; give --depth 10 or less"),
              std::string::npos)
        << r.err;
}

// phase sample reports the renderer's pdf: with evaluate exact and a fit that rings (HG 0.99,
// order 4) the pdf includes the defensive uniform share, and the weights are p/pdf.
// A process ended by SIGTERM while it writes an output leaves neither the output nor its temporary
// (a killed phase sample of 2^32 samples left a 2 GB temporary). The signal is sent once the
// temporary exists, so the test fails if the handler does not remove it.
TEST_F(Cli, SigtermLeavesNoTemporary) {
    const std::string script = "cd " + path("") + "; " + std::string(SHVOL_BINARY) +
                               " phase sample hg:g=0.5 --count 1000000000 --out big.csv "
                               "2>/dev/null & pid=$!; seen=0; for i in $(seq 600); do "
                               "if ls big.csv.tmp* >/dev/null 2>&1; then seen=1; break; fi; "
                               "sleep 0.05; done; kill -TERM $pid; wait $pid; echo \"$seen $?\"";
    const Result r = runCommand("bash -c '" + script + "'");
    EXPECT_EQ(r.out, "1 143\n") << r.err;  // the temporary was there; 128 + SIGTERM
    for (const auto& e : fs::directory_iterator(dir_))
        EXPECT_EQ(e.path().filename().string().rfind("big.csv", 0), std::string::npos)
            << "left behind: " << e.path();
}

// phase sample's output must not replace the table it samples.
TEST_F(Cli, PhaseSampleRefusesToOverwriteItsTable) {
    write("mie.csv", "angle,value\n0,10\n90,1\n180,2\n");
    const std::string before = "angle,value\n0,10\n90,1\n180,2\n";
    Result r = run("phase sample tabulated:file=" + path("mie.csv") + " --count 5 --out " +
                   path("mie.csv"));
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err, "shvol: error: --output: " + path("mie.csv") +
                         " is the phase table being sampled (the spec's file); write the samples "
                         "elsewhere (see --help)\n");
    EXPECT_EQ(test::fileBytes(path("mie.csv")), before);
    r = run("phase sample tabulated:file=" + path("mie.csv") + " --count 5 --out " + path("s.csv"));
    EXPECT_EQ(r.code, 0) << r.err;
}

TEST_F(Cli, PhaseSampleUsesTheRenderersPdf) {
    const Result r =
        run("phase sample hg:g=0.99 --order 4 --window none --evaluate exact --count 2000 --out " +
            path("d.csv"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("defensive share 0.02"), std::string::npos) << r.err;
    const PhaseFunction ph =
        parsePhaseSpec("hg:g=0.99,sampling=sh,order=4,window=none,evaluate=exact", "");
    const PhaseFunction hg = parsePhaseSpec("hg:g=0.99", "");
    std::ifstream f(path("d.csv"));
    std::string line;
    std::getline(f, line);
    int rows = 0;
    while (std::getline(f, line)) {
        double x, y, z, pdf, w;
        ASSERT_EQ(std::sscanf(line.c_str(), "%lf,%lf,%lf,%lf,%lf", &x, &y, &z, &pdf, &w), 5);
        const Vec3 wi(x, y, z), up(0, 0, 1);
        EXPECT_NEAR(pdf, ph.pdf(up, wi), 1e-9 * pdf);
        EXPECT_GE(pdf, 0.02 / (4 * M_PI) * (1 - 1e-12));
        EXPECT_NEAR(w, hg.eval(up, wi) / pdf, 1e-9 * w);
        ++rows;
    }
    EXPECT_EQ(rows, 2000);
}

TEST_F(Cli, RenderWritesExrAndStats) {
    write("s.json", scene(Homogeneous));
    const Result r = run("render " + path("s.json") + " -o " + path("img.exr") +
                         " --spp 3 --seed 7 --threads 2 --set camera.fov=30 --quiet");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    const Image img = readExr(path("img.exr"));
    EXPECT_EQ(img.width, 8);
    EXPECT_EQ(img.height, 6);
    std::ifstream f(path("img.stats.json"));
    const auto stats = nlohmann::json::parse(f);
    EXPECT_EQ(stats["spp"], 3);
    EXPECT_EQ(stats["seed"], 7);
    EXPECT_EQ(stats["threads"], 2);
    EXPECT_EQ(stats["paths"], 8 * 6 * 3);
    for (const char* k : {"wall_time_s", "paths_per_second", "mean_path_length", "peak_memory_mib",
                          "density_lookups_per_second", "effects"})
        EXPECT_TRUE(stats.contains(k)) << k;
    // The whole cost, loading included, and no less than the passes'.
    EXPECT_GE(stats["total_s"].get<double>(), stats["wall_time_s"].get<double>());
    // Under a constant sky next-event estimation is off unless asked for (render.nee).
    EXPECT_EQ(stats["effects"], nlohmann::json::parse(R"(["environment-constant", "volume-tracking",
                                    "multiple-scattering", "roulette-survival-weight"])"));
    EXPECT_EQ(stats["roulette_threshold"], 0.25);  // render.rr_threshold "auto" without NEE
    EXPECT_EQ(stats["sampler"], "sobol");
    // Without --quiet, one summary line.
    const Result one =
        run("render " + path("s.json") + " -o " + path("img.exr") + " --spp 1 --threads 1");
    ASSERT_EQ(one.code, 0) << one.err;
    EXPECT_EQ(
        one.err.rfind("wrote " + path("img.exr") + " and " + path("img.stats.json") + " (", 0), 0u)
        << one.err;
    EXPECT_NE(one.err.find(" paths/s, 1 thread)\n"), std::string::npos) << one.err;
    // Both times: the passes', and the whole cost, loading and set-up included (the passes'
    // alone, unnamed, read "0.00 s" for a render spent in an SH fit; helper 122).
    EXPECT_NE(one.err.find(" s of rendering, "), std::string::npos) << one.err;
    EXPECT_NE(one.err.find(" s in all, "), std::string::npos) << one.err;
    // With --variance it names the standard errors' file too.
    const Result se = run("render " + path("s.json") + " -o " + path("img.exr") +
                          " --spp 2 --threads 1 --variance");
    ASSERT_EQ(se.code, 0) << se.err;
    EXPECT_EQ(se.err.rfind("wrote " + path("img.exr") + ", " + path("img.stderr.exr") + " and " +
                               path("img.stats.json") + " (",
                           0),
              0u)
        << se.err;
}

// A render whose paths are ended by max_depth in numbers says so, and its stats count them (an
// albedo-1 furnace at the default depth 64 rendered half its value without a word).
TEST_F(Cli, RenderWarnsOfPathsEndedByMaxDepth) {
    write("s.json", scene(R"({"type": "homogeneous", "sigma_t": 300, "albedo": 1,
        "shape": {"type": "sphere"}, "phase": {"type": "hg", "g": 0.99}})"));
    const std::string render = "render " + path("s.json") + " --quiet -o " + path("out.exr");
    Result r = run(render);
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("render.max_depth: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("reached depth 64 and were ended there"), std::string::npos) << r.err;
    auto stats = nlohmann::json::parse(std::ifstream(path("out.stats.json")));
    EXPECT_GT(stats["paths_truncated"].get<uint64_t>(), 0u);
    EXPECT_NE(stats["warnings"][0].get<std::string>().find("render.max_depth"), std::string::npos);
    r = run(render + " --set render.max_depth=1000000");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    stats = nlohmann::json::parse(std::ifstream(path("out.stats.json")));
    EXPECT_EQ(stats["paths_truncated"].get<uint64_t>(), 0u);
    // Below depth 8 the cut is taken as meant (single scattering is max_depth 1): counted, not
    // warned about (review: every single-scattering render carried the warning).
    r = run(render + " --set render.max_depth=1");
    EXPECT_EQ(r.err, "");
    stats = nlohmann::json::parse(std::ifstream(path("out.stats.json")));
    EXPECT_GT(stats["paths_truncated"].get<uint64_t>(), 0u);
    // A few paths, half of them cut (4 of 8), are said too: the share's 95% lower bound is what
    // must exceed 0.1% (truncatedShareLowerBound, which keeps one path of 768 below it, a share
    // chance gives in a small render of the shipped default scene, helper 77); the rule of at
    // least 10 paths that was there let them say nothing (helper 94).
    write("few.json", R"({"camera": {"resolution": [2, 2], "position": [0, -3, 0]},
        "render": {"spp": 2, "max_depth": 8}, "environment": {"type": "constant", "radiance": 1},
        "media": [{"type": "homogeneous", "sigma_t": 300, "albedo": 1, "phase": {"type": "hg",
        "g": 0.99}, "shape": {"type": "sphere"}}]})");
    r = run("render " + path("few.json") + " --quiet -o " + path("out.exr"));
    stats = nlohmann::json::parse(std::ifstream(path("out.stats.json")));
    EXPECT_GT(stats["paths_truncated"].get<uint64_t>(), 0u);
    EXPECT_EQ(stats["paths"].get<uint64_t>(), 8u);
    EXPECT_NE(r.err.find("reached depth 8 and were ended there"), std::string::npos) << r.err;
    // A batch of such runs says it once, though each run's counts differ (an 80-run sweep said
    // it for every run: helper 98); each run's stats keep their own.
    write("few_sweep.json", R"({"scene": "few.json", "axes": {"seed": [1, 2, 3, 4]}})");
    r = run("batch " + path("few_sweep.json") + " --quiet --output " + path("few_runs"));
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(occurrences(r.err, "render.max_depth: "), 1u) << r.err;
    std::set<std::string> texts;
    for (const char* run : {"r0000", "r0001", "r0002", "r0003"}) {
        stats = nlohmann::json::parse(
            std::ifstream(path("few_runs/" + std::string(run) + ".stats.json")));
        ASSERT_EQ(stats["warnings"].size(), 1u) << run;
        texts.insert(stats["warnings"][0].get<std::string>());
    }
    EXPECT_GT(texts.size(), 1u);  // the counts differ: the texts did
    // One render's warnings that differ in a number only are all said (media[0] and media[1]).
    write("two.json", scene(std::string(R"({"type": "homogeneous", "sigma_t": 300, "albedo": 1,
        "phase": {"type": "hg", "g": 0.99, "sampling": "sh", "order": 100},
        "shape": {"type": "sphere", "radius": 0.5}})") +
                            ", " +
                            R"({"type": "homogeneous", "sigma_t": 300, "albedo": 1,
        "phase": {"type": "hg", "g": 0.99, "sampling": "sh", "order": 100},
        "shape": {"type": "sphere", "center": [0, 0, 2], "radius": 0.5}})"));
    r = run("render " + path("two.json") + " --quiet -o " + path("out.exr"));
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find(": media[0].phase: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(": media[1].phase: "), std::string::npos) << r.err;
    // A share below 0.1% is warned of once it exceeds the image mean's relative standard error:
    // this furnace cuts 0.086% of its paths, 0.99914 for 1 where the noise is about 0.0001
    // (helper 82; it said nothing).
    write("thin.json", thinFurnace());
    r = run("render " + path("thin.json") + " --quiet -o " + path("out.exr"));
    EXPECT_EQ(r.code, 0) << r.err;
    stats = nlohmann::json::parse(std::ifstream(path("out.stats.json")));
    const double share = stats["paths_truncated"].get<double>() / stats["paths"].get<double>();
    EXPECT_GT(share, 0);
    EXPECT_LT(share, 1e-3);
    EXPECT_NE(r.err.find("reached depth 64 and were ended there, without the light beyond it, "
                         "more than the image mean's relative standard error ("),
              std::string::npos)
        << r.err;
    // Under a sky black below the horizon the same cut is far below the noise: not said.
    write("noisy.json", thinFurnace(R"(, "lower_hemisphere_black": true)"));
    r = run("render " + path("noisy.json") + " --quiet -o " + path("out.exr"));
    EXPECT_EQ(r.code, 0) << r.err;
    stats = nlohmann::json::parse(std::ifstream(path("out.stats.json")));
    EXPECT_GE(stats["paths_truncated"].get<uint64_t>(), 10u);
    EXPECT_EQ(r.err, "");
    // The radiance cache's record paths are counted too: they carry the light after a camera
    // path's first vertex (a floor beside the thick fog; the review found them left out).
    write("cached.json", R"({"camera": {"resolution": [8, 6], "position": [0, -3, 3],
        "target": [0, 0, 0]}, "render": {"spp": 2, "max_depth": 8, "radiance_cache":
        {"enabled": true, "hsh_order": 4, "rays_per_record": 64}},
        "environment": {"type": "constant", "radiance": 1},
        "surfaces": [{"type": "rectangle", "bsdf": {"type": "lambert"}, "transform": {"scale": 3}}],
        "media": [{"type": "homogeneous", "sigma_t": 300, "albedo": 1, "phase": {"type": "hg",
        "g": 0.99}, "shape": {"type": "sphere", "center": [0, 0, 1.2], "radius": 1}}]})");
    r = run("render " + path("cached.json") + " --quiet -o " + path("out.exr"));
    EXPECT_NE(r.err.find("render.max_depth: "), std::string::npos) << r.err;
    stats = nlohmann::json::parse(std::ifstream(path("out.stats.json")));
    EXPECT_GT(stats["radiance_cache"]["record_paths_truncated"].get<uint64_t>(),
              stats["paths_truncated"].get<uint64_t>());
    EXPECT_EQ(stats["radiance_cache"]["record_non_finite_samples"], 0);  // (none is NaN here)
    // Unusable draws (InvalidDraws), by source, of the render and of the records: none here.
    for (const char* source : {"phase", "bsdf", "light", "flight", "transmittance"}) {
        EXPECT_EQ(stats["invalid_draws"].at(source), 0) << source;
        EXPECT_EQ(stats["radiance_cache"]["record_invalid_draws"].at(source), 0) << source;
    }
}

// A render whose SH-sampled phase function is unreliable says so on stderr and in its stats, with
// advice that can be followed: a higher order below the highest, analytic sampling at it.
TEST_F(Cli, RenderWarnsOfUnreliablePhaseFits) {
    write("s.json", scene(R"({"type": "homogeneous", "sigma_t": 2, "albedo": 0.8,
        "shape": {"type": "sphere"}, "phase": {"type": "hg", "g": 0.99, "sampling": "sh"}})"));
    const std::string render = "render " + path("s.json") + " --quiet -o " + path("out.exr");
    Result r = run(render);  // order auto reaches 256
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("shvol: warning: " + path("s.json") +
                         ": media[0].phase: the phase function rendered is its order-256 SH fit"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("that is the highest order: use \"sampling\": \"analytic\""),
              std::string::npos)
        << r.err;
    const auto stats = nlohmann::json::parse(std::ifstream(path("out.stats.json")));
    ASSERT_EQ(stats["warnings"].size(), 1u);
    EXPECT_NE(r.err.find(stats["warnings"][0].get<std::string>()), std::string::npos);
    r = run(render + " --set media[0].phase.order=100");
    EXPECT_NE(r.err.find("order-100 SH fit"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("raise \"order\""), std::string::npos) << r.err;
    r = run(render + " --set media[0].phase.g=0.9 --set media[0].phase.order=8" +
            " --set media[0].phase.evaluate=\\\"exact\\\"");
    EXPECT_NE(r.err.find("the SH-sampled weight p/pdf has second moment"), std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("use \"evaluate\": \"sh\" or a higher order"), std::string::npos) << r.err;
    // A weight whose m₂ passes per bounce compounds over many bounces (helper 178: 1.00072 per
    // bounce rendered a furnace 1.1% low): said from the paths the render made, with the moment
    // in the stats. HG 0.8 at order auto (27) has m₂ 1.0011; at σ_t 300 the paths scatter about
    // 180 times, at σ_t 2 a few times.
    const std::string exact = render + " --set media[0].phase.g=0.8 --set media[0].albedo=1" +
                              " --set media[0].phase.evaluate=\\\"exact\\\"" +
                              " --set render.max_depth=100000 --set render.spp=64";
    r = run(exact + " --set media[0].sigma_t=300");
    EXPECT_EQ(r.err.find("has second moment"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("media[0].phase: the SH-sampled weights p/pdf (\"evaluate\": \"exact\") "
                         "compound along the paths to a second moment of at least"),
              std::string::npos)
        << r.err;
    auto along = [&] {
        const auto st = nlohmann::json::parse(std::ifstream(path("out.stats.json")));
        return st["phase_weight_second_moment_along_paths"].get<double>();
    };
    EXPECT_GT(along(), std::exp(1.0));
    r = run(exact + " --set media[0].sigma_t=2");
    EXPECT_EQ(r.err.find("compound along the paths"), std::string::npos) << r.err;
    EXPECT_LT(along(), 1.1);
    r = run(render + " --set media[0].phase.g=0.8 --set media[0].sigma_t=300");  // weights of 1
    EXPECT_FALSE(nlohmann::json::parse(std::ifstream(path("out.stats.json")))
                     .contains("phase_weight_second_moment_along_paths"));
    // At the highest order a higher one is no advice (helpers 146, 151).
    r = run(render + " --set media[0].phase.g=0.98 --set media[0].phase.order=256" +
            " --set media[0].phase.window=none --set media[0].phase.sh_depth=8");
    EXPECT_NE(r.err.find("of the bins: \"window\": \"hann\"\n"), std::string::npos) << r.err;
    r = run(render + " --set media[0].phase.g=0.999 --set media[0].phase.order=256" +
            " --set media[0].phase.evaluate=\\\"exact\\\"");
    EXPECT_NE(r.err.find("second moment"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("use \"evaluate\": \"sh\" or \"sampling\": \"analytic\" (this is the "
                         "highest order)"),
              std::string::npos)
        << r.err;
    // A close fit drawn over coarse z-bins renders a blurred lobe (HG 0.9 at sh_depth 4: 0.880,
    // as helper 62 computed it independently).
    r = run(render + " --set media[0].phase.g=0.9 --set media[0].phase.sh_depth=4");
    EXPECT_NE(r.err.find("drawn over 2^4 z-bins, with relative L2 error 0.88"), std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("raise \"sh_depth\""), std::string::npos) << r.err;
    const auto coarse = nlohmann::json::parse(std::ifstream(path("out.stats.json")));
    EXPECT_NEAR(coarse["phase"][0]["rendered_relative_l2_error"].get<double>(), 0.88, 0.005);
    EXPECT_LT(coarse["phase"][0]["relative_l2_error"].get<double>(), 0.01);
    // A close fit whose dips are clamped: finer bins do not mend that (0.145 at depth 16, 0.144 at
    // 22), a window does; the advice says both (review).
    r = run(render + " --set media[0].phase.g=0.97 --set media[0].phase.order=115" +
            " --set media[0].phase.window=\\\"none\\\"");
    const size_t dips = r.err.find("or mend its dips below 0, clamped in ");
    ASSERT_NE(dips, std::string::npos) << r.err;
    EXPECT_NE(r.err.find("% of the bins: \"window\": \"hann\" or a higher order", dips),
              std::string::npos)
        << r.err;
    r = run(render + " --set media[0].phase.g=0.5");  // auto meets the tolerance
    EXPECT_EQ(r.code, 0);
    EXPECT_EQ(r.err, "");
    // A batch says a warning its runs share once (it said it for every run); each run's stats
    // keep it.
    write("sweep.json", R"({"scene": "s.json", "set": ["media[0].phase.order=100"],
        "axes": {"spp": [1, 2]}, "repeats": 2})");
    r = run("batch " + path("sweep.json") + " --quiet --jobs 2 --output " + path("b"));
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(occurrences(r.err, "order-100 SH fit"), 1u) << r.err;
    // Named by the run that gave it first (--jobs 2: either of the first two).
    EXPECT_TRUE(
        r.err.rfind("shvol: warning: " + path("s.json") + " (run r0000 spp=1 repeat=0): ", 0) ==
            0 ||
        r.err.rfind("shvol: warning: " + path("s.json") + " (run r0001 spp=2 repeat=0): ", 0) == 0)
        << r.err;
    const auto run3 = nlohmann::json::parse(std::ifstream(path("b/r0003.stats.json")));
    EXPECT_EQ(run3["warnings"].size(), 1u);
}

// The stats say whether next-event estimation is on, towards what, and why for the sky: under a
// constant one "auto" leaves it off, which the effects' names did not say (helper 68).
TEST_F(Cli, StatsSayWhyNextEventEstimationIsOnOrOff) {
    write("s.json", scene(Homogeneous));
    const auto nee = [&](const std::string& set) {
        const Result r =
            run("render " + path("s.json") + " -o " + path("n.exr") + " --spp 1 --quiet" + set);
        EXPECT_EQ(r.code, 0) << r.err;
        return nlohmann::json::parse(std::ifstream(path("n.stats.json")))["next_event_estimation"];
    };
    EXPECT_EQ(nee(""), nlohmann::json({{"setting", "auto"},
                                       {"environment", false},
                                       {"area_lights", false},
                                       {"why",
                                        "render.nee \"auto\" leaves it off under a "
                                        "constant sky, where phase sampling does better"}}));
    EXPECT_EQ(nee(" --set render.nee=true"), nlohmann::json({{"setting", true},
                                                             {"environment", true},
                                                             {"area_lights", false},
                                                             {"why", "render.nee is true"}}));
    EXPECT_EQ(nee(" --set environment.radiance=0")["why"], "the environment is black");
}

// Inside an emitting sphere "auto" draws no light sample towards it (emissionSurrounds): the
// effects name the decision, and the warning of a weighting it leaves unused says why and how to
// turn it on. The stats' why is the sky's (helper 185: the light sampler's warning said the
// surround, and to set render.nee true, which would not use a sky sampler under a black sky).
TEST_F(Cli, EmissionAllRoundTurnsLightSamplesOffAndSaysWhy) {
    write("s.json",
          R"({"camera": {"position": [0, 0, 0], "target": [0, 1, 0], "resolution": [4, 4]},
        "render": {"spp": 2, "max_depth": 50},
        "surfaces": [{"type": "sphere", "radius": 1, "bsdf": {"type": "lambert", "reflectance": 0.5},
                      "emission": 1, "emission_two_sided": true}]})");
    const Result r = run("render " + path("s.json") + " -o " + path("n.exr") +
                         " --quiet --set render.mis=none --set render.light_sampling=wavelet");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("render.mis: \"none\" is not used: no light sample is drawn, as "
                         "next-event estimation is off (render.nee \"auto\" leaves it off where "
                         "emitting surfaces of one radiance surround the scene, where phase and "
                         "BSDF sampling do better; set render.nee to true to use it)"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("render.light_sampling: \"wavelet\" is not used: next-event estimation, "
                         "which draws its samples, is off (the environment is black)"),
              std::string::npos)
        << r.err;
    const auto stats = nlohmann::json::parse(std::ifstream(path("n.stats.json")));
    EXPECT_EQ(stats["next_event_estimation"],
              nlohmann::json({{"setting", "auto"},
                              {"environment", false},
                              {"area_lights", false},
                              {"why", "the environment is black"}}));
    EXPECT_EQ(stats["effects"], nlohmann::json({"environment-black", "surfaces",
                                                "emission-surrounds", "roulette-survival-weight"}));
    EXPECT_EQ(stats["roulette_threshold"], 0.25);
}

// Product light sampling names itself in the stats with what it built and drew; a wrong
// strategy name is one line naming the key.
TEST_F(Cli, ProductLightSamplingStats) {
    write("s.json", scene(Homogeneous));
    Result r = run("render " + path("s.json") + " -o " + path("p.exr") +
                   " --spp 2 --quiet --set render.light_sampling=product --set render.mis=power"
                   " --set render.nee=true"
                   " --set render.product_order=6");
    ASSERT_EQ(r.code, 0) << r.err;
    std::ifstream f(path("p.stats.json"));
    const auto stats = nlohmann::json::parse(f);
    EXPECT_GT(stats["product_samples"].get<long long>(), 0);
    EXPECT_EQ(stats["light_sampling"]["strategy"], "product");
    EXPECT_EQ(stats["light_sampling"]["mis"], "power");
    EXPECT_EQ(stats["light_sampling"]["product_order"], 6);
    EXPECT_GT(stats["light_sampling"]["sky_memory_bytes"].get<long long>(), 0);
    r = run("render " + path("s.json") + " -o " + path("q.exr") +
            " --quiet --set render.light_sampling=sun");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("render.light_sampling: unknown value \"sun\""), std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(path("q.exr")));
}

// (At 40 × 24 pixels: six of the renderer's 16 × 16 tiles. The fixture's 8 × 6 is one tile,
// which any number of threads renders alike; helper 119.)
TEST_F(Cli, SameSeedSameImageAnyThreads) {
    write("s.json", scene(Homogeneous));
    const std::string tiles = " --set camera.resolution=[40,24]";
    ASSERT_EQ(
        run("render " + path("s.json") + " -o " + path("a.exr") + " --threads 1 --quiet" + tiles)
            .code,
        0);
    ASSERT_EQ(
        run("render " + path("s.json") + " -o " + path("b.exr") + " --threads 2 --quiet" + tiles)
            .code,
        0);
    EXPECT_EQ(readExr(path("a.exr")).rgb, readExr(path("b.exr")).rgb);
    // More threads than cores run as asked, without TBB's warning that it ignores the request (on
    // a host of fewer than 48 cores).
    const Result r =
        run("render " + path("s.json") + " -o " + path("c.exr") + " --threads 48 --quiet" + tiles);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    EXPECT_EQ(readExr(path("a.exr")).rgb, readExr(path("c.exr")).rgb);
}

TEST_F(Cli, MalformedJson) {
    write("bad.json", "{\"camera\": {\"fov\": 40,}}");
    expectOneLineError(
        "bad.json",
        path("bad.json") +
            ": line 1, column 23: malformed JSON: syntax error while parsing object key");
}

TEST_F(Cli, UnknownKeyAndWrongType) {
    write("unknown.json", scene(Homogeneous, R"(, "extra": {"x": 1})"));
    expectOneLineError("unknown.json", path("unknown.json") + ": extra: unknown key");
    write("typo.json",
          scene(R"({"type": "homogeneous", "sigma_t": 2, "phase": {"type": "hg", "gg": 0.5}})"));
    expectOneLineError("typo.json", path("typo.json") + ": media[0].phase.gg: unknown key");
    write("type.json", scene(R"({"type": "homogeneous", "sigma_t": "dense"})"));
    expectOneLineError(
        "type.json",
        path("type.json") + ": media[0].sigma_t: expected a number, got string \"dense\"");
    write("range.json", scene(R"({"type": "homogeneous", "albedo": [0.5, 1.5, 0.5]})"));
    expectOneLineError("range.json", path("range.json") + ": media[0].albedo[1]: value 1.5");
}

TEST_F(Cli, BadVdbFiles) {
    write("missing.json", scene(R"({"type": "vdb", "file": "nothere.vdb"})"));
    expectOneLineError("missing.json", path("missing.json") +
                                           ": media[0].file: no such file: " + path("nothere.vdb"));
    write("empty.json", scene(R"({"type": "vdb", "file": ""})"));
    expectOneLineError("empty.json", path("empty.json") +
                                         ": media[0].file: expected a file name, got an empty "
                                         "string");
    fs::create_directories(path("dir.vdb"));
    write("dir.json", scene(R"({"type": "vdb", "file": "dir.vdb"})"));
    expectOneLineError(
        "dir.json", path("dir.json") + ": media[0].file: not a regular file: " + path("dir.vdb"));

    write("corrupt.vdb", "garbage, not a vdb");
    write("corrupt.json", scene(R"({"type": "vdb", "file": "corrupt.vdb"})"));
    // (with the scene and its key too, as a mesh: helper 181)
    expectOneLineError("corrupt.json", path("corrupt.json") + ": media[0].file: " +
                                           path("corrupt.vdb") + ": not a readable OpenVDB file");

    // A file of another kind is named as such (it said "no VDB header"; helper 181).
    write("scene.json", scene(R"({"type": "vdb", "file": "corrupt.json"})"));
    expectOneLineError("scene.json", path("scene.json") +
                                         ": media[0].file: " + path("corrupt.json") +
                                         ": the file is JSON text, not an OpenVDB grid");

    VdbGridSpec s;
    s.resolution = 8;
    s.density = [](const Vec3& p) { return p.norm() < 0.3 ? 1.f : 0.f; };
    writeVdb(path("ok.vdb"), {s});
    write("grid.json", scene(R"({"type": "vdb", "file": "ok.vdb", "grid": "smoke"})"));
    expectOneLineError("grid.json", path("grid.json") + ": media[0].file: " + path("ok.vdb") +
                                        ": grid 'smoke': no such grid; the file has: density");

    s.density = [](const Vec3& p) { return p.norm() < 0.3 ? -1.f : 0.f; };
    writeVdb(path("neg.vdb"), {s});
    write("neg.json", scene(R"({"type": "vdb", "file": "neg.vdb"})"));
    expectOneLineError("neg.json", path("neg.json") + ": media[0].file: " + path("neg.vdb") +
                                       ": grid 'density': negative density");

    // A grid of zeros renders, empty, and says so (it rendered nothing without a word; helper 64).
    s.density = [](const Vec3&) { return 0.f; };
    writeVdb(path("zero.vdb"), {s});
    write("zero.json", scene(R"({"type": "vdb", "file": "zero.vdb"})"));
    const Result zero = run("render " + path("zero.json") + " -o " + path("zero.exr") + " --quiet");
    EXPECT_EQ(zero.code, 0) << zero.err;
    EXPECT_NE(zero.err.find("media[0] is empty: no voxel of its grid is above 0 (vdb " +
                            path("zero.vdb") + ":density, no density"),
              std::string::npos)
        << zero.err;

    s.density = [](const Vec3& p) { return p.norm() < 0.3 ? NAN : 0.f; };
    writeVdb(path("nan.vdb"), {s});
    write("nan.json", scene(R"({"type": "vdb", "file": "nan.vdb"})"));
    expectOneLineError("nan.json", path("nan.vdb") + ": grid 'density': NaN or infinite density");

    s.density = [](const Vec3& p) { return p.norm() < 0.3 ? 1.f : 0.f; };
    s.type = VdbGridSpec::Type::Vec3;
    writeVdb(path("vec.vdb"), {s});
    write("vec.json", scene(R"({"type": "vdb", "file": "vec.vdb"})"));
    expectOneLineError("vec.json", path("vec.vdb") + ": grid 'density': has value type vec3s");
}

TEST_F(Cli, BadMeshFiles) {
    auto surfaceScene = [](const std::string& file, const std::string& extra = "") {
        return scene(Homogeneous, R"(, "surfaces": [{"type": "mesh", "file": ")" + file +
                                      R"(", "bsdf": {"type": "null"}}])" + extra);
    };
    write("missing.json", surfaceScene("nothere.obj"));
    expectOneLineError("missing.json", path("nothere.obj"));

    write("corrupt.ply",
          "ply\nformat binary_little_endian 1.0\nelement vertex 3\n"
          "property float x\nproperty float y\nproperty float z\nend_header\nab");
    write("corrupt.json", surfaceScene("corrupt.ply"));
    expectOneLineError("corrupt.json", path("corrupt.ply") + ": ");

    write("nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
    write("nan.json", surfaceScene("nan.obj"));
    expectOneLineError("nan.json", path("nan.obj") + ": line 3");

    write("flat.obj", "v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
    write("flat.json", surfaceScene("flat.obj"));
    expectOneLineError("flat.json", path("flat.obj") + ": line 4: zero area");

    write("open.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n");
    write(
        "open.json",
        scene(R"({"type": "homogeneous", "boundary": 0})",
              R"(, "surfaces": [{"type": "mesh", "file": "open.obj", "bsdf": {"type": "null"}}])"));
    // (Named in the mesh's file too: the place was the loader's triangle, in the scene's file.)
    expectOneLineError("open.json", "media[0].boundary: surfaces[0]: " + path("open.obj") +
                                        ": line 5: edge from (0, 1, 0) to (1, 0, 0) has no "
                                        "opposite edge: the mesh is not closed");
}

TEST_F(Cli, SurfaceSceneSameImageAnyThreadsAndStats) {
    write("box.obj",
          "v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\n"
          "v -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\n"
          "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n");
    write("s.json", scene(R"({"type": "homogeneous", "sigma_t": 1, "boundary": "glass"})",
                          R"(, "surfaces": [
                 {"type": "mesh", "file": "box.obj", "name": "glass",
                  "bsdf": {"type": "dielectric", "ior": 1.4}},
                 {"type": "rectangle", "emission": 5,
                  "transform": {"translate": [0, 0, 2.5], "rotate": {"axis": [1, 0, 0], "degrees": 180}}},
                 {"type": "rectangle", "bsdf": {"type": "phong", "specular": 0.5, "exponent": 22},
                  "transform": {"translate": [0, 0, -1.5], "scale": 4}}])"));
    // (six 16 × 16 tiles, as in SameSeedSameImageAnyThreads)
    const std::string tiles = " --set camera.resolution=[40,24]";
    ASSERT_EQ(
        run("render " + path("s.json") + " -o " + path("a.exr") + " --threads 1 --quiet" + tiles)
            .code,
        0);
    ASSERT_EQ(
        run("render " + path("s.json") + " -o " + path("b.exr") + " --threads 2 --quiet" + tiles)
            .code,
        0);
    EXPECT_EQ(readExr(path("a.exr")).rgb, readExr(path("b.exr")).rgb);
    std::ifstream f(path("a.stats.json"));
    const nlohmann::json st = nlohmann::json::parse(f);
    EXPECT_EQ(st["surfaces"]["count"], 3);
    EXPECT_EQ(st["surfaces"]["triangles"], 16);
    EXPECT_EQ(st["surfaces"]["emitters"], 1);
    EXPECT_GT(st["surfaces"]["shadow_rays"].get<double>(), 0);
    const auto& fx = st["effects"];
    for (const char* e : {"surfaces", "bounded-media", "nee-area-lights"})
        EXPECT_NE(std::find(fx.begin(), fx.end(), e), fx.end()) << e;
    EXPECT_EQ(st["scene_resolved"]["surfaces"][1]["bsdf"]["type"], "lambert");
    EXPECT_EQ(st["media"].size(), 1u);
    // Without media, the per-medium lists are there and empty (README's stats keys).
    ASSERT_EQ(run("render " + path("s.json") + " -o " + path("c.exr") +
                  " --threads 1 --quiet --spp 1 --set media=null")
                  .code,
              0);
    const nlohmann::json none = nlohmann::json::parse(test::fileBytes(path("c.stats.json")));
    EXPECT_EQ(none["media"], nlohmann::json::array());
    EXPECT_EQ(none["phase"], nlohmann::json::array());
}

TEST_F(Cli, BadExrFiles) {
    const std::string env = R"(, "environment": {"type": "image", "file": "sky.exr"})";
    auto sceneWithSky = [&](const std::string& sky) {
        return R"({"camera": {"resolution": [4, 4]}, "environment": {"type": "image", "file": ")" +
               sky + "\"}}";
    };
    write("missing.json", sceneWithSky("nosky.exr"));
    expectOneLineError("missing.json", path("missing.json") + ": environment.file: no such file: " +
                                           path("nosky.exr"));
    write("bad.exr", "not an exr");
    write("corrupt.json", sceneWithSky("bad.exr"));
    // (with the scene and its key too, as a mesh: helper 181)
    expectOneLineError("corrupt.json", path("corrupt.json") + ": environment.file: " +
                                           path("bad.exr") + ": not a readable OpenEXR file");
    Image img(4, 2);
    img.set(1, 1, Spectrum(1, NAN, 1));
    writeExr(path("nan.exr"), img);
    write("nan.json", sceneWithSky("nan.exr"));
    expectOneLineError("nan.json", path("nan.json") + ": environment.file: " + path("nan.exr") +
                                       ": pixel (1, 1): NaN value");
}

// A bad phase table names the scene and the key before the table and its line, as a mesh, a sky
// and a grid do (it named the table alone; helper 183).
TEST_F(Cli, BadPhaseTableNamesTheSceneAndItsKey) {
    writeTabulatedScene();
    write("t.csv", "angle_deg,value\n0,2\n180,abc\n");
    expectOneLineError("s.json",
                       path("s.json") + ": media[0].phase.file: " + path("t.csv") + ": line 3");
}

TEST_F(Cli, BadOverridesAndOutputs) {
    write("s.json", scene(Homogeneous));
    Result r = run("render " + path("s.json") + " -o " + path("out.exr") +
                   " --set render.spp=zero --quiet");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("render.spp: expected an integer, got string \"zero\""), std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(path("out.exr")));
    r = run("render " + path("s.json") + " -o " + path("no/such/dir/out.exr") + " --quiet");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("no/such/dir/out.exr: cannot write: directory"), std::string::npos)
        << r.err;
    EXPECT_TRUE(r.out.empty());
    // The extension in any case, as the name check takes it; a name is needed before it.
    r = run("render " + path("s.json") + " -o " + path("UP.EXR") + " --spp 1,2 --quiet");
    EXPECT_EQ(r.code, 0) << r.err;
    for (const char* f : {"UP.EXR", "UP.stats.json", "UP.spp1.EXR", "UP.spp1.stats.json"})
        EXPECT_TRUE(fs::exists(path(f))) << f;
    EXPECT_FALSE(fs::exists(path("UP.EXR.exr")));
    r = run("render " + path("s.json") + " -o " + path(".exr") + " --quiet");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find(".exr: the output needs a name before .exr"), std::string::npos) << r.err;
    // A "render" that a --set made something else than an object is refused as such, at that
    // --set, also with --spp and --seed, which set keys inside it (they were blamed as a --set
    // that could not descend into it).
    for (const char* options : {"", " --spp 1", " --seed 3"}) {
        r = run("render " + path("s.json") + " -o " + path("out.exr") + " --set render=[]" +
                options + " --quiet");
        EXPECT_EQ(r.code, 1);
        EXPECT_EQ(r.err, "shvol: error: " + path("s.json") +
                             ": --set render=[]: render: expected an object, got array\n")
            << options;
    }
    EXPECT_FALSE(fs::exists(path("out.exr")));
}

// --set key=null of a key the scene does not have changes nothing, which is said: a typo in a
// reset (media.0.phase.gg=null for g) went by without a word. A key the scene has is deleted
// quietly.
TEST_F(Cli, RenderWarnsOfADeletionThatDeletesNothing) {
    write("s.json", scene(Homogeneous));
    const Result r = run("render " + path("s.json") + " -o " + path("d.exr") +
                         " --quiet --set camera.nosuch=null --set camera.position=null"
                         " --set media.0.phase.g=null");
    EXPECT_EQ(r.code, 0) << r.err;
    // (The last under a key the scene lacks: media[0] has no phase. The walk made it null, which
    // the loader refused.)
    EXPECT_EQ(r.err, "shvol: warning: " + path("s.json") +
                         ": --set camera.nosuch=null: the scene has no such key; nothing was "
                         "deleted\nshvol: warning: " +
                         path("s.json") +
                         ": --set media.0.phase.g=null: the scene has no such key; nothing was "
                         "deleted\n");
    EXPECT_NE(test::fileBytes(path("d.stats.json")).find("nothing was deleted"), std::string::npos);
}

// A stats file's scene_resolved renders again as the same scene without a warning: it leaves out
// the keys the render did not use (the defaults of effects that are off: the product lobe's
// without product sampling, the radiance cache's with it off, the transmittance estimator where
// none is estimated, a majorant cell without a majorant grid), which a render of it would warn
// of. Before, every such render warned of keys no one gave (helper 139).
TEST_F(Cli, ResolvedSceneRendersAgainWithoutWarnings) {
    ASSERT_EQ(run("make-medium plume -o " + path("p.vdb") + " --resolution 16").code, 0);
    write("s.json", R"({"camera": {"resolution": [6, 4], "position": [0, -3, 0]},
        "render": {"spp": 2}, "environment": {"type": "constant", "radiance": 1},
        "media": [{"type": "vdb", "file": "p.vdb", "majorant_grid": false},
                  {"type": "homogeneous", "sigma_t": 1, "shape": {"type": "sphere",
                   "radius": 0.2, "center": [0, 0, 0.6]}}],
        "surfaces": [{"type": "rectangle", "bsdf": {"type": "lambert"},
                      "transform": {"translate": [0, 0, -1]}}]})");
    Result r = run("render " + path("s.json") + " -o " + path("a.exr") + " --quiet");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto first = nlohmann::json::parse(std::ifstream(path("a.stats.json")));
    const nlohmann::json& resolved = first["scene_resolved"];
    EXPECT_EQ(resolved["render"]["radiance_cache"], nlohmann::json::parse(R"({"enabled": false})"));
    for (const char* key : {"product_order", "product_depth", "transmittance"})
        EXPECT_FALSE(resolved["render"].contains(key)) << key;
    EXPECT_FALSE(resolved["media"][0].contains("majorant_cell"));
    EXPECT_EQ(resolved["media"][0]["majorant_grid"], false);
    write("again.json", resolved.dump());
    r = run("render " + path("again.json") + " -o " + path("b.exr"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
    const auto second = nlohmann::json::parse(std::ifstream(path("b.stats.json")));
    EXPECT_EQ(second["scene_resolved"], resolved);
    EXPECT_EQ(readExr(path("b.exr")).rgb, readExr(path("a.exr")).rgb);
    // A checkpoint's identity is that scene too: the stats' scene resumes a render that gave an
    // unused key a value of its own (helper 140: product_order 6 without product sampling was a
    // "scene value render.product_order" that differed), to the image of one uninterrupted run.
    r = run("render " + path("s.json") + " -o " + path("d.exr") + " --quiet --checkpoint " +
            path("ck.bin") + " --set render.product_order=6");
    ASSERT_EQ(r.code, 0) << r.err;
    write("resume.json",
          nlohmann::json::parse(std::ifstream(path("d.stats.json")))["scene_resolved"].dump());
    r = run("render " + path("resume.json") + " -o " + path("e.exr") + " --quiet --spp 4 " +
            "--checkpoint " + path("ck.bin") + " --resume");
    ASSERT_EQ(r.code, 0) << r.err;
    ASSERT_EQ(run("render " + path("s.json") + " -o " + path("f.exr") + " --quiet --spp 4").code,
              0);
    EXPECT_EQ(readExr(path("e.exr")).rgb, readExr(path("f.exr")).rgb);
    // Where they are used, the keys stay.
    r = run("render " + path("s.json") + " -o " + path("c.exr") +
            " --quiet --set render.nee=true --set render.light_sampling=\"product\"" +
            " --set media.0.majorant_grid=true");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto used = nlohmann::json::parse(std::ifstream(path("c.stats.json")))["scene_resolved"];
    for (const char* key : {"product_order", "product_depth", "transmittance"})
        EXPECT_TRUE(used["render"].contains(key)) << key;
    EXPECT_TRUE(used["media"][0].contains("majorant_cell"));
}

// A light sampler asked for where next-event estimation is off goes unused: the render says so
// and why, once (it said nothing; only the stats' effects showed it; helper 54). Where NEE is on,
// or the default sampler is left, nothing is said.
TEST_F(Cli, RenderWarnsOfAnUnusedLightSampler) {
    write("s.json", scene(Homogeneous));
    const std::string warning = "shvol: warning: " + path("s.json") +
                                ": render.light_sampling: \"product\" is not used: next-event "
                                "estimation, which draws its samples, is off (";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"",
         "render.nee \"auto\" leaves it off under a constant sky, where phase sampling does "
         "better; set render.nee to true to use it)\n"},
        {" --set render.nee=false", "render.nee is false)\n"},
        {" --set environment.radiance=0", "the environment is black)\n"},
        {" --set media[0].albedo=0", "no path scatters or reflects)\n"},
        {" --set render.nee=true", ""},
    };
    for (const auto& [sets, why] : cases) {
        const Result r = run("render " + path("s.json") + " -o " + path("a.exr") +
                             " --quiet --set render.light_sampling=\"product\"" + sets);
        EXPECT_EQ(r.code, 0) << r.err;
        EXPECT_EQ(r.err, why.empty() ? "" : warning + why) << sets;
    }
    const Result r = run("render " + path("s.json") + " -o " + path("a.exr") + " --quiet");
    EXPECT_EQ(r.err, "");
    // The sky's wavelet compression, where no sky hierarchy is built, changes nothing.
    const std::string wavelet = "environment.wavelet_coefficients: 100 is not used";
    const std::string compress = " --quiet --set environment.wavelet_coefficients=100";
    EXPECT_NE(run("render " + path("s.json") + " -o " + path("a.exr") + compress).err.find(wavelet),
              std::string::npos);
    EXPECT_EQ(run("render " + path("s.json") + " -o " + path("a.exr") + compress +
                  " --set render.nee=true --set render.light_sampling=\"wavelet\"")
                  .err,
              "");
    // Compressed until the sun is gone, it is used and noisy (helper 108: 30 times the standard
    // error at the same cost); kept well enough, it is not said.
    const std::string sunlit = "render " + std::string(SHVOL_SOURCE_DIR) +
                               "/media/sunlit_cloud.json -o " + path("a.exr") +
                               " --quiet --spp 1 --set camera.resolution=[8,8]"
                               " --set render.light_sampling='\"wavelet\"'";
    for (const std::string& kept : {std::string("8"), std::string("64")}) {
        const Result lost = run(sunlit + " --set environment.wavelet_coefficients=" + kept);
        EXPECT_EQ(lost.code, 0) << lost.err;
        EXPECT_NE(lost.err.find(": environment.wavelet_coefficients: the " + kept +
                                " kept of 1048575 give light samples of the sky "),
                  std::string::npos)
            << lost.err;
        EXPECT_NE(lost.err.find(": light the compression leaves out (a sun) is reached by phase "
                                "and BSDF samples alone"),
                  std::string::npos)
            << lost.err;
    }
    // (At 64 the L2 error, 0.049, said nothing of it; helper 109.)
    EXPECT_EQ(run(sunlit + " --set environment.wavelet_coefficients=128").err, "");
}

// A weighting asked for where no light sample is drawn goes unused: "none" rendered as "balance"
// would, without a word (helper 111). Where light samples are drawn, of the sky or of an emitting
// surface, nothing is said.
TEST_F(Cli, RenderWarnsOfAnUnusedMisHeuristic) {
    write("s.json", scene(Homogeneous));
    const std::string base = "render " + path("s.json") + " -o " + path("a.exr") + " --quiet";
    const std::string unused = "shvol: warning: " + path("s.json") + ": render.mis: \"";
    const std::string off =
        "\" is not used: no light sample is drawn, as next-event estimation is "
        "off (";
    EXPECT_EQ(run(base + " --set render.mis='\"none\"'").err,
              unused + "none" + off +
                  "render.nee \"auto\" leaves it off under a constant sky, where phase sampling "
                  "does better; set render.nee to true to use it)\n");
    EXPECT_EQ(run(base + " --set render.mis='\"power\"' --set render.nee=false").err,
              unused + "power" + off + "render.nee is false)\n");
    EXPECT_EQ(run(base + " --set render.mis='\"power\"' --set render.nee=true").err, "");
    EXPECT_EQ(run(base).err, "");
    // The Cornell box's light is sampled under "auto": its weighting is used.
    const std::string cornell = "render " + std::string(SHVOL_SOURCE_DIR) +
                                "/media/cornell.json -o " + path("c.exr") +
                                " --quiet --spp 1 --set camera.resolution=[8,8]"
                                " --set render.mis='\"power\"'";
    EXPECT_EQ(run(cornell).err, "");
    EXPECT_EQ(run(cornell + " --set render.nee=false").err,
              "shvol: warning: " + std::string(SHVOL_SOURCE_DIR) +
                  "/media/cornell.json: render.mis: \"power" + off + "render.nee is false)\n");
    // Black sky, no emitter: nothing to sample, whatever render.nee says.
    for (const std::string& nee : {"", " --set render.nee=false", " --set render.nee=true"})
        EXPECT_EQ(run(base + " --set render.mis='\"none\"' --set environment.radiance=0" + nee).err,
                  unused + "none" + off + "the environment is black and no surface emits)\n")
            << nee;
}

// The image's relative standard error, and the max_depth warning drawn from it, are the same for
// any thread count and pass layout (helper 93: with --checkpoint-interval 0 the warning went away;
// here the plume at max_depth 24 cuts 28 paths, which the noise decides).
TEST_F(Cli, RenderStatsOfTheNoiseDependOnTheSeedOnly) {
    const std::string plume = std::string(SHVOL_SOURCE_DIR) + "/media/plume.json";
    const std::string base = "render " + plume +
                             " --quiet --set camera.resolution=[48,32] --set render.max_depth=24 "
                             "--spp 64 -o ";
    std::vector<nlohmann::json> stats;
    for (const std::string& how :
         {std::string(" --threads 1"), std::string(" --threads 2"),
          " --threads 2 --checkpoint " + path("ck.bin") + " --checkpoint-interval 0"}) {
        const Result r = run(base + path("p.exr") + how);
        EXPECT_EQ(r.code, 0) << r.err;
        stats.push_back(nlohmann::json::parse(std::ifstream(path("p.stats.json"))));
    }
    ASSERT_TRUE(stats[0]["image_mean_relative_error"].is_number());
    EXPECT_GT(stats[0]["paths_truncated"].get<uint64_t>(), 0u);
    // (said: 28 of 98,304 paths, 95% bound 0.0201% against the noise's 0.0171%)
    ASSERT_EQ(stats[0]["warnings"].size(), 1u);
    // (the count is the stats', not pinned: helper 119)
    EXPECT_EQ(
        stats[0]["warnings"][0].get<std::string>().rfind(
            "render.max_depth: " + std::to_string(stats[0]["paths_truncated"].get<uint64_t>()) +
                " of " + std::to_string(stats[0]["paths"].get<uint64_t>()),
            0),
        0u)
        << stats[0]["warnings"][0];
    for (size_t i = 1; i < stats.size(); ++i) {
        EXPECT_EQ(stats[i]["image_mean_relative_error"], stats[0]["image_mean_relative_error"]);
        EXPECT_EQ(stats[i]["warnings"], stats[0]["warnings"]) << i;
    }
}

// A stated error that rests on few degrees of freedom is said, and the figure is in the stats
// (helper 160: g 0.99 under the sun, 32x24 at 16 spp, renders 14% low stated 0.56%; helper 162:
// Film::meanRelativeErrorDof below 10 in 93% of such renders); not for the plume.
TEST_F(Cli, RenderWarnsOfAStatedErrorOnFewDegreesOfFreedom) {
    const std::string media = std::string(SHVOL_SOURCE_DIR) + "/media/";
    Result r = run("render " + media + "sunlit_cloud.json -o " + path("a.exr") +
                   " --set media.0.phase.g=0.99 --set camera.resolution=[32,24] --spp 16 --seed 5 "
                   "--quiet");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("sunlit_cloud.json: image_mean_relative_error: "), std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("degrees of freedom (image_mean_relative_error_dof): a few pixels' large "
                         "samples hold most of its variance, so it is uncertain by a factor of "),
              std::string::npos)
        << r.err;
    auto stats = nlohmann::json::parse(std::ifstream(path("a.stats.json")));
    EXPECT_LT(stats["image_mean_relative_error_dof"].get<double>(), 10);
    // (The default scene's sun makes it heavy at small sizes too: 3.3-76 at 16x12 and 8 spp, its
    // stated error 1.1-2.4% from seed to seed; 25-108 at 64x48 and 16 spp.)
    r = run("render " + media + "plume.json -o " + path("b.exr") + " --spp 4 --quiet");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    stats = nlohmann::json::parse(std::ifstream(path("b.stats.json")));
    EXPECT_GT(stats["image_mean_relative_error_dof"].get<double>(), 1000);
    // At 1 spp the error is of all samples: no figure.
    r = run("render " + media + "default.json -o " + path("c.exr") +
            " --set camera.resolution=[16,12] --spp 1 --quiet");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(
        nlohmann::json::parse(std::ifstream(path("c.stats.json")))["image_mean_relative_error_dof"]
            .is_null());
}

// render.nee false under an image sky with a sun that phase sampling meets fewer than 4 times in
// a pixel's samples is said (helper 160: g 0.99 under media/sunsky.exr, every render about 10%
// low where its stated error was 0.15%); not with samples enough, with next-event estimation
// on, or under a smooth sky. The sun: row 1 of 32 at 100, 2π(cos π/32 − cos π/16) = 0.090475
// sr; ∫ Y² = 904.75 + (4π − 0.090475) = 917.23, half of it in 0.045861 sr of the row, which
// holds 4.5861 of the 21.524 of light, 21%, and is met 0.058 times at 16 spp and 7.3 times at
// 2000; 4 times from ⌈4 · 4π/0.045861⌉ = 1097 spp.
TEST_F(Cli, RenderWarnsOfNeeOffUnderASun) {
    writeSunAndSmoothSkies();
    write("s.json", R"({"camera": {"resolution": [2, 2], "position": [0, -3, 0]},
        "render": {"nee": false}, "environment": {"type": "image", "file": "sun.exr"},
        "media": [{"type": "homogeneous", "sigma_t": 1, "albedo": 0.9,
                   "shape": {"type": "sphere", "radius": 1}}]})");
    const std::string base = "render " + path("s.json") + " -o " + path("a.exr") + " --quiet";
    Result r = run(base + " --spp 16");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "shvol: warning: " + path("s.json") +
                         ": render.nee: false under an image sky whose brightest 0.0459 sr (0.36% "
                         "of the sky seen) hold 21% of its light: paths meet them only by phase "
                         "or BSDF sampling, about 0.058 times in a pixel's 16 samples, so most "
                         "pixels come out low and a few far too bright, with standard errors that "
                         "do not show it; leave render.nee \"auto\" (on under an image sky with "
                         "a sun), or render 1097 samples per pixel or more\n");
    EXPECT_NE(test::fileBytes(path("a.stats.json")).find("render.nee: false under an image sky"),
              std::string::npos);
    for (const std::string& quiet :
         {base + " --spp 2000", base + " --spp 16 --set render.nee=true",
          base + " --spp 1 --set environment.file=" + path("smooth.exr")}) {
        r = run(quiet);
        EXPECT_EQ(r.code, 0) << r.err;
        EXPECT_EQ(r.err, "") << quiet;
    }
}

// Under an image sky "auto" samples the sky where its light is uneven or it has a sun
// (neePaysUnder), and the stats say which, with m = Ω ∫Y² dω / (∫Y dω)², here against the sum
// over the rows of the 64 × 32 skies of RenderWarnsOfNeeOffUnderASun.
TEST_F(Cli, StatsSayWhyNextEventEstimationIsOnOrOffUnderAnImageSky) {
    const auto m = [](const std::function<double(int)>& rowValue) {
        double omega = 0, power = 0, moment = 0;
        for (int y = 0; y < 32; ++y) {
            const double o = TwoPi * (std::cos(Pi * y / 32) - std::cos(Pi * (y + 1) / 32)),
                         v = rowValue(y);
            omega += o, power += v * o, moment += v * v * o;
        }
        return omega * moment / (power * power);  // (omega: 4π)
    };
    writeSunAndSmoothSkies();
    write("s.json", R"({"camera": {"resolution": [2, 2], "position": [0, -3, 0]},
        "environment": {"type": "image", "file": "sun.exr"},
        "media": [{"type": "homogeneous", "sigma_t": 1, "albedo": 0.9,
                   "shape": {"type": "sphere", "radius": 1}}]})");
    const auto nee = [&](const std::string& sky) {
        const Result r = run("render " + path("s.json") + " -o " + path("n.exr") +
                             " --spp 1 --quiet --set environment.file=" + path(sky));
        EXPECT_EQ(r.code, 0) << r.err;
        return nlohmann::json::parse(std::ifstream(path("n.stats.json")))["next_event_estimation"];
    };
    const nlohmann::json withSun = nee("sun.exr"), even = nee("smooth.exr");
    EXPECT_EQ(withSun["environment"], true);
    const double mSun = m([](int y) { return y == 1 ? 100.0 : 1.0; });
    ASSERT_GE(mSun, 2.5);
    char why[400];
    std::snprintf(why, sizeof why,
                  "render.nee \"auto\" turns it on under a sky image whose light is uneven (m = "
                  "4π ∫Y² dω / (∫Y dω)² = %.3g, at least 2.5)",
                  mSun);
    EXPECT_EQ(withSun["why"], why);
    EXPECT_NEAR(withSun["sky_second_moment_ratio"].get<double>(), mSun, 1e-9);
    const double mEven = m([](int y) { return 1.0 + y; });
    EXPECT_LT(mEven, 2.5);
    EXPECT_NEAR(even["sky_second_moment_ratio"].get<double>(), mEven, 1e-9);
    EXPECT_EQ(even["environment"], false);
    // Its brightest 1% of the sphere: the last rows' texels, brightest first, the last in part.
    double power = 0, held = 0, left = 0.01 * FourPi;
    for (int y = 31; y >= 0; --y) {
        const double o = TwoPi * (std::cos(Pi * y / 32) - std::cos(Pi * (y + 1) / 32));
        power += (1.0 + y) * o;
        held += (1.0 + y) * std::min(o, std::max(0.0, left)), left -= o;
    }
    const double share = held / power;
    EXPECT_LT(share, 0.05);
    EXPECT_NEAR(even["sky_brightest_share"].get<double>(), share, 1e-9);
    std::snprintf(why, sizeof why,
                  "render.nee \"auto\" leaves it off under a sky image whose light is even (m = "
                  "4π ∫Y² dω / (∫Y dω)² = %.3g, under 2.5; its brightest 1%% hold %.2g%% of it, "
                  "under 5%%), where phase sampling does better",
                  mEven, 100 * share);
    EXPECT_EQ(even["why"], why);
}

// render.mis "none" with fewer samples per pixel than 4 times the phase lobe's peak over the
// isotropic value (HG 0.9: 190) is said, naming the medium and the peak (helper 91: most pixels
// come out low, silently); not with as many samples (800 for 760; HG 0.5, 6, at 32), with MIS,
// without next-event estimation or where the medium does not scatter.
TEST_F(Cli, RenderWarnsOfLightSamplesAloneMissingASharpLobe) {
    write("s.json", scene(Homogeneous));
    const std::string base = "render " + path("s.json") + " -o " + path("a.exr") +
                             " --quiet --set media[0].phase='{\"type\": \"hg\", \"g\": 0.9}'"
                             " --set render.nee=true";
    const Result r = run(base + " --set render.mis='\"none\"' --spp 16");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err.rfind("shvol: warning: " + path("s.json") +
                              ": render.mis: \"none\" with 16 samples per pixel, and media[0]'s "
                              "phase function peaks at 190 times the isotropic value",
                          0),
              0u)
        << r.err;
    EXPECT_NE(test::fileBytes(path("a.stats.json")).find("light samples alone rarely"),
              std::string::npos);
    // A glossy surface's lobe as well (Phong n = 10⁴: 20,002).
    write("g.json", R"({"camera": {"resolution": [4, 4], "position": [0, -3, 2]},
        "render": {"spp": 4, "nee": true, "mis": "none"}, "environment": {"type": "constant",
        "radiance": 1}, "surfaces": [{"type": "rectangle", "name": "floor", "bsdf": {"type":
        "phong", "diffuse": 0, "specular": 0.5, "exponent": 10000}}]})");
    const Result glossy = run("render " + path("g.json") + " -o " + path("g.exr") + " --quiet");
    EXPECT_EQ(glossy.code, 0) << glossy.err;
    EXPECT_NE(glossy.err.find("render.mis: \"none\" with 4 samples per pixel, and floor's BSDF "
                              "peaks at 2e+04 times the isotropic value"),
              std::string::npos)
        << glossy.err;
    // Not the same lobe lit by a small emitting surface alone, which light samples reach better
    // than the lobe does (helper 109).
    write("l.json", R"({"camera": {"resolution": [4, 4], "position": [0, -3, 2]},
        "render": {"spp": 4, "mis": "none"}, "surfaces": [{"type": "rectangle", "name": "floor",
        "bsdf": {"type": "phong", "diffuse": 0, "specular": 0.5, "exponent": 10000}},
        {"type": "rectangle", "name": "lamp", "emission": 2, "bsdf": {"type": "lambert",
        "reflectance": 0}, "transform": {"translate": [0, 0, 2],
        "rotate": {"axis": [1, 0, 0], "degrees": 180}}}]})");
    const Result lamp = run("render " + path("l.json") + " -o " + path("l.exr") + " --quiet");
    EXPECT_EQ(lamp.code, 0) << lamp.err;
    EXPECT_EQ(lamp.err, "");
    for (const std::string& quiet :
         {" --set render.mis='\"none\"' --spp 800", " --spp 16",
          " --set render.mis='\"none\"' --spp 32 --set media[0].phase.g=0.5"})
        EXPECT_EQ(run(base + quiet).err, "") << quiet;
    // Without light samples "none" is unused, and said to be
    // (Cli.RenderWarnsOfAnUnusedMisHeuristic), not this.
    for (const std::string& unused : {" --set render.nee=false", " --set media[0].albedo=0"}) {
        const std::string err = run(base + " --set render.mis='\"none\"' --spp 16" + unused).err;
        EXPECT_EQ(err.find("light samples alone rarely"), std::string::npos) << unused;
        EXPECT_NE(err.find("render.mis: \"none\" is not used"), std::string::npos) << unused;
    }
}

// An SH-sampled phase function with structure finer than its fit's quadrature (a tabulated spike
// 2·10⁻⁶° wide, peaking at 10⁻⁶°) is warned of, whichever its use (helper 94: a white furnace came
// out 0.76, without a word); the same table sampled analytically is not.
TEST_F(Cli, RenderWarnsOfSHSamplingBlindToItsPhaseFunction) {
    write("spike.csv", "0,0\n1e-6,1\n2e-6,0\n180,0\n");
    write("s.json", scene(Homogeneous));
    const std::string base = "render " + path("s.json") + " -o " + path("a.exr") +
                             " --quiet --set media[0].phase='{\"type\": \"tabulated\", "
                             "\"file\": \"spike.csv\"";
    const std::string warning =
        "media[0].phase: the function has structure finer than the "
        "quadrature of its SH fit sees";
    for (const std::string& use : {"exact", "sh"}) {
        const Result r =
            run(base + ", \"sampling\": \"sh\", \"order\": 32, \"evaluate\": \"" + use + "\"}'");
        EXPECT_EQ(r.code, 0) << r.err;
        EXPECT_NE(r.err.find(warning), std::string::npos) << use << ": " << r.err;
    }
    const Result analytic = run(base + "}'");
    EXPECT_EQ(analytic.code, 0) << analytic.err;
    EXPECT_EQ(analytic.err.find(warning), std::string::npos) << analytic.err;
}

// `phase fit` and `phase sample` build the fit as a render does, and say what a render says of
// a function finer than its quadrature: they printed a rendered error of 0 and an exact weight
// second moment of 0 (impossible: it is at least 1), and sampled weights of mean 0, without a
// word (helper 110; the quadrature found none of this spike then, 95% now that its panels end at
// the table's nodes). A function the quadrature sees is not warned of.
TEST_F(Cli, PhaseCommandsWarnOfStructureFinerThanTheirQuadrature) {
    write("spike.csv", "0,0\n1e-6,1\n2e-6,0\n180,0\n");
    write("smooth.csv", "0,2\n90,1\n180,0.5\n");
    const std::string spike = "tabulated:file=" + path("spike.csv") + " --order 32";
    // What the quadrature finds of the spike (0.9514 with today's panels) is the program's, not
    // pinned here (helper 118): it must be short of 1 by more than the warning's 10⁻³, and the
    // warnings must give the --json value.
    const auto fit = nlohmann::json::parse(run("phase fit " + spike + " --json").out);
    const double mass = fit["quadrature_mass"].get<double>();
    EXPECT_GT(mass, 0);
    EXPECT_LT(mass, 1 - 1e-3);
    char found[32];
    std::snprintf(found, sizeof found, "%.4g", mass);
    const std::string warning = std::string(
                                    ": the function has structure finer than the quadrature of "
                                    "its SH fit sees (it finds ") +
                                found + " of its integral, 1)";
    for (const std::string& cmd :
         {"phase fit " + spike, "phase sample " + spike + " --count 100 -o " + path("s.csv"),
          "phase sample " + spike + " --sampler general --count 100 -o " + path("s.csv")}) {
        const Result r = run(cmd);
        EXPECT_EQ(r.code, 0) << cmd << ": " << r.err;
        EXPECT_NE(r.err.find("shvol: warning: tabulated:file=" + path("spike.csv") + warning),
                  std::string::npos)
            << cmd << ": " << r.err;
    }
    const std::string smooth = "tabulated:file=" + path("smooth.csv");
    const Result r = run("phase fit " + smooth + " --json");
    EXPECT_EQ(r.err, "");
    EXPECT_NEAR(nlohmann::json::parse(r.out)["quadrature_mass"].get<double>(), 1, 1e-6);
    EXPECT_EQ(run("phase sample " + smooth + " --count 100 -o " + path("s.csv")).err.find(warning),
              std::string::npos);
}

// Records lit by a tiny bulb's hot spot on a wall, which few of their rays meet, are noisy, and
// at 256 rays the render says so with the rays that would do (helper 105: regions 31–49% off at
// 1024 rays, within 2% at 16,384); with those rays it does not.
TEST_F(Cli, RenderWarnsOfNoisyRadianceCacheRecords) {
    write("bulb.json", R"({"camera": {"position": [0, -3, 1.5], "target": [0, 1, 0.3], "fov": 50,
                                      "resolution": [16, 16]},
        "render": {"spp": 1, "radiance_cache": {"enabled": true}},
        "surfaces": [{"name": "floor", "type": "rectangle", "transform": {"scale": 2},
                      "bsdf": {"type": "lambert", "reflectance": 0.8}},
                     {"name": "wall", "type": "rectangle", "bsdf": {"type": "lambert",
                      "reflectance": 0.8}, "transform": {"translate": [0, 1, 1],
                      "rotate": {"axis": [1, 0, 0], "degrees": 90}, "scale": [2, 1, 1]}},
                     {"name": "bulb", "type": "sphere", "center": [0, 0.9, 0.4], "radius": 0.03,
                      "bsdf": {"type": "lambert", "reflectance": 0}, "emission": 3000}]})");
    Result r = run("render " + path("bulb.json") + " -o " + path("a.exr") +
                   " --quiet --set render.radiance_cache.rays_per_record=256");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find(": render.radiance_cache: the records' irradiance estimates are noisy "
                         "(relative standard error, as if their 256 rays were independent: "
                         "median "),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("; give about 8192 rays_per_record\n"), std::string::npos) << r.err;
    auto stats = nlohmann::json::parse(std::ifstream(path("a.stats.json")));
    const nlohmann::json& e = stats["radiance_cache"]["record_irradiance_relative_error"];
    EXPECT_GT(e["p90"].get<double>(), 0.25) << e;
    EXPECT_LE(e["median"].get<double>(), e["p90"].get<double>()) << e;
    EXPECT_LE(e["p90"].get<double>(), e["max"].get<double>()) << e;
    r = run("render " + path("bulb.json") + " -o " + path("a.exr") +
            " --quiet --set render.radiance_cache.rays_per_record=16384");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    stats = nlohmann::json::parse(std::ifstream(path("a.stats.json")));
    EXPECT_LT(stats["radiance_cache"]["record_irradiance_relative_error"]["p90"].get<double>(),
              0.2);
    // One record far noisier than the rest, which the 90th percentile does not see: a floor's
    // records meet a bulb in a mirror ball by rare rays (milk_glass blotched 2–5 times too bright
    // without a word; helper 155). At 2048 rays that record is 0.10 and nothing is said.
    write("mirror.json", R"({"camera": {"position": [0, -3, 1.5], "target": [0, 0, 0], "fov": 50,
                                        "resolution": [16, 16]},
        "render": {"spp": 1, "radiance_cache": {"enabled": true, "rays_per_record": 256}},
        "surfaces": [{"name": "floor", "type": "rectangle", "transform": {"scale": 2},
                      "bsdf": {"type": "lambert", "reflectance": 0.8}},
                     {"name": "bulb", "type": "sphere", "center": [0, 0, 1.5], "radius": 0.2,
                      "bsdf": {"type": "lambert", "reflectance": 0}, "emission": 2000},
                     {"name": "ball", "type": "sphere", "center": [0.5, 0.3, 0.15],
                      "radius": 0.2, "bsdf": {"type": "mirror"}}]})");
    r = run("render " + path("mirror.json") + " -o " + path("a.exr") + " --quiet");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find(": render.radiance_cache: the noisiest record's irradiance estimate is "
                         "far noisier than the others' (relative standard error "),
              std::string::npos)
        << r.err;
    stats = nlohmann::json::parse(std::ifstream(path("a.stats.json")));
    const nlohmann::json& m = stats["radiance_cache"]["record_irradiance_relative_error"];
    EXPECT_GT(m["max"].get<double>(), 0.25) << m;
    EXPECT_GT(m["max"].get<double>(), 8 * m["p90"].get<double>()) << m;
    r = run("render " + path("mirror.json") + " -o " + path("a.exr") +
            " --quiet --set render.radiance_cache.rays_per_record=2048");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    // A floor under a large lamp, which next-event estimation lights, sees a small ball's faint
    // reflection in a few of its records' rays: noisy against that light alone (each p90 1), not
    // against the lamp's (a ground under a sunlit cloud warned so; helper 107).
    write("lamp.json", R"({"camera": {"position": [0, -3, 2], "target": [0, 0, 0], "fov": 40,
                                      "resolution": [16, 16]},
        "render": {"spp": 1, "radiance_cache": {"enabled": true, "rays_per_record": 256}},
        "surfaces": [{"name": "floor", "type": "rectangle", "transform": {"scale": 2},
                      "bsdf": {"type": "lambert", "reflectance": 0.8}},
                     {"name": "lamp", "type": "rectangle", "emission": 5,
                      "bsdf": {"type": "lambert", "reflectance": 0},
                      "transform": {"translate": [0, 0, 2], "scale": 2,
                                    "rotate": {"axis": [1, 0, 0], "degrees": 180}}},
                     {"name": "ball", "type": "sphere", "center": [0.3, 0.2, 0.3], "radius": 0.04,
                      "bsdf": {"type": "lambert", "reflectance": 0.8}}]})");
    r = run("render " + path("lamp.json") + " -o " + path("a.exr") + " --quiet");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    stats = nlohmann::json::parse(std::ifstream(path("a.stats.json")));
    EXPECT_LT(stats["radiance_cache"]["record_irradiance_relative_error"]["p90"].get<double>(),
              0.01);
}

// A deep fog's collisions nearer than a mean free path are no walls to the records: the Cornell box
// filled with fog of optical depth about 8 across makes about as many records as with the shipped
// fog of 0.8 (taken for walls, they ruled the records' harmonic mean distance: 3844 records for
// 785 at 64², and 39 lookups answered for 553).
TEST_F(Cli, DeepFogMakesNoRecordsByTheThousand) {
    const std::string base = "render " + std::string(SHVOL_SOURCE_DIR) +
                             "/media/cornell_fog.json -o " + path("a.exr") +
                             " --quiet --spp 1 --set camera.resolution=[32,32]"
                             " --set render.radiance_cache.enabled=true";
    const auto records = [&](const std::string& sigma) {
        const Result r = run(base + " --set media.0.sigma_t=" + sigma);
        EXPECT_EQ(r.code, 0) << r.err;
        return nlohmann::json::parse(
                   std::ifstream(path("a.stats.json")))["radiance_cache"]["records"]
            .get<double>();
    };
    const double shipped = records("0.0015"), deep = records("0.015");
    EXPECT_GT(shipped, 100);
    EXPECT_LT(deep, 1.5 * shipped) << shipped;
    // Whether a fog hides what lies behind it is judged by ratio tracking whatever
    // render.transmittance says (with "delta", 0 or 1, the records doubled; helper 109).
    EXPECT_EQ(records("0.015 --set render.transmittance='\"delta\"'"), deep);
}

// A radiance cache that cannot be used, or whose BRDF table holds a sharp lobe poorly (the cached
// light then comes out too dark), is said, on stderr and in the stats.
TEST_F(Cli, RenderWarnsOfAnUnusedOrLooseRadianceCache) {
    auto sceneWith = [](const std::string& bsdf) {
        return R"({"camera": {"resolution": [4, 4], "position": [0, -3, 1], "target": [0, 0, 0]},
                   "render": {"spp": 2, "radiance_cache": {"enabled": true, "max_records": 64,
                                                           "rays_per_record": 256}},
                   "environment": {"type": "constant", "radiance": 1},
                   "surfaces": [{"type": "rectangle", "bsdf": )" +
               bsdf + "}]}";
    };
    // The sharp lobe's surface is named; a Lambert wall beside it, held well, is not.
    write("sharp.json", R"({"camera": {"resolution": [4, 4], "position": [0, -3, 1],
                                       "target": [0, 0, 0]},
        "render": {"spp": 2, "radiance_cache": {"enabled": true, "max_records": 64,
                                                "rays_per_record": 256}},
        "environment": {"type": "constant", "radiance": 1},
        "surfaces": [{"type": "rectangle", "name": "wall", "bsdf": {"type": "lambert"},
                      "transform": {"translate": [0, 2, 0]}},
                     {"type": "rectangle", "name": "floor",
                      "bsdf": {"type": "phong", "diffuse": 0, "specular": 1, "exponent": 1000}}]})");
    Result r = run("render " + path("sharp.json") + " -o " + path("a.exr") + " --quiet");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("shvol: warning: " + path("sharp.json") +
                         ": floor: its BRDF table holds the BRDF with relative projection error "
                         "0.8"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(r.err.find("wall"), std::string::npos) << r.err;
    auto stats = nlohmann::json::parse(std::ifstream(path("a.stats.json")));
    ASSERT_EQ(stats["warnings"].size(), 1u) << stats["warnings"];
    const nlohmann::json& cache = stats["radiance_cache"];
    EXPECT_GT(cache["brdf_table_projection_error"].get<double>(), 0.85);
    EXPECT_EQ(cache["brdf_table_projection_errors"]["floor"], cache["brdf_table_projection_error"]);
    EXPECT_LT(cache["brdf_table_projection_errors"]["wall"].get<double>(), 0.1);
    EXPECT_EQ(cache["uncached_surfaces"], nlohmann::json::object());
    EXPECT_GT(cache["brdf_table_peak_errors"]["floor"].get<double>(), 0.5);
    EXPECT_LT(cache["brdf_table_peak_errors"]["wall"].get<double>(), 1e-6);
    // Phong 30 at order 8 keeps all but 8% of the lobe's energy, yet its peak is 22% off (a
    // highlight of a small lamp came out 7.9% dark): the peak error warns of it where the records
    // carry a small lamp's light (render.nee false), and not where next-event estimation takes it
    // or the light is a constant sky.
    write("lamp.json", R"({"camera": {"resolution": [4, 4], "position": [0, -3, 1],
                                      "target": [0, 0, 0]},
        "render": {"spp": 1, "nee": false,
                   "radiance_cache": {"enabled": true, "max_records": 16, "rays_per_record": 256}},
        "surfaces": [{"type": "rectangle", "name": "floor",
                      "bsdf": {"type": "phong", "diffuse": 0, "specular": 1, "exponent": 30}},
                     {"type": "rectangle", "name": "lamp", "emission": 5,
                      "bsdf": {"type": "lambert", "reflectance": 0},
                      "transform": {"translate": [0, 2, 1.2], "scale": 0.3,
                                    "rotate": {"axis": [1, 0, 0], "degrees": 120}}}]})");
    r = run("render " + path("lamp.json") + " -o " + path("a.exr") + " --quiet");
    EXPECT_EQ(r.code, 0) << r.err;
    stats = nlohmann::json::parse(std::ifstream(path("a.stats.json")));
    // The errors are the table's (0.0821 and 0.219 today), read from the stats rather than
    // pinned here (helper 119); the peak error beyond 0.1, with a small source, is what makes
    // the warning due (render_command's kLooseFit).
    const double projection =
                     stats["radiance_cache"]["brdf_table_projection_errors"]["floor"].get<double>(),
                 peak = stats["radiance_cache"]["brdf_table_peak_errors"]["floor"].get<double>();
    EXPECT_GT(projection, 0);
    EXPECT_GT(peak, 0.1);
    char said[400];
    std::snprintf(said, sizeof said,
                  ": floor: its BRDF table holds the BRDF with relative projection error %.3g and "
                  "peak error %.3g at HSH order 8: cached light on it is biased (light straight "
                  "from small sources, which the records carry without next-event estimation, by "
                  "up to %.3g%% of the lobe's peak); raise ",
                  projection, peak, 100 * peak);
    EXPECT_NE(r.err.find(said), std::string::npos) << r.err;
    EXPECT_EQ(stats["radiance_cache"]["brdf_table_peak_error"],
              stats["radiance_cache"]["brdf_table_peak_errors"]["floor"]);
    for (const std::string& quiet :
         {std::string(" --set render.nee=true"),
          std::string(" --set surfaces.1.emission=0 --set environment.radiance=1")}) {
        r = run("render " + path("lamp.json") + " -o " + path("a.exr") + " --quiet" + quiet);
        EXPECT_EQ(r.code, 0) << r.err;
        EXPECT_EQ(r.err.find("floor"), std::string::npos) << quiet << ": " << r.err;
    }
    // A lobe too narrow for the table's quadrature (Phong 10⁶) is path traced, not cached.
    r = run("render " + path("sharp.json") + " -o " + path("a.exr") +
            " --quiet --set surfaces.1.bsdf.exponent=1e6");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("shvol: warning: " + path("sharp.json") +
                         ": floor: its BRDF lobe is too narrow for the radiance cache's BRDF "
                         "table (the table's albedo is off by "),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("%): the surface is path traced, not cached\n"), std::string::npos)
        << r.err;
    stats = nlohmann::json::parse(std::ifstream(path("a.stats.json")));
    EXPECT_GT(stats["radiance_cache"]["uncached_surfaces"]["floor"].get<double>(), 0.5);
    EXPECT_FALSE(stats["radiance_cache"]["brdf_table_projection_errors"].contains("floor"));
    // ... but with specular 0 the floor is Lambertian, and cached (it was judged by the lobe it
    // does not use; helper 132).
    r = run("render " + path("sharp.json") + " -o " + path("a.exr") +
            " --quiet --set surfaces.1.bsdf.exponent=1e6 --set surfaces.1.bsdf.specular=0" +
            " --set surfaces.1.bsdf.diffuse=0.5");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    stats = nlohmann::json::parse(std::ifstream(path("a.stats.json")));
    EXPECT_TRUE(stats["radiance_cache"]["uncached_surfaces"].empty()) << stats["radiance_cache"];
    EXPECT_TRUE(stats["radiance_cache"]["brdf_table_projection_errors"].contains("floor"));
    write("lambert.json", sceneWith(R"({"type": "lambert"})"));
    r = run("render " + path("lambert.json") + " -o " + path("b.exr") + " --quiet");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    // --variance's standard errors leave the records' error out (helper 80: z up to 32.6).
    r = run("render " + path("lambert.json") + " -o " + path("b.exr") + " --quiet --variance");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "shvol: warning: " + path("lambert.json") +
                         ": --variance: the standard errors leave out the radiance cache's own "
                         "error, which every sample of a pixel shares: they can be far too small "
                         "(a z-test against a path-traced reference fails where the records are "
                         "noisy)\n");
    // ... not those of a cache of max_records 0, which holds none (helper 83), nor does its fill
    // "stop at max_records (0)", advising to raise it: 0 asks for no records (helper 105). Its
    // other keys are unused, as those of a cache that is not enabled (helper 137).
    const std::string noRecords =
        ": render.radiance_cache: rays_per_record is not used: the "
        "cache is off (max_records is 0: it makes no records)\n";
    r = run("render " + path("lambert.json") + " -o " + path("b.exr") +
            " --quiet --variance --set render.radiance_cache.max_records=0");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "shvol: warning: " + path("lambert.json") + noRecords);
    // A cache of max_records 0 is off: it built BRDF tables, and reported their errors and the
    // noise of records it did not make (helper 132). Nor is a sharp lobe it would not cache
    // warned of.
    stats = nlohmann::json::parse(std::ifstream(path("b.stats.json")));
    EXPECT_FALSE(stats.contains("radiance_cache")) << stats["radiance_cache"];
    ASSERT_TRUE(stats.contains("effects"));
    for (const auto& effect : stats["effects"]) EXPECT_NE(effect, "radiance-cache");
    r = run(
        "render " + path("sharp.json") + " -o " + path("e.exr") +
        " --quiet --set surfaces.1.bsdf.exponent=1e6 --set render.radiance_cache.max_records=0");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "shvol: warning: " + path("sharp.json") + noRecords);
    // Fewer than 4 rays per HSH coefficient: every record is a noisy fit (helper 63: 1 and 4 rays
    // put regions of the Cornell box off by up to 250%).
    r = run("render " + path("lambert.json") + " -o " + path("b.exr") +
            " --quiet --set render.radiance_cache.rays_per_record=255");
    EXPECT_NE(r.err.find("render.radiance_cache: 255 rays_per_record for the 64 HSH coefficients "
                         "of order 8: each record is a noisy fit"),
              std::string::npos)
        << r.err;
    r = run("render " + path("lambert.json") + " -o " + path("b.exr") +
            " --quiet --set render.radiance_cache.rays_per_record=16 " +
            "--set render.radiance_cache.hsh_order=2");
    EXPECT_EQ(r.err, "");
    // One ray gives no error estimate: unknown (null), not 0, which read as perfect records
    // (helper 155: an image 5.1% dark, blocks −44% to +23%).
    r = run("render " + path("lambert.json") + " -o " + path("b.exr") +
            " --quiet --set render.radiance_cache.rays_per_record=1 " +
            "--set render.radiance_cache.hsh_order=1");
    EXPECT_NE(r.err.find("1 rays_per_record for the 1 HSH coefficients"), std::string::npos)
        << r.err;
    stats = nlohmann::json::parse(std::ifstream(path("b.stats.json")));
    for (const char* q : {"median", "p90", "max"})
        EXPECT_TRUE(stats["radiance_cache"]["record_irradiance_relative_error"][q].is_null()) << q;
    write("mirror.json", sceneWith(R"({"type": "mirror"})"));
    r = run("render " + path("mirror.json") + " -o " + path("c.exr") + " --quiet");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("render.radiance_cache: enabled, but no surface has a BSDF the cache "
                         "holds"),
              std::string::npos)
        << r.err;
    stats = nlohmann::json::parse(std::ifstream(path("c.stats.json")));
    EXPECT_EQ(stats["warnings"].size(), 1u) << stats["warnings"];
    // A fill that stops at max_records is said (its lookups beyond the records are traced); not
    // one that max_records = 0 never started (above: 0 asks for no records; helper 105).
    r = run("render " + path("lambert.json") + " -o " + path("d.exr") +
            " --quiet --set render.radiance_cache.max_records=1");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "shvol: warning: " + path("lambert.json") +
                         ": render.radiance_cache: the fill stopped at max_records (1): lookups "
                         "beyond the records' reach are traced instead (the stats' "
                         "lookups_answered); raise max_records to cache more\n");
}

// An image sky whose scaled radiance no float32 image can hold is refused at load, one line and
// no output: it rendered, then wrote its pixels as inf with a warning (helper 116), and the
// standard errors of a checkerboard of 3·10⁶⁸ and 0 as inf too. Up to the float range it
// renders, finite. (Those warnings stay, for sums beyond the range: a sky of at most 3.4·10³⁸
// and emitters of at most 10³⁰ keep a pixel's mean in range, so a checkpoint's sums reach them,
// RenderWarnsOfPixelsBeyondTheFloatRange.)
TEST_F(Cli, RenderRefusesASkyBeyondTheFloatRange) {
    Image sky(4, 2);  // (3e38 in float32 is 3.00000001e38)
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x) sky.set(x, y, Spectrum::Constant(3e38f));
    writeExr(path("sky.exr"), sky);
    const auto scene = [&](const std::string& scale) {
        write("s.json", R"({"camera": {"resolution": [4, 3]}, "render": {"spp": 2},
            "environment": {"type": "image", "file": "sky.exr", "scale": )" +
                            scale + "}}");
        return run("render " + path("s.json") + " -o " + path("out.exr") + " --quiet");
    };
    Result r = scene("10");
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err, "shvol: error: " + path("s.json") +
                         ": environment.scale: 10 times the largest value the image shows, "
                         "3.00000001e+38, is 3.00000001e+39, beyond the float32 range "
                         "(3.4028235e38) of the images a render writes\n");
    EXPECT_FALSE(fs::exists(path("out.exr")));
    for (int x = 0; x < 4; ++x) sky.set(x, 0, Spectrum::Zero());
    writeExr(path("sky.exr"), sky);
    r = run("render " + path("s.json") + " -o " + path("out.exr") + " --quiet --variance --set " +
            "environment.scale=1e30");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find(": environment.scale: 1e+30 times the largest value the image shows, "
                         "3.00000001e+38, is 3.00000001e+68, beyond"),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(path("out.exr")));
    EXPECT_FALSE(fs::exists(path("out.stderr.exr")));
    // Texels below a black lower hemisphere are never seen: they do not count (helper 120).
    r = run("render " + path("s.json") + " -o " + path("out.exr") + " --quiet --set " +
            "environment.lower_hemisphere_black=true");
    EXPECT_EQ(r.code, 0) << r.err;
    r = scene("1.1");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    const Image out = readExr(path("out.exr"));
    for (float v : out.rgb) EXPECT_TRUE(std::isfinite(v)) << v;
}

// A pixel whose mean, or standard error, is beyond the float range is written as inf with a
// warning naming the image, and counted in the statistics' warnings. No scene reaches one now
// (above), so a checkpoint's sums carry the values: a resume adds its samples to them.
TEST_F(Cli, RenderWarnsOfPixelsBeyondTheFloatRange) {
    write("s.json", scene(Homogeneous));
    const std::string s = "render " + path("s.json") + " --quiet --variance --checkpoint " +
                          path("ck.bin") + " -o " + path("o.exr");
    ASSERT_EQ(run(s + " --spp 2").code, 0);
    // The identity is the file's own (after "SHVOLCK2" and its length).
    std::ifstream in(path("ck.bin"), std::ios::binary);
    char head[12];
    in.read(head, 12);
    uint32_t n;
    std::memcpy(&n, head + 8, 4);
    std::string identity(n, '\0');
    in.read(identity.data(), n);
    const Json id = Json::parse(identity);
    Film film = readCheckpoint(path("ck.bin"), id);
    // Pixel 0's red and green: means of 5e39 and spreads to match (Σx² ≥ (Σx)²/n); pixel 1's
    // green: a spread of about 7e149.
    for (int c : {0, 1}) film.sum[c] = 1e40, film.sumSq[c] = 1e80;
    film.sumSq[4] = 1e300;
    writeCheckpoint(path("ck.bin"), film, id);
    const Result r = run(s + " --spp 3 --resume");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("shvol: warning: " + path("o.exr") +
                         ": 2 pixel values exceed the float32 range of OpenEXR (3.4e38) and are "
                         "written as inf"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("shvol: warning: " + path("o.stderr.exr") + ": 3 standard errors exceed"),
              std::string::npos)
        << r.err;
    const Image image = readExr(path("o.exr"), ExrValues::Preview),
                se = readExr(path("o.stderr.exr"), ExrValues::Preview);
    for (int i : {0, 1}) EXPECT_TRUE(std::isinf(image.rgb[i]) && std::isinf(se.rgb[i])) << i;
    EXPECT_TRUE(std::isfinite(image.rgb[2]) && std::isfinite(se.rgb[2]));
    EXPECT_TRUE(std::isfinite(image.rgb[4]) && std::isinf(se.rgb[4]));
    std::ifstream f(path("o.stats.json"));
    const auto stats = nlohmann::json::parse(f);
    EXPECT_EQ(std::count_if(stats["warnings"].begin(), stats["warnings"].end(),
                            [](const auto& w) {
                                return w.template get<std::string>().find(
                                           "exceed the float32 range") != std::string::npos;
                            }),
              2)
        << stats["warnings"];
}

// Keys given that change nothing in the render are said, each once, and kept in the stats'
// warnings: a sweep over product_order without product sampling rendered one image under two
// names without a word (helper 122). Where the key is used, nothing is said.
TEST_F(Cli, RenderWarnsOfKeysThatChangeNothing) {
    VdbGridSpec g;
    g.resolution = 8;
    g.density = [](const Vec3& p) { return p.norm() < 0.4 ? 1.f : 0.f; };
    writeVdb(path("m.vdb"), {g});
    write("s.json", R"({"camera": {"resolution": [8, 6], "position": [0, -3, 0]},
        "render": {"spp": 2, "product_order": 8, "transmittance": "delta",
                   "radiance_cache": {"hsh_order": 4, "accuracy": 0.5}},
        "environment": {"type": "constant", "radiance": 1},
        "media": [{"type": "vdb", "file": "m.vdb", "majorant_grid": false,
                   "majorant_cell": 2}]})");
    Result r = run("render " + path("s.json") + " -o " + path("o.exr") + " --quiet");
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string w = "shvol: warning: " + path("s.json") + ": ";
    const std::vector<std::string> said = {
        "render.product_order: 8 is not used: it shapes light_sampling \"product\", and this "
        "render's is \"environment\"",
        "render.radiance_cache: accuracy, hsh_order are not used: the cache is off (set "
        "render.radiance_cache.enabled to true to use it)",
        "render.transmittance: \"delta\" is not used: no transmittance is estimated, as "
        "next-event estimation is off (render.nee \"auto\" leaves it off under a constant sky, "
        "where phase sampling does better) and free flights carry the paths",
        "media[0].majorant_cell: 2 is not used: majorant_grid is false (one global majorant)"};
    std::string all;
    for (const std::string& text : said) all += w + text + "\n";
    EXPECT_EQ(r.err, all);
    const auto stats = nlohmann::json::parse(std::ifstream(path("o.stats.json")));
    EXPECT_EQ(stats["warnings"], nlohmann::json(said));
    // Used: product sampling with next-event estimation, shadow rays, the grid; and the cache's
    // keys with the cache on (its own warning says it has no surface to serve).
    r = run("render " + path("s.json") + " -o " + path("o.exr") + " --quiet --set " +
            "render.nee=true --set render.light_sampling=product --set " +
            "media.0.majorant_grid=true --set render.radiance_cache.enabled=true");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, w + "render.radiance_cache: enabled, but no surface has a BSDF the cache "
                         "holds (lambert, phong, ward), or max_depth is 0: the render runs "
                         "without it\n");
    // product_depth 0 warps by the sky alone, which is drawn as the wavelet strategy: the order
    // shapes nothing (helper 148: it cost 4.4x as much at order 32 for wavelet's images).
    r = run("render " + path("s.json") + " -o " + path("o.exr") + " --quiet --set " +
            "render.nee=true --set render.light_sampling=product --set render.product_depth=0");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find(w + "render.product_order: 8 is not used: product_depth 0 warps by the "
                             "sky alone, which is light_sampling \"wavelet\"\n"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(r.err.find("render.product_depth"), std::string::npos) << r.err;
    EXPECT_EQ(
        nlohmann::json::parse(std::ifstream(path("o.stats.json")))["light_sampling"]["strategy"],
        "wavelet");
    // Among surfaces, without next-event estimation, no transmittance is estimated: also where
    // the media only absorb, and where the radiance cache is on, whose light step and records'
    // direct light need next-event estimation too (both were left unsaid; helper 124). Without
    // surfaces, media that only absorb are crossed by transmittance: used.
    write("floor.json", R"({"camera": {"resolution": [6, 4], "position": [0, -3, 0.5]},
        "render": {"spp": 1, "transmittance": "delta", "product_order": 8},
        "environment": {"type": "constant", "radiance": 1},
        "media": [{"type": "homogeneous", "sigma_t": 1, "albedo": 0,
                   "shape": {"type": "sphere", "radius": 0.5}}],
        "surfaces": [{"type": "rectangle", "name": "floor", "bsdf": {"type": "lambert"},
                      "transform": {"translate": [0, 0, -1], "scale": 4}}]})");
    const std::string unusedDelta =
        "render.transmittance: \"delta\" is not used: no transmittance is estimated, as "
        "next-event estimation is off (render.nee \"auto\" leaves it off under a constant sky, "
        "where phase sampling does better) and free flights carry the paths";
    const std::string product = "render.product_order: 8 is not used: ";
    const auto floor = [&](const std::string& sets) {
        const Result f =
            run("render " + path("floor.json") + " -o " + path("f.exr") + " --quiet" + sets);
        EXPECT_EQ(f.code, 0) << f.err;
        return f.err;
    };
    std::string err = floor("");
    EXPECT_NE(err.find(": " + unusedDelta + "\n"), std::string::npos) << err;
    err = floor(" --set render.radiance_cache.enabled=true --set media.0.albedo=0.8");
    EXPECT_NE(err.find(": " + unusedDelta + "\n"), std::string::npos) << err;
    err = floor(" --set render.nee=true");
    EXPECT_EQ(err.find("render.transmittance"), std::string::npos) << err;
    // The cache's light_samples are next-event samples: unused without next-event estimation
    // (1 and 8 rendered bit-identical images without a word; helper 132), used with it. A
    // render.nee false names itself as the reason.
    const std::string lightSamples = "render.radiance_cache.light_samples: 4 is not used: ";
    const std::string cacheOn =
        " --set render.radiance_cache.enabled=true --set "
        "render.radiance_cache.light_samples=4";
    err = floor(cacheOn);
    EXPECT_NE(err.find(lightSamples + "next-event estimation is off (render.nee \"auto\" leaves "
                                      "it off under a constant sky, where phase sampling does "
                                      "better), and the BSDF sample carries a cached vertex's "
                                      "direct light\n"),
              std::string::npos)
        << err;
    // (under a black sky beside a lamp, whose light render.nee false leaves unsampled: the reason
    // named the sky)
    err = floor(cacheOn +
                " --set render.nee=false --set environment.radiance=0 --set 'surfaces=[{\"type\": "
                "\"rectangle\", \"bsdf\": {\"type\": \"lambert\"}, \"transform\": {\"translate\": "
                "[0, 0, -1], \"scale\": 4}}, {\"type\": \"rectangle\", \"emission\": 1, "
                "\"transform\": {\"translate\": [0, 0, 1], \"rotate\": {\"axis\": [1, 0, 0], "
                "\"degrees\": 180}}}]'");
    EXPECT_NE(err.find(lightSamples + "next-event estimation is off (render.nee is false)"),
              std::string::npos)
        << err;
    err = floor(cacheOn + " --set render.nee=true");
    EXPECT_EQ(err.find("light_samples"), std::string::npos) << err;
    // Product sampling's lobes are those of scattering media.
    err = floor(" --set render.nee=true --set render.light_sampling=product");
    EXPECT_NE(
        err.find(product + "it shapes the phase lobes of light_sampling \"product\", and no medium "
                           "scatters\n"),
        std::string::npos)
        << err;
    err = floor(
        " --set render.nee=true --set render.light_sampling=product --set "
        "media.0.albedo=0.8");
    EXPECT_EQ(err.find(product), std::string::npos) << err;
    err = floor(" --set surfaces=null");
    EXPECT_EQ(err.find("render.transmittance"), std::string::npos) << err;
    // Without a medium no transmittance is estimated at all.
    write("empty.json", R"({"camera": {"resolution": [4, 3]}, "render": {"spp": 1,
                           "transmittance": "ratio"}, "environment": {"type": "constant"}})");
    r = run("render " + path("empty.json") + " -o " + path("e.exr") + " --quiet");
    EXPECT_EQ(r.err, "shvol: warning: " + path("empty.json") +
                         ": render.transmittance: \"ratio\" is not used: no transmittance is "
                         "estimated, as the scene has no medium\n");
}

// No output may replace a file the scene reads: a sky written over by its own render, also as an
// intermediate image of --spp or a checkpoint.
TEST_F(Cli, RenderRefusesToOverwriteItsInputs) {
    Image sky(4, 2);
    for (int y = 0; y < 2; ++y)
        for (int x = 0; x < 4; ++x) sky.set(x, y, Spectrum::Constant(0.5));
    for (const char* f : {"sky.exr", "x.spp1.exr", "ck.exr"}) writeExr(path(f), sky);
    const std::string before = test::fileBytes(path("sky.exr"));
    write("s.json", R"({"camera": {"resolution": [4, 3]}, "render": {"spp": 2},
                        "environment": {"type": "image", "file": "sky.exr"}})");
    Result r = run("render " + path("s.json") + " -o " + path("sky.exr") + " --quiet");
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err, "shvol: error: --output: " + path("sky.exr") +
                         ": is an input of the scene (environment.file); write the output "
                         "elsewhere (see --help)\n");
    EXPECT_EQ(test::fileBytes(path("sky.exr")), before);
    write("t.json", R"({"camera": {"resolution": [4, 3]}, "render": {"spp": 2},
                        "environment": {"type": "image", "file": "x.spp1.exr"}})");
    r = run("render " + path("t.json") + " -o " + path("x.exr") + " --spp 1,2 --quiet");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find(path("x.spp1.exr") + ": is an input of the scene"), std::string::npos)
        << r.err;
    write("u.json", R"({"camera": {"resolution": [4, 3]}, "render": {"spp": 2},
                        "environment": {"type": "image", "file": "ck.exr"}})");
    r = run("render " + path("u.json") + " -o " + path("y.exr") + " --checkpoint " +
            path("ck.exr") + " --quiet");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find(path("ck.exr") + ": is an input of the scene"), std::string::npos)
        << r.err;
    r = run("render " + path("u.json") + " -o " + path("y.exr") + " --checkpoint " +
            path("u.json") + " --quiet");
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err, "shvol: error: --checkpoint: " + path("u.json") +
                         ": is the scene file; write the output elsewhere (see --help)\n");
    EXPECT_FALSE(fs::exists(path("x.exr")));
    EXPECT_FALSE(fs::exists(path("y.exr")));
    // Another name: fine.
    r = run("render " + path("s.json") + " -o " + path("out.exr") + " --quiet");
    EXPECT_EQ(r.code, 0) << r.err;
}

// A surface small against the ray offset (2^-16 of the surfaces' extent, set by Embree's float
// intersection) is named in a warning: rays leaving it skip a part of it.
TEST_F(Cli, RenderWarnsOfSurfacesSmallForTheRayOffset) {
    const auto sceneWith = [](double floor) {
        return R"({"camera": {"resolution": [4, 4], "position": [0, -4, 0.5]},
                   "render": {"spp": 1}, "environment": {"type": "constant", "radiance": 1},
                   "surfaces": [{"type": "rectangle", "name": "floor",
                                 "transform": {"translate": [0, 0, -1], "scale": )" +
               std::to_string(floor) + R"(}},
                                {"type": "sphere", "name": "bead", "radius": 1,
                                 "bsdf": {"type": "dielectric"}}]})";
    };
    write("s.json", sceneWith(1e5));
    Result r = run("render " + path("s.json") + " -o " + path("out.exr") + " --quiet");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "shvol: warning: " + path("s.json") +
                         ": bead: 2 across, and the ray offset is 1.53 (2^-16 of the surfaces' "
                         "extent): rays leaving it skip more than 1% of it, and light near it is "
                         "unreliable; bring the scene's surfaces closer together\n");
    write("s.json", sceneWith(100));
    r = run("render " + path("s.json") + " -o " + path("out.exr") + " --quiet");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    // A glass pane 2 wide and 0.0002 thick (a closed box mesh) is judged by its thickness: the
    // offset of a floor 60 wide (4.6e-4) passes through it, 2 across or not.
    write("pane.obj",
          "v -1 -0.0001 -1\nv 1 -0.0001 -1\nv -1 0.0001 -1\nv 1 0.0001 -1\n"
          "v -1 -0.0001 1\nv 1 -0.0001 1\nv -1 0.0001 1\nv 1 0.0001 1\n"
          "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\nf 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n");
    write("s.json", R"({"camera": {"resolution": [4, 4], "position": [0, -4, 0.5]},
                   "render": {"spp": 1}, "environment": {"type": "constant", "radiance": 1},
                   "surfaces": [{"type": "rectangle", "name": "floor",
                                 "transform": {"translate": [0, 0, -1], "scale": 30}},
                                {"type": "mesh", "file": "pane.obj", "name": "pane",
                                 "bsdf": {"type": "dielectric"}}]})");
    r = run("render " + path("s.json") + " -o " + path("out.exr") + " --quiet");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err,
              "shvol: warning: " + path("s.json") +
                  ": pane: 0.0002 thick (2V/A), and the ray offset is 0.000458 (2^-16 of the "
                  "surfaces' extent): rays leaving it skip more than 1% of it, and light "
                  "near it is unreliable; bring the scene's surfaces closer together\n");
    // Far from the origin the offset is 32 steps of a double there, and the remedy is to move the
    // scene (the review: the warning still spoke of the extent, 1.5e-4 for this sphere).
    write("far.json", R"({"camera": {"resolution": [4, 4], "position": [1e14, -1e14, 1e14],
                   "target": [1e14, 0, 1e14]}, "render": {"spp": 1},
                   "environment": {"type": "constant", "radiance": 1},
                   "surfaces": [{"type": "sphere", "name": "bead", "radius": 10,
                                 "center": [1e14, -9.99999999999e13, 1e14],
                                 "bsdf": {"type": "dielectric"}}]})");
    r = run("render " + path("far.json") + " -o " + path("out.exr") + " --quiet");
    EXPECT_EQ(r.err, "shvol: warning: " + path("far.json") +
                         ": bead: 20 across, and the ray offset is 0.5 (32 steps of a double at "
                         "the surfaces' distance from the origin): rays leaving it skip more than "
                         "1% of it, and light near it is unreliable; bring the scene nearer the "
                         "origin\n");
    // Two surfaces closer than the offset: a floor under an emitting ceiling 1 above it, both
    // 2·10⁵ wide (ε = 1.53), rendered the floor black without a word (helper 80).
    const auto gapScene = [](double scale) {
        return R"({"camera": {"resolution": [4, 4], "position": [0, -3, 0.5],
                   "target": [0, 0, 0]}, "render": {"spp": 1},
                   "surfaces": [{"type": "rectangle", "name": "floor",
                                 "transform": {"scale": )" +
               std::to_string(scale) + R"(}},
                                {"type": "rectangle", "name": "ceiling", "emission": 1,
                                 "transform": {"translate": [0, 0, 1], "scale": )" +
               std::to_string(scale) + R"(, "rotate": {"axis": [1, 0, 0], "degrees": 180}}}]})";
    };
    write("gap.json", gapScene(1e5));
    r = run("render " + path("gap.json") + " -o " + path("out.exr") + " --quiet");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, gapWarning(path("gap.json"), "floor and ceiling are 1 apart", "1.53"));
    write("gap.json", gapScene(1e3));  // (ε = 0.0153: no warning)
    r = run("render " + path("gap.json") + " -o " + path("out.exr") + " --quiet");
    EXPECT_EQ(r.err, "");
    // Nested spheres by their own gap (their boxes overlap: a shell 10⁻⁵ thick, under ε 1.5·10⁻⁵,
    // was jumped without a word; helper 101); crossing spheres have none.
    const auto spheres = [](double inner, double x) {
        return R"({"camera": {"resolution": [4, 4], "position": [0, -4, 0]}, "render": {"spp": 1},
                   "surfaces": [{"type": "sphere", "name": "outer", "radius": 1,
                                 "bsdf": {"type": "dielectric"}},
                                {"type": "sphere", "name": "inner", "radius": )" +
               std::to_string(inner) + R"(, "transform": {"translate": [)" + std::to_string(x) +
               R"(, 0, 0]}, "bsdf": {"type": "dielectric", "ior": 0.6667}}]})";
    };
    write("nested.json", spheres(0.99999, 0));
    r = run("render " + path("nested.json") + " -o " + path("out.exr") + " --quiet");
    EXPECT_EQ(r.err,
              gapWarning(path("nested.json"), "outer and inner are 1e-05 apart", "1.53e-05"));
    for (const auto& [inner, x] : {std::pair{0.999, 0.0}, std::pair{0.5, 0.6}}) {
        write("nested.json", spheres(inner, x));  // 10⁻³ apart; crossing
        r = run("render " + path("nested.json") + " -o " + path("out.exr") + " --quiet");
        EXPECT_EQ(r.err, "") << inner;
    }
}

// The gap warning among many surfaces: 200 spheres of radius 100 in a grid 1000 apart in the
// plane z = 0, across the longest axis (two beads at z = ±10⁵ make it z: ε = 10⁵·2⁻¹⁶ = 1.53,
// a gap below 15.3 is warned of), with partners 0.5, 3, 7, 12 and 20 beside five of them, a
// sphere nested 2 inside a sixth and one crossing a seventh: five pairs, the closest named. The
// pairs are found by sweep and prune (since 7 Dec; every pair was compared before: 64,000 spheres
// took 29 s; helper 127), which must find what comparing every pair found.
TEST_F(Cli, RenderWarnsOfTheClosestOfManySurfaces) {
    std::string surfaces;
    const auto sphere = [&](const std::string& name, double x, double y, double z, double r) {
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      R"(%s{"type": "sphere", "name": "%s", "center": [%.17g, %.17g, %.17g],
                      "radius": %.17g})",
                      surfaces.empty() ? "" : ", ", name.c_str(), x, y, z, r);
        surfaces += buf;
    };
    for (int i = 0; i < 20; ++i)
        for (int j = 0; j < 10; ++j)
            sphere("g" + std::to_string(i) + "_" + std::to_string(j), 1000 * i, 1000 * j, 0, 100);
    const double gaps[] = {12, 3, 20, 0.5, 7};
    for (int k = 0; k < 5; ++k)  // (beside along x or along y)
        sphere("partner" + std::to_string(k), 1000 * (3 * k + 1) + (k % 2 ? 0 : 200 + gaps[k]),
               1000 * k + (k % 2 ? 200 + gaps[k] : 0), 0, 100);
    sphere("nested", 1000 * 17, 1000 * 8, 0, 98);
    sphere("crossing", 1000 * 5 + 150, 1000 * 9, 0, 100);
    sphere("top", 0, 0, 1e5, 200);
    sphere("bottom", 0, 0, -1e5, 200);
    write("many.json", R"({"camera": {"resolution": [4, 4], "position": [0, -3000, 0],
                   "target": [0, 0, 0]}, "render": {"spp": 1},
                   "surfaces": [)" +
                           surfaces + "]}");
    const Result r = run("render " + path("many.json") + " -o " + path("out.exr") + " --quiet");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err,
              gapWarning(path("many.json"),
                         "g10_3 and partner3 are 0.5 apart (the closest of 5 such pairs)", "1.53"));
}

// Glass that is not a solid's surface is named in a warning, with its defect's place in its
// file (it rendered without a word; helper 66).
TEST_F(Cli, RenderWarnsOfGlassThatIsNotClosed) {
    write("open.obj",
          "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n# no fourth face\n"
          "f 1 3 2\nf 1 2 4\nf 1 4 3\n");
    write("s.json", R"({"camera": {"resolution": [4, 4], "position": [0.3, -4, 0.3]},
                   "render": {"spp": 1}, "environment": {"type": "constant", "radiance": 1},
                   "surfaces": [{"type": "mesh", "file": "open.obj", "name": "vase",
                                 "bsdf": {"type": "dielectric"}}]})");
    Result r = run("render " + path("s.json") + " -o " + path("out.exr") + " --quiet");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "shvol: warning: " + path("s.json") +
                         ": vase: dielectric, but not the "
                         "closed surface of a solid (" +
                         path("open.obj") +
                         ": line 6: edge from (0, 1, 0) to (1, 0, 0) has no opposite edge: the "
                         "mesh is not closed): light that enters it may leave it only where a "
                         "face happens to lie, and its faces were not turned to face outwards "
                         "(an open sheet meant so, a water surface, is rendered as wound: its "
                         "normals point out of the glass)\n");
    // Closed, no warning.
    write("open.obj",
          "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\n"
          "f 2 3 4\n");
    r = run("render " + path("s.json") + " -o " + path("out.exr") + " --quiet");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    // Two tetrahedra wound inwards that cross: rendered, each turned outwards, and said so.
    write("open.obj",
          "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n"
          "v 0.2 0.2 0.2\nv 1.2 0.2 0.2\nv 0.2 1.2 0.2\nv 0.2 0.2 1.2\n"
          "f 5 6 7\nf 5 8 6\nf 5 7 8\nf 6 8 7\n");
    r = run("render " + path("s.json") + " -o " + path("out.exr") + " --quiet");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find(": vase: dielectric, and its parts cross or touch (" + path("open.obj") +
                         ": line "),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("each part that meets another was turned to face outwards on its own\n"),
              std::string::npos)
        << r.err;
    const Scene scene = loadScene(path("s.json"));
    // (Positions read as floats: 0.2 is not exact.)
    EXPECT_NEAR(signedVolume(scene.surfaces->surfaces()[0].mesh), 2.0 / 6, 1e-7);
}

// A glass rectangle or disk is always an open sheet: warned of as an open mesh is (helper 94: a
// glass disk rendered a white furnace at 0.48 seen from its front, without a word).
TEST_F(Cli, RenderWarnsOfAGlassSheet) {
    for (const std::string type : {"disk", "rectangle"}) {
        write("s.json", R"({"camera": {"resolution": [4, 4], "position": [0, -3, 2]},
                   "render": {"spp": 1}, "environment": {"type": "constant", "radiance": 1},
                   "surfaces": [{"type": ")" +
                            type + R"(", "name": "pane", "bsdf": {"type": "dielectric"}}]})");
        Result r = run("render " + path("s.json") + " -o " + path("out.exr") + " --quiet");
        EXPECT_EQ(r.code, 0) << r.err;
        EXPECT_EQ(r.err.rfind("shvol: warning: " + path("s.json") + ": pane: dielectric, but a " +
                                  type + " is an open sheet, not the closed surface of a solid",
                              0),
                  0u)
            << r.err;
        write("s.json", R"({"camera": {"resolution": [4, 4], "position": [0, -3, 2]},
                   "render": {"spp": 1}, "environment": {"type": "constant", "radiance": 1},
                   "surfaces": [{"type": ")" +
                            type + R"(", "name": "pane"}]})");
        r = run("render " + path("s.json") + " -o " + path("out.exr") + " --quiet");
        EXPECT_EQ(r.err, "") << type;
    }
}

// README: media/cloud.vdb and media/plume.vdb are what make-medium writes, byte for byte; the
// voxels are evaluated on every thread asked for, and the file does not depend on how many.
TEST_F(Cli, MakeMediumRemakesTheShippedMedia) {
    const std::string media = std::string(SHVOL_SOURCE_DIR) + "/media/";
    Result r = run("make-medium plume --resolution 128 --threads 2 -o " + path("plume.vdb"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err.rfind("wrote " + path("plume.vdb") + ": plume grid 'density', 128^3, ", 0), 0u)
        << r.err;
    EXPECT_EQ(test::fileBytes(path("plume.vdb")), test::fileBytes(media + "plume.vdb"));
    r = run("make-medium cloud --resolution 128 --threads 3 -o " + path("cloud.vdb"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(test::fileBytes(path("cloud.vdb")), test::fileBytes(media + "cloud.vdb"));
}

TEST_F(Cli, MakeMediumAndSkyRoundTrip) {
    Result r = run("make-medium sphere --resolution 16 -o " + path("sphere.vdb"));
    ASSERT_EQ(r.code, 0) << r.err;
    r = run("make-medium cloud --resolution 16 -o " + path("cloud.vdb"));
    ASSERT_EQ(r.code, 0) << r.err;
    r = run("make-sky --width 64 -o " + path("sky.exr"));
    ASSERT_EQ(r.code, 0) << r.err;
    const Image sky = readExr(path("sky.exr"));
    EXPECT_EQ(sky.width, 64);
    EXPECT_EQ(sky.height, 32);
    EXPECT_EQ(r.err.find("note:"), std::string::npos) << r.err;
    // Lit, and brightest above the horizon, where the default sun is (a black sky passed).
    const auto brightest = std::max_element(sky.rgb.begin(), sky.rgb.end());
    EXPECT_GT(*brightest, 0);
    EXPECT_LT(size_t(brightest - sky.rgb.begin()) / 3 / size_t(sky.width), size_t(sky.height / 2));
    // A sun below the horizon: hidden by the Preetham ground, not by the simple model's, and
    // either is said (the simple one drew it there without a word; helper 84).
    for (const char* model : {"preetham", "simple"}) {
        r = run(std::string("make-sky --width 64 --sun-elevation -30 --model ") + model + " -o " +
                path("low.exr"));
        ASSERT_EQ(r.code, 0) << r.err;
        EXPECT_NE(r.err.find(model[0] == 'p' ? "note: the Preetham model does not cover twilight"
                                             : "note: the simple model's ground does not hide "
                                               "the sun"),
                  std::string::npos)
            << r.err;
    }
    VdbMediumDesc d;
    d.file = path("sphere.vdb");
    EXPECT_NEAR(loadVdbMedium(d)->sigmaT(Vec3::Zero()), 1.0, 1e-6);
    d.file = path("cloud.vdb");
    // Density inside its bounds, none outside (σ_t ≥ 0 at the origin was all an empty cloud
    // had to pass; helper 119).
    const std::unique_ptr<Medium> cloud = loadVdbMedium(d);
    const Bounds3 b = cloud->bounds();
    ASSERT_TRUE(b.lo.allFinite() && b.hi.allFinite());
    double inside = 0;
    for (int i = 0; i < 512; ++i) {
        const Vec3 f((i % 8 + 0.5) / 8, (i / 8 % 8 + 0.5) / 8, (i / 64 + 0.5) / 8);
        inside += cloud->sigmaT(b.lo + f.cwiseProduct(b.hi - b.lo));
    }
    EXPECT_GT(inside, 0);
    EXPECT_EQ(cloud->sigmaT(b.hi + (b.hi - b.lo)), 0);
    r = run("make-medium torus -o " + path("x.vdb"));
    EXPECT_NE(r.code, 0);
    // Another kind's options are said to have no effect (they were silently ignored), and an
    // empty grid names the option of its own kind.
    r = run("make-medium sphere --resolution 8 --seed 3 --coverage 0.5 -o " + path("s8.vdb"));
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err.rfind("shvol: note: --seed has no effect with sphere\n"
                          "shvol: note: --coverage has no effect with sphere\nwrote ",
                          0),
              0u)
        << r.err;
    r = run("make-medium sphere --radius 0 -o " + path("s0.vdb"));
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err, "shvol: error: " + path("s0.vdb") +
                         ": the grid would be empty (no voxel has density > 0); raise --radius\n");
}

// SIGINT and SIGTERM during a render: the samples finished so far are written (image and stats
// with "interrupted": true) and the exit code is 128 + the signal (130, 143, 129), as a shell
// reports the signal. The render is far too long to finish.
// A signal that comes once the render has finished, while its outputs are written, lets them be
// written whole and exits 130 for SIGINT (it ended the process with none of them: the guard was
// gone). The signal is sent once the stats file's temporary appears, after the EXRs' temporaries
// are written and before the outputs are renamed together.
// A full disk, as a file-size limit (ulimit -f, in KiB) makes one: an output that does not fit
// is one line naming it with the reason, exit 1, and nothing left behind, with SIGXFSZ at its
// default or ignored by the caller (a truncated image or VDB was renamed into place and reported
// written, exit 0, where the last bytes were still in a stream's buffer as it closed; the image's
// stats and the phase samples were refused without the reason; the limit's SIGXFSZ ended shvol
// without a word, exit 153, leaving the temporaries; helper 100).
TEST_F(Cli, OutputsThatDoNotFitAreRefused) {
    write("s.json", scene(Homogeneous));
    const std::string render = "render " + path("s.json") + " -o " + path("out.exr") + " --quiet";
    const std::vector<std::tuple<std::string, int, std::string>> cases = {
        // the image (6 kB: all of it in the stream's buffer until it closes)
        {render + " --spp 1 --set camera.resolution=[64,64]", 4, "out.exr"},
        {render, 2, "out.stats.json"},  // an 8 × 6 image (510 bytes), then its stats (3.7 kB)
        {"make-medium sphere -o " + path("out.vdb") + " --resolution 32", 16, "out.vdb"},
        {"make-sky -o " + path("out_sky.exr") + " --width 256", 16, "out_sky.exr"},
        {"phase sample hg:g=0.5 --count 100000 -o " + path("out.csv"), 16, "out.csv"}};
    for (const auto& [args, kib, output] : cases)
        for (const char* xfsz : {"", "trap '' XFSZ; "}) {  // (SIGXFSZ as given: default, ignored)
            const Result r = runCommand(std::string(xfsz) + "ulimit -f " + std::to_string(kib) +
                                        "; exec " + SHVOL_BINARY + " " + args);
            EXPECT_EQ(r.code, 1) << args;
            EXPECT_EQ(r.err,
                      "shvol: error: " + path(output) + ": cannot write file (File too large)\n")
                << args;
            for (const auto& e : fs::directory_iterator(dir_))
                if (e.path().filename().string().find("out") != std::string::npos)
                    ADD_FAILURE() << args << " left " << e.path(), fs::remove(e.path());
        }
}

TEST_F(Cli, SignalWhileWritingStillWritesEverything) {
    write("s.json", scene(Homogeneous));
    const std::string out = path("w.exr");
    const Result r = runCommand(
        "env --default-signal=INT " + std::string(SHVOL_BINARY) + " render " + path("s.json") +
        " -o " + out + " --spp 2 --variance --quiet --set camera.resolution=[2048,2048] 2>" +
        path("bg.txt") + " & p=$!; i=0; while ! ls " + path("w.stats.json.tmp") +
        "* >/dev/null 2>&1 && [ $i -lt 60000 ]; do sleep 0.001; i=$((i+1)); done; kill -INT $p; "
        "wait $p");
    const std::string err = test::fileBytes(path("bg.txt"));
    EXPECT_EQ(r.code, 130) << err;
    EXPECT_EQ(err, "shvol: interrupted while the outputs were written; they are written whole\n");
    for (const char* f : {"w.exr", "w.stderr.exr", "w.stats.json"})
        EXPECT_TRUE(fs::exists(path(f))) << f;
    EXPECT_EQ(readExr(out).width, 2048);
    EXPECT_EQ(readExr(path("w.stderr.exr"), ExrValues::Preview).width, 2048);
    const auto stats = nlohmann::json::parse(std::ifstream(path("w.stats.json")));
    EXPECT_EQ(stats["stopped_by"], "completed");
    for (const auto& e : fs::directory_iterator(dir_))
        EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
}

// A closing terminal sends SIGHUP twice, from the shell and then from the kernel as the session
// ends: the second, which came while the first's outputs were written, ended the render with 129
// and nothing written (helper 129). The second is sent once the image's temporary appears: the
// first of the outputs' temporaries, which all stay until they are renamed together.
TEST_F(Cli, SecondHangupWhileWritingStillWritesEverything) {
    write("s.json", scene(Homogeneous));
    const std::string out = path("w.exr");
    std::string kills = killOnceCaught("HUP", SIGHUP, "0.3");
    kills.replace(kills.rfind("wait $p"), 7,
                  "i=0; while ! ls " + path("w.exr.tmp") +
                      "* >/dev/null 2>&1 && [ $i -lt 60000 ]; do sleep 0.001; i=$((i+1)); done; "
                      "kill -HUP $p; wait $p");
    const Result r = runCommand(std::string(SHVOL_BINARY) + " render " + path("s.json") + " -o " +
                                out + " --spp 10000000 --variance --quiet --set " +
                                "camera.resolution=[2048,2048] 2>" + path("bg.txt") + kills);
    const std::string err = test::fileBytes(path("bg.txt"));
    EXPECT_EQ(r.code, 128 + SIGHUP) << err;
    EXPECT_NE(err.find("shvol: interrupted: wrote the samples finished so far to " + out),
              std::string::npos)
        << err;
    for (const char* f : {"w.exr", "w.stderr.exr", "w.stats.json"})
        EXPECT_TRUE(fs::exists(path(f))) << f;
    for (const auto& e : fs::directory_iterator(dir_))
        EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
}

// A signal stops the radiance cache's fill: it waited for the whole fill (with 2^20 paths per
// record this scene's 58 records take about 12 s here), and no sample sees the part-filled cache.
// (The time limit counts the passes only: a resumed render fills the cache again.)
TEST_F(Cli, SignalsStopTheRadianceCacheFill) {
    write("s.json", R"({"camera": {"resolution": [32, 32], "position": [0, -3, 1],
        "target": [0, 0, 0]}, "render": {"spp": 2, "radiance_cache": {"enabled": true,
        "max_records": 1000, "rays_per_record": 1048576}},
        "environment": {"type": "constant", "radiance": 1},
        "surfaces": [{"type": "rectangle", "bsdf": {"type": "lambert", "reflectance": 0.5}}]})");
    const Result r = runCommand("env --default-signal=INT " + std::string(SHVOL_BINARY) +
                                " render " + path("s.json") + " -o " + path("i.exr") +
                                " --quiet 2>" + path("bg.txt") + killOnceCaught("INT", SIGINT));
    EXPECT_EQ(r.code, 130) << test::fileBytes(path("bg.txt"));
    ASSERT_TRUE(fs::exists(path("i.stats.json"))) << test::fileBytes(path("bg.txt"));
    const auto stats = nlohmann::json::parse(std::ifstream(path("i.stats.json")));
    EXPECT_EQ(stats["stopped_by"], "cancelled");
    EXPECT_EQ(stats["samples_per_pixel_max"], 0);
    EXPECT_LT(stats["radiance_cache"]["records"].get<int>(), 20);
}

// SIGHUP (the terminal closed) too: it ended the render with 129 and no checkpoint (helper 127).
TEST_F(Cli, InterruptedRenderWritesWhatItHas) {
    write("s.json", scene(Homogeneous));
    for (const char* sig : {"INT", "TERM", "HUP"}) {
        const std::string out = path(std::string("i") + sig + ".exr");
        // The shell's redirections apply to `wait`; the render's stderr goes to bg.txt. A job
        // started with `&` by a script ignores SIGINT (and shvol leaves it ignored): env gives it
        // the default action back, as a user stopping such a job with SIGINT must.
        const int number = std::string(sig) == "INT"    ? SIGINT
                           : std::string(sig) == "TERM" ? SIGTERM
                                                        : SIGHUP;
        std::string kill = killOnceCaught(sig, number, "0.5");
        const Result r = runCommand("env --default-signal=INT " + std::string(SHVOL_BINARY) +
                                    " render " + path("s.json") + " -o " + out +
                                    " --spp 10000000 2>" + path("bg.txt") + kill);
        std::ifstream bg(path("bg.txt"));
        const std::string err((std::istreambuf_iterator<char>(bg)), {});
        EXPECT_EQ(r.code, 128 + number) << sig << ": " << err;  // as the shell reports it
        EXPECT_NE(
            err.find("shvol: interrupted: wrote the samples finished so far to " + out + " ("),
            std::string::npos)
            << err;
        std::ifstream f(path(std::string("i") + sig + ".stats.json"));
        const auto stats = nlohmann::json::parse(f);
        EXPECT_EQ(stats["interrupted"], true);
        EXPECT_EQ(stats["stopped_by"], "cancelled");
        EXPECT_GT(stats["samples_per_pixel_min"].get<int>(), 0);
        const Image img = readExr(out);
        EXPECT_EQ(img.width, 8);
        for (float v : img.rgb) EXPECT_TRUE(std::isfinite(v) && v > 0);
    }
}

// --time-limit stops cleanly (exit 0); --checkpoint and --resume then finish the render, and the
// image equals an uninterrupted run's.
TEST_F(Cli, TimeLimitCheckpointAndResume) {
    write("s.json", scene(Homogeneous));
    const std::string s = "render " + path("s.json") + " --spp 20000 --quiet ";
    ASSERT_EQ(run(s + "-o " + path("full.exr")).code, 0);
    Result r = run(s + "-o " + path("part.exr") + " --time-limit 0.002 --checkpoint " +
                   path("ck.bin") + " --threads 1");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("time limit reached"), std::string::npos) << r.err;
    const auto readStats = [&] {
        std::ifstream f(path("part.stats.json"));
        return nlohmann::json::parse(f);
    };
    const auto part = readStats();
    EXPECT_EQ(part["stopped_by"], "time-limit");
    EXPECT_EQ(part["interrupted"], false);
    EXPECT_LT(part["samples_per_pixel_min"].get<int>(), 20000);
    r = run(s + "-o " + path("part.exr") + " --checkpoint " + path("ck.bin") + " --resume");
    ASSERT_EQ(r.code, 0) << r.err;
    const Image a = readExr(path("part.exr")), b = readExr(path("full.exr"));
    EXPECT_EQ(a.rgb, b.rgb);
    // ... by tracing only the paths the checkpoint lacked: the same image came from a resume
    // that threw the checkpoint away and rendered everything (helper 119).
    const auto resumed = readStats();
    EXPECT_EQ(resumed["resumed_from_samples"], part["samples_per_pixel_min"]);
    EXPECT_EQ(resumed["paths"].get<uint64_t>() + part["paths"].get<uint64_t>(),
              uint64_t(a.width) * a.height * 20000);
    // A checkpoint belongs to one render: another seed is refused.
    r = run(s + "-o " + path("x.exr") + " --seed 9 --checkpoint " + path("ck.bin") + " --resume");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("written for a different render: scene value render.seed differs "
                         "(scene file, --set or --seed) (only the sample count may change)"),
              std::string::npos)
        << r.err;
    // ... but a value given as its default is the same render (it was refused as the seed).
    r = run(s + "-o " + path("d.exr") + " --seed 1 --set render.rr_depth=3 --checkpoint " +
            path("ck.bin") + " --resume");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(readExr(path("d.exr")).rgb, b.rgb);
    // Fewer samples than the checkpoint holds: refused, naming the checkpoint.
    r = run("render " + path("s.json") + " --spp 100 --quiet -o " + path("x.exr") +
            " --checkpoint " + path("ck.bin") + " --resume");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(
        r.err.find(path("ck.bin") + ": has 20000 samples per pixel, more than the 100 asked for"),
        std::string::npos)
        << r.err;
    // Standard errors asked of a checkpoint saved without them: refused, naming it.
    r = run(s + "-o " + path("x.exr") + " --variance --checkpoint " + path("ck.bin") + " --resume");
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err, "shvol: error: " + path("ck.bin") +
                         ": was saved without --variance, so the standard errors of its samples "
                         "are lost; resume without --variance, or start afresh\n");
    // An image at fewer samples than the checkpoint holds cannot be written: a warning says so.
    r = run("render " + path("s.json") + " --spp 16,20000 --quiet -o " + path("y.exr") +
            " --checkpoint " + path("ck.bin") + " --resume");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("shvol: warning: " + path("s.json") + ": --spp 16: the checkpoint " +
                         path("ck.bin") +
                         " already holds up to 20000 samples per pixel; the image at 16 spp is "
                         "not written"),
              std::string::npos)
        << r.err;
    EXPECT_TRUE(fs::exists(path("y.exr")));
    EXPECT_FALSE(fs::exists(path("y.spp16.exr")));
    r = run(s + "-o " + path("x.exr") + " --resume");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("--resume requires --checkpoint (see --help)"), std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(path("x.exr")));
}

// Every file a render would write is checked before it renders: a checkpoint whose directory
// is missing, that is a directory, or that names one of the images or statistics is refused at
// once (it used to fail after the whole render, or to be written over the image), and so is an
// output below a regular file. A directory given to --resume is named as such. A FIFO (or a
// device) is refused: the rename of the finished file used to replace it, and as root
// `--checkpoint /dev/null` replaced /dev/null.
TEST_F(Cli, RenderChecksEveryOutputFirst) {
    write("s.json", scene(Homogeneous));
    write("afile", "");
    fs::create_directories(path("d"));
    ASSERT_EQ(::mkfifo(path("fifo").c_str(), 0600), 0);
    const std::string s = "render " + path("s.json") + " --quiet -o " + path("o.exr") + " ";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"--checkpoint " + path("no/ck.bin"), "--checkpoint: " + path("no/ck.bin") +
                                                  ": cannot write: directory " + path("no") +
                                                  " does not exist"},
        {"--checkpoint " + path("d"),
         "--checkpoint: " + path("d") + ": cannot write: is a directory"},
        {"--checkpoint ''", "--checkpoint: needs a file name"},
        {"--checkpoint-interval 5", "--checkpoint-interval requires --checkpoint"},
        {"--resume", "--resume requires --checkpoint"},
        {"--checkpoint " + path("o.exr"),
         "--checkpoint: " + path("o.exr") + ": the checkpoint would be written over the image"},
        {"--checkpoint " + path("d/../o.stats.json"),
         "--checkpoint: " + path("d/../o.stats.json") +
             ": the checkpoint would be written over the statistics"},
        {"--spp 1,2 --checkpoint " + path("o.spp1.exr"),
         "--checkpoint: " + path("o.spp1.exr") +
             ": the checkpoint would be written over the image at 1 spp"},
        {"--checkpoint " + path("d") + " --resume",
         "--checkpoint: " + path("d") + ": cannot write: is a directory"},
        // (it named neither option; helper 77)
        {"--checkpoint " + path("nock.bin") + " --resume",
         "--checkpoint: " + path("nock.bin") +
             ": no such file: --resume continues it (see "
             "--help)"},
        {"--checkpoint " + path("fifo"), "--checkpoint: " + path("fifo") +
                                             ": cannot write: is not a regular file (a device, "
                                             "FIFO or socket"},
    };
    for (const auto& [options, message] : cases) {
        const Result r = run(s + options);
        EXPECT_EQ(r.code, 1) << options;
        EXPECT_EQ(r.err.rfind("shvol: error: " + message, 0), 0u) << options << ": " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_FALSE(fs::exists(path("o.exr"))) << options;
    }
    // A file named after the image is the --output's (it named no option).
    fs::create_directories(path("p.stats.json"));
    const Result r = run("render " + path("s.json") + " --quiet -o " + path("p.exr"));
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err, "shvol: error: --output: " + path("p.stats.json") +
                         ": cannot write: is a directory (see --help)\n");
    EXPECT_FALSE(fs::exists(path("p.exr")));
    // -o is checked as it is parsed, and so are the outputs of the other commands.
    for (const std::string& command : std::vector<std::string>{
             "render " + path("s.json") + " -o ", "make-medium sphere -o ", "make-sky -o ",
             "tonemap " + path("s.json") + " -o ", "phase sample hg:g=0.5 --out "}) {
        const std::string ext = command.find("medium") != std::string::npos    ? ".vdb"
                                : command.find("tonemap") != std::string::npos ? ".png"
                                : command.find("phase") != std::string::npos   ? ".csv"
                                                                               : ".exr";
        const Result r = run(command + path("afile/o" + ext));
        EXPECT_EQ(r.code, 1) << command;
        EXPECT_NE(r.err.find(path("afile/o" + ext) + ": cannot write: " + path("afile") +
                             " is not a directory"),
                  std::string::npos)
            << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    }
    // tonemap's PNG that is its EXR through a link would replace it (it was written over).
    writeExr(path("in.exr"), Image(2, 2));
    fs::create_symlink(path("in.exr"), path("in.png"));
    const Result t = run("tonemap " + path("in.exr") + " -o " + path("in.png"));
    EXPECT_EQ(t.code, 1);
    EXPECT_EQ(t.err, "shvol: error: --output: " + path("in.png") +
                         " is the image being tonemapped; write the PNG elsewhere (see --help)\n");
    EXPECT_EQ(readExr(path("in.exr")).width, 2);
    // Written, it says so, as make-medium and make-sky do (it said nothing; helper 77).
    const Result ok = run("tonemap " + path("in.exr") + " -o " + path("out.png") + " --exposure 1");
    EXPECT_EQ(ok.code, 0) << ok.err;
    EXPECT_EQ(ok.err, "wrote " + path("out.png") + ": 2x2, exposure 1 stops\n");
    EXPECT_EQ(test::fileBytes(path("out.png")).substr(1, 3), "PNG");
}

// diff's metrics over two small images, against the formulas of README worked by hand; values
// infinite in either image (a standard-error image's unknown errors) are left out and counted,
// negative ones (another renderer's filter ringing) compared; NaN, or nothing finite to compare,
// is one line and exit 1.
TEST_F(Cli, DiffComparesTheValuesFiniteInBoth) {
    Image a(2, 1), b(2, 1);
    a.set(0, 0, Spectrum(1, 2, 4)), a.set(1, 0, Spectrum(0.5, INFINITY, 0));
    b.set(0, 0, Spectrum(1, 1, 2)), b.set(1, 0, Spectrum(-0.5, 3, 0));
    writeExr(path("a.exr"), a);
    writeExr(path("b.exr"), b);
    Result r = run("diff " + path("a.exr") + " " + path("b.exr") + " --json");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    // Differences 0, 1, 2, 1, 0 over five values, the sixth (+inf) left out.
    EXPECT_NEAR(j["rmse"].get<double>(), std::sqrt(6.0 / 5), 1e-12);
    EXPECT_NEAR(j["relative_rmse"].get<double>(),
                std::sqrt((sqr(1 / 1.01) + sqr(2 / 2.01) + sqr(1 / 0.51)) / 5), 1e-12);
    EXPECT_EQ(j["max_abs_error"].get<double>(), 2);
    EXPECT_NEAR(j["mean"].get<double>(), 7.5 / 5, 1e-12);
    EXPECT_NEAR(j["reference_mean"].get<double>(), 3.5 / 5, 1e-12);
    EXPECT_EQ(j["infinite_values"].get<int>(), 1);
    EXPECT_EQ(j["infinite_mismatched"].get<int>(), 1);
    r = run("diff " + path("a.exr") + " " + path("b.exr"));
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("\ninfinite_values 1\ninfinite_mismatched 1\n"), std::string::npos)
        << r.out;

    Image inf(2, 1);
    inf.rgb.assign(inf.rgb.size(), INFINITY);
    writeExr(path("inf.exr"), inf);
    r = run("diff " + path("inf.exr") + " " + path("b.exr"));
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err, "shvol: error: " + path("inf.exr") +
                         ": no channel value is finite in both images: nothing to compare\n");
    b.set(1, 0, Spectrum(NAN, 0, 0));
    writeExr(path("nan.exr"), b);
    r = run("diff " + path("a.exr") + " " + path("nan.exr"));
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err, "shvol: error: " + path("nan.exr") + ": pixel (1, 0): NaN value\n");
}

// diff's thresholds: exit code 2 and one line naming every metric above its threshold, and any
// infinite value the other image does not match (which no metric shows); equal to a threshold
// passes; infinite
// in both alike passes; a threshold's range is checked as options are.
TEST_F(Cli, DiffThresholdsExitWithCode2) {
    Image a(2, 1), b(2, 1);
    a.set(0, 0, Spectrum(1, 2, 4)), a.set(1, 0, Spectrum(0.5, 3, INFINITY));
    b.set(0, 0, Spectrum(1, 1, 2)), b.set(1, 0, Spectrum(-0.5, 3, INFINITY));
    writeExr(path("a.exr"), a);
    writeExr(path("b.exr"), b);
    const std::string images = " " + path("a.exr") + " " + path("b.exr");
    // Differences 0, 1, 2, 1, 0 over five values: rmse √(6/5), max 2; +inf in both is left out.
    Result r = run("diff" + images + " --max-abs-error 2 --max-relative-rmse 2");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    r = run("diff" + images + " --max-rmse 1 --max-abs-error 1.5 --max-relative-rmse 2");
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(r.err, "shvol: diff: " + path("a.exr") +
                         ": rmse 1.09545 is above --max-rmse 1; max_abs_error 2 is above "
                         "--max-abs-error 1.5\n");
    EXPECT_NE(r.out.find("rmse 1.09545\n"), std::string::npos) << r.out;  // metrics as always
    // A value just above its threshold gets the digits that tell them apart: the float 1.1 is
    // 1.10000002384, 0.100000024 above 1 (it read "0.1 is above --max-abs-error 0.1").
    {
        Image c(1, 1), d(1, 1);
        c.set(0, 0, Spectrum::Constant(1.1f)), d.set(0, 0, Spectrum::Constant(1));
        writeExr(path("c.exr"), c), writeExr(path("d.exr"), d);
        const Result near =
            run("diff " + path("c.exr") + " " + path("d.exr") + " --max-abs-error 0.1");
        EXPECT_EQ(near.code, 2) << near.err;
        EXPECT_EQ(near.err, "shvol: diff: " + path("c.exr") +
                                ": max_abs_error 0.10000002 is above --max-abs-error 0.1\n");
    }
    r = run("diff" + images + " --max-rmse 0 --json");
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(nlohmann::json::parse(r.out)["max_abs_error"].get<double>(), 2);

    b.set(1, 0, Spectrum(-0.5, INFINITY, -INFINITY));  // one-sided, then of opposite signs
    writeExr(path("b.exr"), b);
    r = run("diff" + images + " --max-rmse 10");
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(r.err,
              "shvol: diff: " + path("a.exr") +
                  ": 2 infinite values are not matched in the other image (finite there, or of the "
                  "other sign)\n");
    r = run("diff" + images);  // without a threshold: counted, exit 0
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("\ninfinite_values 2\ninfinite_mismatched 2\n"), std::string::npos)
        << r.out;

    r = run("diff" + images + " --max-rmse -1");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("--max-rmse"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("must be in [0, "), std::string::npos) << r.err;
}

// A checkpoint is refused when a file the scene names has changed since it was written (the
// resumed image would mix two renders), and accepted again once the file is as it was.
TEST_F(Cli, ResumeRefusesChangedInputFiles) {
    writeTabulatedScene();
    const std::string s = "render " + path("s.json") + " --spp 20000 --quiet --checkpoint " +
                          path("ck.bin") + " -o " + path("r.exr");
    Result r = run(s + " --time-limit 0.002 --threads 1");
    ASSERT_EQ(r.code, 0) << r.err;
    fs::remove(path("r.exr"));
    write("t.csv", "angle_deg,value\n0,3\n180,1\n");
    r = run(s + " --resume");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find(path("ck.bin") +
                         ": written for a different render: the file named by "
                         "media[0].phase.file differs in contents (only the sample count may "
                         "change)"),
              std::string::npos)
        << r.err;
    EXPECT_FALSE(fs::exists(path("r.exr")));
    write("t.csv", "angle_deg,value\n0,2\n180,1\n");
    r = run(s + " --resume");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(fs::exists(path("r.exr")));
}

// A render stopped before pixels had 2 samples writes their standard error as +inf, and before
// they had 1 their value as 0, and says so, on stderr and in the statistics' warnings (which hold
// every warning printed).
TEST_F(Cli, UnsampledPixelsAreAWarningInTheStats) {
    write("s.json", scene(Homogeneous));
    const Result r = run("render " + path("s.json") + " --quiet -o " + path("v.exr") +
                         " --set camera.resolution=[320,240] --spp 1000000 --variance"
                         " --time-limit 0.001 --threads 1");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto stats = nlohmann::json::parse(std::ifstream(path("v.stats.json")));
    // Each warning is on stderr naming its file, and once in the stats, exactly when it applies
    // (a fast host may leave no pixel short).
    const auto expectWarning = [&](const std::string& file, const std::string& text, bool applies) {
        EXPECT_EQ(
            r.err.find(file + ": ") != std::string::npos && r.err.find(text) != std::string::npos,
            applies)
            << r.err;
        int inStats = 0;
        for (const auto& w : stats["warnings"])
            inStats += w.get<std::string>().find(text) != std::string::npos;
        EXPECT_EQ(inStats, applies ? 1 : 0) << stats["warnings"];
    };
    const int least = stats["samples_per_pixel_min"].get<int>();
    expectWarning(path("v.stderr.exr"), "pixels have fewer than 2 samples", least < 2);
    expectWarning(path("v.exr"),
                  "pixels have no sample (the render stopped early) and are written as 0",
                  least == 0);
}

// Only the standard errors an earlier render of the image wrote are removed (its stats name
// them), never a file of that name the render reads or keeps (helper 87: a checkpoint or a sky
// named OUT.stderr.exr was deleted).
TEST_F(Cli, RenderRemovesOnlyItsOwnStaleStandardErrors) {
    write("s.json", scene(Homogeneous));
    const std::string s = "render " + path("s.json") + " --quiet ";
    ASSERT_EQ(run(s + "-o " + path("c.exr") + " --variance").code, 0);
    // The checkpoint is kept (and resumes).
    Result r = run(s + "-o " + path("c.exr") + " --checkpoint " + path("c.stderr.exr"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err.find("removed"), std::string::npos) << r.err;
    r = run(s + "-o " + path("c.exr") + " --checkpoint " + path("c.stderr.exr") +
            " --resume --spp 4");
    EXPECT_EQ(r.code, 0) << r.err;
    // A sky named like the image's old standard errors is read, and kept.
    ASSERT_EQ(run(s + "-o " + path("k.exr") + " --variance").code, 0);
    write("sky.json", R"({"camera": {"resolution": [4, 3]}, "render": {"spp": 2},
        "environment": {"type": "image", "file": "k.stderr.exr"}})");
    r = run("render " + path("sky.json") + " --quiet -o " + path("k.exr"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(fs::exists(path("k.stderr.exr")));
    // The errors of an earlier render of the image, its directory named otherwise, go (they were
    // compared as paths, ./d/y.exr against d/y.exr; helper 88).
    fs::create_directories(path("d"));
    ASSERT_EQ(run(s + "-o " + path("d") + "/./y.exr --variance").code, 0);
    r = run(s + "-o " + path("d") + "/y.exr");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_FALSE(fs::exists(path("d/y.stderr.exr"))) << r.err;
    // A file of that name that no render of the image wrote (its stats do not name it) stays.
    write("o.stderr.exr", "mine");
    r = run(s + "-o " + path("o.exr"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(fs::exists(path("o.stderr.exr")));
}

// --spp 4,16 writes the 4-spp image on the way (identical to a separate 4-spp render) and
// --variance the standard error of every pixel's mean beside each image.
TEST_F(Cli, ProgressiveSppAndVariance) {
    write("s.json", scene(Homogeneous));
    const std::string s = "render " + path("s.json") + " --quiet ";
    Result r = run(s + "-o " + path("p.exr") + " --spp 4,16 --variance");
    ASSERT_EQ(r.code, 0) << r.err;
    ASSERT_EQ(run(s + "-o " + path("four.exr") + " --spp 4").code, 0);
    EXPECT_EQ(readExr(path("p.spp4.exr")).rgb, readExr(path("four.exr")).rgb);
    std::ifstream f(path("p.spp4.stats.json"));
    const auto stats = nlohmann::json::parse(f);
    EXPECT_EQ(stats["samples_per_pixel_min"], 4);
    // The image is a render of 4 spp, and its statistics say so.
    EXPECT_EQ(stats["spp"], 4);
    EXPECT_EQ(stats["scene_resolved"]["render"]["spp"], 4);
    EXPECT_EQ(stats["standard_error"], path("p.spp4.stderr.exr"));
    const Image se4 = readExr(path("p.spp4.stderr.exr")), se16 = readExr(path("p.stderr.exr"));
    double sum4 = 0, sum16 = 0;
    for (size_t i = 0; i < se4.rgb.size(); ++i) sum4 += se4.rgb[i], sum16 += se16.rgb[i];
    EXPECT_GT(sum16, 0);
    EXPECT_LT(sum16, sum4);  // 4× the samples: about half the standard error
    // Rendered again without --variance, the image loses its old standard errors, which would
    // pass for its own (helper 83); p.spp4's stay with p.spp4.exr, which this render leaves.
    r = run(s + "-o " + path("p.exr") + " --spp 8");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_FALSE(fs::exists(path("p.stderr.exr")));
    EXPECT_TRUE(fs::exists(path("p.spp4.stderr.exr")));
    EXPECT_NE(r.err.find("shvol: warning: " + path("p.stderr.exr") +
                         ": removed: the standard errors of an earlier render"),
              std::string::npos)
        << r.err;
    r = run(s + "-o " + path("x.exr") + " --spp 16,4");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("--spp: sample counts must increase, got 16,4"), std::string::npos)
        << r.err;
    r = run(s + "-o " + path("x.exr") + " --spp 0");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("--spp: "), std::string::npos) << r.err;
    // The standard error of one sample is unknown: an image of 1 spp with --variance is refused,
    // whether it is the last image or one on the way.
    for (const std::string spp : {"1", "1,4"}) {
        r = run(s + "-o " + path("x.exr") + " --variance --spp " + spp);
        EXPECT_EQ(r.code, 1) << spp;
        EXPECT_NE(r.err.find("--variance: a standard error needs at least 2 samples per pixel"),
                  std::string::npos)
            << r.err;
        EXPECT_FALSE(fs::exists(path("x.exr")));
    }
    // An intermediate image's line names its stats and standard errors, as the final one does
    // (helper 77).
    r = run("render " + path("s.json") + " -o " + path("l.exr") + " --spp 2,4 --variance");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("wrote " + path("l.spp2.exr") + ", " + path("l.spp2.stderr.exr") +
                         " and " + path("l.spp2.stats.json") + " (2 spp)\n"),
              std::string::npos)
        << r.err;
    // An image the render stopped before is said not to be written (it was left out silently).
    r = run(s + "-o " + path("z.exr") + " --spp 1,10000000,16000000 --time-limit 0.05");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("shvol: warning: " + path("s.json") +
                         ": --spp 10000000: the render stopped before 10000000 "
                         "samples per pixel; that image is not written\n"),
              std::string::npos)
        << r.err;
    EXPECT_TRUE(fs::exists(path("z.spp1.exr")));
    EXPECT_FALSE(fs::exists(path("z.spp10000000.exr")));
    // ... in the stats too (helper 71: on stderr only).
    const auto zs = nlohmann::json::parse(std::ifstream(path("z.stats.json")));
    EXPECT_NE(zs["warnings"].dump().find("--spp 10000000: the render stopped before"),
              std::string::npos)
        << zs["warnings"];
}

// shvol batch: killed with SIGKILL in the middle and started again, it finishes the remaining
// runs, loses no finished row and duplicates none; the metrics equal an uninterrupted batch's.
// A sweep changed under finished runs is refused.
namespace {

// The rows of DIR/results.jsonl by run id (a duplicated row fails the test).
std::map<std::string, nlohmann::json> ledgerRows(const std::string& dir) {
    std::ifstream f(dir + "/results.jsonl");
    std::map<std::string, nlohmann::json> m;
    int n = 0;
    for (std::string line; std::getline(f, line); ++n) {
        const auto j = nlohmann::json::parse(line);
        m[j["run"]] = j;
    }
    EXPECT_EQ(size_t(n), m.size()) << dir << ": duplicated rows";
    return m;
}

// Two ledgers hold the same runs with the same seeds and errors.
void expectSameRows(const std::string& dirA, const std::string& dirB, size_t runs) {
    const auto a = ledgerRows(dirA), b = ledgerRows(dirB);
    ASSERT_EQ(a.size(), runs) << dirA;
    ASSERT_EQ(b.size(), runs) << dirB;
    for (const auto& [id, row] : a) {
        EXPECT_EQ(b.at(id)["rmse"], row["rmse"]) << id;
        EXPECT_EQ(b.at(id)["seed"], row["seed"]) << id;
    }
}

// A ledger's rows by their point: the values of `keys` (axes and repeat), as JSON text.
std::map<std::string, nlohmann::json> rowsByPoint(const std::string& dir,
                                                  const std::vector<std::string>& keys) {
    std::map<std::string, nlohmann::json> m;
    for (const auto& [id, row] : ledgerRows(dir)) {
        nlohmann::json point = nlohmann::json::object();
        for (const std::string& k : keys) point[k] = row.value(k, nlohmann::json());
        EXPECT_TRUE(m.emplace(point.dump(), row).second) << dir << ": " << point.dump() << " twice";
    }
    return m;
}

// Two ledgers hold the same points with the same seeds and errors, whatever their runs' ids.
void expectSamePoints(const std::string& dirA, const std::string& dirB,
                      const std::vector<std::string>& keys, size_t runs) {
    const auto a = rowsByPoint(dirA, keys), b = rowsByPoint(dirB, keys);
    ASSERT_EQ(a.size(), runs) << dirA;
    ASSERT_EQ(b.size(), runs) << dirB;
    for (const auto& [point, row] : a) {
        ASSERT_TRUE(b.count(point)) << point;
        EXPECT_EQ(b.at(point)["rmse"], row["rmse"]) << point;
        EXPECT_EQ(b.at(point)["seed"], row["seed"]) << point;
    }
}

}  // namespace

TEST_F(Cli, BatchSurvivesKillAndRefusesAChangedSweep) {
    write("s.json", scene(Homogeneous));
    const std::string sweep = R"({"scene": "s.json", "axes": {"spp": [6000, 9000, 12000]},
        "repeats": 3, "reference": {"spp": 20000}, "metrics": ["rmse", "bias"]})";
    write("sweep.json", sweep);
    Result r = run("batch " + path("sweep.json") + " --quiet --output " + path("clean"));
    ASSERT_EQ(r.code, 0) << r.err;
    // Killed in the middle (once the first row is in; about 1.3 s uninterrupted), with one
    // render at a time and with two side by side (--jobs 2), then started again with the other
    // job count.
    for (const std::string jobs : {"1", "2"}) {
        const std::string out = path("killed" + jobs), again = jobs == "1" ? "2" : "1";
        r = run("batch " + path("sweep.json") + " --quiet --jobs " + jobs + " --output " + out +
                " & p=$!; i=0; while [ ! -s " + out + "/results.jsonl ] && [ $i -lt 3000 ]; " +
                "do sleep 0.01; i=$((i+1)); done; kill -9 $p; wait $p");
        EXPECT_EQ(r.code, 137);  // killed: 128 + 9
        EXPECT_LT(ledgerRows(out).size(), 9u) << "some runs are left to do";
        r = run("batch " + path("sweep.json") + " --quiet --jobs " + again + " --output " + out);
        ASSERT_EQ(r.code, 0) << r.err;
        expectSameRows(path("clean"), out, 9);
    }
    const auto clean = ledgerRows(path("clean"));
    EXPECT_EQ(clean.at("r0003")["spp"], clean.at("r0000")["spp"]);    // repeats slowest:
    EXPECT_NE(clean.at("r0003")["seed"], clean.at("r0000")["seed"]);  // repeats differ
    // The same sweep again: nothing to do.
    r = run("batch " + path("sweep.json") + " --output " + path("clean"));
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.err.find("9 of 9 runs already finished"), std::string::npos) << r.err;
    // More repeats: the finished runs keep their ids, and only the new repeat renders, as a
    // batch of four repeats from the start would have.
    fs::copy(path("clean"), path("more"), fs::copy_options::recursive);
    std::string more = sweep;
    more.replace(more.find("\"repeats\": 3"), 12, "\"repeats\": 4");
    write("sweep.json", more);
    r = run("batch " + path("sweep.json") + " --output " + path("more"));
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("9 of 12 runs already finished"), std::string::npos) << r.err;
    r = run("batch " + path("sweep.json") + " --quiet --output " + path("more4"));
    ASSERT_EQ(r.code, 0) << r.err;
    expectSameRows(path("more4"), path("more"), 12);
    write("sweep.json", sweep);
    // Changing what a finished run renders is refused: its axis values, or the settings of all.
    std::string changed = sweep;
    changed.replace(changed.find("9000"), 4, "9500");
    write("sweep.json", changed);
    r = run("batch " + path("sweep.json") + " --quiet --output " + path("clean"));
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("results.jsonl: run r0001: finished with spp=9000, a value axes.spp no "
                         "longer has (a finished run must stay in the sweep: values may be added "
                         "to its axes, and repeats, but not changed or removed); use another "
                         "output directory"),
              std::string::npos)
        << r.err;
    // (naming the value, as a resumed render does, helper 84; also a key the runs did not use,
    // which their stats leave out, helper 140: nothing was named)
    for (const std::string key : {"render.product_order", "render.max_depth"}) {
        changed = sweep;
        changed.replace(changed.find("\"axes\""), 0, "\"set\": [\"" + key + "=7\"], ");
        write("sweep.json", changed);
        r = run("batch " + path("sweep.json") + " --quiet --output " + path("clean"));
        EXPECT_EQ(r.code, 1);
        EXPECT_NE(r.err.find("results.jsonl: run r0000: finished with other settings or another "
                             "scene than the sweep now gives: scene value " +
                             key +
                             " differs (seed, set or axes, or scene file); use another output "
                             "directory"),
                  std::string::npos)
            << r.err;
    }
    // --dry-run, which reads no grid, refuses changed settings too (it listed the runs as
    // finished, which the start then refused).
    r = run("batch " + path("sweep.json") + " --dry-run --output " + path("clean"));
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("results.jsonl: run r0000: finished with other settings"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(r.out, "");
    EXPECT_EQ(run("batch " + path("sweep.json") + " --dry-run").out.substr(0, 10), "reference ");
    // --dry-run marks the runs a ledger holds, and writes nothing (a last line cut short by a
    // kill stays as it is: only a start repairs it).
    write("sweep.json", sweep);
    const std::string ledger = path("clean/results.jsonl"), rows = test::fileBytes(ledger);
    const std::string firstTwo = rows.substr(0, rows.find('\n', rows.find('\n') + 1) + 1);
    std::ofstream(ledger, std::ios::binary) << firstTwo << "{\"run\": \"r00";
    r = run("batch " + path("sweep.json") + " --dry-run --output " + path("clean"));
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("9 runs into " + path("clean") + ", 2 of them finished"),
              std::string::npos)
        << r.out;
    EXPECT_EQ(occurrences(r.out, " (finished)\n"), 2u) << r.out;
    EXPECT_EQ(test::fileBytes(ledger), firstTwo + "{\"run\": \"r00");
}

// Values added anywhere in a sweep's axes (and repeats raised) resume into the same output: the
// finished runs are found by their values and keep their ids, rows and images, and only the new
// points render, each the same render as in a batch of the new sweep from the start.
// A finished run whose sample count the sweep's `set` changed names it (helper 87: the values
// were named, the sample count, which a checkpoint's identity leaves out, was not).
TEST_F(Cli, BatchNamesAChangedSampleCount) {
    write("s.json", scene(Homogeneous));
    write("sweep.json", R"({"scene": "s.json", "set": ["render.spp=2"], "axes": {}})");
    const std::string batch = "batch " + path("sweep.json") + " --quiet --output " + path("out");
    ASSERT_EQ(run(batch).code, 0);
    write("sweep.json", R"({"scene": "s.json", "set": ["render.spp=3"], "axes": {}})");
    const Result r = run(batch);
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("finished with other settings or another scene than the sweep now "
                         "gives: render.spp was 2, is 3; use another output directory"),
              std::string::npos)
        << r.err;
}

// A rendered reference of fewer than 10 times the largest run's samples is warned of: its noise
// counts as the runs' error (helper 86: half the MSE of 1024-spp runs against 1024).
TEST_F(Cli, BatchWarnsOfANoisyReference) {
    write("s.json", scene(Homogeneous));
    for (const std::string spp : {"16", "40"}) {
        write("sweep.json",
              R"({"scene": "s.json", "axes": {"spp": [2, 4]}, "reference": {"spp": )" + spp +
                  R"(}, "metrics": ["rmse"]})");
        const Result r = run("batch " + path("sweep.json") + " --dry-run");
        EXPECT_EQ(r.code, 0) << r.err;
        if (spp == "16")
            EXPECT_EQ(r.err, "shvol: warning: " + path("sweep.json") +
                                 ": reference.spp: 16 samples per pixel, fewer than 10 times the "
                                 "runs' largest (4): the reference's own noise adds about 25% to "
                                 "that run's MSE, counted as the run's error; give the reference "
                                 "more samples\n");
        else
            EXPECT_EQ(r.err, "");
    }
    // The dry run says whether the reference is rendered yet (it said "rendered once, cached"
    // whether it was or not; helper 86).
    const std::string dry = "batch " + path("sweep.json") + " --dry-run --output " + path("o");
    EXPECT_NE(run(dry).out.find("reference.exr (rendered first, then cached)\n"),
              std::string::npos);
    ASSERT_EQ(run("batch " + path("sweep.json") + " --quiet --output " + path("o")).code, 0);
    EXPECT_NE(run(dry).out.find("reference.exr (not needed: every run is finished)\n"),
              std::string::npos);
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [2, 4, 3]}, "reference": {"spp": )"
                        R"(40}, "metrics": ["rmse"]})");
    EXPECT_NE(run(dry).out.find("reference.exr (rendered, cached)\n"), std::string::npos);
}

// Runs added to a finished batch on another thread count are warned of: their times would not
// compare with the finished runs' (helper 86); on the same count nothing is said.
TEST_F(Cli, BatchWarnsOfRunsTimedOnOtherThreadCounts) {
    write("s.json", scene(Homogeneous));
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [2]}})");
    const std::string batch = "batch " + path("sweep.json") + " --quiet --output " + path("out");
    ASSERT_EQ(run(batch + " --threads 2").code, 0);
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [2, 3]}})");
    Result r = run(batch + " --threads 1");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("results.jsonl: 1 finished run was rendered on 2 threads each, this "
                         "batch renders on 1: their times, and the report's efficiencies, do not "
                         "compare with the 1 run left"),
              std::string::npos)
        << r.err;
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [2, 3, 4]}})");
    r = run(batch + " --threads 1");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("1 finished run was rendered on 2 threads each"), std::string::npos)
        << r.err;  // (spp 3 was rendered on 1, as this batch renders)
}

TEST_F(Cli, BatchResumesASweepWithValuesAddedAnywhere) {
    write("s.json", scene(Homogeneous));
    const auto sweep = [&](const std::string& albedos, const std::string& spps, int repeats) {
        write("sweep.json", R"({"scene": "s.json", "axes": {"media[0].albedo": [)" + albedos +
                                R"(], "spp": [)" + spps + R"(]}, "repeats": )" +
                                std::to_string(repeats) +
                                R"(, "reference": {"spp": 64, "seed": 99}, "metrics": ["rmse"]})");
    };
    sweep("0.5, 0.9", "2, 8", 1);
    const std::string batch = "batch " + path("sweep.json") + " --output ";
    Result r = run(batch + path("out") + " --quiet");
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string ledger = test::fileBytes(path("out/results.jsonl"));
    std::map<std::string, std::string> images;  // of the finished runs, by id
    for (const auto& [id, row] : ledgerRows(path("out")))
        images[id] = test::fileBytes(path("out/" + id + ".exr"));
    ASSERT_EQ(images.size(), 4u);

    sweep("0.5, 0.7, 0.9", "2, 4, 8", 2);  // 18 runs, 4 of them finished
    r = run(batch + path("out") + " --dry-run");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("18 runs into " + path("out") + ", 4 of them finished"), std::string::npos)
        << r.out;
    // (0.9, 2) was r0002 and stays so; the new (0.5, 4) would have been r0001, (0.9, 8)'s.
    EXPECT_NE(r.out.find("r0002 media[0].albedo=0.9 spp=2 repeat=0 (finished)\n"),
              std::string::npos)
        << r.out;
    EXPECT_NE(r.out.find("r0003 media[0].albedo=0.9 spp=8 repeat=0 (finished)\n"),
              std::string::npos)
        << r.out;
    EXPECT_EQ(r.out.find("r0001 media[0].albedo=0.5 spp=4 repeat=0"), std::string::npos) << r.out;
    r = run(batch + path("out"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("4 of 18 runs already finished"), std::string::npos) << r.err;
    EXPECT_EQ(test::fileBytes(path("out/results.jsonl")).substr(0, ledger.size()), ledger);
    for (const auto& [id, bytes] : images)
        EXPECT_EQ(test::fileBytes(path("out/" + id + ".exr")), bytes) << id;
    for (const auto& [id, row] : ledgerRows(path("out"))) {
        EXPECT_EQ(row["image"], id + ".exr");
        EXPECT_TRUE(fs::exists(path("out/" + id + ".exr"))) << id;
    }
    ASSERT_EQ(run(batch + path("fresh") + " --quiet").code, 0);
    expectSamePoints(path("out"), path("fresh"), {"media[0].albedo", "spp", "repeat"}, 18);
    r = run(batch + path("out"));
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.err.find("18 of 18 runs already finished"), std::string::npos) << r.err;
    // A finished value taken out is refused, naming the run that holds it and the value.
    sweep("0.5, 0.7", "2, 4, 8", 2);
    r = run(batch + path("out") + " --quiet");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("run r0002: finished with media[0].albedo=0.9, a value "
                         "axes.media[0].albedo no longer has (a finished run must stay"),
              std::string::npos)
        << r.err;
}

// A finished value written otherwise but equal (1.0 for 1) is the same value, the same render:
// --dry-run and the start agree that the runs are finished.
TEST_F(Cli, BatchResumesValuesWrittenOtherwise) {
    write("s.json", scene(Homogeneous));
    const auto sweep = [&](const std::string& albedos) {
        write("sweep.json", R"({"scene": "s.json", "set": ["render.spp=2"], "axes":
                                {"media[0].albedo": [)" +
                                albedos + R"(]}, "output": "out"})");
    };
    sweep("0, 1");
    const std::string batch = "batch " + path("sweep.json");
    ASSERT_EQ(run(batch + " --quiet").code, 0);
    sweep("0.0, 0.5, 1.0");
    Result r = run(batch + " --dry-run");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("3 runs into " + path("out") + ", 2 of them finished"), std::string::npos)
        << r.out;
    r = run(batch);
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("2 of 3 runs already finished"), std::string::npos) << r.err;
}

// The axes come in the sweep's order wherever a batch shows them, in its dry run and its CSV (they
// came alphabetically: a row's keys are sorted; helper 77).
TEST_F(Cli, BatchShowsTheAxesInTheSweepsOrder) {
    write("s.json", scene(Homogeneous));
    write("sweep.json", R"({"scene": "s.json", "output": "out",
        "axes": {"render.max_depth": [8], "media.0.albedo": [0.5]}})");
    Result r = run("batch " + path("sweep.json") + " --dry-run");
    EXPECT_EQ(r.out.substr(0, r.out.find('\n')),
              "r0000 render.max_depth=8 media.0.albedo=0.5 repeat=0");
    r = run("batch " + path("sweep.json") + " --quiet");
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string csv = test::fileBytes(path("out/results.csv"));
    EXPECT_EQ(csv.substr(0, csv.find(",seed,")), "run,repeat,render.max_depth,media.0.albedo");
}

// A file the scene names (here a phase table) changed since a run finished: the start refuses
// the run, naming the files, and so does --dry-run.
TEST_F(Cli, BatchRefusesRunsWhoseInputFilesChanged) {
    writeTabulatedScene();
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [2]}, "output": "out"})");
    const std::string batch = "batch " + path("sweep.json") + " --quiet";
    ASSERT_EQ(run(batch).code, 0);
    Result r = run(batch + " --dry-run");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("1 of them finished"), std::string::npos) << r.out;
    write("t.csv", "angle_deg,value\n0,3\n180,1\n");
    for (const std::string flags : {" --dry-run", ""}) {  // the dry run refuses what the start does
        r = run(batch + flags);
        EXPECT_EQ(r.code, 1) << flags;
        EXPECT_EQ(r.out, "") << flags;
        // Named by the hashes the run's stats kept, as a resumed render names them (it named
        // none; helper 77).
        EXPECT_EQ(r.err, "shvol: error: " + path("out/results.jsonl") +
                             ": run r0000: finished when the files its scene names had other "
                             "contents: the file named by media[0].phase.file differs in "
                             "contents; use another output directory\n")
            << flags;
    }
    // Without the run's stats, what they could be.
    fs::remove(path("out/r0000.stats.json"));
    r = run(batch);
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("run r0000: finished when the files its scene names had other contents: "
                         "which of them (grids, skies, tables, meshes) cannot be told; use "),
              std::string::npos)
        << r.err;
}

// A signal while a batch's run writes its outputs: they are written whole and its row goes in,
// and the batch stops before its next run, exit code 130 (it started the next run, which the
// signal cancelled at once into an image of no samples). The same signal during the last run's
// writing says that every run is in.
TEST_F(Cli, BatchStopsBeforeItsNextRunAtASignalWhileARunWrites) {
    write("s.json", R"({"camera": {"resolution": [2048, 2048], "position": [0, -3, 0]},
        "render": {"spp": 2}, "environment": {"type": "constant", "radiance": 1},
        "media": [)" + Homogeneous +
                        "]}");
    for (const int runs : {2, 1}) {
        SCOPED_TRACE(runs);
        const std::string out = path("out" + std::to_string(runs));
        write("sweep.json", R"({"scene": "s.json", "axes": {"seed": )" +
                                std::string(runs == 2 ? "[1, 2]" : "[1]") + "}}");
        const Result r = runCommand(
            "env --default-signal=INT " + std::string(SHVOL_BINARY) + " batch " +
            path("sweep.json") + " --quiet --output " + out + " 2>" + path("bg.txt") +
            " & p=$!; i=0; while ! ls " + out +
            "/r0000.stats.json.tmp* >/dev/null 2>&1 && [ $i -lt 60000 ]; do sleep 0.001; "
            "i=$((i+1)); done; kill -INT $p; wait $p");
        const std::string err = test::fileBytes(path("bg.txt"));
        EXPECT_EQ(r.code, 130) << err;
        EXPECT_EQ(err, runs == 2 ? "batch: stopped; 1 run is in " + out +
                                       "/results.jsonl, run again to finish\n"
                                 : "batch: interrupted as its last run finished; all 1 run is "
                                   "in " +
                                       out + "/results.jsonl\n");
        EXPECT_EQ(ledgerRows(out).size(), 1u);
        EXPECT_EQ(readExr(out + "/r0000.exr").width, 2048);
        EXPECT_FALSE(fs::exists(out + "/r0001.exr"));
        for (const auto& e : fs::directory_iterator(out))
            EXPECT_EQ(e.path().string().find(".tmp"), std::string::npos) << e.path();
    }
}

// A second job's run that a signal stops before its first sample writes nothing (helper 159: a
// --jobs 2 batch left a black image and stats of no samples beside the finished runs'): the
// signal comes as run 0, 8x8 at 1 spp, is written, while run 1 still fits its order-256 SH phase
// function (2.6 s).
TEST_F(Cli, BatchRunStoppedBeforeItsFirstSampleWritesNothing) {
    write("s.json", R"({"camera": {"resolution": [8, 8], "position": [0, -3, 0]},
        "render": {"spp": 1}, "environment": {"type": "constant", "radiance": 1},
        "media": [{"type": "homogeneous", "sigma_t": 1, "shape": {"type": "sphere"}}]})");
    write("sweep.json", R"({"scene": "s.json", "axes": {"media[0].phase": [{"type": "hg", "g": 0.5},
        {"type": "hg", "g": 0.999999, "sampling": "sh", "order": 256, "sh_depth": 18}]}})");
    const std::string out = path("out");
    const Result r = runCommand(
        "env --default-signal=INT " + std::string(SHVOL_BINARY) + " batch " + path("sweep.json") +
        " --quiet --jobs 2 --threads 1 --output " + out + " 2>" + path("bg.txt") +
        " & p=$!; i=0; while ! ls " + out +
        "/r0000.stats.json >/dev/null 2>&1 && [ $i -lt 60000 ]; do sleep 0.001; i=$((i+1)); done; "
        "kill -INT $p; wait $p");
    const std::string err = test::fileBytes(path("bg.txt"));
    EXPECT_EQ(r.code, 130) << err;
    EXPECT_NE(err.find("shvol: interrupted before the first sample of " + out +
                       "/r0001.exr: nothing written\n"),
              std::string::npos)
        << err;
    EXPECT_EQ(ledgerRows(out).size(), 1u);
    EXPECT_TRUE(fs::exists(out + "/r0000.exr"));
    for (const char* name : {"/r0001.exr", "/r0001.stats.json"})
        EXPECT_FALSE(fs::exists(out + name)) << name;
}

// A given reference is compared as `shvol diff` compares it: negative values (another
// renderer's filter rings below 0) are taken, as README says (batch refused them; helper 67);
// infinite ones are refused (every run's metrics were infinite, null in the ledger; review).
TEST_F(Cli, BatchTakesAReferenceWithNegativeValues) {
    write("s.json", scene(Homogeneous));
    ASSERT_EQ(run("render " + path("s.json") + " --quiet --spp 16 -o " + path("ref.exr")).code, 0);
    Image ref = readExr(path("ref.exr"));
    ref.set(0, 0, Spectrum(-0.25, 0.5, 0.5));
    writeExr(path("ref.exr"), ref);
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [2]}, "metrics": ["rmse"],
        "reference": {"file": "ref.exr"}, "output": "out"})");
    const Result r = run("batch " + path("sweep.json") + " --quiet");
    ASSERT_EQ(r.code, 0) << r.err;
    const auto rows = ledgerRows(path("out"));
    ASSERT_EQ(rows.size(), 1u);
    EXPECT_GT(rows.at("r0000").at("rmse").get<double>(), 0);
    // An infinite value is refused, naming its pixel: every run's metrics would be infinite.
    for (const float inf : {INFINITY, -INFINITY}) {
        ref.set(1, 2, Spectrum(0.5, inf, 0.5));
        writeExr(path("ref.exr"), ref);
        std::filesystem::remove_all(path("out"));
        const Result bad = run("batch " + path("sweep.json") + " --quiet");
        EXPECT_EQ(bad.code, 1);
        EXPECT_EQ(bad.err, "shvol: error: " + path("ref.exr") +
                               ": pixel (1, 2): infinite value: every run's error against this "
                               "reference would be infinite\n");
        EXPECT_TRUE(ledgerRows(path("out")).empty());
    }
}

// A finished run whose image is gone keeps its row and is not rendered again, and the batch (and
// its dry run) says so: it went unnoticed (helper 67).
TEST_F(Cli, BatchSaysWhenAFinishedRunsImageIsMissing) {
    write("s.json", scene(Homogeneous));
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [1, 2, 3]}, "output": "out"})");
    ASSERT_EQ(run("batch " + path("sweep.json") + " --quiet").code, 0);
    fs::remove(path("out/r0001.exr"));
    fs::remove(path("out/r0002.exr"));
    const std::string warning =
        "shvol: warning: " + path("out") +
        ": finished runs' images are missing: " + path("out/r0001.exr") +
        " and 1 more; their rows stand and the runs are not rendered again (to render one "
        "again, delete its line from " +
        path("out/results.jsonl") + ")\n";
    Result r = run("batch " + path("sweep.json") + " --quiet");
    EXPECT_EQ(r.code, 0);
    EXPECT_EQ(r.err, warning);
    EXPECT_FALSE(fs::exists(path("out/r0001.exr")));
    r = run("batch " + path("sweep.json") + " --dry-run");
    EXPECT_EQ(r.code, 0);
    EXPECT_EQ(r.err, warning);
    // An image there but damaged is said too: it passed as finished (helper 116). Here bytes of
    // its size that are no OpenEXR file, found by the header.
    const std::string whole = test::fileBytes(path("out/r0000.exr"));
    write("out/r0000.exr", std::string(whole.size(), 'x'));
    r = run("batch " + path("sweep.json") + " --dry-run");
    EXPECT_EQ(r.code, 0);
    EXPECT_EQ(r.err.rfind(warning, 0), 0u) << r.err;
    const std::string damaged =
        "shvol: warning: " + path("out") +
        ": finished runs' images are not as their runs wrote them: " + path("out/r0000.exr") +
        " (not a readable OpenEXR file (";
    EXPECT_EQ(r.err.find(damaged), warning.size()) << r.err;
    EXPECT_NE(r.err.find(")); their rows stand"), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 2) << r.err;
    // Cut short after its header, by the resume itself (not only its dry run), read from the
    // chunk table alone: no pixel is decoded (helper 120).
    write("out/r0000.exr", whole.substr(0, whole.size() - 40));
    r = run("batch " + path("sweep.json") + " --quiet");
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.err.find(": finished runs' images are not as their runs wrote them: " +
                         path("out/r0000.exr") + " (" + std::to_string(whole.size() - 40) +
                         " bytes, where its run wrote " + std::to_string(whole.size()) +
                         "); their rows stand"),
              std::string::npos)
        << r.err;
}

// A signal while the batch checks its sweep's scenes (here an SH fit of order 256, seconds long)
// stops it as one during a run does, with exit code 143 and a word: caught only during renders,
// SIGTERM ended it with 143 and nothing said (helper 67).
TEST_F(Cli, BatchStopsAtASignalOutsideItsRenders) {
    write("s.json", R"({"camera": {"resolution": [8, 8], "position": [0, -3, 0]},
        "render": {"spp": 1}, "environment": {"type": "constant", "radiance": 1},
        "media": [{"type": "homogeneous", "sigma_t": 1, "shape": {"type": "sphere"},
                   "phase": {"type": "hg", "g": 0.999999, "sampling": "sh", "order": 256,
                             "sh_depth": 18}}]})");
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [1]}})");
    // SIGTERM once the batch catches it, while the scene is checked (2.6 s).
    Result r = runCommand(std::string(SHVOL_BINARY) + " batch " + path("sweep.json") +
                          " --quiet --output " + path("out") + " 2>" + path("bg.txt") +
                          killOnceCaught("TERM", SIGTERM));
    EXPECT_EQ(r.code, 128 + SIGTERM);
    EXPECT_EQ(test::fileBytes(path("bg.txt")),
              "batch: stopped before a run finished; run again to finish\n");
    EXPECT_FALSE(fs::exists(path("out/r0000.exr")));
    // A dry run writes nothing and ends by the signal (it caught it, and carried on to print
    // the runs; review).
    r = runCommand(std::string(SHVOL_BINARY) + " batch " + path("sweep.json") +
                   " --dry-run --output " + path("out") + " >" + path("bg.txt") +
                   " & p=$!; sleep 0.5; kill -TERM $p; wait $p");
    EXPECT_EQ(r.code, 128 + SIGTERM);
    EXPECT_EQ(test::fileBytes(path("bg.txt")), "");
}

// A finished row must be the run as the sweep names and measures it now: an axis renamed
// (media.0.albedo for media[0].albedo), added or dropped, or another list of metrics, renders the
// same images but would leave the report columns of nulls and configurations split in two (they
// were resumed into the same ledger). --dry-run refuses them too, printing nothing.
TEST_F(Cli, BatchRefusesRowsOfOtherAxesOrMetrics) {
    write("s.json", scene(Homogeneous));
    const auto sweep = [&](const std::string& axes, const std::string& metrics) {
        write("sweep.json", R"({"scene": "s.json", "set": ["render.spp=2"], )" +
                                (axes.empty() ? "" : R"("axes": {)" + axes + "}, ") +
                                R"("reference": {"spp": 32, "seed": 99}, "metrics": [)" + metrics +
                                R"(], "output": "out"})");
    };
    sweep(R"("media[0].albedo": [0.5, 0.9])", R"("rmse")");
    const std::string batch = "batch " + path("sweep.json") + " --quiet";
    Result r = run(batch);
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string rows = test::fileBytes(path("out/results.jsonl"));
    const std::vector<std::array<std::string, 3>> cases = {
        {R"("media.0.albedo": [0.5, 0.9])", R"("rmse")",
         "finished with no media.0.albedo, an axis the sweep now has"},
        {R"("media[0].albedo": [0.5, 0.9], "render.max_depth": [64])", R"("rmse")",
         "finished with no render.max_depth, an axis the sweep now has"},
        {"", R"("rmse")", "finished with media[0].albedo=0.5, an axis the sweep no longer has"},
        {R"("media[0].albedo": [0.5, 0.9])", R"("mae")",
         "finished without mae, which the sweep now asks for"},
        {R"("media[0].albedo": [0.5, 0.9])", R"("rmse", "ztest")",
         "finished without ztest, which the sweep now asks for"},
    };
    for (const auto& [axes, metrics, message] : cases) {
        sweep(axes, metrics);
        for (const char* dry : {"", " --dry-run"}) {
            r = run(batch + dry);
            EXPECT_EQ(r.code, 1) << axes << metrics << dry;
            // (The z-test's runs of 2 spp are warned of once the finished rows pass, after their
            // ledger ids are known.)
            EXPECT_EQ(r.err, "shvol: error: " + path("out/results.jsonl") +
                                 ": run r0000: " + message + "; use another output directory\n")
                << axes << metrics << dry;
            EXPECT_EQ(r.out, "") << dry;
        }
    }
    EXPECT_EQ(test::fileBytes(path("out/results.jsonl")), rows);
}

// A finished row must be as the batch wrote it: a run id of its own and numbers where it wrote
// numbers. A row with "run": "zzz" gave its run that id (its image "zzz.exr"), and one with
// "rmse": "abc" was taken as finished, for shvol report to refuse later, or never (helper 127).
TEST_F(Cli, BatchRefusesRowsItDidNotWrite) {
    write("s.json", scene(Homogeneous));
    write("sweep.json", R"({"scene": "s.json", "set": ["render.spp=2"],
                            "axes": {"media[0].albedo": [0.5, 0.9]},
                            "reference": {"spp": 32, "seed": 99}, "metrics": ["rmse", "bias"],
                            "output": "out"})");
    const std::string batch = "batch " + path("sweep.json") + " --quiet";
    Result r = run(batch);
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string rows = test::fileBytes(path("out/results.jsonl"));
    const auto replaced = [&](const std::string& from, const std::string& to) {
        std::string text = rows;
        const size_t at = text.find(from);
        EXPECT_NE(at, std::string::npos) << from;
        return text.replace(at, from.size(), to);
    };
    const size_t rmse = rows.find("\"rmse\":");
    ASSERT_NE(rmse, std::string::npos);
    const std::string rmseValue = rows.substr(rmse, rows.find_first_of(",}", rmse) - rmse);
    const std::vector<std::array<std::string, 3>> cases = {
        {R"("run":"r0000")", R"("run":"zzz")",
         "run zzz: not a run id of shvol batch (r0000, r0001, …); delete its line to render "
         "that run again"},
        {rmseValue, R"("rmse":"abc")",
         "run r0000: rmse: expected a finite number >= 0 of at most 1e100, got \"abc\"; delete "
         "its line to render that run again"},
        {rmseValue, R"("rmse":-1)",
         "run r0000: rmse: expected a finite number >= 0 of at most 1e100, got -1; delete its "
         "line to render that run again"},
        {rmseValue, R"("rmse":1e308)",  // (report's arithmetic overflowed; helper 130)
         "run r0000: rmse: expected a finite number >= 0 of at most 1e100, got 1e+308; delete "
         "its line to render that run again"},
        {R"("spp":2)", R"("spp":null)",
         "run r0000: spp: expected an integer >= 1, got null; delete its line to render that "
         "run again"},
        {R"("spp":2)", R"("spp":2.5)",  // (as report refuses it; helper 129)
         "run r0000: spp: expected an integer >= 1, got 2.5; delete its line to render that run "
         "again"},
        {R"("run":"r0001")", R"("run":"r00001")",  // (not the id of run 1, r0001)
         "run r00001: not a run id of shvol batch (r0000, r0001, …); delete its line to render "
         "that run again"},
    };
    for (const auto& [from, to, message] : cases) {
        const std::string damaged = replaced(from, to);
        std::ofstream(path("out/results.jsonl"), std::ios::binary) << damaged;
        for (const char* dry : {"", " --dry-run"}) {
            r = run(batch + dry);
            EXPECT_EQ(r.code, 1) << to << dry;
            EXPECT_EQ(r.err, "shvol: error: " + path("out/results.jsonl") + ": " + message + "\n")
                << to << dry;
        }
        EXPECT_EQ(test::fileBytes(path("out/results.jsonl")), damaged);
    }
    // The rows as the batch wrote them pass (a negative bias among them or not).
    std::ofstream(path("out/results.jsonl"), std::ios::binary) << rows;
    r = run(batch);
    EXPECT_EQ(r.code, 0) << r.err;
}

// A z-test of runs below 64 spp is warned of before the batch renders (and by --dry-run): their
// standard errors are too poor, and unbiased runs of the default scene failed every repeat at 2
// and 4 spp, p down to 1e-277, said nowhere (helper 122). From 64 spp on, nothing is said.
TEST_F(Cli, BatchWarnsOfZTestsAtFewSamples) {
    write("s.json", scene(Homogeneous));
    const auto dryRun = [&](const std::string& spps) {
        write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [)" + spps +
                                R"(]}, "reference": {"spp": 4096}, "metrics": ["ztest"]})");
        return run("batch " + path("sweep.json") + " --dry-run");
    };
    Result r = dryRun("128, 8, 64, 4");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, unreliableZTestWarning(path("sweep.json"), 2, 4, "r0003"));
    r = dryRun("64, 128");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    // Run ids are the ledger's: with the 64-spp run finished as r0000, 8 put first on the axis is
    // r0001, as the start and the dry run list it (it was named r0000, the finished run's id;
    // helper 159).
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [64]}, "reference": {"spp": 4096},
        "metrics": ["ztest"], "output": "out"})");
    r = run("batch " + path("sweep.json") + " --quiet");
    ASSERT_EQ(r.code, 0) << r.err;
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [8, 64]}, "reference": {"spp": 4096},
        "metrics": ["ztest"], "output": "out"})");
    for (const char* dry : {" --dry-run", " --quiet"}) {
        r = run("batch " + path("sweep.json") + dry);
        EXPECT_EQ(r.code, 0) << r.err;
        EXPECT_EQ(r.err, unreliableZTestWarning(path("sweep.json"), 1, 8, "r0001")) << dry;
    }
    std::istringstream rows(test::fileBytes(path("out/results.jsonl")));
    std::map<std::string, int> sppOf;
    for (std::string line; std::getline(rows, line);) {
        const auto row = nlohmann::json::parse(line);
        sppOf[row["run"].get<std::string>()] = row["spp"].get<int>();
    }
    EXPECT_EQ(sppOf, (std::map<std::string, int>{{"r0000", 64}, {"r0001", 8}}));
}

// A key misspelt, or a value refused, by a --set, or by a sweep's `set`, axis or reference
// `set`, is named at the assignment that brought it in: it was blamed on the scene file and a
// sweep's `set`, which every run has, "in the reference" (helpers 127, 133). A key or value of
// the scene itself is still the scene's, whatever a --set sets beside it.
TEST_F(Cli, ErrorsOfOverridesAreNamedWhereTheyWereGiven) {
    write("s.json", scene(Homogeneous));
    const std::string render = "render " + path("s.json") + " -o " + path("out.exr") + " --quiet ";
    const std::string fvo = ": camera.fvo: unknown key (did you mean \"fov\"?)\n";
    Result r = run(render + "--set camera.fvo=30");
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err, "shvol: error: " + path("s.json") + ": --set camera.fvo=30" + fvo);
    r = run(render + "--set camera.fov=30 --set 'camera={\"fvo\": 30}'");
    EXPECT_EQ(r.err, "shvol: error: " + path("s.json") + ": --set camera={\"fvo\": 30}" + fvo);
    // A misspelt key above the one set (helper 170: the scene was blamed).
    r = run(render + "--set calera.fov=30");
    EXPECT_EQ(r.err, "shvol: error: " + path("s.json") +
                         ": --set calera.fov=30: calera: unknown key (did you mean \"camera\"?)\n");
    std::string typo = scene(Homogeneous);
    typo.replace(typo.find("\"position\""), 0, "\"fvo\": 30, ");
    write("typo.json", typo);
    r = run("render " + path("typo.json") + " -o " + path("out.exr") +
            " --quiet --set camera.fvo=40");
    EXPECT_EQ(r.err, "shvol: error: " + path("typo.json") + fvo);
    // A key of the scene whose name holds a dot reads as a path inside what a --set sets: still
    // the scene's (it was blamed on --set camera.fov=30; helper 131).
    std::string dotted = scene(Homogeneous);
    dotted.replace(dotted.find("\"position\""), 0, "\"fov.x\": 1, ");
    write("dotted.json", dotted);
    r = run("render " + path("dotted.json") + " -o " + path("out.exr") +
            " --quiet --set camera.fov=30");
    EXPECT_EQ(
        r.err.rfind("shvol: error: " + path("dotted.json") + ": camera.fov.x: unknown key", 0), 0u)
        << r.err;
    // So is a value out of range (helper 133: --set camera.fov=500 was blamed on the scene, whose
    // fov is 30), but not the file's own, where a --set leaves it as it is.
    const std::string fov = ": camera.fov: value 500 out of range [0.001, 179]\n";
    r = run(render + "--set camera.fov=500");
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err, "shvol: error: " + path("s.json") + ": --set camera.fov=500" + fov);
    r = run(render + "--set media.0.phase.g=1");
    EXPECT_EQ(
        r.err.rfind(
            "shvol: error: " + path("s.json") + ": --set media.0.phase.g=1: media[0].phase.g: ", 0),
        0u)
        << r.err;
    // A key that the type a --set gives asks for is named at that --set (helper 137).
    r = run(render + "--set media.0.phase.type=tabulated");
    EXPECT_EQ(r.err.rfind("shvol: error: " + path("s.json") +
                              ": --set media.0.phase.type=tabulated: media[0].phase.file: ",
                          0),
              0u)
        << r.err;
    // A key the file has, given again by a --set after another --set changed its object's type,
    // or inside an object a --set gives, is the --set's (helper 139: both blamed the file's g).
    write("hg.json", scene(R"({"type": "homogeneous", "sigma_t": 2, "shape": {"type": "sphere"},
                              "phase": {"type": "hg", "g": 0.3}})"));
    const std::string hg = "render " + path("hg.json") + " -o " + path("out.exr") + " --quiet ";
    const std::string g = ": media[0].phase.g: unknown key\n";
    r = run(hg + "--set media.0.phase.type=rayleigh --set media.0.phase.g=0.5");
    EXPECT_EQ(r.err, "shvol: error: " + path("hg.json") + ": --set media.0.phase.g=0.5" + g);
    r = run(hg + "--set 'media.0.phase={\"type\": \"rayleigh\", \"g\": 0.5}'");
    EXPECT_EQ(r.err, "shvol: error: " + path("hg.json") +
                         ": --set media.0.phase={\"type\": \"rayleigh\", \"g\": 0.5}" + g);
    // Also where the value is the file's, and where the type alone was deleted, which leaves the
    // file's g to the default type (helper 140).
    r = run(hg + "--set media.0.phase.type=rayleigh --set media.0.phase.g=0.3");
    EXPECT_EQ(r.err, "shvol: error: " + path("hg.json") + ": --set media.0.phase.g=0.3" + g);
    r = run(hg + "--set 'media.0.phase={\"type\": \"rayleigh\", \"g\": 0.3}'");
    EXPECT_EQ(r.err, "shvol: error: " + path("hg.json") +
                         ": --set media.0.phase={\"type\": \"rayleigh\", \"g\": 0.3}" + g);
    r = run(hg + "--set media.0.phase.type=null");
    EXPECT_EQ(r.err, "shvol: error: " + path("hg.json") + ": --set media.0.phase.type=null" + g);
    std::string wide = scene(Homogeneous);
    wide.replace(wide.find("\"position\""), 0, "\"fov\": 500, ");
    write("wide.json", wide);
    for (const std::string set : {"camera.fov=500", "render.seed=3"}) {
        r = run("render " + path("wide.json") + " -o " + path("out.exr") + " --quiet --set " + set);
        EXPECT_EQ(r.err, "shvol: error: " + path("wide.json") + fov) << set;
    }
    write("sweep.json", R"({"scene": "s.json", "axes": {"camera.fov": [30, 500]}})");
    r = run("batch " + path("sweep.json") + " --dry-run");
    EXPECT_EQ(r.err, "shvol: error: " + path("sweep.json") + ": axes.camera.fov" +
                         fov.substr(0, fov.size() - 1) + " (in the run camera.fov=500 repeat=0)\n");
    write("sweep.json", R"({"scene": "s.json", "set": ["render.spp=2", "camera.fvo=30"],
                            "axes": {"spp": [2, 4]}})");
    const std::string batch = "batch " + path("sweep.json") + " --dry-run";
    r = run(batch);
    EXPECT_EQ(r.err, "shvol: error: " + path("sweep.json") + ": set[1]" + fvo);
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [2, 4], "camera.fvo": [30]}})");
    r = run(batch);
    EXPECT_EQ(r.err, "shvol: error: " + path("sweep.json") +
                         ": axes.camera.fvo: camera.fvo: unknown key (did you mean \"fov\"?) (in "
                         "the run spp=2 camera.fvo=30 repeat=0)\n");
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [2, 4]}, "metrics": ["rmse"],
                            "reference": {"spp": 32, "set": ["camera.fvo=30"]}})");
    r = run(batch);
    EXPECT_EQ(r.err, "shvol: error: " + path("sweep.json") +
                         ": reference.set[0]: camera.fvo: unknown key (did you mean \"fov\"?) (in "
                         "the reference)\n");
    EXPECT_FALSE(fs::exists(path("out.exr")));
}

// A --set whose value a later --set removes (a new type of its object starts it afresh, or the
// object is replaced or deleted) is said to be unused: it was dropped without a word (helper
// 139). One that a later --set of the same type keeps, or that comes after, is not.
TEST_F(Cli, AnOverrideALaterOneRemovesIsWarnedOf) {
    write("hg.json", scene(R"({"type": "homogeneous", "sigma_t": 2, "shape": {"type": "sphere"},
                              "phase": {"type": "hg", "g": 0.3}})"));
    const std::string render = "render " + path("hg.json") + " -o " + path("out.exr") + " --quiet ";
    const std::string g = "shvol: warning: " + path("hg.json") +
                          ": --set media.0.phase.g=0.5: not used: the later --set ";
    Result r = run(render + "--set media.0.phase.g=0.5 --set media.0.phase.type=rayleigh");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find(g + "media.0.phase.type=rayleigh starts its object afresh with a new "
                             "type; give it after that one\n"),
              std::string::npos)
        << r.err;
    auto stats = nlohmann::json::parse(std::ifstream(path("out.stats.json")));
    EXPECT_EQ(stats["warnings"].size(), 1u) << stats["warnings"];
    r = run(render + "--set media.0.phase.g=0.5 --set 'media[0].phase={\"type\": \"hg\"}'");
    EXPECT_NE(r.err.find(g + "media[0].phase={\"type\": \"hg\"} replaces or deletes its object"),
              std::string::npos)
        << r.err;
    r = run(render + "--set media.0.phase.g=0.5 --set media.0.phase=null");
    EXPECT_NE(r.err.find(g + "media.0.phase=null replaces or deletes its object"),
              std::string::npos)
        << r.err;
    // The one that removed it is named, not a later one of its object (helper 140).
    r = run(render + "--set media.0.phase.g=0.5 --set media.0.phase.type=rayleigh " +
            "--set media.0.phase.sampling=sh --set media[0].phase.type=rayleigh");
    EXPECT_NE(r.err.find(g + "media.0.phase.type=rayleigh starts"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("media[0].phase.type=rayleigh starts"), std::string::npos) << r.err;
    EXPECT_EQ(occurrences(r.err, "not used"), 1u) << r.err;
    for (const std::string sets :
         {"--set media.0.phase.g=0.5 --set media.0.phase.type=hg",
          "--set media.0.phase.type=rayleigh --set media.0.phase.type=hg --set media.0.phase.g=0.5",
          "--set camera.fov=20 --set camera.fov=30"}) {
        r = run(render + sets);
        ASSERT_EQ(r.code, 0) << sets << r.err;
        EXPECT_EQ(r.err.find("not used"), std::string::npos) << sets << r.err;
    }
    stats = nlohmann::json::parse(std::ifstream(path("out.stats.json")));
    EXPECT_EQ(stats["scene_resolved"]["camera"]["fov"], 30);
}

// An emitting mesh with coincident faces is refused, naming the scene, the surface and both
// faces' lines: a lamp of a quad and its reverse shone one way (helper 143). Without emission
// the same mesh renders (a ray meets either face, and they reflect alike).
TEST_F(Cli, AnEmittingMeshOfCoincidentFacesIsRefused) {
    write("panel.obj", "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\nf 4 3 2 1\n");
    const auto sceneWith = [](const std::string& emission) {
        return R"({"camera": {"resolution": [4, 4], "position": [0, 0, 3], "up": [0, 1, 0]},
                   "render": {"spp": 1}, "environment": {"type": "constant", "radiance": 1},
                   "surfaces": [{"type": "mesh", "file": "panel.obj")" +
               emission + "}]}";
    };
    write("lamp.json", sceneWith(R"(, "emission": 3)"));
    Result r = run("render " + path("lamp.json") + " -o " + path("a.exr"));
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err, "shvol: error: " + path("lamp.json") +
                         ": surfaces[0].file: " + path("panel.obj") +
                         ": line 6: the same corners as line 5: coincident faces of an emitting "
                         "mesh, of which a ray meets either while light samples count both; give "
                         "one (a lamp lit on both sides is one face with emission_two_sided)\n");
    EXPECT_FALSE(fs::exists(path("a.exr")));
    write("wall.json", sceneWith(""));
    r = run("render " + path("wall.json") + " -o " + path("a.exr") + " --quiet");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    // Two-sided emission on a surface that does not emit is said to be unused (helper 143).
    write("wall.json", sceneWith(R"(, "emission_two_sided": true)"));
    r = run("render " + path("wall.json") + " -o " + path("a.exr") + " --quiet");
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "shvol: warning: " + path("wall.json") +
                         ": surfaces[0]: emission_two_sided is not used: the surface does not "
                         "emit\n");
}

// A file of the wrong kind is named as such, in one line, before anything is written: a scene
// given to batch was told "scene: missing required string", a sweep given to render "axes:
// unknown key", a grid "malformed JSON: a NUL byte", a scene given to phase fit was read as a
// type name (helper 122).
TEST_F(Cli, InputsOfAnotherKindAreNamedAsSuch) {
    write("s.json", scene(Homogeneous));
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [1, 2]}})");
    write("r.json", R"({"render": {"spp": 1}})");
    write("nested.json", R"({"scene": "sweep.json", "axes": {"media[0].albedo": [0.5]}})");
    write("r.stats.json", R"({"scene": "s.json", "scene_resolved": {}, "spp": 2})");
    const std::string media = std::string(SHVOL_SOURCE_DIR) + "/media/";
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"batch " + path("s.json") + " --dry-run",
         path("s.json") + ": a scene (it has \"camera\"), not a sweep: render it with shvol "
                          "render, or name it in a sweep's \"scene\""},
        {"render " + path("sweep.json"),
         path("sweep.json") + ": a sweep of shvol batch (it has \"axes\"), not a scene: run it "
                              "with shvol batch"},
        // (--set gives the sweep a camera: "axes" still decides; helper 124)
        {"render " + path("sweep.json") + " --set camera.fov=30",
         path("sweep.json") + ": a sweep of shvol batch (it has \"axes\"), not a scene: run it "
                              "with shvol batch"},
        // (a stats file was called a sweep, for its "scene")
        {"render " + path("r.stats.json"),
         path("r.stats.json") +
             ": a render's statistics (it has \"scene_resolved\"), not a scene: the scene it "
             "rendered is its scene_resolved, which loads from a file of its own in the scene's "
             "folder"},
        // (also where an axis would index the sweep's arrays; helper 141)
        {"batch " + path("nested.json") + " --dry-run",
         path("sweep.json") + ": a sweep of shvol batch (it has \"axes\"), not a scene: run it "
                              "with shvol batch"},
        {"batch " + path("r.json"),
         path("r.json") + ": a scene (it has \"render\"), not a sweep: render it with shvol "
                          "render, or name it in a sweep's \"scene\""},
        {"render " + media + "cloud.vdb",
         media + "cloud.vdb: the file is an OpenVDB grid, not JSON: a scene or a sweep names "
                 "such files by their keys"},
        {"batch " + media + "sky.exr",
         media + "sky.exr: the file is an OpenEXR image, not JSON: a scene or a sweep names such "
                 "files by their keys"},
        {"render " + media + "blob.ply",
         media + "blob.ply: the file is a PLY mesh, not JSON: a scene or a sweep names such "
                 "files by their keys"},
        {"diff " + media + "sky.exr " + media + "cloud.vdb",
         media + "cloud.vdb: the file is an OpenVDB grid, not an OpenEXR image"},
        {"tonemap " + path("s.json") + " -o " + path("t.png"),
         path("s.json") + ": the file is JSON text, not an OpenEXR image"},
        {"phase fit " + path("s.json"),
         "phase spec \"" + path("s.json") +
             "\": a file, where a phase function is JSON or a short form such as hg:g=0.9 (a "
             "table file is named by tabulated:file=NAME.csv)"}};
    for (const auto& [args, message] : cases) {
        const Result r = run(args + (args.rfind("render", 0) == 0 ? " -o " + path("o.exr") : ""));
        EXPECT_EQ(r.code, 1) << args;
        EXPECT_EQ(r.err, "shvol: error: " + message + "\n") << args;
    }
    EXPECT_FALSE(fs::exists(path("o.exr")));
    // A file named like a type is no file of the wrong kind: the spec is the type.
    EXPECT_EQ(runCommand("cd " + path("") + " && touch rayleigh && " + SHVOL_BINARY +
                         " phase fit rayleigh")
                  .code,
              0);
}

// A batch belongs to one build: rows finished by another shvol build are refused (a changed
// default or a fix would mix two experiments in one ledger). A rendered reference belongs to a
// scene: once the scene file changes it is rendered again, not reused.
TEST_F(Cli, BatchRefusesAnotherBuildAndRenewsAStaleReference) {
    write("s.json", scene(Homogeneous));
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [4, 8]},
        "reference": {"spp": 64}, "metrics": ["rmse"]})");
    const std::string batch = "batch " + path("sweep.json") + " --output " + path("out");
    Result r = run(batch);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("rendering the reference"), std::string::npos) << r.err;
    const std::string jsonl = path("out/results.jsonl");
    std::string rows;
    {
        std::ifstream f(jsonl);
        for (std::string line; std::getline(f, line);) {
            auto j = nlohmann::json::parse(line);
            EXPECT_FALSE(j.value("git_revision", "").empty());
            j["git_revision"] = "0000000";
            rows += j.dump() + "\n";
        }
    }
    std::ofstream(jsonl) << rows;
    for (const std::string dry : {"", " --dry-run"}) {  // (a dry run said all was well)
        r = run(batch + dry);
        EXPECT_EQ(r.code, 1) << dry;
        EXPECT_NE(r.err.find(jsonl + ": run r0000: finished by shvol 0000000, this is "),
                  std::string::npos)
            << r.err;
    }
    fs::remove(jsonl);
    fs::remove(path("out/results.csv"));
    write("s.json", scene(R"({"type": "homogeneous", "sigma_t": 3, "albedo": 0.8,
                              "shape": {"type": "sphere"}})"));
    r = run(batch);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("rendering the reference"), std::string::npos) << r.err;
    // Every run finished: a reference deleted since is not rendered again for nothing.
    const std::string ledgerBefore = test::fileBytes(jsonl);
    fs::remove(path("out/reference.exr"));
    r = run(batch);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err.find("rendering the reference"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("2 of 2 runs already finished"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("out/reference.exr")));
    EXPECT_EQ(test::fileBytes(jsonl), ledgerBefore);
}

// A rendered reference is its image as rendered: another image put in its place is not used (the
// stamp beside it named only the scene, and one ledger mixed two references), and a number of the
// scene written otherwise (3 as 3.0) is the same reference (helper 67: refused as another).
TEST_F(Cli, BatchKnowsItsRenderedReferenceByItsImage) {
    write("s.json", scene(R"({"type": "homogeneous", "sigma_t": 3, "albedo": 0.8,
                              "shape": {"type": "sphere"}})"));
    const auto sweep = [&](const std::string& spps) {
        write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [)" + spps + R"(]},
            "reference": {"spp": 64}, "metrics": ["rmse"]})");
    };
    sweep("4");
    const std::string batch = "batch " + path("sweep.json") + " --output " + path("out");
    ASSERT_EQ(run(batch).code, 0);
    const std::string reference = test::fileBytes(path("out/reference.exr"));
    ASSERT_EQ(run("render " + path("s.json") + " --quiet --spp 2 -o " + path("other.exr")).code, 0);
    fs::copy_file(path("other.exr"), path("out/reference.exr"),
                  fs::copy_options::overwrite_existing);
    sweep("4, 8");
    Result r = run(batch);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("rendering the reference"), std::string::npos) << r.err;
    EXPECT_EQ(test::fileBytes(path("out/reference.exr")), reference);  // (the same render)
    // 3 written 3.0: the same scene, the same reference, the finished runs resumed.
    write("s.json", scene(R"({"type": "homogeneous", "sigma_t": 3.0, "albedo": 0.8,
                              "shape": {"type": "sphere"}})"));
    sweep("4, 8, 16");
    r = run(batch);
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err.find("rendering the reference"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("2 of 3 runs already finished"), std::string::npos) << r.err;
}

// A given reference that is one of the batch's own outputs (a run's image, its stats, the ledger)
// is refused before anything renders, by --dry-run too: it was written over by the run, and the
// ledger lost at the next start.
TEST_F(Cli, BatchRefusesAReferenceAmongItsOutputs) {
    write("s.json", scene(Homogeneous));
    fs::create_directories(path("out"));
    ASSERT_EQ(run("render " + path("s.json") + " --quiet -o " + path("out/r0001.exr")).code, 0);
    const std::string before = test::fileBytes(path("out/r0001.exr"));
    fs::copy_file(path("out/r0001.exr"), path("out/report.md"));
    fs::copy_file(path("out/r0001.exr"), path("out/report.html"));
    // (r0005 is no run of this sweep's, but a resumed batch gives its new runs free ids.)
    fs::copy_file(path("out/r0001.exr"), path("out/r0005.exr"));
    for (const std::string& reference :
         {"out/r0001.exr", "out/report.md", "out/report.html", "out/r0005.exr"}) {
        write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [1, 2]}, "metrics": ["rmse"],
                                "reference": {"file": ")" +
                                reference + R"("}, "output": "out"})");
        for (const std::string dry : {"", " --dry-run"}) {
            const Result r = run("batch " + path("sweep.json") + " --quiet" + dry);
            EXPECT_EQ(r.code, 1) << reference << dry;
            EXPECT_NE(r.err.find(": the reference would be written over by the batch's own " +
                                 fs::path(reference).filename().string()),
                      std::string::npos)
                << r.err;
        }
    }
    // The z-test reads the reference's standard errors (r0001.stderr.exr beside r0001.ref),
    // which run r0001 would write over; without the z-test they are not read.
    fs::copy_file(path("out/r0001.exr"), path("out/r0001.ref"));
    for (const std::string metric : {"ztest", "rmse"}) {
        write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [2, 4]}, "metrics": [")" +
                                metric + R"("], "reference": {"file": "out/r0001.ref"},
                                "output": "out"})");
        const Result r = run("batch " + path("sweep.json") + " --dry-run");
        EXPECT_EQ(r.code, metric == "ztest" ? 1 : 0) << r.err;
        EXPECT_EQ(r.err, metric == "ztest"
                             ? "shvol: error: " + path("out/r0001.ref") +
                                   ": its standard errors would be written over by the batch's "
                                   "own r0001.stderr.exr; keep it outside the output directory " +
                                   path("out") + "\n"
                             : "");
    }
    EXPECT_EQ(test::fileBytes(path("out/r0001.exr")), before);
    EXPECT_FALSE(fs::exists(path("out/results.jsonl")));
}

// A reference render interrupted after writing its partial image leaves no stamp behind: the old
// reference's stamp, left beside the partial image, made a later batch of the old spec take that
// image for its finished reference without a word.
TEST_F(Cli, BatchInterruptedReferenceIsRenderedAgain) {
    write("s.json", scene(Homogeneous));
    write("a.json", R"({"scene": "s.json", "axes": {"spp": [2]}, "reference": {"spp": 16},
                        "metrics": ["rmse"], "output": "out"})");
    write("b.json", R"({"scene": "s.json", "axes": {"spp": [2]}, "reference": {"spp": 16000000},
                        "metrics": ["rmse"], "output": "out"})");
    Result r = run("batch " + path("a.json") + " --quiet");
    ASSERT_EQ(r.code, 0) << r.err;
    ASSERT_TRUE(fs::exists(path("out/reference.exr.fingerprint")));
    fs::remove(path("out/results.jsonl"));
    fs::remove(path("out/results.csv"));
    r = runCommand("timeout --foreground --preserve-status -s TERM 4 " + std::string(SHVOL_BINARY) +
                   " batch " + path("b.json") + " --threads 1");
    // (--foreground: else timeout signals its process group as well, and a second SIGTERM ends
    // shvol at once, as a second Ctrl-C does, without the word below.)
    ASSERT_EQ(r.code, 128 + SIGTERM) << r.err;  // stopped inside the reference's render
    ASSERT_NE(r.err.find("shvol: interrupted: wrote the samples finished so far"),
              std::string::npos)
        << r.err;
    EXPECT_NE(r.err.find("rendering the reference"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(path("out/reference.exr.fingerprint")));
    r = run("batch " + path("a.json"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("rendering the reference"), std::string::npos) << r.err;
    EXPECT_EQ(nlohmann::json::parse(std::ifstream(path("out/reference.stats.json")))["spp"], 16);
}

// A reference render stopped by a signal is saved in a checkpoint beside it, which the batch run
// again resumes, to the image of a reference never stopped (a Ctrl-C lost all of it; helper
// 147). Finished, the checkpoint and its stamp are removed.
TEST_F(Cli, BatchResumesAnInterruptedReference) {
    write("s.json", scene(Homogeneous));
    write("a.json", R"({"scene": "s.json", "axes": {"spp": [2]}, "reference": {"spp": 250000},
                        "metrics": ["rmse"]})");
    Result r = runCommand(std::string(SHVOL_BINARY) + " batch " + path("a.json") +
                          " --threads 1 --output " + path("out") + " 2>" + path("bg.txt") +
                          killOnceCaught("TERM", SIGTERM, "0.5"));
    std::string err = test::fileBytes(path("bg.txt"));
    ASSERT_EQ(r.code, 128 + SIGTERM) << err;
    ASSERT_NE(err.find("shvol: interrupted: wrote the samples finished so far to " +
                       path("out/reference.exr") + " ("),
              std::string::npos)
        << err;
    EXPECT_EQ(err.find("--resume"), std::string::npos) << err;  // (the batch resumes it)
    ASSERT_TRUE(fs::exists(path("out/reference.exr.checkpoint")));
    EXPECT_FALSE(fs::exists(path("out/reference.exr.fingerprint")));
    r = run("batch " + path("a.json") + " --dry-run --output " + path("out"));
    EXPECT_NE(r.out.find("reference " + path("out/reference.exr") +
                         " (rendered first, from its checkpoint where that reads, then cached)\n"),
              std::string::npos)
        << r.out;
    r = run("batch " + path("a.json") + " --quiet --threads 2 --output " + path("out"));
    ASSERT_EQ(r.code, 0) << r.err;
    const auto stats = nlohmann::json::parse(std::ifstream(path("out/reference.stats.json")));
    EXPECT_LT(stats["paths"].get<uint64_t>(), 250000ull * stats["resolution"][0].get<uint64_t>() *
                                                  stats["resolution"][1].get<uint64_t>());
    for (const char* gone : {"out/reference.exr.checkpoint", "out/reference.exr.checkpoint.stamp"})
        EXPECT_FALSE(fs::exists(path(gone))) << gone;
    r = run("batch " + path("a.json") + " --quiet --threads 2 --output " + path("whole"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(test::fileBytes(path("out/reference.exr")),
              test::fileBytes(path("whole/reference.exr")));
    EXPECT_EQ(ledgerRows(path("out"))["r0000"]["rmse"], ledgerRows(path("whole"))["r0000"]["rmse"]);
    // A damaged checkpoint of this reference is warned of and the reference starts afresh (every
    // start failed on it; helper 151), and the temporaries a killed batch left among its outputs
    // go, others stay (helper 147).
    fs::remove_all(path("out"));
    r = runCommand(std::string(SHVOL_BINARY) + " batch " + path("a.json") +
                   " --threads 1 --output " + path("out") + " 2>" + path("bg.txt") +
                   killOnceCaught("TERM", SIGTERM, "0.5"));
    ASSERT_EQ(r.code, 128 + SIGTERM) << test::fileBytes(path("bg.txt"));
    {
        std::fstream ck(path("out/reference.exr.checkpoint"),
                        std::ios::in | std::ios::out | std::ios::binary);
        ck.seekp(200);
        ck.put('\x5a');
    }
    const pid_t child = ::fork();
    if (child == 0) ::_exit(0);
    ::waitpid(child, nullptr, 0);  // (its PID runs nothing now)
    const std::string dead = ".tmp" + std::to_string(child);
    for (const std::string name : {"r0000.exr", "reference.stats.json", "mine.exr"})
        std::ofstream(path("out/" + name + dead)) << "left by kill -9";
    r = run("batch " + path("a.json") + " --threads 2 --output " + path("out"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("reference.exr.checkpoint: checksum mismatch (corrupt file): the "
                         "checkpoint is not resumed; the render starts afresh"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(test::fileBytes(path("out/reference.exr")),
              test::fileBytes(path("whole/reference.exr")));
    EXPECT_FALSE(fs::exists(path("out/r0000.exr" + dead)));
    EXPECT_FALSE(fs::exists(path("out/reference.stats.json" + dead)));
    EXPECT_TRUE(fs::exists(path("out/mine.exr" + dead)));
}

// A batch's reference checkpoint that does not fit on the disk (here a file-size limit, `ulimit -f
// 80` in dash's 512-byte blocks, 40 KiB: the checkpoint is 112 kB, the image 4-9 kB) is warned of,
// and at a stop the warning says the samples are not kept, not that the render goes on (helper
// 156); the partial image is written.
TEST_F(Cli, BatchReferenceCheckpointThatDoesNotFitIsWarnedOf) {
    write("s.json", scene(Homogeneous));
    write("a.json", R"({"scene": "s.json", "axes": {"spp": [2]}, "reference": {"spp": 4000000},
                        "set": ["camera.resolution=[64,48]"], "metrics": ["rmse"]})");
    const Result r = runCommand("ulimit -f 80; " + std::string(SHVOL_BINARY) + " batch " +
                                path("a.json") + " --threads 1 --output " + path("out") + " 2>" +
                                path("bg.txt") + killOnceCaught("TERM", SIGTERM, "0.5"));
    const std::string err = test::fileBytes(path("bg.txt"));
    ASSERT_EQ(r.code, 128 + SIGTERM) << err;
    EXPECT_NE(err.find("reference.exr.checkpoint: cannot write file (File too large): the samples "
                       "so far are not kept; the next start begins afresh"),
              std::string::npos)
        << err;
    EXPECT_EQ(err.find("the render goes on"), std::string::npos) << err;
    EXPECT_TRUE(fs::exists(path("out/reference.exr")));
    EXPECT_FALSE(fs::exists(path("out/reference.exr.checkpoint")));
    // Where an earlier save is in place, the next start resumes from it, and the warning says so
    // (helper 158).
    const std::string batch = std::string(SHVOL_BINARY) + " batch " + path("a.json") +
                              " --threads 1 --output " + path("out") + " 2>" + path("bg.txt");
    ASSERT_EQ(runCommand(batch + killOnceCaught("TERM", SIGTERM, "0.5")).code, 128 + SIGTERM);
    ASSERT_TRUE(fs::exists(path("out/reference.exr.checkpoint")));
    ASSERT_EQ(runCommand("ulimit -f 80; " + batch + killOnceCaught("TERM", SIGTERM, "0.5")).code,
              128 + SIGTERM);
    const std::string again = test::fileBytes(path("bg.txt"));
    EXPECT_NE(again.find("reference.exr.checkpoint: cannot write file (File too large): the "
                         "samples since the checkpoint's last save are not kept; the next start "
                         "resumes from that save"),
              std::string::npos)
        << again;
}

// An error in a run's scene names the scene and the key, and the run of the sweep that set it.
TEST_F(Cli, BatchErrorsNameTheRun) {
    write("s.json", scene(Homogeneous));
    write("sweep.json", R"({"scene": "s.json", "axes": {"media[0].nosuch": [1]}})");
    const Result r = run("batch " + path("sweep.json") + " --quiet --output " + path("out"));
    EXPECT_EQ(r.code, 1);
    // (at the axis that brought the key in, since 7 Dec: the scene file was named)
    EXPECT_NE(r.err.find(path("sweep.json") +
                         ": axes.media[0].nosuch: media[0].nosuch: unknown key (in the run "
                         "media[0].nosuch=1 repeat=0)"),
              std::string::npos)
        << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

// Memory that runs out (here a 16384² film under a 3 GB address-space limit) is one line saying
// so, exit 1 and no output, not an "internal error: std::bad_alloc".
TEST_F(Cli, OutOfMemoryIsOneLine) {
    write("s.json", scene(Homogeneous));
    const Result r = runCommand("ulimit -v 3000000 && " + std::string(SHVOL_BINARY) + " render " +
                                path("s.json") + " --quiet -o " + path("big.exr") +
                                " --set camera.resolution=[16384,16384] --spp 1");
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err.rfind("shvol: error: out of memory;", 0), 0u) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_FALSE(fs::exists(path("big.exr")));
}

// The output directory must be one or become one: a regular file there, or above it, is refused
// with one line before anything renders, by --dry-run too.
TEST_F(Cli, BatchOutputMustBeADirectory) {
    write("s.json", scene(Homogeneous));
    write("sweep.json", R"({"scene": "s.json", "axes": {"render.spp": [1]}})");
    write("afile", "");
    for (const std::string dry : {"", " --dry-run"})
        for (const auto& [out, message] : std::vector<std::pair<std::string, std::string>>{
                 {path("afile"), path("afile") + ": it is not a directory"},
                 {path("afile/x/y"),
                  path("afile/x/y") + ": " + path("afile") + " is not a directory"}}) {
            // Named where it was given: the option in its form (helper 116), the sweep's key.
            Result r = run("batch " + path("sweep.json") + " --quiet --output " + out + dry);
            EXPECT_EQ(r.code, 1) << out << dry;
            EXPECT_EQ(r.err, "shvol: error: --output: " + message +
                                 " (batch writes a directory of runs there) (see --help)\n")
                << dry;
            write("keyed.json",
                  R"({"scene": "s.json", "axes": {"render.spp": [1]}, "output": ")" + out + "\"}");
            r = run("batch " + path("keyed.json") + " --quiet" + dry);
            EXPECT_EQ(r.code, 1) << out << dry;
            EXPECT_EQ(r.err, "shvol: error: " + path("keyed.json") + ": output: " + message +
                                 " (batch writes a directory of runs there)\n")
                << dry;
        }
    EXPECT_EQ(test::fileBytes(path("afile")), "");
    // The default, <sweep name>_results, is said to be the default: the sweep has no key
    // `output` to name (helper 120).
    write("d_results", "");
    write("d.json", R"({"scene": "s.json", "axes": {"render.spp": [1]}})");
    Result d = run("batch " + path("d.json") + " --quiet --dry-run");
    EXPECT_EQ(d.code, 1);
    EXPECT_EQ(d.err, "shvol: error: " + path("d.json") + ": the default output directory " +
                         path("d_results") +
                         ": it is not a directory (batch writes a directory of runs there)\n");
    // An empty name is refused where it is given (it named no file; --output "" was ignored).
    Result r = run("batch " + path("sweep.json") + " --quiet --dry-run --output ''");
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err, "shvol: error: --output: an empty name (see --help)\n");
    write("empty.json", R"({"scene": "s.json", "output": ""})");
    r = run("batch " + path("empty.json") + " --quiet --dry-run");
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err, "shvol: error: " + path("empty.json") +
                         ": output: expected a directory name, got an empty string\n");
    write("nul.json", R"({"scene": "s.json", "output": "runs\u0000x"})");
    r = run("batch " + path("nul.json") + " --quiet --dry-run");
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err, "shvol: error: " + path("nul.json") +
                         ": output: the directory name contains a NUL character (\\u0000)\n");
    r = run("batch " + path("sweep.json") + " --quiet --output " + path("new/runs"));
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_TRUE(fs::is_directory(path("new/runs")));
}

// The files a batch writes into its directory are checked before anything renders, by --dry-run
// too: the ledger, the reference, the runs' outputs and the report. A directory named
// results.csv was found after the reference and the first run had rendered (their files left
// without a ledger row); one named report.md after every run.
TEST_F(Cli, BatchChecksTheFilesItWritesBeforeItRenders) {
    write("s.json", scene(Homogeneous));
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [2, 4], "media.0.albedo": [0.5]},
                           "reference": {"spp": 64}, "metrics": ["rmse", "ztest"],
                           "output": "out"})");
    for (const char* name :
         {"results.jsonl", "results.csv", "reference.exr", "reference.stats.json",
          "reference.stderr.exr", "r0001.exr", "r0000.stats.json", "r0001.stderr.exr", "report.md",
          "time_vs_media_0_albedo.png"}) {
        fs::remove_all(path("out"));
        fs::create_directories(path("out/") + name);
        for (const std::string dry : {"", " --dry-run"}) {
            const Result r = run("batch " + path("sweep.json") + " --quiet --report" + dry);
            EXPECT_EQ(r.code, 1) << name << dry;
            // (After the warning of z-tests at 2 and 4 spp, once the ledger is open.)
            std::string err = r.err;
            if (const std::string z = unreliableZTestWarning(path("sweep.json"), 2, 2, "r0000");
                err.rfind(z, 0) == 0)
                err = err.substr(z.size());
            EXPECT_EQ(
                err.rfind("shvol: error: " + path("out/") + name + ": cannot write: is a directory",
                          0),
                0u)
                << name << dry << ": " << r.err;
            // Nothing rendered, nothing written but the directory that was there.
            EXPECT_EQ(std::distance(fs::directory_iterator(path("out")), {}), 1) << name << dry;
        }
    }
    // Only the files the report writes: no time plot of a seed axis (a ledger column beside
    // the axes), no error plots without an error metric.
    write("seeds.json", R"({"scene": "s.json", "axes": {"seed": [1, 2]}, "output": "seeds"})");
    for (const char* name : {"time_vs_seed.png", "error_vs_time.png"}) {
        fs::remove_all(path("seeds"));
        fs::create_directories(path("seeds/") + name);
        const Result r = run("batch " + path("seeds.json") + " --quiet --report --dry-run");
        EXPECT_EQ(r.code, 0) << name << ": " << r.err;
    }
}

// Every command that writes takes -o and --output (batch took --output only, phase sample --out
// only).
TEST_F(Cli, OutputOptionsAreSpelledAlike) {
    for (const char* option : {"-o", "--output", "--out"}) {
        const std::string csv = path(std::string("p") + option + ".csv");
        const Result r = run(std::string("phase sample hg:g=0.5 --count 10 ") + option + " " + csv);
        EXPECT_EQ(r.code, 0) << option << ": " << r.err;
        EXPECT_TRUE(fs::exists(csv)) << option;
    }
    write("s.json", scene(Homogeneous));
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [1]}})");
    const Result r = run("batch " + path("sweep.json") + " --dry-run -o " + path("runs"));
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.out.find("1 run into " + path("runs")), std::string::npos) << r.out;
}

// A second batch into a directory another batch is writing into (held here by the test's own
// flock, as a running batch holds it) is refused before it renders its reference or a run: the
// two appended the same runs to one ledger, which report then counted twice.
TEST_F(Cli, BatchRefusesADirectoryAnotherBatchWrites) {
    write("s.json", scene(Homogeneous));
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [1]}, "reference": {"spp": 16},
                           "metrics": ["rmse"], "output": "out"})");
    fs::create_directories(path("out"));
    const int held = ::open(path("out").c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    ASSERT_GE(held, 0);
    ASSERT_EQ(::flock(held, LOCK_EX | LOCK_NB), 0);
    Result r = run("batch " + path("sweep.json") + " --quiet");
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err, "shvol: error: " + path("out") +
                         ": another shvol batch is writing into this directory; wait for it to "
                         "end or use another output directory\n");
    EXPECT_TRUE(fs::is_empty(path("out")));
    ::close(held);
    r = run("batch " + path("sweep.json") + " --quiet");
    EXPECT_EQ(r.code, 0) << r.err;
}

// Every run's scene, and a rendered reference's, is checked before the first render, and by
// --dry-run: a bad value in the last run of an axis stops the batch before anything is written.
TEST_F(Cli, BatchChecksEveryRunsSceneFirst) {
    write("s.json", scene(Homogeneous));
    write("sweep.json", R"({"scene": "s.json", "axes": {"media[0].albedo": [0.5, 2]}})");
    const std::string expected =
        path("sweep.json") +
        ": axes.media[0].albedo: media[0].albedo: value 2 out of range [0, 1] (in the run "
        "media[0].albedo=2 repeat=0)";
    for (const std::string flags : {" --dry-run", ""}) {
        const Result r =
            run("batch " + path("sweep.json") + flags + " --quiet --output " + path("out"));
        EXPECT_EQ(r.code, 1) << flags;
        EXPECT_NE(r.err.find(expected), std::string::npos) << flags << ": " << r.err;
        EXPECT_EQ(r.out, "") << flags;
        EXPECT_FALSE(fs::exists(path("out/r0000.exr"))) << flags;
    }
    // Repeats differ only in their seeds, and are checked once: the first bad run is named.
    write("sweep.json",
          R"({"scene": "s.json", "axes": {"media[0].albedo": [0.5, 2]}, "repeats": 2})");
    Result r = run("batch " + path("sweep.json") + " --dry-run");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("(in the run media[0].albedo=2 repeat=0)"), std::string::npos) << r.err;
    // A grid or a sky named by a run must exist, though neither is read before its render.
    write("sweep.json", R"({"scene": "s.json", "set": ["media[0].type=\"vdb\""],
        "axes": {"media[0].file": ["nosuch.vdb"]}})");
    r = run("batch " + path("sweep.json") + " --dry-run");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("media[0].file: no such file"), std::string::npos) << r.err;
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [4]},
        "reference": {"spp": 64, "set": ["render.max_depth=-1"]}})");
    r = run("batch " + path("sweep.json") + " --dry-run");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("render.max_depth"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("(in the reference)"), std::string::npos) << r.err;
    // A reference of another size than a run's image (the scene's camera is 8x6), a file or
    // rendered: said before anything renders, with the sweep's key.
    writeExr(path("ref.exr"), Image(16, 16));
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [4]},
        "reference": {"file": "ref.exr"}})");
    for (const std::string flags : {" --dry-run", ""}) {
        r = run("batch " + path("sweep.json") + flags + " --quiet --output " + path("out"));
        EXPECT_EQ(r.code, 1) << flags;
        EXPECT_NE(r.err.find(path("sweep.json") + ": reference: " + path("ref.exr") +
                             " is 16x16, the run's image 8x6 (in the run spp=4 repeat=0)"),
                  std::string::npos)
            << flags << ": " << r.err;
        EXPECT_FALSE(fs::exists(path("out/r0000.exr"))) << flags;
    }
    // The standard errors beside a reference file, which the z-test reads, likewise (they were
    // found once the first run had rendered, in a message naming no file).
    writeExr(path("ref.exr"), Image(8, 6));
    writeExr(path("ref.stderr.exr"), Image(16, 16));
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [4]},
        "reference": {"file": "ref.exr"}, "metrics": ["ztest"]})");
    for (const std::string flags : {" --dry-run", ""}) {
        r = run("batch " + path("sweep.json") + flags + " --quiet --output " + path("out"));
        EXPECT_EQ(r.code, 1) << flags;
        EXPECT_EQ(r.err, "shvol: error: " + path("ref.stderr.exr") +
                             ": the reference's standard errors are 16x16, the reference " +
                             path("ref.exr") + " is 8x6\n")
            << flags;
        EXPECT_FALSE(fs::exists(path("out/r0000.exr"))) << flags;
    }
    // Without them the z-test takes the reference as exact, which is said (helper 77: a 64-spp
    // reference failed every run's z-test, and nothing said why).
    fs::remove(path("ref.stderr.exr"));
    r = run("batch " + path("sweep.json") + " --dry-run --output " + path("out"));
    EXPECT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("shvol: warning: " + path("sweep.json") +
                         ": reference.file: " + path("ref.exr") +
                         " has no standard errors beside it (" + path("ref.stderr.exr") +
                         ", as render --variance writes them): the " + "z-test takes it as exact"),
              std::string::npos)
        << r.err;
    write("sweep.json", R"({"scene": "s.json", "axes": {"camera.resolution": [[8, 6], [4, 4]]},
        "reference": {"spp": 64}})");
    r = run("batch " + path("sweep.json") + " --dry-run");
    EXPECT_EQ(r.code, 1);
    EXPECT_NE(r.err.find("the rendered reference is 8x6, the run's image 4x4 (in the run "
                         "camera.resolution=[4,4] repeat=0)"),
              std::string::npos)
        << r.err;
}

// Rows measured against one reference are not continued against another: a rendered reference
// whose settings changed, or a reference file whose contents changed, is refused by name (the
// runs themselves, and so their fingerprints, are unchanged).
TEST_F(Cli, BatchRefusesRowsOfAnotherReference) {
    write("s.json", scene(Homogeneous));
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [4, 8]},
        "reference": {"spp": 64}, "metrics": ["rmse"]})");
    const std::string batch = "batch " + path("sweep.json") + " --quiet --output ";
    ASSERT_EQ(run(batch + path("out")).code, 0);
    for (const auto& [id, row] : ledgerRows(path("out")))
        EXPECT_FALSE(row.value("reference_fingerprint", "").empty()) << id;
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [4, 8, 16]},
        "reference": {"spp": 128}, "metrics": ["rmse"]})");
    for (const std::string flags : {" --dry-run", ""}) {  // the dry run refuses what the start does
        const Result r = run(batch + path("out") + flags);
        EXPECT_EQ(r.code, 1) << flags;
        EXPECT_NE(r.err.find(path("out/results.jsonl") +
                             ": run r0000: measured against another reference"),
                  std::string::npos)
            << flags << r.err;
    }
    EXPECT_EQ(ledgerRows(path("out")).size(), 2u);  // nothing was added
    EXPECT_FALSE(fs::exists(path("out/r0002.exr")));

    // A reference file: the same contents continue, other contents are refused.
    ASSERT_EQ(run("render " + path("s.json") + " --spp 32 --quiet -o " + path("ref.exr")).code, 0);
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [4, 8]},
        "reference": {"file": "ref.exr"}, "metrics": ["rmse"]})");
    ASSERT_EQ(run(batch + path("file")).code, 0);
    ASSERT_EQ(run(batch + path("file")).code, 0) << "the same reference continues";
    ASSERT_EQ(run(batch + path("file") + " --dry-run").code, 0);
    ASSERT_EQ(run("render " + path("s.json") + " --spp 33 --quiet -o " + path("ref.exr")).code, 0);
    for (const std::string flags : {" --dry-run", ""}) {
        const Result r = run(batch + path("file") + flags);
        EXPECT_EQ(r.code, 1) << flags;
        EXPECT_NE(r.err.find(": run r0000: measured against another reference"), std::string::npos)
            << flags << r.err;
    }
}

#ifdef SHVOL_MPIEXEC
// mpirun -np 2 shvol render: the ranks share the pixels, and the image, the intermediate --spp
// image and the standard errors equal a single process's bit for bit; the stats count every
// rank's paths. What a shared render cannot do is refused in one line.
TEST_F(Cli, MpiRenderEqualsOneProcess) {
    write("s.json", scene(Homogeneous));
    const std::string args = path("s.json") + " --spp 4,16 --seed 7 --variance --quiet -o ";
    Result r = run("render " + args + path("one.exr"));
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string mpi = std::string(SHVOL_MPIEXEC) + " " + SHVOL_BINARY + " ";
    r = runCommand(mpi + "render " + args + path("two.exr"));
    ASSERT_EQ(r.code, 0) << r.err;
    for (const char* f : {".exr", ".spp4.exr", ".stderr.exr"})
        EXPECT_EQ(readExr(path(std::string("one") + f)).rgb,
                  readExr(path(std::string("two") + f)).rgb)
            << f;
    auto stats = [&](const std::string& f) {
        return nlohmann::json::parse(std::ifstream(path(f)));
    };
    const auto one = stats("one.stats.json"), two = stats("two.stats.json");
    EXPECT_EQ(two["mpi_ranks"], 2);
    EXPECT_EQ(one["mpi_ranks"], 1);
    EXPECT_EQ(two["paths"], one["paths"]);
    EXPECT_EQ(two["density_lookups"], one["density_lookups"]);
    EXPECT_EQ(two["image"], one["image"]);
    // The warnings drawn from the counters too: max_depth's, judged against the image mean's
    // standard error (the ranks' luminance sums were added as integers, which silenced it;
    // helper 87).
    write("thin.json", thinFurnace());
    for (const std::string& launch : {std::string(SHVOL_BINARY) + " ", mpi})
        ASSERT_EQ(runCommand(launch + "render " + path("thin.json") + " --quiet -o " +
                             path(launch == mpi ? "thin2.exr" : "thin1.exr"))
                      .code,
                  0);
    const auto thin1 = stats("thin1.stats.json"), thin2 = stats("thin2.stats.json");
    ASSERT_EQ(thin1["warnings"].size(), 1u) << thin1["warnings"];
    EXPECT_EQ(thin2["warnings"], thin1["warnings"]);
    r = runCommand(mpi + "render " + args + path("x.exr") + " --time-limit 5");
    EXPECT_EQ(r.code, 1);
    const std::string line =
        "shvol: error: --time-limit: not available in a render over several MPI ranks";
    EXPECT_NE(r.err.find(line), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find(line), r.err.rfind(line)) << "rank 0 alone reports it: " << r.err;
    EXPECT_FALSE(fs::exists(path("x.exr")));
}

// An image of --spp N1,… that rank 0 cannot write (its directory removed once the first is
// written) ends every rank with the error: the others rendered on and waited for rank 0 at the
// next reduction for ever (helper 71: killed after 60 s of a 4 s render).
TEST_F(Cli, MpiRenderEndsEveryRankWhenAnImageCannotBeWritten) {
    const std::string mpi = std::string(SHVOL_MPIEXEC) + " " + SHVOL_BINARY + " ";
    fs::create_directories(path("od"));
    const Result r = runCommand(
        "timeout 120 " + mpi + "render " + SHVOL_SOURCE_DIR + "/media/default.json" +
        " --set camera.resolution=[64,64] --set media.0.density_scale=3000"
        " --set media.0.albedo=0.999 --set render.max_depth=100000 --spp 2,4,8,16,32,64 -o " +
        path("od/x.exr") + " 2>" + path("err.txt") +
        " & p=$!; for i in $(seq 3000); do grep -q 'x.spp2.exr' " + path("err.txt") +
        " && break; sleep 0.01; done; rm -rf " + path("od") + "; wait $p");
    const std::string err = test::fileBytes(path("err.txt"));
    EXPECT_EQ(r.code, 1) << err;  // (124: the timeout)
    EXPECT_NE(err.find("shvol: error: " + path("od/x.spp")), std::string::npos) << err;
}

// An error rank 0 alone meets after the set-up ends every rank: a batch's reference that rank 0
// cannot write (a file-size limit on every rank, of which rank 0 alone writes) left the other rank
// waiting for it for ever, as did rank 0 alone running out of memory in a render (helper 104).
TEST_F(Cli, MpiBatchEndsEveryRankWhenTheReferenceCannotBeWritten) {
    write("s.json", scene(Homogeneous));
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [2]}, "reference": {"spp": 8},
                            "metrics": ["rmse"]})");
    // (OpenMPI's shared memory through SysV: its default maps a file, which the limit refuses)
    const Result r =
        runCommand("timeout 120 " + std::string(SHVOL_MPIEXEC) +
                   " --mca shmem sysv sh -c 'ulimit -f 2; exec " + SHVOL_BINARY + " batch " +
                   path("sweep.json") + " --threads 1 --quiet -o " + path("o") + "'");
    EXPECT_EQ(r.code, 1) << r.err;  // (124: the timeout)
    EXPECT_NE(r.err.find("shvol: error: " + path("o/reference.stats.json") +
                         ": cannot write file (File too large)"),
              std::string::npos)
        << r.err;
    // A run that fails ends the batch with its one line and no abort: every other rank has been
    // told to stop by then, and none waits for rank 0 (review: an abort's banner followed it).
    write("runs.json", R"({"scene": "s.json", "axes": {"spp": [2, 3]}})");
    const Result run =
        runCommand("timeout 120 " + std::string(SHVOL_MPIEXEC) +
                   " --mca shmem sysv sh -c 'ulimit -f 2; exec " + SHVOL_BINARY + " batch " +
                   path("runs.json") + " --threads 1 --quiet -o " + path("o2") + "'");
    EXPECT_EQ(run.code, 1) << run.err;
    EXPECT_NE(run.err.find(".stats.json: cannot write file (File too large) (in run r000"),
              std::string::npos)
        << run.err;
    EXPECT_EQ(run.err.find("MPI_ABORT"), std::string::npos) << run.err;
}

// A rank that mpirun bound to fewer cores than its share renders on the cores it is bound to, and
// says so (helper 165: a batch under mpirun -np 1, bound to one core by OpenMPI's default, ran
// two threads on it; a render ran one without a word).
TEST_F(Cli, MpiWarnsOfARankBoundToFewerCores) {
    const unsigned cores = std::thread::hardware_concurrency();
    if (cores < 2) GTEST_SKIP() << "one core: a rank bound to it has its share";
    std::string mpi = SHVOL_MPIEXEC;
    mpi.replace(mpi.rfind(" 2"), 2, " 1 --bind-to core");
    write("s.json", scene(Homogeneous));
    const std::string said = "shvol: warning: this rank may run on 1 of the machine's " +
                             std::to_string(cores) +
                             " cores (its CPU affinity; 1 rank on the machine): it renders on 1 "
                             "thread unless --threads says otherwise; where mpirun bound it "
                             "(OpenMPI binds each rank to one core where it starts at most two), "
                             "`mpirun --bind-to none` gives each rank its share, " +
                             std::to_string(cores) + " cores\n";
    Result r = runCommand(mpi + " " + SHVOL_BINARY + " render " + path("s.json") + " --quiet -o " +
                          path("a.exr"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, said);
    EXPECT_EQ(nlohmann::json::parse(std::ifstream(path("a.stats.json")))["threads"], 1);
    r = runCommand(mpi + " " + SHVOL_BINARY + " render " + path("s.json") +
                   " --quiet --threads 2 -o " + path("b.exr"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    EXPECT_EQ(nlohmann::json::parse(std::ifstream(path("b.stats.json")))["threads"], 2);
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [2]}})");
    // (Not by a dry run, which renders nothing.)
    r = runCommand(mpi + " " + SHVOL_BINARY + " batch " + path("sweep.json") + " --dry-run -o " +
                   path("out"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, "");
    r = runCommand(mpi + " " + SHVOL_BINARY + " batch " + path("sweep.json") + " --quiet -o " +
                   path("out"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.err, said);
    EXPECT_EQ(nlohmann::json::parse(std::ifstream(path("out/r0000.stats.json")))["threads"], 1);
}

// A warning every run gives is said once by an MPI batch, as by one process: the other ranks send
// their runs' warnings to rank 0 with the rows (each rank said it once; helper 165).
TEST_F(Cli, MpiBatchSaysAWarningOnce) {
    write("s.json", R"({"camera": {"resolution": [8, 6], "position": [0, -3, 0]},
        "render": {"product_order": 8}, "environment": {"type": "constant", "radiance": 1},
        "media": [)" + Homogeneous +
                        "]}");
    write("sweep.json", R"({"scene": "s.json", "axes": {"seed": [1, 2, 3, 4, 5, 6]},
        "set": ["render.spp=64"]})");
    const std::string said = "render.product_order: 8 is not used";
    const auto count = [&](const std::string& err) {
        size_t n = 0;
        for (size_t at = err.find(said); at != std::string::npos; at = err.find(said, at + 1)) ++n;
        return n;
    };
    Result r = run("batch " + path("sweep.json") + " --quiet --output " + path("one"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(count(r.err), 1u) << r.err;
    r = runCommand(std::string(SHVOL_MPIEXEC) + " " + SHVOL_BINARY + " batch " +
                   path("sweep.json") + " --quiet --output " + path("two"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(count(r.err), 1u) << r.err;
    EXPECT_EQ(ledgerRows(path("two")).size(), 6u);
}

// mpirun -np 2 shvol batch: the runs are shared out dynamically, rank 0 keeps the ledger, the
// reference is rendered by both ranks; the rows equal a single process's, also after the batch
// was stopped in the middle and started again. A run that fails on either rank ends the batch
// with its one-line error.
TEST_F(Cli, MpiBatchEqualsOneProcess) {
    write("s.json", scene(Homogeneous));
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [64, 128, 256],
        "media[0].albedo": [0.5, 0.8]}, "repeats": 2, "reference": {"spp": 2048},
        "metrics": ["rmse", "ztest"]})");
    const std::string mpi = std::string(SHVOL_MPIEXEC) + " " + SHVOL_BINARY + " ";
    Result r = run("batch " + path("sweep.json") + " --quiet --output " + path("one"));
    ASSERT_EQ(r.code, 0) << r.err;
    r = runCommand(mpi + "batch " + path("sweep.json") + " --quiet --output " + path("two"));
    ASSERT_EQ(r.code, 0) << r.err;
    expectSameRows(path("one"), path("two"), 12);
    EXPECT_EQ(readExr(path("one/reference.exr")).rgb, readExr(path("two/reference.exr")).rgb);
    r = runCommand(mpi + "batch " + path("sweep.json") + " --output " + path("two"));
    EXPECT_EQ(r.code, 0);
    EXPECT_NE(r.err.find("12 of 12 runs already finished"), std::string::npos) << r.err;
    // A value added in the middle of an axis: rank 0 gives the new runs their ids (the finished
    // ones keep theirs), the other rank renders under them.
    write("sweep.json", R"({"scene": "s.json", "axes": {"spp": [64, 96, 128, 256],
        "media[0].albedo": [0.5, 0.8]}, "repeats": 2, "reference": {"spp": 2048},
        "metrics": ["rmse", "ztest"]})");
    r = runCommand(mpi + "batch " + path("sweep.json") + " --output " + path("two"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_NE(r.err.find("12 of 16 runs already finished"), std::string::npos) << r.err;
    ASSERT_EQ(run("batch " + path("sweep.json") + " --quiet --output " + path("one")).code, 0);
    const std::vector<std::string> point = {"spp", "media[0].albedo", "repeat"};
    expectSamePoints(path("one"), path("two"), point, 16);
    const auto onePoints = rowsByPoint(path("one"), point);
    for (const auto& [p, row] : rowsByPoint(path("two"), point))  // the images, under their ids
        EXPECT_EQ(readExr(path("two/" + row["image"].get<std::string>())).rgb,
                  readExr(path("one/" + onePoints.at(p)["image"].get<std::string>())).rgb)
            << p;
    // Killed (SIGKILL to mpirun and both ranks, found by their command lines in /proc) once the
    // first row is in, and started again: the rows of one process.
    write("slow.json", R"({"scene": "s.json", "axes": {"spp": [6000, 9000, 12000]},
        "repeats": 3, "reference": {"spp": 20000}, "metrics": ["rmse"]})");
    ASSERT_EQ(run("batch " + path("slow.json") + " --quiet --output " + path("slow1")).code, 0);
    const std::string slow2 = path("slow2");
    r = runCommand(mpi + "batch " + path("slow.json") + " --quiet --output " + slow2 +
                   " & p=$!; i=0; while [ ! -s " + slow2 + "/results.jsonl ] && [ $i -lt 1000 ]; " +
                   "do sleep 0.02; i=$((i+1)); done; " + "for f in $(grep -la -e '" + slow2 +
                   "' /proc/[0-9]*/cmdline); do " +
                   "q=${f#/proc/}; q=${q%/cmdline}; [ $q != $$ ] && kill -9 $q 2>/dev/null; " +
                   "done; wait $p");
    EXPECT_NE(r.code, 0);
    EXPECT_LT(ledgerRows(path("slow2")).size(), 9u) << "some runs are left to do";
    r = runCommand(mpi + "batch " + path("slow.json") + " --quiet --output " + path("slow2"));
    ASSERT_EQ(r.code, 0) << r.err;
    expectSameRows(path("slow1"), path("slow2"), 9);
    write("bad.json", R"({"scene": "s.json", "axes": {"media[0].albedo": [0.5, 0.6, 3, 0.7]}})");
    r = runCommand(mpi + "batch " + path("bad.json") + " --quiet --output " + path("bad"));
    EXPECT_EQ(r.code, 1);
    const std::string line =
        "shvol: error: " + path("bad.json") + ": axes.media[0].albedo: media[0].albedo: value 3";
    EXPECT_NE(r.err.find(line), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find(line), r.err.rfind(line)) << r.err;
}
#endif

// batch --report: the report has the plots and one table row per (configuration, spp).
// The report's configurations: one value however written (38 and 38.0: the batch takes them as
// one, the report split them), a | in a value kept inside its cell of report.md, and a
// configuration biased in every repeat marked, since 1/(MSE·time) favours it (helper 86).
TEST_F(Cli, ReportGroupsValuesAsTheBatchDoesAndMarksBias) {
    fs::create_directories(path("o"));
    std::ofstream(path("o/results.jsonl"))
        << R"({"run": "r0000", "spp": 8, "wall_time_s": 1, "rmse": 0.1, "bias": 0.5, "bias_ci95": 0.1, "x": 38})"
        << "\n"
        << R"({"run": "r0001", "spp": 8, "wall_time_s": 1, "rmse": 0.1, "bias": 0.5, "bias_ci95": 0.1, "x": 38.0})"
        << "\n"
        << R"({"run": "r0002", "spp": 8, "wall_time_s": 1, "rmse": 0.2, "bias": 0.01, "bias_ci95": 0.1, "x": "a|b"})"
        << "\n"
        // outside on both sides, and an interval unknown: no mark (helper 88; null crashed)
        << R"({"run": "r0003", "spp": 8, "wall_time_s": 1, "rmse": 0.1, "bias": 0.5, "bias_ci95": 0.1, "x": 1})"
        << "\n"
        << R"({"run": "r0004", "spp": 8, "wall_time_s": 1, "rmse": 0.1, "bias": -0.5, "bias_ci95": 0.1, "x": 1})"
        << "\n"
        << R"({"run": "r0005", "spp": 8, "wall_time_s": 1, "rmse": 0.1, "bias": 0.5, "bias_ci95": null, "x": 2})"
        << "\n"
        << R"({"run": "r0006", "spp": 8, "wall_time_s": 1, "rmse": 0.1, "bias": 0.5, "bias_ci95": 0.1, "x": 2})"
        << "\n";
    Result r = run("report " + path("o"));
    ASSERT_EQ(r.code, 0) << r.err;
    // What it wrote is named on stderr, as every command does (it printed report.md's path
    // alone on stdout, also under batch --quiet; helper 139), and not with --quiet.
    size_t plots = 0;
    for (const auto& e : fs::directory_iterator(path("o"))) plots += e.path().extension() == ".png";
    EXPECT_GT(plots, 1u);
    EXPECT_EQ(r.out, "");
    EXPECT_EQ(r.err, "report: wrote " + path("o/report.md") + ", report.html and " +
                         std::to_string(plots) + " plots beside them\n");
    r = run("report " + path("o") + " --quiet");
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.out + r.err, "");
    const std::string report = test::fileBytes(path("o/report.md"));
    EXPECT_NE(report.find("\n7 runs, 4 configurations; "), std::string::npos) << report;
    EXPECT_NE(report.find("| x=1 | 8 | 2 | 0.1 ± 0 | 1 | 100 | 0 |"), std::string::npos) << report;
    EXPECT_NE(report.find("| x=2 | 8 | 2 | 0.1 ± 0 | 1 | 100 | 0.5 |"), std::string::npos)
        << report;
    EXPECT_NE(report.find("| x=38 | 8 | 2 | 0.1 ± 0 | 1 | 100 | 0.5 ‡ |"), std::string::npos)
        << report;
    EXPECT_NE(report.find("| x=\"a\\|b\" | 8 | 1 | 0.2 | 1 | 25 | 0.01 |"), std::string::npos)
        << report;
    EXPECT_NE(report.find("‡ Biased against the reference (every repeat's bias outside its 95% "
                          "interval, on one side, over two repeats or more): x=38 at 8 spp."),
              std::string::npos)
        << report;
    EXPECT_EQ(report.find("No efficiency"), std::string::npos) << report;
    EXPECT_EQ(report.find("cut short"), std::string::npos) << report;
    // A last line a kill cut short is left out, and said; without rmse there is no efficiency
    // column, and that is said too (helper 141: the row went without a word, the column was
    // empty).
    std::string rows = test::fileBytes(path("o/results.jsonl"));
    for (size_t at; (at = rows.find("\"rmse\": ")) != std::string::npos;)
        rows.replace(at, 8, "\"mae\": ");
    std::ofstream(path("o/results.jsonl"), std::ios::binary)
        << rows << R"({"run": "r0007", "spp": 8, "wall_t)";
    r = run("report " + path("o") + " --quiet");
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string cut = test::fileBytes(path("o/report.md"));
    EXPECT_NE(cut.find("\n7 runs, 4 configurations; error metric: mae;"), std::string::npos) << cut;
    EXPECT_NE(cut.find(" Line 8 of results.jsonl, cut short by a batch stopped while writing it, "
                       "is left out: the next start of the batch renders that run again."),
              std::string::npos)
        << cut;
    EXPECT_NE(cut.find(" No efficiency 1/(MSE·time) column: it needs the sweep's rmse metric."),
              std::string::npos)
        << cut;
    EXPECT_NE(cut.find("| x=1 | 8 | 2 | 0.1 ± 0 | 1 | 0 |"), std::string::npos) << cut;
    // Without any error metric (no reference): no error column, which was empty in every row,
    // and the note says what rmse needs (helper 159).
    std::istringstream lines(rows);
    std::string bare;
    for (std::string line; std::getline(lines, line);) {
        auto row = nlohmann::json::parse(line);
        row.erase("mae");
        bare += row.dump() + "\n";
    }
    std::ofstream(path("o/results.jsonl"), std::ios::binary) << bare;
    r = run("report " + path("o") + " --quiet");
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string none = test::fileBytes(path("o/report.md"));
    EXPECT_NE(none.find("error metric: none;"), std::string::npos) << none;
    EXPECT_NE(none.find(" No efficiency 1/(MSE·time) column: it needs the sweep's rmse metric, "
                        "which needs a reference (no error metric here)."),
              std::string::npos)
        << none;
    EXPECT_NE(none.find("\n| configuration | spp | runs | time (s) | bias (mean) |"),
              std::string::npos)
        << none;
}

// A ledger of three runs of two configurations, for the report tests.
void writeLedger(const std::string& dir, double rmse) {
    fs::create_directories(dir);
    std::ofstream(dir + "/results.jsonl")
        << R"({"run": "r0000", "spp": 8, "g": 1, "wall_time_s": 1, "rmse": )" << rmse << "}\n"
        << R"({"run": "r0001", "spp": 16, "g": 1, "wall_time_s": 2, "rmse": 0.5})"
        << "\n"
        << R"({"run": "r0002", "spp": 8, "g": 2, "wall_time_s": 2, "rmse": 1})"
        << "\n";
}

// The report is replaced whole or not at all: an output that cannot be written leaves the last
// report as it was (each output was renamed as soon as it was written, and the new plots stood
// beside the old tables; helper 100), and no temporary.
TEST_F(Cli, ReportIsReplacedWhole) {
    const std::string dir = path("o");
    writeLedger(dir, 1);
    ASSERT_EQ(run("report " + dir).code, 0);
    std::map<std::string, std::string> before;
    for (const auto& e : fs::directory_iterator(dir))
        if (e.path().filename() != "results.jsonl")
            before[e.path().string()] = test::fileBytes(e.path().string());
    ASSERT_GE(before.size(), 5u);
    writeLedger(dir, 3);  // other numbers: every plot and table changes
    fs::create_directories(dir + "/report.html.tmp");  // the last output's temporary cannot be made
    const Result r = run("report " + dir);
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err, "shvol: error: " + dir + "/report.html: cannot write (Is a directory)\n");
    for (const auto& [file, bytes] : before)
        EXPECT_TRUE(test::fileBytes(file) == bytes) << file << " changed";
    for (const auto& e : fs::directory_iterator(dir))
        EXPECT_TRUE(e.path().extension() != ".tmp" || fs::is_directory(e.path())) << e.path();
}

// A signal to shvol report ends the script too, which writes nothing and removes its
// temporaries; shvol waits for it and exits as the signal asks (std::system ignored SIGINT, and
// at a SIGTERM shvol ended at once while the script went on and wrote the report a second
// later; helper 100).
TEST_F(Cli, ReportStopsAtASignal) {
    for (const int sig : {SIGTERM, SIGINT, SIGHUP}) {
        const std::string dir = path("o" + std::to_string(sig));
        writeLedger(dir, 1);
        const pid_t pid = fork();
        ASSERT_GE(pid, 0);
        if (pid == 0) {
            std::signal(SIGINT, SIG_DFL), std::signal(SIGTERM, SIG_DFL),
                std::signal(SIGHUP, SIG_DFL);
            const int null = ::open("/dev/null", O_WRONLY);
            ::dup2(null, 1), ::dup2(null, 2);
            ::execl(SHVOL_BINARY, SHVOL_BINARY, "report", dir.c_str(), static_cast<char*>(nullptr));
            ::_exit(127);
        }
        // Once the script runs (its start, the import of matplotlib, takes a good part of a
        // second before it writes anything).
        const std::string children =
            "/proc/" + std::to_string(pid) + "/task/" + std::to_string(pid) + "/children";
        pid_t script = 0;
        for (int i = 0; i < 2000 && script == 0; ++i) {
            std::ifstream(children) >> script;
            if (script == 0) ::usleep(1000);
        }
        ASSERT_GT(script, 0) << "no script started";
        ::kill(pid, sig);
        int status = 0;
        ASSERT_EQ(::waitpid(pid, &status, 0), pid);
        ASSERT_TRUE(WIFEXITED(status));
        EXPECT_EQ(WEXITSTATUS(status), 128 + sig);
        EXPECT_NE(::kill(script, 0), 0) << "the script outlived shvol";
        for (const auto& e : fs::directory_iterator(dir))
            EXPECT_EQ(e.path().filename(), "results.jsonl") << e.path();
    }
}

TEST_F(Cli, BatchReport) {
    write("s.json", scene(Homogeneous));
    write("sweep.json", R"({"scene": "s.json", "axes": {"media[0].albedo": [0.8, 0.5],
        "spp": [8, 32]}, "repeats": 2, "reference": {"spp": 512}})");
    const Result r = run("batch " + path("sweep.json") + " --quiet --report --output " + path("o"));
    ASSERT_EQ(r.code, 0) << r.err;
    EXPECT_EQ(r.out + r.err, "");  // (report.md's path was on stdout; helper 139)
    for (const char* f : {"report.md", "report.html", "error_vs_time.png", "error_vs_spp.png",
                          "time_vs_media_0__albedo.png", "time_vs_spp.png"})
        EXPECT_TRUE(fs::exists(path(std::string("o/") + f))) << f;
    std::ifstream md(path("o/report.md"));
    int rows = 0;
    for (std::string line; std::getline(md, line);)
        rows += line.rfind("| media[0].albedo=", 0) == 0;
    EXPECT_EQ(rows, 4);
    const std::string report = test::fileBytes(path("o/report.md"));
    EXPECT_NE(report.find("\n8 runs, 2 configurations; "), std::string::npos);
    // Each row has what its image cost in all, set-up included, beside the passes' time.
    std::ifstream rowsIn(path("o/results.jsonl"));
    for (std::string line; std::getline(rowsIn, line);) {
        const nlohmann::json row = nlohmann::json::parse(line);
        EXPECT_GE(row.at("total_s").get<double>(), row.at("wall_time_s").get<double>()) << line;
    }
    // In the sweep's order, not sorted as text.
    EXPECT_LT(report.find("| media[0].albedo=0.8 | 8 |"),
              report.find("| media[0].albedo=0.5 | 8 |"))
        << report;
    write("one.json", R"({"scene": "s.json", "axes": {"spp": [2]}})");  // counted in the singular
    const Result one = run("batch " + path("one.json") + " --dry-run --output " + path("one"));
    EXPECT_NE(one.out.find("\n1 run into " + path("one") + "\n"), std::string::npos) << one.out;
    // What is there is said (each case said "no results.jsonl here"; helper 77).
    const auto reportError = [&](const std::string& dir) {
        const Result r = run("report " + dir);
        EXPECT_EQ(r.code, 1) << dir;
        return r.err;
    };
    EXPECT_EQ(reportError(path("nothing")),
              "shvol: error: " + path("nothing") + ": no such directory\n");
    EXPECT_EQ(reportError(path("one.json")),
              "shvol: error: " + path("one.json") +
                  ": not a directory (report reads the output directory of shvol batch)\n");
    fs::create_directories(path("empty"));
    EXPECT_EQ(reportError(path("empty")),
              "shvol: error: " + path("empty") +
                  ": no results.jsonl here: not the output directory of shvol batch\n");
    // A copy of the program outside its build tree finds tools/report.py in the source tree it
    // was built from.
    fs::copy_file(SHVOL_BINARY, path("shvol_copy"));
    Result c = runCommand(path("shvol_copy") + " report " + path("o"));
    EXPECT_EQ(c.code, 0) << c.err;
    // Rows the report cannot read: one line naming the file and the line, no traceback.
    const std::string ledger = path("o/results.jsonl");
    std::ofstream(ledger, std::ios::app) << R"({"run": "r0099", "spp": 8, "rmse": "abc"})"
                                         << "\n";
    c = run("report " + path("o"));
    EXPECT_EQ(c.code, 1);
    EXPECT_EQ(c.err, "shvol: error: " + ledger +
                         ": line 9: no \"wall_time_s\" (not a row of shvol batch)\n");
    std::ofstream(ledger) << R"({"run": "r0000", "spp": 8, "wall_time_s": 1, "rmse": "abc"})"
                          << "\n[1, 2]\n";
    c = run("report " + path("o"));
    EXPECT_EQ(c.err, "shvol: error: " + ledger +
                         ": line 1: rmse: expected a finite number >= 0 of at most 1e100, got "
                         "\"abc\"\n");
    std::ofstream(ledger) << R"({"run": "r0000", "spp": 8, "wall_time_s": 1, "rmse": 1e308})"
                          << "\n";
    c = run("report " + path("o"));  // (a traceback of OverflowError; helper 130)
    EXPECT_EQ(c.err, "shvol: error: " + ledger +
                         ": line 1: rmse: expected a finite number >= 0 of at most 1e100, got "
                         "1e+308\n");
    std::ofstream(ledger) << R"({"run": "r0000", "spp": 8, "wall_time_s": 1})"
                          << "\n[1, 2]\n";
    c = run("report " + path("o"));
    EXPECT_EQ(c.err, "shvol: error: " + ledger + ": line 2: a row must be a JSON object\n");
    // A UTF-8 byte-order mark before the first row is skipped, as the batch skips it (it was a
    // malformed row; helper 170).
    std::ofstream(ledger) << "\xEF\xBB\xBF"
                          << R"({"run": "r0000", "spp": 8, "wall_time_s": 1})"
                          << "\n[1, 2]\n";
    c = run("report " + path("o"));
    EXPECT_EQ(c.err, "shvol: error: " + ledger + ": line 2: a row must be a JSON object\n");
    std::ofstream(ledger) << "{\"run\": \n";
    c = run("report " + path("o"));
    EXPECT_EQ(c.code, 1);
    EXPECT_EQ(c.err, "shvol: error: " + ledger + ": line 1: malformed JSON row\n");
    // A row nested 100 000 deep (a Python traceback before), and the compared columns as strings
    // only, as batch reads them (helpers 98, 99).
    std::ofstream(ledger) << R"({"run": "r0000", "spp": 8, "wall_time_s": 1, "x": )"
                          << std::string(100000, '[') << std::string(100000, ']') << "}\n";
    c = run("report " + path("o"));
    EXPECT_EQ(c.err, "shvol: error: " + ledger + ": line 1: objects and arrays nested too deep\n");
    std::ofstream(ledger) << R"({"run": "r0000", "spp": 8, "wall_time_s": 1, "git_revision": 5})"
                          << "\n";
    c = run("report " + path("o"));
    EXPECT_EQ(c.err, "shvol: error: " + ledger + ": line 1: \"git_revision\" is not a string\n");
    std::ofstream(ledger) << R"({"run": "zzz", "spp": 8, "wall_time_s": 1})"
                          << "\n";
    c = run("report " + path("o"));  // (reported as a run before helper 127)
    EXPECT_EQ(c.err, "shvol: error: " + ledger +
                         ": line 1: run: expected a run id of shvol batch (r0000, r0001, …), got "
                         "\"zzz\"\n");
    std::ofstream(ledger) << R"({"run": "r0000", "spp": 8, "wall_time_s": 1})"
                          << "\n"
                          << R"({"run": "r0001", "spp": 8, "wall_time_s": 1})"
                          << "\n"
                          << R"({"run": "r0000", "spp": 8, "wall_time_s": 2})"
                          << "\n";
    c = run("report " + path("o"));  // (it would be counted twice)
    EXPECT_EQ(c.code, 1);
    EXPECT_EQ(c.err, "shvol: error: " + ledger +
                         ": line 3: run r0000 again (first at line 1): two batches wrote into "
                         "this directory\n");
    // Rows of other metrics than the first row's: refused (the report's one error metric, the
    // first of rmse, relmse and mae that every row had, switched without a word).
    std::ofstream(ledger) << R"({"run": "r0000", "spp": 8, "wall_time_s": 1, "rmse": 1, "mae": 1})"
                          << "\n"
                          << R"({"run": "r0001", "spp": 8, "wall_time_s": 1, "mae": 1})"
                          << "\n";
    c = run("report " + path("o"));
    EXPECT_EQ(c.code, 1);
    EXPECT_EQ(c.err, "shvol: error: " + ledger +
                         ": line 2: measured by mae, the first row by rmse, mae: not the rows of "
                         "one batch\n");
    // Efficiency is 1/(MSE·time) with the MSE's mean over the repeats, (1 + 9)/2 here, not the
    // mean RMSE squared (4); a configuration of one run has no spread to show.
    std::ofstream(ledger) << R"({"run": "r0000", "spp": 8, "g": 1, "wall_time_s": 1, "rmse": 1})"
                          << "\n"
                          << R"({"run": "r0001", "spp": 8, "g": 1, "wall_time_s": 1, "rmse": 3})"
                          << "\n"
                          << R"({"run": "r0002", "spp": 8, "g": 2, "wall_time_s": 2, "rmse": 1})"
                          << "\n";
    c = run("report " + path("o"));
    ASSERT_EQ(c.code, 0) << c.err;
    const std::string table = test::fileBytes(path("o/report.md"));
    EXPECT_NE(table.find("| g=1 | 8 | 2 | 2 ± 1.4 | 1 | 0.2 |"), std::string::npos) << table;
    EXPECT_NE(table.find("| g=2 | 8 | 1 | 1 | 2 | 0.5 |"), std::string::npos) << table;
    // The time is total_s where every row has it (loading and set-up included: a cached run's
    // fill was left out of its cost; helper 67); an axis equal to spp in every row (render.spp)
    // is no configuration.
    std::ofstream(ledger)
        << R"({"run": "r0000", "spp": 8, "render.spp": 8, "g": 1, "wall_time_s": 1, "total_s": 4, "rmse": 1})"
        << "\n"
        << R"({"run": "r0001", "spp": 16, "render.spp": 16, "g": 1, "wall_time_s": 2, "total_s": 5, "rmse": 1})"
        << "\n";
    c = run("report " + path("o"));
    ASSERT_EQ(c.code, 0) << c.err;
    const std::string total = test::fileBytes(path("o/report.md"));
    EXPECT_NE(total.find("| g=1 | 8 | 1 | 1 | 4 | 0.25 |"), std::string::npos) << total;
    EXPECT_NE(total.find("| g=1 | 16 | 1 | 1 | 5 | 0.2 |"), std::string::npos) << total;
    EXPECT_NE(total.find("2 runs, 1 configuration; error metric: rmse; time: total_s"),
              std::string::npos)
        << total;
    // The z-test's column, where every row has it: the runs that passed and the smallest p (it
    // was left out; helper 67); a malformed z-test row is one line.
    std::ofstream(ledger)
        << R"({"run": "r0000", "spp": 8, "g": 1, "wall_time_s": 1, "rmse": 1, "ztest_passed": true, "ztest_min_p": 0.5})"
        << "\n"
        << R"({"run": "r0001", "spp": 8, "g": 1, "wall_time_s": 1, "rmse": 1, "ztest_passed": false, "ztest_min_p": 1e-9})"
        << "\n"
        << R"({"run": "r0002", "spp": 64, "g": 1, "wall_time_s": 1, "rmse": 1, "ztest_passed": true, "ztest_min_p": 0.25})"
        << "\n";
    c = run("report " + path("o"));
    ASSERT_EQ(c.code, 0) << c.err;
    const std::string z = test::fileBytes(path("o/report.md"));
    EXPECT_NE(z.find("| 1/(MSE·time) | z-test passed |"), std::string::npos) << z;
    // Below 64 spp the cell is marked and the summary says why: an unbiased renderer failed
    // every repeat there, and the column read as a biased one (helper 122).
    EXPECT_NE(z.find("| g=1 | 8 | 2 | 1 ± 0 | 1 | 1 | 1/2 (min p 1e-09) § |"), std::string::npos)
        << z;
    EXPECT_NE(z.find("| g=1 | 64 | 1 | 1 | 1 | 1 | 1/1 (min p 0.25) |"), std::string::npos) << z;
    EXPECT_NE(z.find(" § Fewer than 64 samples per pixel: the standard errors the z-test divides "
                     "by come from too few samples, and unbiased runs fail it there; it needs 64 "
                     "spp or more, and a few hundred where samples have heavy tails: g=1 at 8 "
                     "spp."),
              std::string::npos)
        << z;
    std::ofstream(ledger)
        << R"({"run": "r0000", "spp": 8, "wall_time_s": 1, "rmse": 1, "ztest_passed": 1})"
        << "\n";
    c = run("report " + path("o"));
    EXPECT_EQ(c.err, "shvol: error: " + ledger +
                         ": line 1: ztest_passed: expected true or false with a finite "
                         "ztest_min_p, got 1 and null\n");
    // An error of 0 (runs equal to the reference) stays in the table but not on the log axes,
    // which said so in matplotlib's warnings on stderr; an spp of 0 cannot be on them either.
    std::ofstream(ledger) << R"({"run": "r0000", "spp": 8, "g": 1, "wall_time_s": 1, "rmse": 0})"
                          << "\n"
                          << R"({"run": "r0001", "spp": 16, "g": 1, "wall_time_s": 2, "rmse": 1})"
                          << "\n";
    c = run("report " + path("o") + " --quiet");
    EXPECT_EQ(c.code, 0);
    EXPECT_EQ(c.err, "");
    EXPECT_NE(test::fileBytes(path("o/report.md"))
                  .find("Left out of the error plots (log axes): 1 row of the table with an "
                        "error or a time of 0."),
              std::string::npos);
    std::ofstream(ledger) << R"({"run": "r0000", "spp": 0, "wall_time_s": 1, "rmse": 1})"
                          << "\n";
    c = run("report " + path("o"));
    EXPECT_EQ(c.code, 1);
    EXPECT_EQ(c.err,
              "shvol: error: " + ledger + ": line 1: spp: expected an integer >= 1, got 0\n");
    // An output that cannot be written: one line, and nothing written, no temporary left: every
    // output is checked before the first is written (the plots were written, then report.md
    // refused).
    std::ofstream(ledger) << R"({"run": "r0000", "spp": 8, "wall_time_s": 1, "rmse": 1})"
                          << "\n";
    fs::remove(path("o/report.md"));
    fs::remove(path("o/error_vs_spp.png"));
    fs::create_directory(path("o/report.md"));
    c = run("report " + path("o"));
    EXPECT_EQ(c.code, 1);
    EXPECT_EQ(c.err, "shvol: error: " + path("o/report.md") + ": cannot write: is a directory\n");
    EXPECT_FALSE(fs::exists(path("o/error_vs_spp.png")));
    EXPECT_FALSE(fs::exists(path("o/report.md.tmp")));
}

// A scene whose file name is not valid UTF-8 renders, and its stats are valid JSON (the name is
// written with U+FFFD where the bad byte was).
TEST_F(Cli, NonUtf8FileNames) {
    const std::string name = path(
        "sc\xff"
        "e.json");
    std::ofstream(name) << scene(Homogeneous);
    const Result r = run("render '" + name + "' -o " + path("u.exr") + " --quiet");
    ASSERT_EQ(r.code, 0) << r.err;
    std::ifstream f(path("u.stats.json"));
    const auto stats = nlohmann::json::parse(f);
    EXPECT_NE(stats["scene"].get<std::string>().find("\xef\xbf\xbd"), std::string::npos);
}

// The stats name the source revision the program was built from: a 40-digit commit, with
// "-dirty-" and 12 hex digits of its changes' hash when the tree had uncommitted changes (two
// differently changed builds were both "-dirty"), or "no-git-" and 12 hex digits of its sources'
// hash outside a checkout of its own.
TEST_F(Cli, StatsNameTheGitRevision) {
    write("s.json", scene(Homogeneous));
    ASSERT_EQ(run("render " + path("s.json") + " -o " + path("g.exr") + " --quiet").code, 0);
    std::ifstream f(path("g.stats.json"));
    const std::string rev = nlohmann::json::parse(f)["git_revision"];
    const bool commit =
        rev.size() >= 40 && rev.find_first_not_of("0123456789abcdef") >= 40 &&
        (rev.size() == 40 || (rev.size() == 40 + 19 && rev.substr(40, 7) == "-dirty-" &&
                              rev.find_first_not_of("0123456789abcdef", 47) == std::string::npos));
    // A build from a git checkout names its commit (if the stamp broke and said "unknown", a
    // test accepting either passed; helper 78); one from a tree outside git says "no-git-<hash>".
    // (a checkout of its own: the top of its work tree is the source directory)
    const Result top =
        runCommand("git -C " + std::string(SHVOL_SOURCE_DIR) + " rev-parse --show-toplevel");
    const bool inGit =
        top.code == 0 && fs::equivalent(top.out.substr(0, top.out.find('\n')), SHVOL_SOURCE_DIR);
    if (inGit)
        EXPECT_TRUE(commit) << rev;
    else
        EXPECT_TRUE(rev.size() == 19 && rev.substr(0, 7) == "no-git-" &&
                    rev.find_first_not_of("0123456789abcdef", 7) == std::string::npos)
            << rev;
}

// The phase command quotes a long spec by its first 77 characters, as the loader does (its own
// messages quoted the whole spec: helper 99).
TEST_F(Cli, PhaseCommandQuotesLongSpecsBriefly) {
    const std::string spec =
        R"({"type":"hg","g":0.5,"sampling":"analytic","x":")" + std::string(200, 'y') + "\"}";
    const Result r = run("phase fit '" + spec + "'");
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(
        r.err.rfind("shvol: error: phase spec \"" + spec.substr(0, 77) + "...\": sampling: ", 0),
        0u)
        << r.err;
}

// --set takes one value, so a scene may follow it: with several, `--set k=v s.json --threads 1`
// took s.json for a second override and said "scene is required" (helper 96). A second value
// without its --set is refused, with the hint.
TEST_F(Cli, SetTakesOneValueSoTheSceneMayFollowIt) {
    write("s.json", scene(Homogeneous));
    Result r = run("render --set camera.resolution=[4,4] " + path("s.json") +
                   " --spp 1 --quiet -o " + path("out.exr"));
    ASSERT_EQ(r.code, 0) << r.err;
    auto stats = nlohmann::json::parse(std::ifstream(path("out.stats.json")));
    EXPECT_EQ(stats["scene_resolved"]["camera"]["resolution"], nlohmann::json::parse("[4, 4]"));
    r = run("render --set camera.resolution=[4,4] --set render.spp=1 " + path("s.json") +
            " --quiet -o " + path("out.exr"));
    ASSERT_EQ(r.code, 0) << r.err;
    stats = nlohmann::json::parse(std::ifstream(path("out.stats.json")));
    EXPECT_EQ(stats["spp"], 1);
    r = run("render " + path("s.json") + " --set camera.resolution=[4,4] render.spp=1 --quiet -o " +
            path("out.exr"));
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err,
              "shvol: error: an unexpected argument (an unknown option, or a value no option "
              "takes): render.spp=1; each --set takes one key.path=value: give --set before each "
              "(see --help)\n");
    // Before the scene, or with no scene, the second value is taken for the scene, which is no
    // file: the hint too (helper 99). Without a --set there is none.
    const std::string stray =
        "shvol: error: scene: render.spp=1: no such file; each --set takes "
        "one key.path=value: give --set before each (see --help)\n";
    for (const std::string& after :
         {" " + path("s.json") + " -o " + path("out.exr"), std::string()}) {
        r = run("render --set camera.resolution=[4,4] render.spp=1 --quiet" + after);
        EXPECT_EQ(r.code, 1);
        EXPECT_EQ(r.err, stray);
    }
    r = run("phase fit hg:g=0.5 hg:g=0.3");
    EXPECT_EQ(r.code, 1);
    EXPECT_EQ(r.err,
              "shvol: error: an unexpected argument (an unknown option, or a value no option "
              "takes): hg:g=0.3 (see --help)\n");
}

// Hostile nesting, 100 000 arrays deep in a 200 kB scene, is refused in one line wherever it is
// (under "media", in a medium's value, in a surface): it crashed the loader's recursive copies
// (exit 139, nothing said; helper 96), while the same depth under "camera" was refused.
TEST_F(Cli, DeeplyNestedScenesAreRefused) {
    const std::string deep = std::string(100000, '[') + std::string(100000, ']');
    const std::string limit = "objects and arrays nested more than 256 levels deep";
    write("s.json", R"({"media": )" + deep + "}");
    expectOneLineError("s.json", "s.json: media[0][0][0]…: " + limit);
    write("s.json", R"({"media": [{"type": "homogeneous", "albedo": )" + deep + "}]}");
    expectOneLineError("s.json", "s.json: media[0].albedo[0]…: " + limit);
    write("s.json", R"({"surfaces": [{"type": "sphere", "x": )" + deep + "}]}");
    expectOneLineError("s.json", "s.json: surfaces[0].x[0]…: " + limit);
}

// cmake/git_revision.cmake on trees of its own: outside git a build is named by its sources
// (src/, include/, cmake/, CMakeLists.txt), so two archives' builds differ (both were "unknown"
// before 6 Dec, and one resumed the other's checkpoints); in a checkout, by its commit, with the
// hash of its changes when it has any.
TEST_F(Cli, BuildRevisionNamesTheSources) {
    const std::string tree = path("tree"), out = path("rev.h");
    fs::create_directories(tree + "/src"), fs::create_directories(tree + "/include/x");
    const auto put = [&](const std::string& file, const std::string& text) {
        std::ofstream(tree + "/" + file) << text;
    };
    put("src/a.cpp", "int a;\n"), put("include/x/b.h", "int b;\n");
    put("CMakeLists.txt", "project(t)\n"), put("README.md", "r\n");
    const auto revision = [&] {
        const Result r = runCommand("cmake -DSRC=" + tree + " -DOUT=" + out + " -P " +
                                    SHVOL_SOURCE_DIR + "/cmake/git_revision.cmake");
        EXPECT_EQ(r.code, 0) << r.err;
        std::stringstream text;
        text << std::ifstream(out).rdbuf();
        const std::string s = text.str(), head = "#define SHVOL_GIT_REVISION \"";
        EXPECT_EQ(s.substr(0, head.size()), head) << s;
        return s.size() > head.size() + 2 ? s.substr(head.size(), s.size() - head.size() - 2) : s;
    };
    const auto hex = [](const std::string& s) {
        return !s.empty() && s.find_first_not_of("0123456789abcdef") == std::string::npos;
    };
    const std::string first = revision();
    ASSERT_EQ(first.size(), 7u + 12) << first;
    EXPECT_EQ(first.substr(0, 7), "no-git-");
    EXPECT_TRUE(hex(first.substr(7))) << first;
    put("src/a.cpp", "int a2;\n");
    const std::string changed = revision();
    EXPECT_NE(changed, first);
    put("include/x/c.h", "int c;\n");  // a new header
    EXPECT_NE(revision(), changed);
    fs::remove(tree + "/include/x/c.h");
    put("src/a.cpp", "int a;\n");
    EXPECT_EQ(revision(), first);  // the same sources, the same name
    put("README.md", "r2\n");      // not built from
    EXPECT_EQ(revision(), first);
    fs::create_directories(tree + "/cmake");
    put("cmake/f.cmake", "x\n");
    EXPECT_NE(revision(), first);
    fs::remove_all(tree + "/cmake");
    // Weird names are sources too (a CMake list split them at ';' and paired '[' with ']').
    put("include/x/a[1;b.h", "w\n");
    const std::string weird = revision();
    EXPECT_NE(weird, first);
    put("include/x/zz.h", "z\n");  // sorted after it
    EXPECT_NE(revision(), weird);
    fs::remove(tree + "/include/x/a[1;b.h"), fs::remove(tree + "/include/x/zz.h");
    EXPECT_EQ(revision(), first);

    // Inside another repository's work tree, still named by its sources (it was named by that
    // repository's commit: helper 99).
    const std::string outer = "git -C " + path("") + " -c user.name=t -c user.email=t@t ";
    ASSERT_EQ(runCommand(outer + "init -q && " + outer + "add rev.h && " + outer +
                         "-c commit.gpgsign=false commit -qm o")
                  .code,
              0);
    EXPECT_EQ(revision(), first);

    // A checkout: its commit, and "-dirty-" with the hash of its changes.
    const std::string git = "git -C " + tree + " -c user.name=t -c user.email=t@t ";
    ASSERT_EQ(runCommand(git + "init -q && " + git + "add -A && " + git +
                         "-c commit.gpgsign=false commit -qm t")
                  .code,
              0);
    const std::string commit = revision();
    EXPECT_EQ(commit.size(), 40u) << commit;
    EXPECT_TRUE(hex(commit)) << commit;
    put("src/a.cpp", "int a3;\n");
    const std::string dirty = revision();
    ASSERT_EQ(dirty.size(), 40u + 7 + 12) << dirty;
    EXPECT_EQ(dirty.substr(0, 47), commit + "-dirty-");
    put("src/a.cpp", "int a4;\n");
    EXPECT_NE(revision(), dirty);
    put("src/a.cpp", "int a;\n");
    EXPECT_EQ(revision(), commit);
    // A weird name's changes change the name too (the list of changed files was a CMake list,
    // which hashed a[1;b.cpp as the two deleted files "src/a[1" and "b.cpp").
    put("src/a[1;b.cpp", "w\n");
    const std::string weirdDirty = revision();
    EXPECT_EQ(weirdDirty.substr(0, 47), commit + "-dirty-");
    put("src/a[1;b.cpp", "w2\n");
    EXPECT_NE(revision(), weirdDirty);
    fs::remove(tree + "/src/a[1;b.cpp");
    EXPECT_EQ(revision(), commit);
    fs::remove(tree + "/src/a.cpp");  // a deleted file is a change
    EXPECT_EQ(revision().substr(0, 47), commit + "-dirty-");
}

}  // namespace shvol
