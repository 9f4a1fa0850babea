#include "shvol/surfaces/area_lights.h"

#include <gtest/gtest.h>

#include <iostream>

#include "shvol/sampling/chi2.h"
#include "surfaces/surface_test_util.h"

namespace shvol {
namespace {

/// χ² over the sphere of the directions AreaLights::sample draws from x, against AreaLights::pdf
/// at the point each direction first meets an emitter.
Chi2Result lightChi2(const SurfaceScene& scene, const Vec3& x, int numTests) {
    const AreaLights lights(scene);
    Chi2Options opt;
    opt.numTests = numTests;
    opt.sampleCount = 400000;
    return chi2TestSphere(
        [&](Rng& rng) -> std::optional<Vec3> {
            const AreaLightSample s = lights.sample(x, rng.uniform(), rng.uniform2());
            if (!(s.pdf > 0)) return std::nullopt;
            return s.wi;
        },
        [&](const Vec3& w) {
            SurfaceHit hit;
            if (!scene.intersect(Ray{x, w}, NoHit, &hit)) return 0.0;
            return lights.pdf(x, hit.surface, hit.p, hit.ng);
        },
        opt);
}

Surface emitting(Surface s, double Le) {
    s.emission = Spectrum::Constant(Le);
    return s;
}

Eigen::Affine3d placed(const Vec3& t, double angle, const Vec3& axis, const Vec3& scale) {
    Eigen::Affine3d m = Eigen::Affine3d::Identity();
    m.translate(t).rotate(Eigen::AngleAxisd(angle, axis.normalized())).scale(scale);
    return m;
}

constexpr int kFamily = 6;

/// The χ² test of lightChi2 for an emitter seen from x, and ∫ pdf = 1.
void expectChi2(Surface emitter, const Vec3& x) {
    std::vector<Surface> s;
    s.push_back(emitting(std::move(emitter), 1));
    const SurfaceScene scene(std::move(s));
    const Chi2Result r = lightChi2(scene, x, kFamily);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdfIntegral, 1, 1e-5);
}

TEST(AreaLights, RectangleChi2) {
    std::vector<Surface> s;
    s.push_back(emitting(
        Surface::rectangle(placed(Vec3(0, 0, 1), 0.4, Vec3(1, 1, 0), Vec3(2, 0.5, 1))), 1));
    const SurfaceScene scene(std::move(s));
    const Chi2Result r = lightChi2(scene, Vec3(0.3, -0.2, 0), kFamily);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdfIntegral, 1, 1e-5);
}

TEST(AreaLights, DiskChi2) {
    expectChi2(Surface::disk(placed(Vec3(0, 0.5, 1), 2.5, Vec3(1, 0, 0.3), Vec3::Ones())),
               Vec3(0, 0, 0));
}

TEST(AreaLights, SphereByConeFromOutsideChi2) {
    expectChi2(Surface::sphere(Vec3(0.5, 1, 2), 1), Vec3(0, 0, 0));
}

TEST(AreaLights, SphereByAreaFromInsideChi2) {
    expectChi2(Surface::sphere(Vec3(0, 0, 0), 1), Vec3(0.2, 0.5, -0.3));
}

TEST(AreaLights, MeshOfUnequalTrianglesChi2) {
    // A planar fan of triangles of very different areas: the density per unit area is uniform
    // only if triangles are chosen in proportion to their areas (the pdf is continuous across
    // the inner edges, so quadrature stays cheap).
    Surface m;
    m.kind = Surface::Kind::Mesh;
    m.mesh.p.push_back(Vec3(0.2, 0.1, 1.5));
    const double angles[] = {0, 0.2, 0.5, 1.4, 2.0, 3.5, 4.1, 6.0};
    for (double a : angles) m.mesh.p.push_back(Vec3(std::cos(a), std::sin(a) * 0.7, 1.5));
    for (uint32_t k = 1; k < 8; ++k) m.mesh.indices.insert(m.mesh.indices.end(), {0, k, k + 1});
    expectChi2(std::move(m), Vec3(0.1, -0.3, 0.2));
}

TEST(AreaLights, EmittersAreChosenByPower) {
    std::vector<Surface> s;
    s.push_back(emitting(Surface::sphere(Vec3(-2, 0, 2), 0.5), 1));
    s.push_back(emitting(Surface::disk(placed(Vec3(2, 0, 2), Pi, Vec3(1, 0, 0), Vec3::Ones())), 3));
    s.push_back(Surface::sphere(Vec3(0, 0, 5), 0.5));  // not an emitter: never sampled
    const SurfaceScene scene(std::move(s));
    const AreaLights lights(scene);
    EXPECT_EQ(lights.count(), 2u);
    // Powers ∝ A·L: sphere 4π(0.25)·1 = π, disk π·3: the disk is chosen with probability 3/4.
    Rng rng(3, 0);
    int disk = 0, n = 200000;
    for (int i = 0; i < n; ++i)
        disk += lights.sample(Vec3(0, 0, 0), rng.uniform(), rng.uniform2()).surface == 1;
    const double p = 0.75, sd = std::sqrt(p * (1 - p) / n);
    EXPECT_NEAR(double(disk) / n, p, 4 * sd);
    const Chi2Result r = lightChi2(scene, Vec3(0, 0, 0), kFamily);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdfIntegral, 1, 1e-5);
}

TEST(AreaLights, OneSidedEmission) {
    std::vector<Surface> s;
    s.push_back(emitting(Surface::rectangle(Eigen::Affine3d::Identity()), 2));  // faces +z
    const SurfaceScene scene(std::move(s));
    const AreaLights lights(scene);
    const AreaLightSample above = lights.sample(Vec3(0, 0, 1), 0.5, Vec2(0.3, 0.6));
    const AreaLightSample below = lights.sample(Vec3(0, 0, -1), 0.5, Vec2(0.3, 0.6));
    EXPECT_EQ(above.Le[0], 2);
    EXPECT_EQ(below.Le[0], 0);
    EXPECT_GT(below.pdf, 0);
}

}  // namespace
}  // namespace shvol
