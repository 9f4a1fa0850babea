// libFuzzer target: the PLY reader (parsePly, behind readPly and readMesh). The input is the
// file's content; an accepted mesh must be what validateMesh promises, and closedMeshDefect must
// run on it.
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_util.h"
#include "shvol/core/error.h"
#include "shvol/io/mesh_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    try {
        const shvol::TriangleMesh m = shvol::parsePly(
            std::string_view(reinterpret_cast<const char*>(data), size), "input.ply");
        if (m.triangleCount() == 0 || m.indices.size() % 3 != 0)
            shvol::fuzz::bug("parsePly accepted a mesh without whole triangles");
        if ((!m.n.empty() && m.n.size() != m.p.size()) ||
            (!m.uv.empty() && m.uv.size() != m.p.size()))
            shvol::fuzz::bug("parsePly returned attributes that do not match the vertices");
        for (uint32_t i : m.indices)
            if (i >= m.p.size()) shvol::fuzz::bug("parsePly accepted an index out of range");
        for (const shvol::Vec3& p : m.p)
            if (!p.allFinite()) shvol::fuzz::bug("parsePly accepted a non-finite position");
        for (const shvol::Vec3& n : m.n)
            if (!n.allFinite() || n.squaredNorm() == 0)
                shvol::fuzz::bug("parsePly accepted a non-finite or zero normal");
        for (const auto& uv : m.uv)
            if (!uv.allFinite())
                shvol::fuzz::bug("parsePly accepted non-finite texture coordinates");
        for (size_t f = 0; f < m.triangleCount(); ++f) {
            const shvol::Vec3& p0 = m.p[m.indices[3 * f]];
            const shvol::Vec3 n =
                (m.p[m.indices[3 * f + 1]] - p0).cross(m.p[m.indices[3 * f + 2]] - p0);
            if (!n.allFinite() || n.squaredNorm() == 0)
                shvol::fuzz::bug("parsePly accepted a triangle without a normal");
        }
        (void)shvol::closedMeshDefect(m);
    } catch (const shvol::Error& e) {  // the expected outcome of bad input
        shvol::fuzz::expected(e);
    }
    return 0;
}
