#include "shvol/io/sweep.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <set>

#include "test_util.h"

namespace shvol {

namespace {

namespace fs = std::filesystem;

/// Writes a scene and a sweep into a fresh directory; returns the sweep's path.
std::string writeSweep(const std::string& name, const std::string& sweep) {
    const fs::path dir = fs::path(testing::TempDir()) / ("shvol_sweep_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    // (two media: the sweeps below set keys of media[0] and media[1], and --set refuses an index
    // into an array the scene lacks)
    std::ofstream(dir / "scene.json") << R"({"render": {"spp": 4}, "media": [{}, {}]})";
    std::ofstream(dir / "sweep.json") << sweep;
    return (dir / "sweep.json").string();
}

}  // namespace

// Repeats are the slowest loop, then the axes, the first slowest: more repeats append runs.
TEST(Sweep, GridExpandsRepeatsSlowestThenFirstAxis) {
    const Sweep s =
        readSweep(writeSweep("grid", R"({"scene": "scene.json", "set": ["camera.fov=20"],
        "axes": {"media": [[], [{"type": "homogeneous"}]], "spp": [1, 2, 3]}, "repeats": 2,
        "seed": 5})"));
    ASSERT_EQ(s.runs.size(), 2u * 3u * 2u);
    EXPECT_EQ(s.axes, (std::vector<std::string>{"media", "spp"}));
    EXPECT_EQ(s.runs[0].values["spp"], 1);
    EXPECT_EQ(s.runs[1].values["spp"], 2);
    EXPECT_EQ(s.runs[1].values["repeat"], 0);
    EXPECT_EQ(s.runs[2].values["media"].size(), 0u);
    EXPECT_EQ(s.runs[3].values["media"].size(), 1u);
    EXPECT_EQ(s.runs[3].values["spp"], 1);
    EXPECT_EQ(s.runs[3].id, "r0003");
    Json second = s.runs[0].values;  // the first point's second repeat
    second["repeat"] = 1;
    EXPECT_EQ(s.runs[6].values, second);
    EXPECT_EQ(s.runs[0].sets, (std::vector<std::string>{"camera.fov=20", "media=[]", "render.spp=1",
                                                        "render.seed=5"}));
    EXPECT_EQ(s.runs[6].sets.back(), "render.seed=6");  // each repeat its own seed
    EXPECT_EQ(s.runs[11].sets.back(), "render.seed=6");
    EXPECT_NE(s.runs[0].fingerprint, s.runs[6].fingerprint);
    // With one repeat, values appended to the first axis keep the ids too.
    const Sweep one = readSweep(writeSweep("grid1", R"({"scene": "scene.json",
        "axes": {"spp": [1, 2], "media": [[], [{"type": "homogeneous"}]]}})"));
    const Sweep appended = readSweep(writeSweep("grid1", R"({"scene": "scene.json",
        "axes": {"spp": [1, 2, 5], "media": [[], [{"type": "homogeneous"}]]}})"));
    ASSERT_EQ(appended.runs.size(), 6u);
    for (size_t i = 0; i < one.runs.size(); ++i) {
        EXPECT_EQ(appended.runs[i].id, one.runs[i].id);
        EXPECT_EQ(appended.runs[i].fingerprint, one.runs[i].fingerprint);
    }
    // With more repeats the first runs are the same runs, under the same ids.
    const Sweep more =
        readSweep(writeSweep("grid3", R"({"scene": "scene.json", "set": ["camera.fov=20"],
        "axes": {"media": [[], [{"type": "homogeneous"}]], "spp": [1, 2, 3]}, "repeats": 3,
        "seed": 5})"));
    ASSERT_EQ(more.runs.size(), 18u);
    for (size_t i = 0; i < s.runs.size(); ++i) {
        EXPECT_EQ(more.runs[i].id, s.runs[i].id);
        EXPECT_EQ(more.runs[i].values, s.runs[i].values);
        EXPECT_EQ(more.runs[i].fingerprint, s.runs[i].fingerprint);
    }
    EXPECT_EQ(fs::path(s.scene).filename(), "scene.json");
    EXPECT_EQ(fs::path(s.output).filename(), "sweep_results");
    EXPECT_FALSE(s.reference.has_value());
}

// A resumed batch finds its finished runs by their values (axis values and repeat), wherever a
// changed sweep puts them; new runs keep their own ids where no row has them, else take the
// lowest free ones. A row that holds no run (its values gone, or an axis renamed) keeps its id out
// of use and holds nothing.
TEST(Sweep, AdoptFinishedIdsFindsRunsByTheirValues) {
    const std::string old =
        R"({"scene": "scene.json", "axes": {"spp": [1, 4], "camera.fov": [20, 40]}})";
    const Sweep before = readSweep(writeSweep("adopt", old));
    std::vector<Json> rows;
    for (const SweepRun& r : before.runs) {
        Json row = r.values;
        row["run"] = r.id, row["wall_time_s"] = 1.0;  // and columns that are no axis
        rows.push_back(row);
    }
    // Unchanged: every run is finished under its own id.
    Sweep same = readSweep(writeSweep("adopt", old));
    EXPECT_EQ(adoptFinishedIds(same, rows), 4u);
    for (size_t i = 0; i < same.runs.size(); ++i) EXPECT_EQ(same.runs[i].id, before.runs[i].id);
    // A value inserted into each axis, and a second repeat: 3 × 3 × 2 runs.
    Sweep grown = readSweep(writeSweep("adopt", R"({"scene": "scene.json",
        "axes": {"spp": [1, 2, 4], "camera.fov": [20, 30, 40]}, "repeats": 2})"));
    ASSERT_EQ(grown.runs.size(), 18u);
    EXPECT_EQ(adoptFinishedIds(grown, rows), 4u);
    std::set<std::string> ids;
    for (const SweepRun& r : grown.runs) {
        EXPECT_TRUE(ids.insert(r.id).second) << r.id << " twice";
        for (const SweepRun& b : before.runs)  // a finished run: its row's id, else none's
            EXPECT_EQ(r.values == b.values, r.id == b.id) << dumpJson(r.values);
    }
    // Finished: (1, 20) r0000, (1, 40) r0001, (4, 20) r0002, (4, 40) r0003, at places 0, 2, 6, 8.
    // New runs whose own id is free keep it: (2, 30) at place 4. Those whose own id a row has,
    // (1, 30) at 1 and (2, 20) at 3, take the lowest ids no row and no run has: r0006 (place 6
    // is the finished (4, 20), r0002), then r0008.
    EXPECT_EQ(grown.runs[0].id, "r0000");
    EXPECT_EQ(grown.runs[2].id, "r0001");
    EXPECT_EQ(grown.runs[6].id, "r0002");
    EXPECT_EQ(grown.runs[4].id, "r0004");
    EXPECT_EQ(grown.runs[1].id, "r0006");
    EXPECT_EQ(grown.runs[3].id, "r0008");
    EXPECT_EQ(grown.runs[17].id, "r0017");
    // Rows that hold no run: a value changed (spp 4 → 5) and an axis renamed. Their ids stay out
    // of use, and the runs they would have held are new.
    Sweep changed = readSweep(writeSweep("adopt", R"({"scene": "scene.json",
        "axes": {"spp": [1, 5], "camera.fov": [20, 40]}})"));
    EXPECT_EQ(adoptFinishedIds(changed, rows), 2u);
    EXPECT_EQ(changed.runs[2].id, "r0004");
    EXPECT_EQ(changed.runs[3].id, "r0005");
    Sweep renamed = readSweep(writeSweep("adopt", R"({"scene": "scene.json",
        "axes": {"render.spp": [1, 4], "camera.fov": [20, 40]}})"));
    EXPECT_EQ(adoptFinishedIds(renamed, rows), 0u);
    EXPECT_EQ(renamed.runs[0].id, "r0004");
}

// A value written otherwise but equal (20.0 for 20) is the same value: its run stays finished.
TEST(Sweep, AdoptFinishedIdsComparesNumbersAsNumbers) {
    const Sweep before = readSweep(
        writeSweep("adopt-num", R"({"scene": "scene.json", "axes": {"camera.fov": [20, 40.5]}})"));
    std::vector<Json> rows;
    for (const SweepRun& r : before.runs) rows.push_back(r.values), rows.back()["run"] = r.id;
    Sweep after = readSweep(writeSweep(
        "adopt-num", R"({"scene": "scene.json", "axes": {"camera.fov": [30, 20.0, 4.05e1]}})"));
    EXPECT_EQ(adoptFinishedIds(after, rows), 2u);
    EXPECT_EQ(after.runs[1].id, "r0000");
    EXPECT_EQ(after.runs[2].id, "r0001");
    EXPECT_EQ(after.runs[1].fingerprint, before.runs[0].fingerprint);  // the same render
}

// A finished row no run holds is refused with what the sweep no longer has: not compared with
// whichever run is now at the row's place, which after an insertion is an unrelated point.
TEST(Sweep, UnheldRowReasonNamesWhatTheSweepNoLongerHas) {
    const std::string stay =
        " (a finished run must stay in the sweep: values may be added to its axes, and repeats, "
        "but not changed or removed)";
    const auto reason = [](const std::string& sweep, const std::string& row) {
        return unheldRowReason(readSweep(writeSweep("unheld", sweep)), Json::parse(row));
    };
    const std::string grid =
        R"({"scene": "scene.json", "axes": {"spp": [1, 4, 8], "camera.fov": [20, 40]},
            "repeats": 2})";
    EXPECT_EQ(reason(grid, R"({"run": "r0001", "spp": 2, "camera.fov": 40, "repeat": 0})"),
              "finished with spp=2, a value axes.spp no longer has" + stay);
    EXPECT_EQ(reason(grid, R"({"run": "r0001", "spp": 4, "camera.fov": 30, "repeat": 1})"),
              "finished with camera.fov=30, a value axes.camera.fov no longer has" + stay);
    EXPECT_EQ(reason(grid, R"({"run": "r0013", "spp": 4, "camera.fov": 40, "repeat": 2})"),
              "finished as repeat 2, and the sweep now has 2 repeats" + stay);
    EXPECT_EQ(reason(grid, R"({"run": "r0001", "spp": 4, "repeat": 0})"),
              "finished with no camera.fov, an axis the sweep now has");
    EXPECT_EQ(reason(grid, R"({"run": "r0009", "spp": 4, "camera.fov": 20.0, "repeat": 0})"),
              "finished at spp=4 camera.fov=20.0 repeat=0, the point of run r0002, which another "
              "row holds");
    const std::string zip =
        R"({"scene": "scene.json", "combine": "zip", "axes": {"spp": [1, 4], "camera.fov": [20, 40]}})";
    EXPECT_EQ(reason(zip, R"({"run": "r0000", "spp": 1, "camera.fov": 40, "repeat": 0})"),
              "finished at spp=1 camera.fov=40 repeat=0, a combination the zipped axes no longer "
              "give" +
                  stay);
}

