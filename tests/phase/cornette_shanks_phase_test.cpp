#include "shvol/phase/cornette_shanks_phase.h"

#include <gtest/gtest.h>

#include <algorithm>

#include "phase/phase_test_util.h"
#include "shvol/phase/henyey_greenstein.h"
#include "shvol/phase/rayleigh_phase.h"

namespace shvol {
namespace {

using testing::checkFiniteAtExtremes;
using testing::checkSamples;
using testing::evalIntegral;
using testing::phaseChi2;

// Straight from Cornette & Shanks 1992.
double csRef(double mu, double g) {
    return 3 / (8 * Pi) * (1 - g * g) * (1 + mu * mu) /
           ((2 + g * g) * std::pow(1 + g * g - 2 * g * mu, 1.5));
}

TEST(CornetteShanks, MatchesFormula) {
    for (double g : {-0.9, -0.3, 0.0, 0.5, 0.95})
        for (double mu : {-1.0, -0.4, 0.0, 0.7, 1.0})
            EXPECT_NEAR(cornetteShanks(mu, g), csRef(mu, g), 1e-13 * csRef(mu, g));
    // g = 0 is Rayleigh.
    for (double mu : {-1.0, 0.2, 0.8}) EXPECT_NEAR(cornetteShanks(mu, 0.0), rayleigh(mu), 1e-16);
}

TEST(CornetteShanks, NormalisedExactly) {
    // The closed form integrates to 1 (see the header); quadrature over the sphere agrees.
    for (double g : {-0.99, -0.5, 0.0, 0.8, 0.99})
        EXPECT_NEAR(evalIntegral(CornetteShanksPhase(g)), 1.0, 1e-6) << "g = " << g;
}

TEST(CornetteShanks, MeanCosine) {
    // ⟨μ⟩ = 3g(4 + g²)/(5(2 + g²)), by quadrature.
    for (double g : {-0.6, 0.3, 0.8}) {
        const double m =
            testing::zonalIntegral([g](const Vec3& w) { return w.z() * cornetteShanks(w.z(), g); });
        EXPECT_NEAR(m, 3 * g * (4 + g * g) / (5 * (2 + g * g)), 1e-7) << g;
    }
}

TEST(CornetteShanks, SamplerPdfIsCloseToEvalAndNormalised) {
    // pdf is the sampler's own density: normalised, and within the tabulation error of eval.
    for (double g : {-0.999, -0.95, 0.0, 0.5, 0.95, 0.999}) {
        const CornetteShanksPhase p(g);
        const Vec3 z(0, 0, 1);
        if (std::abs(g) < 0.99)  // the chi² tests check the integral at 0.99
            EXPECT_NEAR(testing::zonalIntegral([&](const Vec3& w) { return p.pdf(z, w); }), 1.0,
                        1e-6)
                << g;
        // Probe uniformly in t (the lobe) and in μ (the tail).
        double maxDev = 0;
        for (int i = 0; i <= 20000; ++i) {
            for (double mu : {sampleHenyeyGreensteinCosTheta(i / 20000.0, g), -1 + i / 10000.0}) {
                const Vec3 w = sphericalDirection(mu, 0.0);
                maxDev = std::max(maxDev, std::abs(p.eval(z, w) / p.pdf(z, w) - 1));
            }
        }
        // Midpoints are refined to 1e-5; allow for the error between midpoints.
        EXPECT_LT(maxDev, 3e-5) << "g = " << g;
        std::cout << "[ measured ] g = " << g << ": max |value/pdf - 1| = " << maxDev << " with "
                  << p.warpedTable().nodes().size() << " nodes\n";
    }
}

class CornetteShanksChi2 : public ::testing::TestWithParam<double> {};

TEST_P(CornetteShanksChi2, SamplerMatchesPdf) {
    const double g = GetParam();
    const auto r = phaseChi2(CornetteShanksPhase(g), 4, 700 + uint64_t(1000 * (g + 1)));
    EXPECT_TRUE(r.passed) << "g = " << g << "\n" << r.report;
    EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-6) << "g = " << g;
}

INSTANTIATE_TEST_SUITE_P(CornetteShanks, CornetteShanksChi2,
                         ::testing::Values(-0.95, 0.0, 0.8, 0.99));

TEST(CornetteShanks, Chi2RejectsHgAsPdf) {
    // The chi² test can fail here: claiming plain HG as the density of the sampler (forgetting
    // the 1 + μ² factor of the warped table) must be rejected.
    const CornetteShanksPhase p(0.5);
    Chi2Options opt;
    opt.sampleCount = 300000;
    const auto r = chi2TestSphere(
        [&](Rng& rng) { return std::optional<Vec3>(p.sample(testing::kWo, rng.uniform2()).wi); },
        [&](const Vec3& wi) { return henyeyGreenstein(testing::kWo.dot(wi), 0.5); }, opt);
    EXPECT_FALSE(r.passed) << r.report;
}

TEST(CornetteShanks, SamplesConsistentAndFinite) {
    for (double g : {-0.9, 0.0, 0.6, 0.95}) checkSamples(CornetteShanksPhase(g), false, 1e-8, 2000);
    for (double g : {-0.999999, -0.999, 0.999, 0.999999})
        checkFiniteAtExtremes(CornetteShanksPhase(g));
    EXPECT_EQ(PhaseFunction(CornetteShanksPhase(0.1)).name(), "cornette_shanks");
}

}  // namespace
}  // namespace shvol
