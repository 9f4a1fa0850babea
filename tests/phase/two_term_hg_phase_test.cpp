#include "shvol/phase/two_term_hg_phase.h"

#include <gtest/gtest.h>

#include <tuple>

#include "phase/phase_test_util.h"

namespace shvol {
namespace {

using testing::checkFiniteAtExtremes;
using testing::checkSamples;
using testing::evalIntegral;
using testing::phaseChi2;

// Two-term HG with one lobe at the end of its range, forward (g₁ = 0.999999 beside g₂ = −0.3,
// w = 0.2) and backward (g₂ = −0.999999 beside g₁ = 0.5, w = 0.7), binned from the sharp lobe's
// pole against the mixture's formula: the equal-area χ² cannot see either spike (helper 92).
// From the forward pole 1 + g² − 2gμ = (1 − g)² + 2gd (d = 1 − μ), from the backward one
// (1 + g)² − 2gd (d = 1 + μ).
TEST(TwoTermHg, NarrowLobeChi2) {
    // HG over d (φ integrated out) from the forward pole, and from the backward one.
    const auto fromFront = [](double d, double g) {
        return (1 - g * g) / (2 * std::pow((1 - g) * (1 - g) + 2 * g * d, 1.5));
    };
    const auto fromBack = [](double d, double g) {
        return (1 - g * g) / (2 * std::pow((1 + g) * (1 + g) - 2 * g * d, 1.5));
    };
    const Chi2Result forward = testing::narrowLobeChi2(
        PhaseFunction(TwoTermHenyeyGreensteinPhase(0.999999, -0.3, 0.2)), false,
        [&](double d) { return 0.2 * fromFront(d, 0.999999) + 0.8 * fromFront(d, -0.3); }, 2, 31);
    EXPECT_TRUE(forward.passed) << forward.report;
    const Chi2Result backward = testing::narrowLobeChi2(
        PhaseFunction(TwoTermHenyeyGreensteinPhase(0.5, -0.999999, 0.7)), true,
        [&](double d) { return 0.7 * fromBack(d, 0.5) + 0.3 * fromBack(d, -0.999999); }, 2, 32);
    EXPECT_TRUE(backward.passed) << backward.report;
}

TEST(TwoTermHg, IsTheMixture) {
    const TwoTermHenyeyGreensteinPhase p(0.9, -0.3, 0.8);
    const Vec3 wo(0, 0, 1);
    for (double mu : {-1.0, -0.2, 0.5, 0.99, 1.0}) {
        const Vec3 wi = sphericalDirection(mu, 1.0);
        EXPECT_NEAR(p.eval(wo, wi),
                    0.8 * henyeyGreenstein(wi.z(), 0.9) + 0.2 * henyeyGreenstein(wi.z(), -0.3),
                    1e-14 * p.eval(wo, wi));
    }
    // w = 1 and w = 0 reduce to one lobe, in eval and in the sampler.
    const TwoTermHenyeyGreensteinPhase only1(0.7, -0.5, 1.0), only2(0.7, -0.5, 0.0);
    for (double u : {0.0, 0.3, 0.999}) {
        EXPECT_EQ(sampleTwoTermHenyeyGreensteinCosTheta(u, 0.7, -0.5, 1.0),
                  sampleHenyeyGreensteinCosTheta(u, 0.7));
        EXPECT_EQ(sampleTwoTermHenyeyGreensteinCosTheta(u, 0.7, -0.5, 0.0),
                  sampleHenyeyGreensteinCosTheta(u, -0.5));
    }
    EXPECT_EQ(only1.eval(wo, wo), henyeyGreenstein(1.0, 0.7));
    EXPECT_EQ(only2.eval(wo, wo), henyeyGreenstein(1.0, -0.5));
}

TEST(TwoTermHg, IntegratesToOne) {
    for (auto [g1, g2, w] : {std::tuple{0.9, -0.3, 0.8}, {0.99, -0.99, 0.5}, {-0.9, 0.2, 0.3}})
        EXPECT_NEAR(evalIntegral(TwoTermHenyeyGreensteinPhase(g1, g2, w)), 1.0, 1e-6);
}

TEST(TwoTermHg, MeanCosine) {
    // E[μ] = w g₁ + (1 − w) g₂, estimated from the sampler.
    Rng rng(8, 8);
    const double g1 = 0.85, g2 = -0.4, w = 0.7;
    const int n = 200000;
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n; ++i) {
        const double mu = sampleTwoTermHenyeyGreensteinCosTheta(rng.uniform(), g1, g2, w);
        sum += mu, sum2 += mu * mu;
    }
    const double mean = sum / n, var = sum2 / n - mean * mean;
    EXPECT_NEAR(mean, w * g1 + (1 - w) * g2, 5 * std::sqrt(var / n));
}

struct Params {
    double g1, g2, w;
};
// The parameters in test names, instead of gtest's dump of the struct's bytes.
void PrintTo(const Params& p, std::ostream* os) {
    *os << "g1_" << p.g1 << "_g2_" << p.g2 << "_w_" << p.w;
}
class TwoTermHgChi2 : public ::testing::TestWithParam<Params> {};

TEST_P(TwoTermHgChi2, SamplerMatchesPdf) {
    const auto [g1, g2, w] = GetParam();
    const auto r = phaseChi2(TwoTermHenyeyGreensteinPhase(g1, g2, w), 4,
                             500 + uint64_t(100 * (g1 + 1) + 10 * (g2 + 1) + w));
    EXPECT_TRUE(r.passed) << g1 << " " << g2 << " " << w << "\n" << r.report;
    EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-6);
}

INSTANTIATE_TEST_SUITE_P(TwoTermHg, TwoTermHgChi2,
                         ::testing::Values(Params{0.9, -0.3, 0.8}, Params{0.99, -0.95, 0.5},
                                           Params{-0.7, 0.95, 0.2}, Params{0.5, 0.0, 0.999}));

TEST(TwoTermHg, SamplesConsistentAndFinite) {
    checkSamples(TwoTermHenyeyGreensteinPhase(0.9, -0.3, 0.8), true);
    checkSamples(TwoTermHenyeyGreensteinPhase(0.95, -0.95, 0.5), true, 1e-9, 2000);
    for (double w : {0.0, 0.5, 1.0}) {
        checkFiniteAtExtremes(TwoTermHenyeyGreensteinPhase(0.999999, -0.999999, w));
        checkFiniteAtExtremes(TwoTermHenyeyGreensteinPhase(0.999, -0.999, w));
    }
    EXPECT_EQ(PhaseFunction(TwoTermHenyeyGreensteinPhase(0.1, 0.2, 0.3)).name(), "two_term_hg");
}

}  // namespace
}  // namespace shvol
