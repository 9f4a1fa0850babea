#include "shvol/io/checkpoint.h"

#include <gtest/gtest.h>

#include "shvol/io/provenance.h"
#include "shvol/io/scene_loader.h"

#include <filesystem>
#include <fstream>

#include "shvol/core/error.h"
#include "test_util.h"

namespace shvol {

namespace {

std::string tempPath(const std::string& name) {
    return testing::TempDir() + "ckpt_" + name;
}

Film sampleFilm() {
    Film f(3, 2);
    for (size_t i = 0; i < f.pixels(); ++i) {
        f.count[i] = uint32_t(i + 1);
        for (int c = 0; c < 3; ++c) f.sum[3 * i + c] = 0.1 * double(i) + c + 1e-17 * double(i);
    }
    return f;
}

}  // namespace

TEST(Checkpoint, RoundTripIsExact) {
    const std::string p = tempPath("round.bin");
    const Film f = sampleFilm();
    writeCheckpoint(p, f, 42);
    const Film g = readCheckpoint(p, 42);
    EXPECT_EQ(g.width, 3);
    EXPECT_EQ(g.height, 2);
    EXPECT_EQ(g.count, f.count);
    EXPECT_EQ(g.sum, f.sum);  // bit-exact doubles
    EXPECT_TRUE(g.sumSq.empty());
    Film v = sampleFilm();  // with sums of squares (--variance)
    v.sumSq.assign(v.sum.size(), 0.25);
    v.sumSq[5] = 7.5;
    writeCheckpoint(p, v, 42);
    EXPECT_EQ(readCheckpoint(p, 42).sumSq, v.sumSq);
}

TEST(Checkpoint, DamagedOrForeignFilesAreRefused) {
    const std::string p = tempPath("bad.bin");
    writeCheckpoint(p, sampleFilm(), 42);
    EXPECT_EQ(test::messageOf([&] { readCheckpoint(p, 43); }),
              p + ": written for a different render (scene, --set values, seed, resolution, input "
                  "files or shvol build differ; only the sample count may change)");
    {  // flip one byte of the sums
        std::fstream f(p, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(60);
        f.put('\x7f');
    }
    EXPECT_EQ(test::messageOf([&] { readCheckpoint(p, 42); }),
              p + ": checksum mismatch (corrupt file)");
    std::filesystem::resize_file(p, 50);
    // (the layout of checkpoint.h: a header of 28 bytes, 4 + 3·8 per pixel, a checksum of 8)
    EXPECT_EQ(test::messageOf([&] { readCheckpoint(p, 42); }),
              p + ": 50 bytes where its header (3x2) needs " +
                  std::to_string(28 + 6 * (4 + 3 * 8) + 8) + ": truncated, padded or corrupt");
    std::ofstream(p) << "{\"not\": \"a checkpoint\"}";
    EXPECT_EQ(test::messageOf([&] { readCheckpoint(p, 42); }), p + ": not a shvol checkpoint");
    EXPECT_EQ(test::messageOf([&] { readCheckpoint(tempPath("missing.bin"), 42); }),
              tempPath("missing.bin") + ": no such file");
    // A directory opens as a stream and fails only when read: named as what it is.
    EXPECT_EQ(test::messageOf([&] { readCheckpoint(testing::TempDir(), 42); }),
              testing::TempDir() + ": not a regular file");
}

// The identity ignores render.spp (a render may be continued to more samples) and follows the
// rest of the scene document, the contents of the files it names (not their names' spelling
// alone) and the program's build.
TEST(Checkpoint, IdentityIgnoresOnlyTheSampleCount) {
    const std::string scene = tempPath("scene.json"), table = tempPath("table.csv");
    std::ofstream(scene) << R"({"render": {"spp": 4, "seed": 1}, "camera": {"fov": 30},
        "media": [{"type": "homogeneous", "sigma_t": 1,
                   "phase": {"type": "tabulated", "file": "ckpt_table.csv"}}]})";
    std::ofstream(table) << "angle_deg,value\n0,2\n180,1\n";
    auto id = [&](const std::vector<std::string>& sets, const std::string& build = "abc") {
        const Json doc = sceneDocument(scene, sets);
        return renderIdentity(doc, namedFileContents(inputFiles(doc, scene)), build);
    };
    const uint64_t id0 = id({});
    EXPECT_EQ(id({"render.spp=100"}), id0);
    EXPECT_NE(id({"render.seed=2"}), id0);
    EXPECT_NE(id({"camera.fov=31"}), id0);
    EXPECT_NE(id({}, "abd"), id0);                            // another build of shvol
    std::ofstream(table) << "angle_deg,value\n0,3\n180,1\n";  // same name, other contents
    EXPECT_NE(id({}), id0);
}

}  // namespace shvol
