#include "shvol/io/provenance.h"

#include <gtest/gtest.h>

#include "shvol/io/scene_loader.h"

#include <filesystem>
#include <fstream>

#include "shvol/core/hash.h"

namespace shvol {

namespace fs = std::filesystem;

// Published FNV-1a 64 test vectors: "" → cbf29ce484222325, "a" → af63dc4c8601ec8c.
TEST(Provenance, Fnv1aTestVectors) {
    EXPECT_EQ(hexHash(fnv1a("", 0)), "cbf29ce484222325");
    EXPECT_EQ(hexHash(fnv1a("a", 1)), "af63dc4c8601ec8c");
}

TEST(Provenance, InputFilesFollowEveryFileKey) {
    const fs::path dir = fs::path(testing::TempDir()) / "shvol_provenance";
    fs::create_directories(dir / "sub");
    std::ofstream(dir / "sub" / "grid.vdb") << "a";
    std::ofstream(dir / "sky.exr") << "";
    std::ofstream(dir / "table.csv") << "0,1\n180,1\n";
    const std::string scene = (dir / "scene.json").string();
    std::ofstream(scene) << R"({"environment": {"type": "image", "file": "sky.exr"},
        "media": [{"file": "sub/grid.vdb"}, {"phase": {"type": "tabulated", "file": "nope.csv"}}]})";
    const Json in = inputFiles(
        sceneDocument(scene, {"media[1].phase.file=" + (dir / "table.csv").string()}), scene);
    ASSERT_EQ(in.size(), 4u);
    EXPECT_EQ(in[0]["key"], "(scene)");
    EXPECT_EQ(in[1]["key"], "environment.file");
    EXPECT_EQ(in[1]["fnv1a64"], "cbf29ce484222325");
    EXPECT_EQ(in[2]["key"], "media[0].file");
    EXPECT_EQ(in[2]["path"], (dir / "sub" / "grid.vdb").string());
    EXPECT_EQ(in[2]["bytes"], 1);
    EXPECT_EQ(in[2]["fnv1a64"], "af63dc4c8601ec8c");
    EXPECT_EQ(in[3]["key"], "media[1].phase.file");  // the override, not the missing nope.csv
    EXPECT_EQ(in[3]["bytes"], 10);
}

TEST(Provenance, CommandLineAndMachine) {
    const std::string cl = commandLine();
    EXPECT_NE(cl.find("test_io"), std::string::npos) << cl;
    const Json m = machineDescription();
    EXPECT_GT(m["hardware_threads"].get<int>(), 0);
    EXPECT_TRUE(m.contains("os"));
}

}  // namespace shvol
