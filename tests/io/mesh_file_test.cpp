#include "shvol/io/mesh_file.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>

#include "shvol/core/error.h"
#include "test_util.h"

namespace shvol {
namespace {

using shvol::test::messageOf;

std::string tmp(const std::string& name) {
    return test::privateTempPath(name);
}

std::string write(const std::string& name, const std::string& bytes) {
    const std::string path = tmp(name);
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
}

/// The message of the shvol::Error that reading `bytes` as a file called `name` throws; checks
/// that it is one line starting with the file's path.
std::string errorOf(const std::string& name, const std::string& bytes) {
    const std::string path = write(name, bytes);
    const std::string m = messageOf([&] { readMesh(path); });
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    EXPECT_EQ(m.rfind(path + ": ", 0), 0u) << m;
    return m;
}

#define EXPECT_CONTAINS(text, part) \
    EXPECT_NE(std::string(text).find(part), std::string::npos) << (text)

/// Binary data in either byte order.
struct Bytes {
    bool big;
    std::string s;
    template <typename T>
    Bytes& put(T x) {
        char b[sizeof(T)];
        std::memcpy(b, &x, sizeof x);
        if (big) std::reverse(b, b + sizeof b);
        s.append(b, sizeof b);
        return *this;
    }
};

// A square pyramid: base quad (0, 3, 2, 1) facing −z, four triangles to the apex 4.
const double kPyramid[5][3] = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {1, 1, 1}};
const uint32_t kPyramidQuad[4] = {0, 3, 2, 1};
const uint32_t kPyramidTris[4][3] = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
const std::vector<uint32_t> kPyramidIndices = {0, 3, 2, 0, 2, 1, 0, 1, 4,
                                               1, 2, 4, 2, 3, 4, 3, 0, 4};

void expectPyramid(const TriangleMesh& m, bool normals, bool uvs) {
    ASSERT_EQ(m.p.size(), 5u);
    for (int i = 0; i < 5; ++i)
        EXPECT_EQ(m.p[i], Vec3(kPyramid[i][0], kPyramid[i][1], kPyramid[i][2])) << i;
    EXPECT_EQ(m.indices, kPyramidIndices);
    EXPECT_EQ(closedMeshDefect(m), "");
    EXPECT_DOUBLE_EQ(signedVolume(m), 4.0 / 3);
    ASSERT_EQ(m.n.size(), normals ? 5u : 0u);
    for (size_t i = 0; i < m.n.size(); ++i) EXPECT_EQ(m.n[i], Vec3(0, 0.5 * i, -1)) << i;
    ASSERT_EQ(m.uv.size(), uvs ? 5u : 0u);
    for (size_t i = 0; i < m.uv.size(); ++i) EXPECT_EQ(m.uv[i], Vec2(0.25 * i, 1 - 0.25 * i));
}

TEST(MeshFile, AsciiPly) {
    std::string t =
        "ply\n"
        "format ascii 1.0\n"
        "comment made by hand\n"
        "obj_info pyramid\n"
        "element vertex 5\n"
        "property float x\n"
        "property float y\n"
        "property float z\n"
        "property uchar red\n"  // skipped
        "property float nx\n"
        "property float ny\n"
        "property float nz\n"
        "property float s\n"
        "property float t\n"
        "element face 5\n"
        "property int flags\n"                      // skipped
        "property list uchar int vertex_indices\n"  //
        "property list uchar float texcoord\n"      // skipped
        "element material 1\n"                      // skipped
        "property list ushort uint8 name\n"         //
        "end_header\n";
    for (int i = 0; i < 5; ++i)
        t += std::to_string(kPyramid[i][0]) + " " + std::to_string(kPyramid[i][1]) + "\t" +
             std::to_string(kPyramid[i][2]) + " 255 0 " + std::to_string(0.5 * i) + " -1 " +
             std::to_string(0.25 * i) + " " + std::to_string(1 - 0.25 * i) + "\n";
    t += "7 4 0 3 2 1 2 0.5 0.5\n";
    t += "\n";  // blank lines are allowed between records
    for (const auto& f : kPyramidTris)
        t += "-3 3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " +
             std::to_string(f[2]) + " 0\r\n";
    t += "3 65 66 67\n\n";
    expectPyramid(readPly(write("ascii.ply", t)), true, true);
    // A UTF-8 byte-order mark is skipped, as for OBJ (it was "not a PLY file"; helper 161).
    expectPyramid(readPly(write("bom.ply", "\xEF\xBB\xBF" + t)), true, true);
}

/// The pyramid in binary: double positions, normals and texture coordinates (u, v) as floats,
/// uchar counts and int indices, with unused properties and elements in between.
std::string binaryPyramid(bool big) {
    std::string h = std::string("ply\nformat ") +
                    (big ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\n"
                    "element camera 1\n"
                    "property list int short view\n"
                    "property double focal\n"
                    "element vertex 5\n"
                    "property double x\n"
                    "property double y\n"
                    "property double z\n"
                    "property float u\n"
                    "property float v\n"
                    "property uint16 confidence\n"
                    "property float nx\n"
                    "property float ny\n"
                    "property float nz\n"
                    "element face 5\n"
                    "property list uchar int vertex_indices\n"
                    "property char flag\n"
                    "end_header\n";
    Bytes b{big, h};
    b.put<int32_t>(2).put<int16_t>(-7).put<int16_t>(300).put<double>(35);
    for (int i = 0; i < 5; ++i) {
        b.put(kPyramid[i][0]).put(kPyramid[i][1]).put(kPyramid[i][2]);
        b.put(float(0.25 * i)).put(float(1 - 0.25 * i)).put<uint16_t>(65535);
        b.put(0.0f).put(float(0.5 * i)).put(-1.0f);
    }
    b.put<uint8_t>(4);
    for (uint32_t i : kPyramidQuad) b.put(int32_t(i));
    b.put<int8_t>(-1);
    for (const auto& f : kPyramidTris) {
        b.put<uint8_t>(3);
        for (uint32_t i : f) b.put(int32_t(i));
        b.put<int8_t>(1);
    }
    return b.s;
}

TEST(MeshFile, BinaryLittleEndianPly) {
    expectPyramid(readPly(write("le.ply", binaryPyramid(false))), true, true);
}

TEST(MeshFile, BinaryBigEndianPly) {
    expectPyramid(readPly(write("be.ply", binaryPyramid(true))), true, true);
    expectPyramid(parsePly(binaryPyramid(true), "in memory"), true, true);
}

/// Every PLY scalar type, by both of its names, as positions, list counts and indices.
TEST(MeshFile, PlyScalarTypes) {
    const char* names[][2] = {{"char", "int8"},     {"uchar", "uint8"},   {"short", "int16"},
                              {"ushort", "uint16"}, {"int", "int32"},     {"uint", "uint32"},
                              {"float", "float32"}, {"double", "float64"}};
    for (int t = 0; t < 8; ++t)
        for (const char* name : names[t])
            for (const char* format : {"ascii", "binary_little_endian", "binary_big_endian"}) {
                SCOPED_TRACE(std::string(name) + " " + format);
                const std::string type = name;
                const bool integer = t < 6;
                std::string h = std::string("ply\nformat ") + format + " 1.0\nelement vertex 4\n";
                for (const char* c : {"x", "y", "z"}) h += "property " + type + " " + c + "\n";
                h += "element face 4\n";
                h += "property list " + std::string(integer ? name : "uchar") + " " +
                     (integer ? type : "uint") + " vertex_indices\nend_header\n";
                const int p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
                const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
                std::string body;
                if (format[0] == 'a') {
                    for (const auto& v : p)
                        body += std::to_string(v[0]) + " " + std::to_string(v[1]) + " " +
                                std::to_string(v[2]) + "\n";
                    for (const auto& v : f)
                        body += "3 " + std::to_string(v[0]) + " " + std::to_string(v[1]) + " " +
                                std::to_string(v[2]) + "\n";
                } else {
                    Bytes b{format[7] == 'b', ""};
                    const auto put = [&](int x) {
                        switch (t) {
                            case 0:
                                b.put(int8_t(x));
                                break;
                            case 1:
                                b.put(uint8_t(x));
                                break;
                            case 2:
                                b.put(int16_t(x));
                                break;
                            case 3:
                                b.put(uint16_t(x));
                                break;
                            case 4:
                                b.put(int32_t(x));
                                break;
                            case 5:
                                b.put(uint32_t(x));
                                break;
                            case 6:
                                b.put(float(x));
                                break;
                            default:
                                b.put(double(x));
                        }
                    };
                    for (const auto& v : p)
                        for (int x : v) put(x);
                    for (const auto& v : f) {
                        if (integer)
                            put(3);
                        else
                            b.put(uint8_t(3));
                        for (int x : v)
                            if (integer)
                                put(x);
                            else
                                b.put(uint32_t(x));
                    }
                    body = b.s;
                }
                const TriangleMesh m = parsePly(h + body, "types.ply");
                ASSERT_EQ(m.p.size(), 4u);
                for (int i = 0; i < 4; ++i) EXPECT_EQ(m.p[i], Vec3(p[i][0], p[i][1], p[i][2]));
                EXPECT_EQ(m.indices, std::vector<uint32_t>({0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3}));
                EXPECT_DOUBLE_EQ(signedVolume(m), 1.0 / 6);
            }
}

TEST(MeshFile, PlyFanKeepsTheWinding) {
    const std::string t =
        "ply\nformat ascii 1.0\nelement vertex 6\nproperty float x\nproperty float y\n"
        "property float z\nelement face 1\nproperty list uchar uint vertex_index\nend_header\n"
        "0 0 0\n1 0 0\n2 1 0\n1 2 0\n0 2 0\n-1 1 0\n6 0 1 2 3 4 5\n";
    const TriangleMesh m = parsePly(t, "hexagon.ply");
    EXPECT_EQ(m.indices, std::vector<uint32_t>({0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 5}));
    for (size_t f = 0; f < m.triangleCount(); ++f) {  // all facing +z, as the hexagon
        const Vec3 p0 = m.p[m.indices[3 * f]];
        EXPECT_GT((m.p[m.indices[3 * f + 1]] - p0).cross(m.p[m.indices[3 * f + 2]] - p0).z(), 0);
    }
    EXPECT_DOUBLE_EQ(surfaceArea(m), 4.0);
}

const std::string kAsciiHead =
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
    "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n";
const std::string kFaces = "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
const std::string kAsciiTet = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n" + kFaces;

TEST(MeshFile, PlyHeaderErrors) {
    EXPECT_CONTAINS(errorOf("e1.ply", "plyx\n"), "line 1: not a PLY file");
    EXPECT_CONTAINS(errorOf("e2.ply", "PK\3\4 zip"), "line 1: not a PLY file");
    EXPECT_CONTAINS(
        errorOf("e3.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"),
        "line 4: end of file before end_header");
    EXPECT_CONTAINS(errorOf("e4.ply",
                            "ply\nformat ascii 1.0\nelement vertex 1\nproperty "
                            "float128 x\nend_header\n"),
                    "line 4: unknown type \"float128\"");
    EXPECT_CONTAINS(errorOf("e5.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n"),
                    "line 2: unknown format \"binary_middle_endian\"");
    EXPECT_CONTAINS(errorOf("e6.ply", "ply\nformat ascii 2.0\nend_header\n"),
                    "line 2: unsupported PLY version \"2.0\"");
    EXPECT_CONTAINS(errorOf("e7.ply", "ply\nformat ascii 1.0\nelemnt vertex 1\nend_header\n"),
                    "line 3: unknown header keyword \"elemnt\"");
    EXPECT_CONTAINS(errorOf("e8.ply", "ply\nformat ascii 1.0\nproperty float x\nend_header\n"),
                    "line 3: property before any element");
    EXPECT_CONTAINS(errorOf("e9.ply", "ply\nformat ascii 1.0\nelement vertex -1\nend_header\n"),
                    "line 3: element count \"-1\" is not a whole number");
    EXPECT_CONTAINS(
        errorOf("e10.ply", "ply\nformat ascii 1.0\nelement vertex 99999999999999999999\n"),
        "line 3: element count \"99999999999999999999\" is not a whole number");
    std::string noZ = kAsciiHead;
    noZ.replace(noZ.find("property float z"), 16, "property float w");
    EXPECT_CONTAINS(errorOf("e11.ply", noZ + kAsciiTet),
                    "line 3: element vertex has no property z");
    std::string noFaces = kAsciiHead;
    noFaces.replace(noFaces.find("vertex_indices"), 14, "vertex_labels");
    EXPECT_CONTAINS(errorOf("e12.ply", noFaces + kAsciiTet),
                    "line 7: element face has no list property vertex_indices");
    std::string floatIndices = kAsciiHead;
    floatIndices.replace(floatIndices.find("uchar int"), 9, "uchar float");
    EXPECT_CONTAINS(errorOf("e13.ply", floatIndices + kAsciiTet),
                    "line 8: face property vertex_indices must be a list of integers");
    std::string floatCount = kAsciiHead;
    floatCount.replace(floatCount.find("uchar int"), 9, "float int");
    EXPECT_CONTAINS(errorOf("e14.ply", floatCount + kAsciiTet),
                    "line 8: list count type \"float\" is not an integer");
    EXPECT_CONTAINS(errorOf("e15.ply",
                            "ply\nformat ascii 1.0\nelement face 0\nproperty list "
                            "uchar int vertex_indices\nend_header\n"),
                    "line 5: the header declares no element vertex");
    std::string partialNormal = kAsciiHead;
    partialNormal.replace(partialNormal.find("element face"), 0, "property float nx\n");
    EXPECT_CONTAINS(errorOf("e16.ply", partialNormal + kAsciiTet),
                    "line 3: element vertex has only some of the normal (nx, ny, nz) properties");
    EXPECT_CONTAINS(errorOf("e17.ply",
                            "ply\nformat ascii 1.0\nelement vertex 1\n"
                            "property float x\nproperty double x\nend_header\n"),
                    "line 5: property \"x\" twice in element \"vertex\"");
}

TEST(MeshFile, PlyHugeCountsFailBeforeAllocating) {
    const std::string h =
        "ply\nformat binary_little_endian 1.0\nelement vertex 1099511627776\n"
        "property float x\nend_header\n";
    const std::string bytes = h + std::string(100 - h.size(), '\0');
    ASSERT_EQ(bytes.size(), 100u);
    EXPECT_EQ(errorOf("huge.ply", bytes),
              tmp("huge.ply") +
                  ": line 3: element \"vertex\" claims 1099511627776 records, but the rest of "
                  "the file holds at most 1");
    std::string ascii = kAsciiHead;
    ascii.replace(ascii.find("face 4"), 6, "face 4000000000");
    EXPECT_CONTAINS(errorOf("huge_ascii.ply", ascii + kAsciiTet),
                    "line 7: element \"face\" claims 4000000000 records, but the rest of the file "
                    "holds at most 16");
    // A list length beyond the limit, and one beyond the end of the file.
    Bytes b{false,
            "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
            "property float y\nproperty float z\nelement face 1\n"
            "property list uint uint vertex_indices\nend_header\n"};
    const size_t body = b.s.size();
    for (int i = 0; i < 9; ++i) b.put(float(i % 4 == 0));
    b.put<uint32_t>(4000000000u).put<uint32_t>(0);
    EXPECT_EQ(errorOf("long_list.ply", b.s),
              tmp("long_list.ply") + ": byte " + std::to_string(body + 36) +
                  ": list of 4000000000 items in face 0 (at most 65536); the header declares 3 "
                  "\"vertex\", 1 \"face\"");
    b.s.resize(body + 36);
    b.put<uint32_t>(1000).put<uint32_t>(0);
    EXPECT_EQ(errorOf("long_list.ply", b.s),
              tmp("long_list.ply") + ": byte " + std::to_string(body + 36) +
                  ": end of file inside face 0; the header declares 3 \"vertex\", 1 \"face\"");
}

TEST(MeshFile, PlyBodyErrors) {
    // Every body error ends with the header's counts, which a wrong count would otherwise hide
    // (a vertex line read as face 0: "face 0 has 0 vertices"; helper 66).
    const std::string counts = "; the header declares 1 \"camera\", 5 \"vertex\", 5 \"face\"";
    std::string fewer = kAsciiHead;
    fewer.replace(fewer.find("vertex 4"), 8, "vertex 3");
    EXPECT_EQ(errorOf("fewer.ply", fewer + kAsciiTet),
              tmp("fewer.ply") +
                  ": line 13: face 0 has 0 vertices (a polygon needs at least 3); "
                  "the header declares 3 \"vertex\", 4 \"face\"");
    std::string binary = binaryPyramid(false);
    const size_t size = binary.size();  // the last face: uchar count, 3 ints, char flag
    binary.resize(size - 3);            // the list (3 ints) at size − 13 is cut short
    EXPECT_EQ(errorOf("truncated.ply", binary), tmp("truncated.ply") + ": byte " +
                                                    std::to_string(size - 14) +
                                                    ": end of file inside face 4" + counts);
    binary.resize(size - 14);  // without the last face
    EXPECT_EQ(errorOf("truncated.ply", binary), tmp("truncated.ply") + ": byte " +
                                                    std::to_string(size - 14) +
                                                    ": end of file inside face 4" + counts);
    // After a byte-order mark the bytes counted are still the file's.
    EXPECT_EQ(errorOf("truncated.ply", "\xEF\xBB\xBF" + binary),
              tmp("truncated.ply") + ": byte " + std::to_string(size - 11) +
                  ": end of file inside face 4" + counts);
    binary.resize(size - 320 + 100);  // 100 bytes of the body: not even the vertices fit
    EXPECT_CONTAINS(errorOf("truncated.ply", binary),
                    "line 6: element \"vertex\" claims 5 records, but the rest of the file holds "
                    "at most 1");
    EXPECT_EQ(errorOf("trailing.ply", binaryPyramid(true) + "xy"),
              tmp("trailing.ply") + ": byte " + std::to_string(binaryPyramid(true).size()) +
                  ": 2 bytes after the last element" + counts);

    EXPECT_EQ(errorOf("range.ply", kAsciiHead + "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 4\n"
                                                "3 0 3 2\n3 1 2 3\n"),
              tmp("range.ply") +
                  ": line 15: vertex index 4 of face 1 out of range (4 vertices); the header "
                  "declares 4 \"vertex\", 4 \"face\"");
    EXPECT_CONTAINS(errorOf("negative.ply", kAsciiHead + "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n"
                                                         "3 0 1 -3\n3 0 3 2\n3 1 2 3\n"),
                    "line 15: vertex index -3 of face 1 out of range (4 vertices)");
    EXPECT_CONTAINS(errorOf("few.ply", kAsciiHead + "0 0 0\n1 0\n0 1 0\n0 0 1\n" + kFaces),
                    "line 11: fewer values than the header declares for vertex 1");
    EXPECT_CONTAINS(errorOf("many.ply", kAsciiHead + "0 0 0\n1 0 0 0\n0 1 0\n0 0 1\n" + kFaces),
                    "line 11: more values than the header declares for vertex 1");
    EXPECT_CONTAINS(errorOf("short.ply", kAsciiHead + "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 "
                                                      "1 3\n3 0 3 2\n"),
                    "line 17: end of file: expected face 3");
    EXPECT_CONTAINS(errorOf("after.ply", kAsciiHead + kAsciiTet + "\n 1 2 3\n"),
                    "line 19: data after the last element");
    EXPECT_CONTAINS(errorOf("word.ply", kAsciiHead + "0 0 zero\n1 0 0\n0 1 0\n0 0 1\n" + kFaces),
                    "line 10: \"zero\" in vertex 0 is not a number");
    EXPECT_CONTAINS(
        errorOf("uchar.ply", kAsciiHead + "0 0 0\n1 0 0\n0 1 0\n0 0 1\n256 0 2 1\n" + kFaces),
        "line 14: \"256\" in face 0 is not an integer from 0 to 255");
    EXPECT_CONTAINS(errorOf("two.ply", kAsciiHead + "0 0 0\n1 0 0\n0 1 0\n0 0 1\n2 0 2\n" + kFaces),
                    "line 14: face 0 has 2 vertices (a polygon needs at least 3)");
    EXPECT_CONTAINS(
        errorOf("overflow.ply", kAsciiHead + "1e999 0 0\n1 0 0\n0 1 0\n0 0 1\n" + kFaces),
        "line 10: \"1e999\" in vertex 0 is not a number");
    // Beyond a float, within a double: the property is a float (helper 127: named by the scene).
    // What rounds to an infinite float: 3.4028236e38 does, the largest float as printed,
    // 3.4028235e+38, does not (helper 129).
    for (const std::string beyond : {"-1e39", "3.4028236e38"})
        EXPECT_CONTAINS(errorOf("beyond.ply",
                                kAsciiHead + "0 " + beyond + " 0\n1 0 0\n0 1 0\n0 0 1\n" + kFaces),
                        "line 10: \"" + beyond +
                            "\" in vertex 0 is beyond the range of a float (±3.4e38), the "
                            "property's type");
    EXPECT_NO_THROW(
        parsePly(kAsciiHead + "0 0 3.4028235e+38\n1 0 0\n0 1 0\n0 0 1\n" + kFaces, "largest.ply"));
}

TEST(MeshFile, PlyValidationErrors) {
    // A NaN position in a binary file, an infinite normal, a degenerate triangle.
    Bytes b{false,
            "ply\nformat binary_little_endian 1.0\nelement vertex 4\nproperty float x\n"
            "property float y\nproperty float z\nelement face 4\n"
            "property list uchar int vertex_indices\nend_header\n"};
    const float p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 3; ++j)
            b.put(i == 2 && j == 1 ? std::numeric_limits<float>::quiet_NaN() : p[i][j]);
    for (int f : {0x000201, 0x000103, 0x000302, 0x010203}) {
        b.put<uint8_t>(3);
        for (int s : {16, 8, 0}) b.put<int32_t>((f >> s) & 0xff);
    }
    EXPECT_EQ(errorOf("nan.ply", b.s),
              tmp("nan.ply") + ": vertex 2: position (0, nan, 0) is not finite");

    std::string normals = kAsciiHead;
    normals.replace(normals.find("element face"), 0,
                    "property float nx\nproperty float ny\nproperty float nz\n");
    EXPECT_EQ(errorOf("normal.ply", normals + "0 0 0 0 0 1\n1 0 0 inf 0 0\n0 1 0 0 0 1\n"
                                              "0 0 1 0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n"),
              tmp("normal.ply") + ": vertex 1: normal (inf, 0, 0) is not finite");
    EXPECT_EQ(errorOf("degenerate.ply", kAsciiHead + "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n"
                                                     "3 0 1 3\n3 0 3 3\n3 1 2 3\n"),
              tmp("degenerate.ply") +
                  ": face 2: repeated vertex index in (0, 3, 3): degenerate triangle");
    // A polygon counts as one face of the file, not as the triangles it is fanned into.
    EXPECT_EQ(
        errorOf("polygon.ply", kAsciiHead + "0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n"
                                            "3 0 1 1\n3 0 2 3\n3 1 2 3\n"),
        tmp("polygon.ply") + ": face 1: repeated vertex index in (0, 1, 1): degenerate triangle");
    EXPECT_EQ(
        errorOf("collinear.ply", kAsciiHead + "0 0 0\n1 0 0\n2 0 0\n0 0 1\n3 0 2 1\n"
                                              "3 0 1 3\n3 0 3 2\n3 1 2 3\n"),
        tmp("collinear.ply") + ": face 0: zero area (collinear vertices): degenerate triangle");
}

TEST(MeshFile, MissingFiles) {
    EXPECT_EQ(messageOf([] { readMesh(tmp("missing.ply")); }),
              tmp("missing.ply") + ": no such file");
    EXPECT_EQ(messageOf([] { readMesh(tmp("missing.OBJ")); }),
              tmp("missing.OBJ") + ": no such file");
    EXPECT_EQ(messageOf([] { readPly(testing::TempDir()); }),
              testing::TempDir() + ": not a regular file");
    EXPECT_EQ(messageOf([] { readMesh("mesh.stl"); }),
              "mesh.stl: unknown mesh file extension \".stl\" (expected .obj or .ply)");
    EXPECT_EQ(messageOf([] { readMesh("dir.ply/mesh"); }),
              "dir.ply/mesh: unknown mesh file extension \"\" (expected .obj or .ply)");
}

TEST(MeshFile, Obj) {
    // Two objects, relative indices in the second, a quad, a missing material library.
    const std::string obj =
        "# pyramid\n"
        "mtllib missing.mtl\n"
        "o base\n"
        "v 0 0 0\nv 2 0 0\nv 2 2 0\nv 0 2 0\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n"
        "vn 0 0 -1\n"
        "usemtl stone\n"
        "f 1/1/1 4/4/1 3/3/1 2/2/1\n"
        "o sides\n"
        "v 1 1 1 # apex\n"
        "vn 0 -1 1\r\n"
        "vn 1 0 1\rvn 0 1 1\n"
        "vn -1 0 1\n"
        "g walls\n"
        "f -5/1/-4 -4/2/-4 -1/5/-4\n"
        "f 2/2/3 3/3/3 5/5/3\n"
        "\tf 3/3/4 4/4/4 5/5/4\n"
        "f 4/4/5 1/1/5 5/5/5\n";
    const TriangleMesh m = readObj(write("pyramid.obj", obj));
    // Distinct (v, vt, vn) corners in order of appearance.
    const int corners[][3] = {{1, 1, 1}, {4, 4, 1}, {3, 3, 1}, {2, 2, 1}, {1, 1, 2}, {2, 2, 2},
                              {5, 5, 2}, {2, 2, 3}, {3, 3, 3}, {5, 5, 3}, {3, 3, 4}, {4, 4, 4},
                              {5, 5, 4}, {4, 4, 5}, {1, 1, 5}, {5, 5, 5}};
    const double vt[5][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}, {0.5, 0.5}};
    const double vn[5][3] = {{0, 0, -1}, {0, -1, 1}, {1, 0, 1}, {0, 1, 1}, {-1, 0, 1}};
    ASSERT_EQ(m.p.size(), 16u);
    ASSERT_EQ(m.uv.size(), 16u);
    ASSERT_EQ(m.n.size(), 16u);
    for (int i = 0; i < 16; ++i) {
        const auto& c = corners[i];
        EXPECT_EQ(m.p[i], Vec3(kPyramid[c[0] - 1][0], kPyramid[c[0] - 1][1], kPyramid[c[0] - 1][2]))
            << i;
        EXPECT_EQ(m.uv[i], Vec2(vt[c[1] - 1][0], vt[c[1] - 1][1])) << i;
        EXPECT_EQ(m.n[i], Vec3(vn[c[2] - 1][0], vn[c[2] - 1][1], vn[c[2] - 1][2])) << i;
    }
    EXPECT_EQ(m.indices,
              std::vector<uint32_t>({0, 1, 2, 0, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15}));
    EXPECT_DOUBLE_EQ(signedVolume(m), 4.0 / 3);
    EXPECT_DOUBLE_EQ(surfaceArea(m), 4 + 4 * std::sqrt(2.0));
}

