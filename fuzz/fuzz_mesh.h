#pragma once
// What every mesh a reader accepts must be (validateMesh's promises), checked by the mesh fuzzers.
#include <cstdint>
#include <string>

#include "fuzz_util.h"
#include "shvol/io/mesh_file.h"
#include "shvol/surfaces/triangle_mesh.h"

namespace shvol::fuzz {

/// Aborts (a finding) unless `m`, accepted by `reader`, has whole triangles, indices in range,
/// attributes matching its vertices, finite positions, normals and texture coordinates, and a
/// non-degenerate normal per triangle, computed at its widest angle as validateMesh promises and
/// the renderer computes it (widestAngleFirst: at another vertex a sliver's normal can round to
/// zero, as for a triangle with one vertex at 3·10³⁸ and two a unit apart near the origin); then
/// runs closedMeshDefect on it.
inline void checkAcceptedMesh(const TriangleMesh& m, const std::string& reader) {
    const auto fail = [&](const char* what) { bug((reader + " accepted " + what).c_str()); };
    if (m.triangleCount() == 0 || m.indices.size() % 3 != 0) fail("a mesh without whole triangles");
    if ((!m.n.empty() && m.n.size() != m.p.size()) || (!m.uv.empty() && m.uv.size() != m.p.size()))
        fail("attributes that do not match the vertices");
    for (uint32_t i : m.indices)
        if (i >= m.p.size()) fail("an index out of range");
    for (const Vec3& p : m.p)
        if (!p.allFinite()) fail("a non-finite position");
    for (const Vec3& n : m.n)
        if (!n.allFinite() || n.squaredNorm() == 0) fail("a non-finite or zero normal");
    for (const auto& uv : m.uv)
        if (!uv.allFinite()) fail("non-finite texture coordinates");
    for (size_t f = 0; f < m.triangleCount(); ++f) {
        const uint32_t* t = &m.indices[3 * f];
        const int w = widestAngle(m, f);
        const Vec3& p0 = m.p[t[w]];
        const Vec3 n = (m.p[t[(w + 1) % 3]] - p0).cross(m.p[t[(w + 2) % 3]] - p0);
        if (!n.allFinite() || n.squaredNorm() == 0) fail("a triangle without a normal");
    }
    (void)closedMeshDefect(m);
}

}  // namespace shvol::fuzz