TEST(Sweep, ZipAndReference) {
    const Sweep s = readSweep(writeSweep("zip", R"({"scene": "scene.json", "combine": "zip",
        "axes": {"spp": [1, 2], "seed": [7, 8]}, "reference": {"spp": 64, "set": ["camera.fov=10"]},
        "output": "out"})"));
    ASSERT_EQ(s.runs.size(), 2u);
    EXPECT_EQ(s.runs[1].sets, (std::vector<std::string>{"render.spp=2", "render.seed=8"}));
    ASSERT_TRUE(s.reference && s.reference->render);
    EXPECT_EQ(s.reference->sets, (std::vector<std::string>{"camera.fov=10", "render.spp=64",
                                                           "render.seed=1000000000"}));
    EXPECT_EQ(fs::path(s.reference->file).filename(), "reference.exr");
    EXPECT_EQ(s.metrics, (std::vector<std::string>{"rmse", "relmse", "mae", "bias"}));
}

// After fingerprintInputs a run's fingerprint covers the files its scene names, not only their
// names: a grid rewritten in place is another experiment. Two axis values name two files, so each
// run is checked against its own file. readSweep alone reads no file (batch --dry-run).
TEST(Sweep, FingerprintFollowsTheContentsOfNamedFiles) {
    const fs::path dir = fs::path(testing::TempDir()) / "shvol_sweep_contents";
    const std::string a = (dir / "a.exr").string(), b = (dir / "b.exr").string();
    const std::string sweep = writeSweep("contents", R"({"scene": "scene.json",
        "axes": {"environment.file": ["a.exr", "b.exr"]}})");
    std::ofstream(dir / "scene.json") << R"({"environment": {"type": "image", "file": "a.exr"}})";
    auto stamped = [&] {
        Sweep s = readSweep(sweep);
        std::map<std::string, Json> memo;
        fingerprintInputs(s, memo);
        return s;
    };
    auto write = [](const std::string& path, const char* bytes) { std::ofstream(path) << bytes; };
    write(a, "first");
    write(b, "first");
    const Sweep s0 = stamped();
    ASSERT_EQ(s0.runs.size(), 2u);
    EXPECT_NE(s0.runs[0].fingerprint, readSweep(sweep).runs[0].fingerprint);  // contents added
    write(b, "second");
    const Sweep s1 = stamped();
    EXPECT_EQ(s1.runs[0].fingerprint, s0.runs[0].fingerprint);  // a.exr: still the same
    EXPECT_NE(s1.runs[1].fingerprint, s0.runs[1].fingerprint);  // b.exr: rewritten
    fs::remove(a);
    EXPECT_EQ(readSweep(sweep).runs.size(), 2u);  // listing the runs needs no file
    const std::string m = test::messageOf([&] { stamped(); });
    EXPECT_EQ(m, a + ": cannot open file (named by environment.file)");
}

