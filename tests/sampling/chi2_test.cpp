// The harness must be able to fail: wrong pdfs, lost samples and samples where pdf = 0.
#include "shvol/sampling/chi2.h"

#include <gtest/gtest.h>

#include "shvol/sampling/warp.h"

namespace shvol {
namespace {

// Cosine-weighted hemisphere (Malley's method), written here so the test needs no other module.
Vec3 sampleCosine(const Vec2& u) {
    const double r = std::sqrt(u.x()), phi = TwoPi * u.y();
    return {r * std::cos(phi), r * std::sin(phi), safeSqrt(1 - u.x())};
}

// Henyey–Greenstein written out independently of shvol_phase (inverse CDF, pbrt-v3 §15.2.3).
double hg(double mu, double g) {
    return (1 - g * g) / (FourPi * std::pow(1 + g * g - 2 * g * mu, 1.5));
}
Vec3 sampleHgAboutZ(const Vec2& u, double g) {
    const double s = (1 - g * g) / (1 - g + 2 * g * u.x());
    const double mu = std::clamp((1 + g * g - s * s) / (2 * g), -1.0, 1.0);
    return sphericalDirection(mu, TwoPi * u.y());
}

TEST(Chi2, CorrectCosineSamplerPasses) {
    const auto r =
        chi2TestSphere([](Rng& rng) { return std::optional<Vec3>(sampleCosine(rng.uniform2())); },
                       [](const Vec3& w) { return std::max(0.0, w.z()) * InvPi; });
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-7);
}

// The Šidák correction: a family of numTests tests passes a test iff its p-value exceeds
// 1 − (1 − α)^(1/numTests). Pinned on both sides of one run's p-value (the same seed gives the
// same p): α chosen so that the corrected threshold is 1% below p passes, 1% above fails. An
// uncorrected threshold (α itself, which exceeds p in both cases) would fail both.
TEST(Chi2, SidakCorrectionSetsTheThreshold) {
    auto run = [](double alpha, int numTests) {
        Chi2Options opt;
        opt.sampleCount = 100000;
        opt.alpha = alpha;
        opt.numTests = numTests;
        return chi2TestSphere(
            [](Rng& rng) { return std::optional<Vec3>(sampleCosine(rng.uniform2())); },
            [](const Vec3& w) { return std::max(0.0, w.z()) * InvPi; }, opt);
    };
    const double p = run(0.01, 1).pValue;
    ASSERT_GT(p, 0.01);
    ASSERT_LT(p, 0.99);
    for (int k : {2, 10}) {
        // 1 − (1 − α)^(1/k) = t  ⇔  α = 1 − (1 − t)^k.
        auto alphaFor = [k](double t) { return 1 - std::pow(1 - t, k); };
        const Chi2Result below = run(alphaFor(0.99 * p), k), above = run(alphaFor(1.01 * p), k);
        EXPECT_EQ(below.pValue, p);
        EXPECT_TRUE(below.passed) << k << "\n" << below.report;
        EXPECT_FALSE(above.passed) << k << "\n" << above.report;
    }
}

TEST(Chi2, UniformPdfForCosineSamplesFails) {
    const auto r =
        chi2TestSphere([](Rng& rng) { return std::optional<Vec3>(sampleCosine(rng.uniform2())); },
                       [](const Vec3& w) { return w.z() >= 0 ? Inv2Pi : 0.0; });
    EXPECT_FALSE(r.passed) << r.report;
}

// Samples leaked where the claimed pdf is tiny but not zero (0.5% of them into a lower
// hemisphere of density 10⁻⁹/(2π)): every cell there expects far below 5 and is pooled, and the
// pool, filled up with the next cells to 5 expected, shows the leak (a pool left out of χ² while
// below 5 would hide it; helper 78 asked).
TEST(Chi2, SamplesLeakedWhereThePdfIsTinyFail) {
    constexpr double eps = 1e-9;
    const auto sample = [](Rng& rng) {
        const Vec2 u = rng.uniform2();
        if (rng.uniform() < 0.005) {
            const Vec3 w = sampleUniformSphere(u);
            return std::optional<Vec3>(Vec3(w.x(), w.y(), -std::abs(w.z())));
        }
        return std::optional<Vec3>(sampleCosine(u));
    };
    const auto pdf = [](const Vec3& w) {
        return w.z() > 0 ? (1 - eps) * w.z() * InvPi : eps * Inv2Pi;
    };
    const Chi2Result r = chi2TestSphere(sample, pdf);
    EXPECT_FALSE(r.passed) << r.report;
    // The 40 × 80 grid's 1600 lower cells, and the one upper cell that fills the pool to 5.
    EXPECT_NE(r.report.find("pooled 1601 cells"), std::string::npos) << r.report;
}

TEST(Chi2, CorrectHgSamplerPasses) {
    const auto r = chi2TestSphere(
        [](Rng& rng) { return std::optional<Vec3>(sampleHgAboutZ(rng.uniform2(), 0.6)); },
        [](const Vec3& w) { return hg(w.z(), 0.6); });
    EXPECT_TRUE(r.passed) << r.report;
}

TEST(Chi2, HgPdfWithWrongGFails) {
    const auto r = chi2TestSphere(
        [](Rng& rng) { return std::optional<Vec3>(sampleHgAboutZ(rng.uniform2(), 0.6)); },
        [](const Vec3& w) { return hg(w.z(), 0.5); });
    EXPECT_FALSE(r.passed) << r.report;
}

TEST(Chi2, SlightlyWrongGFailsToo) {
    // g off by 0.01 on 1e6 samples: a sensitive harness catches this.
    const auto r = chi2TestSphere(
        [](Rng& rng) { return std::optional<Vec3>(sampleHgAboutZ(rng.uniform2(), 0.6)); },
        [](const Vec3& w) { return hg(w.z(), 0.61); });
    EXPECT_FALSE(r.passed) << r.report;
}

// A sampler that returns NaN once in 10⁴ draws fails, which χ² alone cannot see (it adds about
// f²·N = 0.01 to the statistic; helper 89); one that returns nothing as often fails unless that
// is allowed.
TEST(Chi2, AnyNonFiniteSampleFails) {
    const auto sample = [](Rng& rng) -> std::optional<Vec3> {
        const Vec2 u = rng.uniform2();
        return rng.uniform() < 1e-4 ? Vec3::Constant(NAN) : sampleUniformSphere(u);
    };
    const auto pdf = [](const Vec3&) { return Inv4Pi; };
    const auto r = chi2TestSphere(sample, pdf);
    EXPECT_FALSE(r.passed) << r.report;
    EXPECT_GT(r.failedSamples, 0);
    // ... also where empty samples are allowed (helper 90: NaN hid among them), which pass.
    Chi2Options allowed;
    allowed.allowFailedSamples = true;
    EXPECT_FALSE(chi2TestSphere(sample, pdf, allowed).passed);
    const auto empty = [](Rng& rng) -> std::optional<Vec3> {
        const Vec2 u = rng.uniform2();
        if (rng.uniform() < 1e-4) return std::nullopt;
        return sampleUniformSphere(u);
    };
    EXPECT_FALSE(chi2TestSphere(empty, pdf).passed);
    EXPECT_TRUE(chi2TestSphere(empty, pdf, allowed).passed);
}

TEST(Chi2, NonUnitDirectionsFail) {
    // Right in direction, 1% too long in one sample of 10⁴: binning normalised them (before
    // 6 Dec), so the test passed a sampler whose directions its callers use as they are.
    const auto sample = [](Rng& rng) -> std::optional<Vec3> {
        const Vec3 w = sampleUniformSphere(rng.uniform2());
        return rng.uniform() < 1e-4 ? Vec3(1.01 * w) : w;
    };
    const auto r = chi2TestSphere(sample, [](const Vec3&) { return Inv4Pi; });
    EXPECT_FALSE(r.passed) << r.report;
    EXPECT_GT(r.nonUnitSamples, 0);
    // Rounding (a length within 10⁻⁶ of 1) passes.
    const auto rounded = [](Rng& rng) -> std::optional<Vec3> {
        return Vec3((1 + 1e-9) * sampleUniformSphere(rng.uniform2()));
    };
    EXPECT_TRUE(chi2TestSphere(rounded, [](const Vec3&) { return Inv4Pi; }).passed);
}

TEST(Chi2, LostSamplesFail) {
    // 2% of the samples come back empty, yet the pdf claims they are all there.
    const auto r = chi2TestSphere(
        [](Rng& rng) -> std::optional<Vec3> {
            const Vec2 u = rng.uniform2();
            if (rng.uniform() < 0.02) return std::nullopt;
            return sampleUniformSphere(u);
        },
        [](const Vec3&) { return Inv4Pi; });
    EXPECT_FALSE(r.passed) << r.report;
    EXPECT_GT(r.failedSamples, 0);
}

TEST(Chi2, SamplesWherePdfIsZeroFail) {
    // Uniform-sphere samples against a hemisphere pdf: samples fall where expected = 0.
    Chi2Options opt;
    opt.sampleCount = 100000;
    const auto r = chi2TestSphere(
        [](Rng& rng) { return std::optional<Vec3>(sampleUniformSphere(rng.uniform2())); },
        [](const Vec3& w) { return w.z() >= 0 ? Inv2Pi : 0.0; }, opt);
    EXPECT_FALSE(r.passed) << r.report;
    EXPECT_EQ(r.pValue, 0.0);
}

// Counts binned by the caller: the statistic, its degrees of freedom and p against closed forms
// (for 3 and 2 degrees of freedom Q(dof/2, x/2) is erfc(√(x/2)) + √(2x/π) e^{−x/2} and e^{−x/2}),
// the pooling of cells that expect fewer than 5, and the failures that need no statistic.
TEST(Chi2, CountsAgainstClosedForms) {
    Chi2Result r = chi2TestCounts({10, 20, 30, 40}, {25, 25, 25, 25});
    EXPECT_DOUBLE_EQ(r.statistic, 20.0);
    EXPECT_EQ(r.dof, 3);
    EXPECT_NEAR(r.pValue, std::erfc(std::sqrt(10.0)) + std::sqrt(40 / Pi) * std::exp(-10.0), 1e-15);
    EXPECT_FALSE(r.passed) << r.report;  // p ≈ 1.7e-4
    // The two cells expecting 3 are pooled (6 expected, 9 seen); the others are tested alone.
    r = chi2TestCounts({4, 5, 90, 101}, {3, 3, 94, 100});
    const double x = 9.0 / 6 + 16.0 / 94 + 1.0 / 100;
    EXPECT_NEAR(r.statistic, x, 1e-14);
    EXPECT_EQ(r.dof, 2);
    EXPECT_NEAR(r.pValue, std::exp(-x / 2), 1e-15);
    EXPECT_TRUE(r.passed) << r.report;
    // A family of 10 lowers the threshold to 1 − 0.99^{1/10} ≈ 0.001005.
    Chi2Options ten;
    ten.numTests = 10;
    // χ² 12.5, p = e^{−6.25} ≈ 0.0019: rejected alone, not as one of ten.
    const std::vector<double> seen = {125, 75, 100}, expected = {100, 100, 100};
    EXPECT_FALSE(chi2TestCounts(seen, expected).passed);
    EXPECT_TRUE(chi2TestCounts(seen, expected, ten).passed);
    // Samples where none are expected; counts that are no counts, where no sample fell too (a
    // negative expectation would pass as 0, a NaN one poison the statistic, a NaN count sit
    // unseen in a pool of nothing expected); options out of range; too few cells.
    EXPECT_FALSE(chi2TestCounts({1, 99, 100}, {0, 100, 100}).passed);
    for (const auto& [seen, expect] :
         std::vector<std::pair<std::vector<double>, std::vector<double>>>{
             {{0, 100, 100}, {-1, 100, 100}},
             {{0, 100, 100}, {NAN, 100, 100}},
             {{0, 100, 100}, {INFINITY, 100, 100}},
             {{NAN, 100, 100}, {0, 100, 100}},
             {{-1, 101, 100}, {0, 100, 100}}}) {
        r = chi2TestCounts(seen, expect);
        EXPECT_FALSE(r.passed) << r.report;
        EXPECT_EQ(r.dof, 0) << r.report;  // (refused before any statistic)
    }
    Chi2Options bad;
    for (int k = 0; k < 4; ++k) {
        bad = Chi2Options{};
        if (k == 0) bad.numTests = 0;
        if (k == 1) bad.numTests = -1;  // (a negative threshold: anything would pass)
        if (k == 2) bad.alpha = 1;
        if (k == 3) bad.minExpected = 0;
        EXPECT_FALSE(chi2TestCounts({100, 100}, {100, 100}, bad).passed) << k;
    }
    EXPECT_TRUE(chi2TestCounts({100, 100}, {100, 100}).passed);
    EXPECT_FALSE(chi2TestCounts({100}, {100}).passed);
    EXPECT_FALSE(chi2TestCounts({100, 100}, {100, 100, 0}).passed);
    // Whole counts are reported whole.
    r = chi2TestCounts({1234567, 2345678}, {1790122.5, 1790122.5});
    EXPECT_NE(r.report.find("observed 1234567,"), std::string::npos) << r.report;
}

TEST(Chi2, IntegrateOverSphereOfPeakedLobe) {
    // HG g = 0.99 around an off-axis direction integrates to 1.
    const Vec3 axis = Vec3(0.3, -0.5, 0.8).normalized();
    const double I = integrateOverSphere([&](const Vec3& w) { return hg(axis.dot(w), 0.99); });
    EXPECT_NEAR(I, 1.0, 1e-6);
    EXPECT_NEAR(integrateOverSphere([](const Vec3&) { return 1.0; }), FourPi, 1e-12);
}

}  // namespace
}  // namespace shvol
