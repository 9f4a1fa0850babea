#include "shvol/sampling/warp.h"

#include <gtest/gtest.h>

#include "shvol/sampling/chi2.h"

namespace shvol {
namespace {

TEST(Warp, UniformSphereIsUnitAndCoversBothPoles) {
    EXPECT_NEAR(sampleUniformSphere({0.0, 0.3}).z(), 1.0, 1e-15);
    EXPECT_NEAR(sampleUniformSphere({1.0, 0.3}).z(), -1.0, 1e-15);
    Rng rng(7, 0);
    for (int i = 0; i < 1000; ++i)
        EXPECT_NEAR(sampleUniformSphere(rng.uniform2()).norm(), 1, 1e-14);
}

TEST(Warp, UniformSphereChi2) {
    Chi2Options opt;
    opt.numTests = 3;  // sphere, hemisphere and cosine hemisphere in this file
    const auto r = chi2TestSphere(
        [](Rng& rng) { return std::optional<Vec3>(sampleUniformSphere(rng.uniform2())); },
        [](const Vec3&) { return uniformSpherePdf(); }, opt);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-9);
}

TEST(Warp, UniformHemisphereChi2) {
    Chi2Options opt;
    opt.numTests = 3;
    opt.seed = 2;
    const auto r = chi2TestSphere(
        [](Rng& rng) { return std::optional<Vec3>(sampleUniformHemisphere(rng.uniform2())); },
        [](const Vec3& w) { return w.z() >= 0 ? uniformHemispherePdf() : 0.0; }, opt);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-9);
}

TEST(Warp, CosineHemisphereChi2) {
    Chi2Options opt;
    opt.numTests = 3;
    opt.seed = 3;
    const auto r = chi2TestSphere(
        [](Rng& rng) { return std::optional<Vec3>(sampleCosineHemisphere(rng.uniform2())); },
        [](const Vec3& w) { return cosineHemispherePdf(w.z()); }, opt);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-7);
    EXPECT_NEAR(sampleCosineHemisphere({0.0, 0.7}).z(), 1.0, 1e-15);
    EXPECT_NEAR(sampleCosineHemisphere({1.0, 0.7}).z(), 0.0, 1e-15);
}

TEST(Warp, UniformHemisphereStaysAbove) {
    Rng rng(3, 0);
    for (int i = 0; i < 10000; ++i) EXPECT_GE(sampleUniformHemisphere(rng.uniform2()).z(), 0.0);
}

}  // namespace
}  // namespace shvol