// A relative path assigned to a file key, in "set", "axes" or the reference's "set", is relative
// to the sweep file, as the sweep's scene and output are (on the command line, --set takes it
// relative to the current directory); paths inside an object value stay the scene's.
TEST(Sweep, FilePathsAreRelativeToTheSweepFile) {
    const std::string sweep = writeSweep("paths", R"({"scene": "scene.json",
        "set": ["media[0].file=grids/a.vdb", "camera.fov=20", "environment.file=\"/abs/sky.exr\""],
        "axes": {"media.0.phase.file": ["t.csv"], "media[1].phase": [{"file": "u.csv"}]},
        "reference": {"spp": 4, "set": ["environment.file=sky.exr"]}})");
    const std::string dir = fs::path(sweep).parent_path().string();
    const Sweep s = readSweep(sweep);
    ASSERT_EQ(s.runs.size(), 1u);
    EXPECT_EQ(s.runs[0].sets,
              (std::vector<std::string>{"media[0].file=\"" + dir + "/grids/a.vdb\"",
                                        "camera.fov=20", "environment.file=\"/abs/sky.exr\"",
                                        "media.0.phase.file=\"" + dir + "/t.csv\"",
                                        R"(media[1].phase={"file":"u.csv"})", "render.seed=1"}));
    ASSERT_TRUE(s.reference.has_value());
    EXPECT_EQ(s.reference->sets[3], "environment.file=\"" + dir + "/sky.exr\"");
}