TEST(MeshFile, ObjSharesVerticesAndKeepsTheWinding) {
    const std::string obj =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nv 0.5 0.5 0.5\n"
        "f 1 3 2\nf 1 2 4\nf 1 4 3\n"
        "f 2 3 5 4\n"  // a non-planar quad: the fan (2, 3, 5), (2, 5, 4) and
        "f 3 4 5\n";   // this triangle put a roof on the face (2, 3, 4) of the tetrahedron
    const TriangleMesh m = readObj(write("tet.obj", obj));
    EXPECT_EQ(m.p.size(), 5u);
    EXPECT_TRUE(m.n.empty());
    EXPECT_TRUE(m.uv.empty());
    EXPECT_EQ(m.indices,
              std::vector<uint32_t>({0, 1, 2, 0, 2, 3, 0, 3, 1, 2, 1, 4, 2, 4, 3, 1, 3, 4}));
    EXPECT_EQ(closedMeshDefect(m), "");
    EXPECT_DOUBLE_EQ(signedVolume(m), 1.0 / 6 + 1.0 / 12);
}

TEST(MeshFile, ObjErrors) {
    const std::string tet = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
    // A damaged statement is named at its line: skipped without a word, a lost v line moved every
    // later vertex (helper 73). OBJ's other statements (groups, materials, lines) pass.
    EXPECT_EQ(errorOf("v1.obj", "v 0 0 0\nv1 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\n"),
              tmp("v1.obj") +
                  ": line 2: unknown statement \"v1\" (a damaged line? OBJ's are v, vt, vn, f, g, "
                  "o, s, usemtl, mtllib, l, p and those of curves and surfaces)");
    EXPECT_NE(errorOf("F.obj", tet + "F 1 2 3\n").find(": line 5: unknown statement \"F\""),
              std::string::npos);
    EXPECT_EQ(errorOf("bare.obj", tet + "v\n"),
              tmp("bare.obj") + ": line 5: \"v\" without numbers");
    // A byte-order mark is no part of the first statement (helper 75: a first comment was
    // refused, a first v line lost before), and a DOS end-of-file byte is blank.
    const std::string faces = "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
    EXPECT_EQ(readObj(write("bom.obj", "\xEF\xBB\xBF# made on Windows\r\n" + tet + faces + "\x1a"))
                  .triangleCount(),
              4u);
    const TriangleMesh bomV = readObj(write("bomv.obj", "\xEF\xBB\xBF" + tet + faces));
    ASSERT_EQ(bomV.p.size(), 4u);
    EXPECT_EQ(bomV.p[0], Vec3(0, 0, 0));
    EXPECT_EQ(readObj(write("groups.obj", "# a tetrahedron\nmtllib a.mtl\no tet\ng side\n" + tet +
                                              "usemtl red\ns off\nl 1 2\nf 1 3 2\nf 1 2 4\n"
                                              "f 1 4 3\nf 2 3 4\n"))
                  .triangleCount(),
              4u);
    EXPECT_EQ(errorOf("nan.obj", "v 0 0 0\nv 1 nan 0\n"),
              tmp("nan.obj") + ": line 2: \"nan\" is not a finite number");
    EXPECT_EQ(errorOf("inf.obj", "v 0 0 0\nvn -inf 0 1\n"),
              tmp("inf.obj") + ": line 2: \"-inf\" is not a finite number");
    EXPECT_EQ(errorOf("word.obj", "v 0 0 0\r\nvt 0 0\r\nv 1 zero 0\r\n"),
              tmp("word.obj") + ": line 3: \"zero\" is not a number");
    EXPECT_EQ(errorOf("two.obj", "v 0 0 0\nv 1 0\n"),
              tmp("two.obj") + ": line 2: 2 numbers; expected v (x y z [w or r g b])");
    // Beyond float range (tinyobjloader would read infinity), at the line and number; the
    // largest float and what rounds down to it pass.
    EXPECT_EQ(errorOf("big.obj", tet + "v 1e39 0 0\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 5\n"),
              tmp("big.obj") +
                  ": line 5: \"1e39\" is beyond the range of a float (±3.4e38), in "
                  "which OBJ numbers are read");
    EXPECT_EQ(errorOf("big2.obj", "v 0 0 0\nvn 0 -3.4028235677973366e38 0\n"),
              tmp("big2.obj") +
                  ": line 2: \"-3.4028235677973366e38\" is beyond the range of a "
                  "float (±3.4e38), in which OBJ numbers are read");
    EXPECT_NEAR(readObj(write("max.obj", "v 0 0 0\nv 3.4e38 0 0\nv 0 1 0\nf 1 2 3\n")).p[1].x(),
                3.4e38, 3.4e38 * 1e-6);
    // tinyobjloader's own rounding takes the largest float, 3.4028235677973362e38, to infinity.
    EXPECT_EQ(errorOf("max2.obj", "v 0 0 0\nv 3.4028235677973362e38 0 0\nv 0 1 0\nf 1 2 3\n"),
              tmp("max2.obj") +
                  ": line 2: a coordinate is not finite as tinyobjloader reads it "
                  "(a number it misreads, such as 0e999 for 0)");
    // tinyobjloader reads "0e999" as 0 · 5^999 · 2^999 = 0 · ∞ = NaN: named at its line.
    EXPECT_EQ(errorOf("nan2.obj", tet + "v 0e999 0 0\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 5\n"),
              tmp("nan2.obj") +
                  ": line 5: a coordinate is not finite as tinyobjloader reads it "
                  "(a number it misreads, such as 0e999 for 0)");
    // More corners than tinyobjloader can count (in an unsigned char), at the face's line.
    for (const int n : {256, 300}) {
        std::string polygon, face = "f";
        for (int i = 0; i < n; ++i) {
            polygon += "v " + std::to_string(std::cos(i * TwoPi / n)) + " " +
                       std::to_string(std::sin(i * TwoPi / n)) + " 0\n";
            face += " " + std::to_string(i + 1);
        }
        EXPECT_EQ(errorOf("polygon.obj", polygon + face + "\n"),
                  tmp("polygon.obj") + ": line " + std::to_string(n + 1) + ": a face of " +
                      std::to_string(n) + " corners; at most 255 (tinyobjloader's limit)");
    }
    EXPECT_EQ(errorOf("range.obj", tet + "f 1 3 2\nf 1 2 4\n\nf 1 4 5\n"),
              tmp("range.obj") + ": line 8: v index 5 out of range (4 v lines)");
    EXPECT_EQ(errorOf("relative.obj", tet + "f -1 -2 -5\n"),
              tmp("relative.obj") + ": line 5: relative v index -5 points before the first v line");
    // Just before the first vn or vt line: tinyobjloader's −1, its "no index", was read as a face
    // without normals (or uvs), without a word (helper 103); counted from the face's own line.
    EXPECT_EQ(errorOf("relvn.obj", tet + "vn 1 -1 0\nf 1//-2 2//-2 3//-2\n"),
              tmp("relvn.obj") + ": line 6: relative vn index -2 points before the first vn line");
    EXPECT_EQ(errorOf("relvt.obj", tet + "f 1/-1 2/-1 3/-1\nvt 0 0\n"),
              tmp("relvt.obj") + ": line 5: relative vt index -1 points before the first vt line");
    // Face corners tinyobjloader would misread: its integer parser wraps (4294967299 would be
    // vertex 3) and stops at the first character that is not a digit.
    EXPECT_EQ(errorOf("wrap.obj", tet + "f 1 2 4294967299\n"),
              tmp("wrap.obj") + ": line 5: index \"4294967299\" is beyond ±2147483647");
    EXPECT_EQ(errorOf("huge.obj", tet + "f 1 2 99999999999999999999\n"),
              tmp("huge.obj") + ": line 5: index \"99999999999999999999\" is beyond ±2147483647");
    EXPECT_EQ(errorOf("int.obj", tet + "f 1 2 -2147483648\n"),
              tmp("int.obj") + ": line 5: index \"-2147483648\" is beyond ±2147483647");
    const std::string notACorner =
        " is not a face corner (v, v/vt, v//vn or v/vt/vn with integers)";
    EXPECT_EQ(errorOf("x.obj", tet + "f 1 2 3x\n"), tmp("x.obj") + ": line 5: \"3x\"" + notACorner);
    EXPECT_EQ(errorOf("four.obj", tet + "vt 0 0\nvn 0 0 1\nf 1/1/1/1 2/1/1 3/1/1\n"),
              tmp("four.obj") + ": line 7: \"1/1/1/1\"" + notACorner);
    EXPECT_EQ(errorOf("nov.obj", tet + "vt 0 0\nf /1 2/1 3/1\n"),
              tmp("nov.obj") + ": line 6: \"/1\"" + notACorner);
    EXPECT_EQ(errorOf("comment.obj", tet + "f 1 3 2 # the base\n"),
              tmp("comment.obj") +
                  ": line 5: a comment after a face's corners (tinyobjloader cannot read it); put "
                  "it on a line of its own");
    // Leading zeros are no overflow.
    const std::string zeros = write("zeros.obj", tet +
                                                     "f 0000000000001 3 2\n"
                                                     "f 1 2 4\nf 1 4 3\nf 2 3 4\n");
    EXPECT_EQ(messageOf([&] { readMesh(zeros); }), "(no error)");
    EXPECT_EQ(errorOf("vt.obj", tet + "vt 0 0\nf 1/1 3/1 2/2\n"),
              tmp("vt.obj") + ": line 6: vt index 2 out of range (1 vt lines)");
    EXPECT_EQ(errorOf("zero.obj", tet + "f 1 3 2\nf 0 1 2\n"),
              tmp("zero.obj") + ": line 6: malformed face: an index is 0 or not a number");
    EXPECT_EQ(errorOf("mixed.obj", tet + "vt 0 0\nf 1/1 3/1 2/1\nf 1 2 4\n"),
              tmp("mixed.obj") +
                  ": line 7: some face corners have texture coordinates (vt) and others do not");
    EXPECT_EQ(errorOf("line.obj", tet + "f 1 3 2\nf 1 2\n"),
              tmp("line.obj") + ": line 6: a face of 2 corners; a face needs at least 3");
    EXPECT_EQ(errorOf("point.obj", tet + "f 1\nf 1 3 2\n"),
              tmp("point.obj") + ": line 5: a face of 1 corner; a face needs at least 3");
    // Faces by their lines, vertices by the line of the first face that names them (the mesh's
    // vertex numbers, de-duplicated corners, are not the file's).
    EXPECT_EQ(
        errorOf("degenerate.obj", tet + "f 1 3 2\nf 1 2 2\n"),
        tmp("degenerate.obj") + ": line 6: a vertex repeated in a triangle: degenerate triangle");
    EXPECT_EQ(
        errorOf("degenerate4.obj", tet + "f 1 3 2 4\nf 4 2 3\nf 1 2 2\n"),
        tmp("degenerate4.obj") + ": line 7: a vertex repeated in a triangle: degenerate triangle");
    EXPECT_EQ(errorOf("empty.obj", tet), tmp("empty.obj") + ": the mesh has no triangles");
    // A normal or texture coordinate at its own vn or vt line (it was named by the first face
    // that used it).
    EXPECT_EQ(errorOf("normal.obj", tet + "vn 0 0 0\nf 1//1 3//1 2//1\n"),
              tmp("normal.obj") + ": line 5: normal is zero");
    EXPECT_EQ(errorOf("vn0e999.obj", tet + "vn 0 0 1\nvn 0e999 1 0\n# x\nf 1//1 3//1 2//1\n"
                                           "f 1//2 2//2 4//2\n"),
              tmp("vn0e999.obj") +
                  ": line 6: a normal coordinate is not finite as tinyobjloader reads it (a number "
                  "it misreads, such as 0e999 for 0)");
    EXPECT_EQ(errorOf("vt0e999.obj", tet + "vt 0e999 0.5\nv 0 0 2\nf 1/1 3/1 2/1\n"),
              tmp("vt0e999.obj") +
                  ": line 5: a texture coordinate is not finite as tinyobjloader reads it (a "
                  "number it misreads, such as 0e999 for 0)");
}

