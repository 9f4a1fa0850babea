// shvol: a participating-media simulator. See README.md for the command-line reference.
#include <algorithm>
#include <cctype>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "commands.h"
#include "mpi_world.h"
#include "shvol/core/error.h"
#include "shvol/core/spelling.h"

namespace {

/// CLI11's message of a command line it cannot parse, in shvol's words.
std::string plainParseError(std::string what, int argc, char** argv) {
    // An option given twice: "--spp: At Most 1 required but received 2".
    const std::string twice = "At Most 1 required but received ";
    if (const size_t at = what.find(twice); at != std::string::npos)
        what =
            what.substr(0, at) + "given " + what.substr(at + twice.size()) + " times; give it once";
    // A value the option's type cannot hold: "Could not convert: --width = 8.5", in the form of
    // the other option errors.
    const std::string convert = "Could not convert: ";
    if (const size_t eq = what.find(" = "); what.rfind(convert, 0) == 0 && eq != std::string::npos)
        what = what.substr(convert.size(), eq - convert.size()) + ": cannot read \"" +
               what.substr(eq + 3) + "\" as a value of this option";
    // Arguments no option takes: "The following arguments were not expected: x.exr --outptu",
    // listed backwards ("The following argument was not expected: --outptu" for one), in the
    // order given (helper 77). The list is split at spaces: one with an argument holding a
    // space is left in CLI11's words.
    for (const std::string extras : {"The following argument was not expected: ",
                                     "The following arguments were not expected: "}) {
        if (what.rfind(extras, 0) != 0) continue;
        std::vector<std::string> args;
        std::istringstream list(what.substr(extras.size()));
        for (std::string arg; list >> arg;) args.push_back(arg);
        const auto place = [&](const std::string& arg) {
            return std::find(argv, argv + argc, arg) - argv;
        };
        if (args.empty() || !std::all_of(args.begin(), args.end(),
                                         [&](const std::string& arg) { return place(arg) < argc; }))
            break;
        std::stable_sort(args.begin(), args.end(), [&](const std::string& a, const std::string& b) {
            return place(a) < place(b);
        });
        what = std::string(args.size() > 1 ? "unexpected arguments" : "an unexpected argument") +
               " (an unknown option, or a value no option takes):";
        for (const std::string& arg : args) what += " " + arg;
        // key=value right after an override's value: each --set takes one (it took several
        // before 6 Dec; `--set a=1 b=2 s.json` reads b=2 as the scene and s.json as extra).
        bool stray = false;
        for (int i = 2; i < argc; ++i)
            stray = stray || (std::strchr(argv[i], '=') && argv[i][0] != '-' &&
                              std::string(argv[i - 1]).find('=') != std::string::npos &&
                              (std::string(argv[i - 2]) == "--set" ||
                               std::string(argv[i - 1]).rfind("--set=", 0) == 0));
        if (stray) what += std::string("; ") + shvol::app::kOneValuePerSet;
    }
    // CLI11's other words start with a capital, shvol's do not ("A subcommand is required").
    if (!what.empty() && std::isupper(static_cast<unsigned char>(what[0])))
        what[0] = char(std::tolower(static_cast<unsigned char>(what[0])));
    return what;
}

int runMain(int argc, char** argv) {
    // Under mpirun every rank parses the same command line: rank 0 alone speaks for them.
    const bool speaks = shvol::app::MpiWorld::get().root();
    CLI::App app{"shvol " SHVOL_VERSION " - volumetric path tracing of participating media"};
    app.set_version_flag("--version", "shvol " SHVOL_VERSION);
    app.require_subcommand(1);
    // --help shows every option's default (inherited by the subcommands added below).
    app.option_defaults()->always_capture_default();
    std::function<int()> run;
    shvol::app::addRenderCommand(app, run);
    shvol::app::addMakeMediumCommand(app, run);
    shvol::app::addMakeSkyCommand(app, run);
    shvol::app::addBenchCommand(app, run);
    shvol::app::addPhaseCommand(app, run);
    shvol::app::addDiffCommand(app, run);
    shvol::app::addTonemapCommand(app, run);
    shvol::app::addBatchCommand(app, run);
    shvol::app::addReportCommand(app, run);
    // An unknown first word is a wrong subcommand, not a missing one (CLI11 would say "A
    // subcommand is required", and print the main help with exit 0 for `shvol typo --help`).
    // The same one level down (`shvol phase foo`: CLI11 said "A subcommand is required").
    CLI::App* parent = &app;
    for (int level = 1; level < argc && argv[level][0] != '-'; ++level) {
        // (named ones: CLI11's option groups are nameless subcommands)
        const std::vector<CLI::App*> subs =
            parent->get_subcommands([](const CLI::App* a) { return !a->get_name().empty(); });
        if (subs.empty()) break;
        std::vector<std::string> nameList;
        CLI::App* known = nullptr;
        for (CLI::App* sub : subs) {
            if (sub->get_name() == argv[level]) known = sub;
            nameList.push_back(sub->get_name());
        }
        if (!known) {
            std::string names;
            for (const std::string& n : nameList) names += (names.empty() ? "" : ", ") + n;
            // (a typo is named, as a scene key's is; helper 84)
            const std::string nearest = shvol::nearestSpelling(argv[level], nameList);
            if (speaks)
                std::fprintf(stderr,
                             "shvol: error: unknown subcommand \"%s\"%s; %sexpected one of %s\n",
                             argv[level], level == 1 ? "" : (" of " + parent->get_name()).c_str(),
                             nearest.empty() ? "" : ("did you mean \"" + nearest + "\"? ").c_str(),
                             names.c_str());
            return 1;
        }
        parent = known;
    }
    try {
        app.parse(argc, argv);
    } catch (const CLI::CallForHelp& e) {
        return speaks ? app.exit(e) : 0;
    } catch (const CLI::CallForAllHelp& e) {
        return speaks ? app.exit(e) : 0;
    } catch (const CLI::CallForVersion& e) {
        return speaks ? app.exit(e) : 0;
    } catch (const CLI::ParseError& e) {
        // Like every other error: one line and exit code 1 (CLI11 would print two lines and use
        // its own codes).
        const std::string what = plainParseError(e.what(), argc, argv);
        if (speaks) std::fprintf(stderr, "shvol: error: %s (see --help)\n", what.c_str());
        return 1;
    }
    const std::string command = app.get_subcommands().front()->get_name();
    if (shvol::app::MpiWorld::get().parallel() && command != "render" && command != "batch") {
        if (speaks)
            std::fprintf(stderr,
                         "shvol: error: %s does not run over MPI ranks (render and batch do); "
                         "run it without mpirun\n",
                         command.c_str());
        return 1;
    }
    std::string error;
    try {
        return run();
    } catch (const shvol::app::ReportedOnRoot&) {
        return 1;
    } catch (const shvol::app::KnownToEveryRank& e) {  // (the others end with ReportedOnRoot)
        std::fprintf(stderr, "%s\n", shvol::app::errorLine(e).c_str());
        return 1;
    } catch (const std::exception& e) {  // shvol::Error, memory running out, or a defect
        error = shvol::app::errorLine(e);
    }
    std::fprintf(stderr, "%s\n", error.c_str());
    // An error on one rank only ends every rank, rank 0's too: the others may be waiting for it
    // (rank 0 alone out of memory in a render, or unable to write a batch's reference, left them
    // in a reduction for ever; helper 104).
    if (shvol::app::MpiWorld::get().parallel()) shvol::app::MpiWorld::abort(1);
    return 1;
}

}  // namespace

int main(int argc, char** argv) {
    // A file-size limit (ulimit -f) ends a process that writes past it by SIGXFSZ: no message,
    // exit 153 and the temporaries left (helper 100). Ignored (unless whoever started shvol
    // chose otherwise), the write fails with EFBIG instead, which each writer reports as it does
    // a full disk: one line naming the file, exit 1, nothing left.
    struct sigaction fileSize {};
    if (::sigaction(SIGXFSZ, nullptr, &fileSize) == 0 && fileSize.sa_handler == SIG_DFL)
        std::signal(SIGXFSZ, SIG_IGN);
    shvol::app::MpiWorld::init(argc, argv);
    const int code = runMain(argc, argv);
    shvol::app::MpiWorld::finalize();
    return code;
}
