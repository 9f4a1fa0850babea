#pragma once
// Meshes for the surfaces tests: a closed latitude-longitude sphere and a closed box, both facing
// outwards.
#include <memory>
#include <vector>

#include "shvol/surfaces/surface_scene.h"
#include "shvol/surfaces/triangle_mesh.h"

namespace shvol::testing {

/// A sphere of nTheta latitude bands and nPhi longitude sectors, with one vertex per pole.
inline TriangleMesh sphereMesh(const Vec3& c, double r, int nTheta, int nPhi) {
    TriangleMesh m;
    m.p.push_back(c + Vec3(0, 0, r));  // north pole: vertex 0
    for (int i = 1; i < nTheta; ++i)
        for (int j = 0; j < nPhi; ++j)
            m.p.push_back(c + r * sphericalDirection(std::cos(Pi * i / nTheta), TwoPi * j / nPhi));
    m.p.push_back(c - Vec3(0, 0, r));  // south pole
    const uint32_t south = uint32_t(m.p.size() - 1);
    auto ring = [&](int i, int j) { return uint32_t(1 + (i - 1) * nPhi + (j % nPhi)); };
    for (int j = 0; j < nPhi; ++j) {
        m.indices.insert(m.indices.end(), {0, ring(1, j), ring(1, j + 1)});
        for (int i = 1; i + 1 < nTheta; ++i)
            m.indices.insert(m.indices.end(), {ring(i, j), ring(i + 1, j), ring(i + 1, j + 1),
                                               ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
        m.indices.insert(m.indices.end(), {ring(nTheta - 1, j), south, ring(nTheta - 1, j + 1)});
    }
    return m;
}

/// The box [lo, hi] as 12 triangles facing outwards.
inline TriangleMesh boxMesh(const Vec3& lo, const Vec3& hi) {
    TriangleMesh m;
    for (int k = 0; k < 8; ++k)
        m.p.push_back(
            Vec3(k & 1 ? hi.x() : lo.x(), k & 2 ? hi.y() : lo.y(), k & 4 ? hi.z() : lo.z()));
    m.indices = {0, 2, 1, 1, 2, 3,   // z = lo
                 4, 5, 6, 5, 7, 6,   // z = hi
                 0, 1, 4, 1, 5, 4,   // y = lo
                 2, 6, 3, 3, 6, 7,   // y = hi
                 0, 4, 2, 2, 4, 6,   // x = lo
                 1, 3, 5, 3, 7, 5};  // x = hi
    return m;
}

/// A closed room [−1, 1]³ of coloured Lambertian walls, a glossy Phong-22 back wall at y = 0.99
/// and a 0.6 × 0.6 rectangle light under the ceiling facing down.
inline std::unique_ptr<const SurfaceScene> glossyRoom() {
    std::vector<Surface> v;
    Surface box;
    box.kind = Surface::Kind::Mesh;
    box.mesh = boxMesh(Vec3(-1, -1, -1), Vec3(1, 1, 1));
    box.bsdf = Bsdf::lambert(Spectrum(0.7, 0.5, 0.3));
    v.push_back(std::move(box));
    Eigen::Affine3d back = Eigen::Affine3d::Identity();
    back.translate(Vec3(0, 0.99, 0)).rotate(Eigen::AngleAxisd(Pi / 2, Vec3::UnitX()));
    Surface glossy = Surface::rectangle(back);
    glossy.bsdf = Bsdf::phong(Spectrum::Constant(0.2), Spectrum::Constant(0.6), 22);
    v.push_back(std::move(glossy));
    Eigen::Affine3d top = Eigen::Affine3d::Identity();
    top.translate(Vec3(0, 0, 0.98)).rotate(Eigen::AngleAxisd(Pi, Vec3::UnitX())).scale(0.3);
    Surface light = Surface::rectangle(top);
    light.emission = Spectrum(8, 6, 4);
    v.push_back(std::move(light));
    return std::make_unique<const SurfaceScene>(std::move(v));
}

}  // namespace shvol::testing