// A reader's places name the file's faces in what is checked after reading (a closed mesh's
// defects): the OBJ line and the PLY face, not the loader's triangle (a quad is two).
TEST(MeshFile, ReadersGiveTheFilesPlacesOfTheirTriangles) {
    // A cube of quads facing outwards but the last, flipped; comments, blank and v lines between
    // the faces. Triangle 1 (the first quad's second half, 1 4 2) has the edge 4 → 2, which the
    // flipped quad 2 6 8 4 has too (its triangle 11).
    const std::string obj =
        "v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\n# top\nv -1 -1 1\nv 1 -1 1\nv -1 1 1\n"
        "v 1 1 1\nf 1 3 4 2\n\n# sides\nf 5 6 8 7\nf 1 2 6 5\n# more\nf 3 7 8 4\nf 1 5 7 3\n"
        "f 2 6 8 4\n";
    const std::string twice =
        "edge from (1, 1, -1) to (1, -1, -1) appears twice (also at LATER): inconsistent "
        "winding or non-manifold";
    const auto expected = [&](const std::string& path, const std::string& first,
                              const std::string& later) {
        std::string m = path + ": " + first + ": " + twice;
        return m.replace(m.find("LATER"), 5, later);
    };
    MeshPlaces places;
    const std::string objPath = write("flipped.obj", obj);
    TriangleMesh m = readMesh(objPath, nullptr, &places);
    EXPECT_EQ(closedMeshDefect(m, places), expected(objPath, "line 10", "line 18"));
    // After a transform, the places say so.
    const Eigen::Affine3d half(Eigen::Scaling(0.5));
    m = readMesh(objPath, &half, &places);
    EXPECT_EQ(closedMeshDefect(m, places).rfind(objPath + ": line 10, after the surface's "
                                                          "transform: edge from (0.5, 0.5, -0.5)",
                                                0),
              0u)
        << closedMeshDefect(m, places);

    std::string ply =
        "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
        "property float z\nelement face 6\nproperty list uchar int vertex_indices\n"
        "end_header\n-1 -1 -1\n1 -1 -1\n-1 1 -1\n1 1 -1\n-1 -1 1\n1 -1 1\n-1 1 1\n1 1 1\n"
        "4 0 2 3 1\n4 4 5 7 6\n4 0 1 5 4\n4 2 6 7 3\n4 0 4 6 2\n4 1 5 7 3\n";
    const std::string plyPath = write("flipped.ply", ply);
    m = readMesh(plyPath, nullptr, &places);
    EXPECT_EQ(closedMeshDefect(m, places), expected(plyPath, "face 0", "face 5"));
}

}  // namespace
}  // namespace shvol
