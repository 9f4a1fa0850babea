#pragma once
// What every mesh a reader accepts must be (validateMesh's promises), checked by the mesh fuzzers.
#include <cstdint>
#include <string>

#include "fuzz_util.h"
#include "shvol/io/mesh_file.h"

namespace shvol::fuzz {

/// Aborts (a finding) unless `m`, accepted by `reader`, has whole triangles, indices in range,
/// attributes matching its vertices, finite positions, normals and texture coordinates, and a
/// non-degenerate normal per triangle; then runs closedMeshDefect on it.
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
        const Vec3& p0 = m.p[m.indices[3 * f]];
        const Vec3 n = (m.p[m.indices[3 * f + 1]] - p0).cross(m.p[m.indices[3 * f + 2]] - p0);
        if (!n.allFinite() || n.squaredNorm() == 0) fail("a triangle without a normal");
    }
    (void)closedMeshDefect(m);
}

}  // namespace shvol::fuzz
