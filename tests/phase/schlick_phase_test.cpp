#include "shvol/phase/schlick_phase.h"

#include <gtest/gtest.h>

#include "phase/phase_test_util.h"

namespace shvol {
namespace {

using testing::checkFiniteAtExtremes;
using testing::checkSamples;
using testing::evalIntegral;
using testing::phaseChi2;

double schlickRef(double mu, double k) {
    return (1 - k * k) / (FourPi * sqr(1 - k * mu));
}
double schlickCdfRef(double mu, double k) {
    return (1 - k) * (1 + mu) / (2 * (1 - k * mu));
}

TEST(Schlick, MatchesFormula) {
    for (double k : {-0.9, -0.3, 0.0, 0.5, 0.95})
        for (double mu : {-1.0, -0.4, 0.0, 0.7, 1.0})
            EXPECT_NEAR(schlick(mu, k), schlickRef(mu, k), 1e-13 * schlickRef(mu, k));
    EXPECT_DOUBLE_EQ(schlick(0.3, 0.0), Inv4Pi);
}

TEST(Schlick, PositiveKIsForward) {
    EXPECT_GT(schlick(1.0, 0.5), schlick(-1.0, 0.5));
    EXPECT_LT(schlick(1.0, -0.5), schlick(-1.0, -0.5));
    // The sampled directions follow wo for k > 0.
    const PhaseFunction p = SchlickPhase(0.9);
    Rng rng(3, 3);
    double mean = 0;
    for (int i = 0; i < 10000; ++i)
        mean += p.sample(testing::kWo, rng.uniform2()).wi.dot(testing::kWo);
    EXPECT_GT(mean / 10000, 0.6);
}

TEST(Schlick, IntegratesToOne) {
    for (double k : {-0.99, 0.0, 0.99})  // the chi² tests check more
        EXPECT_NEAR(evalIntegral(SchlickPhase(k)), 1.0, 1e-6) << "k = " << k;
}

TEST(Schlick, SamplerInvertsCdf) {
    for (double k : {-0.999, -0.9, -0.2, 0.0, 1e-9, 0.4, 0.9, 0.999}) {
        EXPECT_DOUBLE_EQ(sampleSchlickCosTheta(0.0, k), -1.0);
        EXPECT_DOUBLE_EQ(sampleSchlickCosTheta(1.0, k), 1.0);
        for (double u : {1e-9, 0.05, 0.3, 0.5, 0.8, 0.99, 1 - 1e-9}) {
            const double mu = sampleSchlickCosTheta(u, k);
            EXPECT_NEAR(schlickCdfRef(mu, k), u, 1e-12) << "k = " << k << " u = " << u;
        }
    }
}

class SchlickChi2 : public ::testing::TestWithParam<double> {};

TEST_P(SchlickChi2, SamplerMatchesPdf) {
    const double k = GetParam();
    const auto r = phaseChi2(SchlickPhase(k), 6, 300 + uint64_t(1000 * (k + 1)));
    EXPECT_TRUE(r.passed) << "k = " << k << "\n" << r.report;
    EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-6) << "k = " << k;
}

INSTANTIATE_TEST_SUITE_P(Schlick, SchlickChi2, ::testing::Values(-0.9, -0.5, 0.0, 0.5, 0.9, 0.99));

TEST(Schlick, Chi2RejectsTheOppositeSignConvention) {
    // The (1 + kμ)² form, i.e. the pdf of −k, must not pass for the (1 − kμ)² sampler.
    const SchlickPhase p(0.3), flipped(-0.3);
    Chi2Options opt;
    opt.sampleCount = 200000;
    const auto r = chi2TestSphere(
        [&](Rng& rng) { return std::optional<Vec3>(p.sample(testing::kWo, rng.uniform2()).wi); },
        [&](const Vec3& wi) { return flipped.pdf(testing::kWo, wi); }, opt);
    EXPECT_FALSE(r.passed) << r.report;
}

TEST(Schlick, SamplesConsistentAndFinite) {
    for (double k : {-0.99, -0.6, 0.0, 0.3, 0.99}) checkSamples(SchlickPhase(k), true, 1e-9, 2000);
    for (double k : {-0.999999, -0.999, 0.999, 0.999999}) checkFiniteAtExtremes(SchlickPhase(k));
    EXPECT_EQ(PhaseFunction(SchlickPhase(0.1)).name(), "schlick");
}

}  // namespace
}  // namespace shvol
