#include "shvol/io/checkpoint.h"

#include <gtest/gtest.h>

#include "shvol/io/provenance.h"
#include "shvol/io/scene_loader.h"

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>

#include "shvol/core/error.h"
#include "shvol/core/hash.h"
#include "test_util.h"

namespace shvol {

namespace {

std::string tempPath(const std::string& name) {
    return testing::TempDir() + "ckpt_" + name;
}

/// The identity of a small scene, rendered by build "abc".
Json sampleIdentity() {
    return renderIdentity(Json{{"camera", {{"fov", 30}}}, {"render", {{"seed", 1}}}}, Json::array(),
                          "abc");
}

Film sampleFilm() {
    Film f(3, 2);
    for (size_t i = 0; i < f.pixels(); ++i) {
        f.count[i] = uint32_t(i + 1);
        for (int c = 0; c < 3; ++c) f.sum[3 * i + c] = 0.1 * double(i) + c + 1e-17 * double(i);
        f.luminanceSumSq[i] = 0.3 * double(i) + 1e-17;
    }
    return f;
}

/// Rewrites checkpoint `p` through `edit` (given the bytes before the checksum) and gives it the
/// right checksum again (checkpoint.h: FNV-1a of all before it).
void rewriteWithChecksum(const std::string& p, const std::function<void(std::string&)>& edit) {
    std::string bytes = test::fileBytes(p);
    bytes.resize(bytes.size() - 8);
    edit(bytes);
    const uint64_t sum = fnv1a(bytes.data(), bytes.size());
    bytes.append(reinterpret_cast<const char*>(&sum), 8);
    std::ofstream(p, std::ios::binary | std::ios::trunc) << bytes;
}

}  // namespace

TEST(Checkpoint, RoundTripIsExact) {
    const std::string p = tempPath("round.bin");
    const Film f = sampleFilm();
    writeCheckpoint(p, f, sampleIdentity());
    const Film g = readCheckpoint(p, sampleIdentity());
    EXPECT_EQ(g.width, 3);
    EXPECT_EQ(g.height, 2);
    EXPECT_EQ(g.count, f.count);
    EXPECT_EQ(g.sum, f.sum);  // bit-exact doubles
    EXPECT_TRUE(g.sumSq.empty());
    EXPECT_EQ(g.luminanceSumSq, f.luminanceSumSq);
    // A film whose luminances' squares are unknown is read back so (flags bit 1 clear).
    Film unknown = sampleFilm();
    unknown.luminanceSumSq.clear();
    writeCheckpoint(p, unknown, sampleIdentity());
    EXPECT_TRUE(readCheckpoint(p, sampleIdentity()).luminanceSumSq.empty());
    Film v = sampleFilm();  // with sums of squares (--variance)
    v.sumSq.assign(v.sum.size(), 0.25);
    v.sumSq[5] = 7.5;
    writeCheckpoint(p, v, sampleIdentity());
    EXPECT_EQ(readCheckpoint(p, sampleIdentity()).sumSq, v.sumSq);
}

TEST(Checkpoint, DamagedOrForeignFilesAreRefused) {
    const std::string p = tempPath("bad.bin");
    const Json id = sampleIdentity();
    writeCheckpoint(p, sampleFilm(), id);
    Json other = id;
    other["build"] = "abd";
    EXPECT_EQ(test::messageOf([&] { readCheckpoint(p, other); }),
              p + ": written for a different render: it was saved by shvol build abc, this is abd "
                  "(only the sample count may change)");
    // (the layout of checkpoint.h: magic and identity length, the identity, width, height and
    // flags, 4 + 3·8 + 8 bytes per pixel, a checksum of 8)
    const size_t header = 8 + 4 + dumpJson(id).size() + 12;
    ASSERT_EQ(std::filesystem::file_size(p), header + 6 * (4 + 3 * 8 + 8) + 8);
    {  // flip one byte of the sums
        std::fstream f(p, std::ios::in | std::ios::out | std::ios::binary);
        f.seekp(std::streamoff(header + 6 * 4 + 5));
        f.put('\x7f');
    }
    EXPECT_EQ(test::messageOf([&] { readCheckpoint(p, id); }),
              p + ": checksum mismatch (corrupt file)");
    std::filesystem::resize_file(p, header + 10);
    EXPECT_EQ(test::messageOf([&] { readCheckpoint(p, id); }),
              p + ": " + std::to_string(header + 10) + " bytes where its header (3x2) needs " +
                  std::to_string(header + 6 * (4 + 3 * 8 + 8) + 8) +
                  ": truncated, padded or corrupt");
    std::filesystem::resize_file(p, 40);
    EXPECT_EQ(test::messageOf([&] { readCheckpoint(p, id); }),
              p + ": header: 40 bytes, too few for its header (an identity of " +
                  std::to_string(dumpJson(id).size()) + " bytes): truncated or corrupt");
    std::ofstream(p) << "SHVOLCK1" << std::string(100, '\0');  // format 1
    EXPECT_EQ(test::messageOf([&] { readCheckpoint(p, id); }),
              p + ": a checkpoint of an earlier shvol (checkpoint format 1), which this build "
                  "cannot resume: start afresh");
    // A file of another kind, or an empty one, is named as such (helper 139: all were "not a
    // shvol checkpoint").
    std::ofstream(p) << "{\"not\": \"a checkpoint\"}";
    EXPECT_EQ(test::messageOf([&] { readCheckpoint(p, id); }),
              p + ": the file is JSON text, not a shvol checkpoint");
    // (its brace past the 8 bytes of the magic: a byte order mark and blank lines before it)
    std::ofstream(p) << "\xEF\xBB\xBF\n\n\n\n    \n{\"a\": 1}";
    EXPECT_EQ(test::messageOf([&] { readCheckpoint(p, id); }),
              p + ": the file is JSON text, not a shvol checkpoint");
    std::ofstream(p) << "\x76\x2f\x31\x01" << std::string(40, 'x');
    EXPECT_EQ(test::messageOf([&] { readCheckpoint(p, id); }),
              p + ": the file is an OpenEXR image, not a shvol checkpoint");
    std::ofstream(p) << "";
    EXPECT_EQ(test::messageOf([&] { readCheckpoint(p, id); }),
              p + ": empty, not a shvol checkpoint");
    std::ofstream(p) << "SHVOLCK";
    EXPECT_EQ(test::messageOf([&] { readCheckpoint(p, id); }), p + ": not a shvol checkpoint");
    EXPECT_EQ(test::messageOf([&] { readCheckpoint(tempPath("missing.bin"), id); }),
              tempPath("missing.bin") + ": no such file");
    // A directory opens as a stream and fails only when read: named as what it is.
    EXPECT_EQ(test::messageOf([&] { readCheckpoint(testing::TempDir(), id); }),
              testing::TempDir() + ": not a regular file");
}

// Damage the checksum does not catch (a file edited and re-summed, or shvol's own bug): a sum that
// is not finite would reach the image, and an identity of another form could not be compared.
TEST(Checkpoint, DamageBehindAValidChecksumIsRefused) {
    const std::string p = tempPath("resummed.bin");
    const Json id = sampleIdentity();
    const size_t header = 8 + 4 + dumpJson(id).size() + 12, sums = header + 6 * 4;
    const auto withValue = [&](size_t offset, double v) {
        writeCheckpoint(p, sampleFilm(), id);
        rewriteWithChecksum(p, [&](std::string& b) { std::memcpy(&b[offset], &v, 8); });
    };
    withValue(sums + (3 * 4 + 1) * 8, std::nan(""));  // pixel 4 = (1, 1), green
    EXPECT_EQ(test::messageOf([&] { readCheckpoint(p, id); }),
              p + ": pixel (1, 1): a sum that is not finite (corrupt file)");
    withValue(sums + 2 * 8, -HUGE_VAL);  // pixel (0, 0), blue
    EXPECT_EQ(test::messageOf([&] { readCheckpoint(p, id); }),
              p + ": pixel (0, 0): a sum that is not finite (corrupt file)");
    withValue(sums, -1e300);  // finite, whatever its sign: read back as it is
    EXPECT_EQ(readCheckpoint(p, id).sum[0], -1e300);
    // Sums in a pixel of no samples (helper 170: the image had them).
    writeCheckpoint(p, sampleFilm(), id);
    rewriteWithChecksum(p, [&](std::string& b) { std::memset(&b[header + 3 * 4], 0, 4); });
    EXPECT_EQ(test::messageOf([&] { readCheckpoint(p, id); }),
              p + ": pixel (0, 1): sums in a pixel of no samples (corrupt file)");

    Film variance = sampleFilm();
    variance.sumSq = variance.sum;
    writeCheckpoint(p, variance, id);
    rewriteWithChecksum(p, [&](std::string& b) {
        const double v = -0.5;
        std::memcpy(&b[sums + 6 * 3 * 8 + (3 * 5) * 8], &v, 8);  // pixel 5 = (2, 1)
    });
    EXPECT_EQ(test::messageOf([&] { readCheckpoint(p, id); }),
              p + ": pixel (2, 1): a sum of squares that is negative or not finite (corrupt file)");
    writeCheckpoint(p, sampleFilm(), id);  // the luminances' squares follow the sums
    rewriteWithChecksum(p, [&](std::string& b) {
        const double v = std::nan("");
        std::memcpy(&b[sums + 6 * 3 * 8 + 4 * 8], &v, 8);  // pixel 4 = (1, 1)
    });
    EXPECT_EQ(test::messageOf([&] { readCheckpoint(p, id); }),
              p + ": pixel (1, 1): a sum of squared luminances that is negative or not finite "
                  "(corrupt file)");

    for (const char* identity : {R"({"scene": 5, "inputs": {}, "build": "abc"})",
                                 R"({"scene": {"a": 1}, "inputs": {}, "build": "abc"})",
                                 R"({"scene": {}, "inputs": {}})", "[1, 2]"}) {
        writeCheckpoint(p, sampleFilm(), id);
        rewriteWithChecksum(p, [&](std::string& b) {
            const std::string text = identity;
            const uint32_t n = uint32_t(text.size());
            b = b.substr(0, 8) + std::string(reinterpret_cast<const char*>(&n), 4) + text +
                b.substr(12 + dumpJson(id).size());
        });
        EXPECT_EQ(test::messageOf([&] { readCheckpoint(p, id); }),
                  p + ": header: its identity is not of the form shvol writes (corrupt file)")
            << identity;
    }
    // The comparison itself takes any JSON without throwing (parts of another form count as empty).
    EXPECT_EQ(identityDifference(Json::parse(R"({"scene": [1], "inputs": 2, "build": 3})"), id),
              "scene values camera.fov and render.seed differ (scene file, --set or --seed); it "
              "was saved by shvol build (unknown), this is abc");
    EXPECT_EQ(identityDifference(Json(7), Json(7)), "");
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
        return renderIdentity(doc, inputFiles(doc, scene), build);
    };
    const Json id0 = id({});
    EXPECT_EQ(id({"render.spp=100"}), id0);
    EXPECT_EQ(identityDifference(id0, id({"render.spp=100"})), "");
    EXPECT_EQ(identityDifference(id0, id({"render.seed=2"})),
              "scene value render.seed differs (scene file, --set or --seed)");
    EXPECT_EQ(identityDifference(id0, id({"camera.fov=31", "media[0].phase.type=hg"})),
              "scene values camera.fov and media[0].phase differ (scene file, --set or --seed)");
    // One file named otherwise is the same input (its name was compared as text; helper 55).
    EXPECT_EQ(identityDifference(id0, id({"media[0].phase.file=\"" + table + "\""})), "");
    EXPECT_EQ(identityDifference(
                  id0, id({"media[0].phase.file=\"" + testing::TempDir() + "./ckpt_table.csv\""})),
              "");
    // Numbers compare as numbers, however written (40.0 was refused against 40; helper 55).
    EXPECT_EQ(identityDifference(id0, id({"camera.fov=30.0", "render.seed=1e0"})), "");
    // A value only one of them has differs too.
    EXPECT_EQ(identityDifference(id0, id({"camera.up=[0,0,1]"})),
              "scene value camera.up differs (scene file, --set or --seed)");
    EXPECT_EQ(identityDifference(id0, id({}, "abd")),
              "it was saved by shvol build abc, this is abd");
    std::ofstream(table) << "angle_deg,value\n0,3\n180,1\n";  // same name, other contents
    EXPECT_EQ(identityDifference(id0, id({"render.seed=2"}, "abd")),
              "scene value render.seed differs (scene file, --set or --seed); the file named by "
              "media[0].phase.file differs in contents; it was saved by shvol build abc, this is "
              "abd");
}

// An object the sample count leaves empty sets nothing: it is no part of the identity.
TEST(Checkpoint, IdentityLeavesOutEmptiedObjects) {
    EXPECT_EQ(renderIdentity(Json{{"render", {{"spp", 4}}}}, Json::array(), "x"),
              renderIdentity(Json::object(), Json::array(), "x"));
    EXPECT_NE(renderIdentity(Json{{"render", {{"seed", 4}}}}, Json::array(), "x"),
              renderIdentity(Json::object(), Json::array(), "x"));
}

// Many differing parts are listed up to six, then counted.
TEST(Checkpoint, IdentityDifferenceListsAtMostSixParts) {
    Json a = Json::object(), b = Json::object();
    for (int i = 0; i < 9; ++i) a["k" + std::to_string(i)] = i, b["k" + std::to_string(i)] = -i;
    EXPECT_EQ(
        identityDifference(renderIdentity(a, Json::array(), "x"),
                           renderIdentity(b, Json::array(), "x")),
        "scene values k1, k2, k3, k4, k5, k6 and 2 more differ (scene file, --set or --seed)");
}

}  // namespace shvol