TEST(Sweep, ErrorsNameFileAndKey) {
    auto err = [](const std::string& name, const std::string& body) {
        const std::string p = writeSweep(name, body);
        std::string m = test::messageOf([&] { readSweep(p); });
        return m.substr(m.find("sweep.json") + 10);
    };
    EXPECT_EQ(err("e1", R"({"scene": "nope.json"})").substr(0, 18), ": scene: no such f");
    // A reference rendered with a run's seed would share that run's first samples.
    EXPECT_EQ(err("e1s", R"({"scene": "scene.json", "axes": {"spp": [1, 2]}, "repeats": 2,
                            "reference": {"spp": 8, "seed": 2}})"),
              ": reference.seed: is also the seed of run r0002, which would repeat the "
              "reference's first samples; give the reference another seed");
    EXPECT_EQ(err("e1t", R"({"scene": "scene.json", "axes": {"seed": [5, 6]},
                            "reference": {"spp": 8, "seed": 6}})"),
              ": reference.seed: is also the seed of run r0001, which would repeat the "
              "reference's first samples; give the reference another seed");
    // The default seed that clashes is named as such: the sweep has no reference.seed.
    EXPECT_EQ(err("e1u", R"({"scene": "scene.json", "axes": {"seed": [1000000000]},
                            "reference": {"spp": 8}})"),
              ": reference: its default seed 1000000000 is also the seed of run r0000, which "
              "would repeat the reference's first samples; give the reference a \"seed\" of "
              "its own");
    // No axes, as {} or left out, is one configuration (repeated by "repeats").
    EXPECT_EQ(readSweep(writeSweep("e1a", R"({"scene": "scene.json", "axes": {}, "repeats": 3})"))
                  .runs.size(),
              3u);
    // The spp and seed axes take integral numbers however written, as every integer key does
    // (2.0 and 4e0 were refused here, and taken by render.spp), and keep them as integers.
    {
        const Sweep w =
            readSweep(writeSweep("e3i", R"({"scene": "scene.json", "axes": {"spp": [2.0, 4e0]}})"));
        ASSERT_EQ(w.runs.size(), 2u);
        EXPECT_EQ(w.runs[1].values.at("spp"), Json(4));
        EXPECT_TRUE(w.runs[1].values.at("spp").is_number_integer());
    }
    EXPECT_EQ(err("e3j", R"({"scene": "scene.json", "axes": {"spp": [2.5]}})"),
              ": axes.spp[0]: expected an integer in [1, 2^24], got number 2.5");
    // Each value named by its place, as written (helper 159: none was), 1e30 as out of range.
    for (const auto& [values, said] : std::vector<std::pair<std::string, std::string>>{
             {"[4, -2]", "[1]: expected an integer in [1, 2^24], got number -2"},
             {"[4, \"16\"]", "[1]: expected an integer in [1, 2^24], got string \"16\""},
             {"[true]", "[0]: expected an integer in [1, 2^24], got boolean true"},
             {"[4, 1e30]", "[1]: expected an integer in [1, 2^24], got number 1e+30"},
             {"[16777217]", "[0]: expected an integer in [1, 2^24], got number 16777217"}})
        EXPECT_EQ(err("e3p", R"({"scene": "scene.json", "axes": {"spp": )" + values + "}}"),
                  ": axes.spp" + said)
            << values;
    EXPECT_EQ(err("e1b", R"({"scene": "scene.json", "axes": [1]})"),
              ": axes: expected an object {\"key.path\": [values], …}");
    EXPECT_EQ(
        err("e2",
            R"({"scene": "scene.json", "combine": "zip", "axes": {"spp": [1], "seed": [1, 2]}})"),
        ": axes.seed: zipped axes need equal lengths (2 vs 1)");
    EXPECT_EQ(err("e3", R"({"scene": "scene.json", "axes": {"spp": [0]}})"),
              ": axes.spp[0]: expected an integer in [1, 2^24], got number 0");
    // A malformed key path is named in the sweep, not later as a --set of the scene.
    EXPECT_EQ(err("e3k", R"({"scene": "scene.json", "axes": {"camera[fov": [30, 40]}})"),
              ": axes.camera[fov: expected an index in brackets, as in media[0]");
    EXPECT_EQ(err("e3l", R"({"scene": "scene.json", "axes": {"spp": [1]},
                            "set": ["camera]fov=30"]})"),
              ": set[0]: ']' without '[' in key path");
    // So is a value no scene takes, at the sweep's key (it said "--set value 1e999: …", a --set
    // nobody gave, and no file).
    EXPECT_EQ(err("e3m", R"({"scene": "scene.json", "set": ["media[0].albedo=1e999"]})"),
              ": set[0]: number beyond the range of a double (±1.8e308)");
    EXPECT_EQ(
        err("e3n",
            R"({"scene": "scene.json", "reference": {"set": ["camera={\"fov\": 1, \"fov\": 2}"]}})"),
        ": reference.set[0]: camera: key \"fov\" appears twice (the last would replace the "
        "first)");
    EXPECT_EQ(err("e3s", R"({"scene": "scene.json", "axes": {"seed": [-1]}})"),
              ": axes.seed[0]: expected an integer in [0, 2^53], got number -1");
    // Written with a fraction or an exponent from 2^52 on, where a double holds no fraction:
    // 9007199254740993.0 ran as seed 2^53 (helper 129), as a scene's seed did (helper 127).
    for (const char* seed : {"1e16", "9007199254740993.0", "4503599627370496.5"})
        EXPECT_EQ(
            err("e3t", std::string(R"({"scene": "scene.json", "axes": {"seed": [)") + seed + "]}}"),
            std::string(": axes.seed[0]: ") + kWrittenAsADouble)
            << seed;
    EXPECT_EQ(
        readSweep(
            writeSweep("e3u", R"({"scene": "scene.json", "axes": {"seed": [4503599627370495.0]}})"))
            .runs[0]
            .values["seed"],
        Json(4503599627370495LL));
    EXPECT_EQ(err("e4", R"({"scene": "scene.json", "metrics": ["rmse"]})"),
              ": metrics: metrics need a \"reference\"");
    EXPECT_EQ(err("e4d", R"({"scene": "scene.json", "metrics": ["rmse", "bias", "rmse"],
                             "reference": {"spp": 8}})"),
              ": metrics: \"rmse\" is given twice; give each metric once");
    EXPECT_EQ(err("e4r", R"({"scene": "scene.json", "metrics": [], "reference": {"spp": 8}})"),
              ": metrics: none, but the sweep has a \"reference\", which only metrics use; name "
              "a metric or drop the reference");
    EXPECT_EQ(err("e5", R"({"scene": "scene.json", "axes": {"seed": [1]}, "repeats": 2})"),
              ": axes.seed: give either a seed axis or repeats, not both");
    // The repeats' seeds are integers a scene takes: the last of them at most 2^53.
    EXPECT_EQ(err("e5s", R"({"scene": "scene.json", "seed": 1.5})"),
              ": seed: expected a non-negative integer");
    EXPECT_EQ(err("e5r", R"({"scene": "scene.json", "seed": 9007199254740992, "repeats": 2})"),
              ": seed: the last repeat's seed, seed + repeats - 1, exceeds 2^53");
    EXPECT_EQ(test::messageOf([] {
                  readSweep(writeSweep(
                      "e5e", R"({"scene": "scene.json", "seed": 9007199254740991, "repeats": 2})"));
              }),
              "(no error)");
    EXPECT_EQ(err("e5f", R"({"scene": "scene.json", "reference": {"spp": 8, "seed": 0.5}})"),
              ": reference.seed: expected a non-negative integer");
    // render.seed is the sweep's: in "set" or as an axis it would be replaced without a word.
    const std::string seedIsTheSweeps =
        "the sweep sets render.seed: use its \"seed\" key (or a \"seed\" axis)";
    EXPECT_EQ(err("e5g", R"({"scene": "scene.json", "set": ["render.seed=5"]})"),
              ": set[0]: " + seedIsTheSweeps);
    EXPECT_EQ(err("e5h", R"({"scene": "scene.json", "axes": {"render.seed": [1, 2]}})"),
              ": axes.render.seed: " + seedIsTheSweeps);
    EXPECT_EQ(err("e5i", R"({"scene": "scene.json", "reference": {"set": ["render.seed=5"]}})"),
              ": reference.set[0]: " + seedIsTheSweeps);
    // ... also inside a render object (the sweep's seed replaced it, and the ledger recorded the
    // object's seed, never rendered), and with a seed axis beside the sweep's "seed".
    EXPECT_EQ(err("e5s", R"({"scene": "scene.json", "set": ["render={\"seed\": 77}"]})"),
              ": set[0]: " + seedIsTheSweeps);
    EXPECT_EQ(err("e5t", R"({"scene": "scene.json",
                            "axes": {"render": [{"spp": 2}, {"spp": 2, "seed": 6}]}})"),
              ": axes.render: " + seedIsTheSweeps);
    EXPECT_EQ(
        err("e5u", R"({"scene": "scene.json", "reference": {"set": ["render={\"seed\": 1}"]}})"),
        ": reference.set[0]: " + seedIsTheSweeps);
    EXPECT_EQ(err("e5v", R"({"scene": "scene.json", "seed": 7, "axes": {"seed": [1, 2]}})"),
              ": axes.seed: give either a seed axis or a \"seed\", not both");
    // The same point twice is the same render (the report counted it as a repeat of no spread).
    EXPECT_EQ(err("e5z", R"({"scene": "scene.json", "axes": {"spp": [16, 4, 16]}})"),
              ": axes: runs r0000 and r0002 would be the same render "
              "({\"repeat\":0,\"spp\":16}); give each value once");
    EXPECT_EQ(err("e5z", R"({"scene": "scene.json", "axes": {"seed": [5, 5]}})"),
              ": axes: runs r0000 and r0001 would be the same render "
              "({\"repeat\":0,\"seed\":5}); give each value once");
    EXPECT_EQ(err("e5z", R"({"scene": "scene.json", "combine": "zip",
                            "axes": {"spp": [2, 4, 2], "render.max_depth": [1, 1, 1]}})"),
              ": axes: runs r0000 and r0002 would be the same render "
              "({\"render.max_depth\":1,\"repeat\":0,\"spp\":2}); give each value once");
    // ... also when one of them is written as a float (numbers compare as numbers).
    EXPECT_EQ(err("e5z", R"({"scene": "scene.json", "axes": {"camera.fov": [20, 30, 20.0]}})"),
              ": axes: runs r0000 and r0002 would be the same render "
              "({\"camera.fov\":20.0,\"repeat\":0}); give each value once");
    // The reference's samples per pixel are its "spp" (which replaced render.spp in its "set").
    for (const char* set : {"render.spp=8", "render={\"spp\": 8}"})
        EXPECT_EQ(err("e5w", std::string(R"({"scene": "scene.json", "reference": {"set": [)") +
                                 dumpJson(set) + "]}}"),
                  ": reference.set[0]: the reference's samples per pixel are its \"spp\" key "
                  "(default 4096)");
    // The runs' samples per pixel may come from "set" (without an spp axis).
    EXPECT_EQ(test::messageOf([] {
                  readSweep(writeSweep(
                      "e5x", R"({"scene": "scene.json", "set": ["render={\"spp\": 8}"]})"));
              }),
              "(no error)");
    // An assignment the scene cannot take is named at the sweep's key that gave it, with the
    // scene's place and the run (it named only the scene, and a --set nobody gave).
    const std::string scene =
        (fs::path(testing::TempDir()) / "shvol_sweep_e5y" / "scene.json").string();
    EXPECT_EQ(err("e5y", R"({"scene": "scene.json", "axes": {"render.spp.x": [1]}})"),
              ": axes.render.spp.x: " + scene +
                  ": render.spp: cannot descend into a number (in the run render.spp.x=1 "
                  "repeat=0)");
    EXPECT_EQ(err("e5y", R"({"scene": "scene.json", "set": ["render=5"]})"),
              ": render.seed (set by the sweep): " + scene +
                  ": render: cannot descend into a number (in the run repeat=0)");
    EXPECT_EQ(err("e5y", R"({"scene": "scene.json", "reference": {"set": ["render.spp.x=1"]}})"),
              ": reference.set[0]: " + scene +
                  ": render.spp: cannot descend into a number (in the reference)");
    // Two axes for one key: the later would overwrite the earlier, whose values the ledger
    // would record although they were never rendered.
    EXPECT_EQ(err("e5j", R"({"scene": "scene.json",
                            "axes": {"media.0.albedo": [0.1, 0.5], "media[0].albedo": [0.9]}})"),
              ": axes.media[0].albedo: sets the same key as axes.media.0.albedo");
    EXPECT_EQ(err("e5k", R"({"scene": "scene.json", "axes": {"spp": [2, 4], "render.spp": [8]}})"),
              ": axes.render.spp: sets the same key as axes.spp");
    EXPECT_EQ(err("e5l", R"({"scene": "scene.json",
                            "axes": {"media[0].phase": [{"type": "hg", "g": 0.5}],
                                     "media[0].phase.g": [0.1, 0.2]}})"),
              ": axes.media[0].phase.g: sets a key inside axes.media[0].phase; vary one of them");
    EXPECT_EQ(err("e5m", R"({"scene": "scene.json",
                            "axes": {"media.0.albedo": [0.2, 0.9], "media.0": [{"albedo": 0.5}]}})"),
              ": axes.media.0: contains the key of axes.media.0.albedo; vary one of them");
    // Keys that share only the start of a name are different keys.
    EXPECT_EQ(test::messageOf([] {
                  readSweep(writeSweep("e5n", R"({"scene": "scene.json",
                      "axes": {"media[0].albedo": [0.5], "media[0].albedo_x": [1]}})"));
              }),
              "(no error)");
    // The number of runs is checked before they are expanded (1000³ would exhaust memory).
    std::string thousand = "[0";
    for (int i = 1; i < 1000; ++i) thousand += "," + std::to_string(i);
    thousand += "]";
    EXPECT_EQ(err("e5j", R"({"scene": "scene.json", "axes": {"render.max_depth": )" + thousand +
                             R"(, "render.rr_depth": )" + thousand + R"(, "camera.fov": )" +
                             thousand + "}}"),
              ": axes: 1000000000 runs (1000 × 1000 × 1000 points, 1 repeat each); a sweep has at "
              "most 100000");
    EXPECT_EQ(err("e5k", R"({"scene": "scene.json", "combine": "zip", "repeats": 1001,
                             "axes": {"render.max_depth": )" +
                             thousand + R"(, "render.rr_depth": )" + thousand + "}}"),
              ": axes: 1001000 runs (1000 zipped points, 1001 repeats each); a sweep has at most "
              "100000");
    EXPECT_EQ(err("e5l", R"({"scene": "scene.json", "repeats": 1000000, "axes": {"spp": [1, 2]}})"),
              ": axes: 2000000 runs (2 points, 1000000 repeats each); a sweep has at most 100000");
    // 101 × 1000: a little above the limit (10⁶ until 7 Dec, which took minutes to read).
    std::string hundredOne = "[1";
    for (int i = 2; i <= 101; ++i) hundredOne += "," + std::to_string(i);
    hundredOne += "]";
    EXPECT_EQ(err("e5q", R"({"scene": "scene.json", "axes": {"spp": )" + hundredOne +
                             R"(, "render.max_depth": )" + thousand + "}}"),
              ": axes: 101000 runs (101 × 1000 points, 1 repeat each); a sweep has at most "
              "100000");
    // A lower limit (the sweep fuzzer's): at it the sweep is read, above it refused.
    const std::string six = writeSweep("e5o", R"({"scene": "scene.json", "repeats": 3,
                                                  "axes": {"spp": [1, 2]}})");
    EXPECT_EQ(readSweep(six, 6).runs.size(), 6u);
    const std::string over = test::messageOf([&] { readSweep(six, 5); });
    EXPECT_EQ(over.substr(over.find("sweep.json") + 10),
              ": axes: 6 runs (2 points, 3 repeats each); a sweep has at most 5");
    const std::string repeats = test::messageOf(
        [&] { readSweep(writeSweep("e5p", R"({"scene": "scene.json", "repeats": 6})"), 5); });
    EXPECT_EQ(repeats.substr(repeats.find("sweep.json") + 10),
              ": repeats: 6 runs (1 point, 6 repeats each); a sweep has at most 5");
    // (with the key the reader asks about though the sweep lacks it; helper 86)
    EXPECT_EQ(err("e6", R"({"scene": "scene.json", "axis": {}})"),
              ": axis: unknown key (did you mean \"axes\"?)");
    // The z-test's standard errors need 2 samples per pixel, in every run and in the reference.
    EXPECT_EQ(err("e8", R"({"scene": "scene.json", "axes": {"spp": [1, 4]},
                            "reference": {"spp": 64}, "metrics": ["ztest"]})"),
              ": metrics: ztest needs standard errors, which need at least 2 samples per pixel; "
              "run r0000 has 1");
    EXPECT_EQ(
        err("e9", R"({"scene": "scene.json", "reference": {"spp": 1}, "metrics": ["ztest"]})"),
        ": metrics: ztest needs standard errors, which need at least 2 samples per pixel; "
        "the reference has 1");
    // A reference file is looked for when the sweep is read (so --dry-run finds it missing too).
    const std::string e7 = err("e7", R"({"scene": "scene.json", "reference": {"file": "r.exr"}})");
    EXPECT_EQ(e7.rfind(": reference.file: no such file: ", 0), 0u) << e7;
    EXPECT_EQ(err("e10", R"({"scene": "scene.json", "reference": {"file": "r.exr", "spp": 4}})"),
              ": reference.file: a reference is either a file or a render spec (spp, set, seed), "
              "not both");
}

}  // namespace shvol
