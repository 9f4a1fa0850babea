#include "shvol/phase/rayleigh_phase.h"

#include <gtest/gtest.h>

#include "phase/phase_test_util.h"

namespace shvol {
namespace {

using testing::checkFiniteAtExtremes;
using testing::checkSamples;
using testing::evalIntegral;
using testing::phaseChi2;

double rayleighCdfRef(double mu) {
    return (mu * mu * mu + 3 * mu + 4) / 8;
}

TEST(Rayleigh, MatchesFormula) {
    for (double mu : {-1.0, -0.5, 0.0, 0.3, 1.0})
        EXPECT_NEAR(rayleigh(mu), 3 / (16 * Pi) * (1 + mu * mu), 1e-16);
    EXPECT_DOUBLE_EQ(rayleigh(1.0), rayleigh(-1.0));
    EXPECT_DOUBLE_EQ(rayleigh(1.0), 2 * rayleigh(0.0));
}

TEST(Rayleigh, IntegratesToOne) {
    EXPECT_NEAR(evalIntegral(RayleighPhase()), 1.0, 1e-9);
}

TEST(Rayleigh, SamplerInvertsCdf) {
    EXPECT_DOUBLE_EQ(sampleRayleighCosTheta(0.0), -1.0);
    EXPECT_DOUBLE_EQ(sampleRayleighCosTheta(1.0), 1.0);
    EXPECT_NEAR(sampleRayleighCosTheta(0.5), 0.0, 1e-16);
    for (double u : {1e-12, 1e-6, 0.01, 0.1, 0.3, 0.49, 0.51, 0.7, 0.99, 1 - 1e-9}) {
        const double mu = sampleRayleighCosTheta(u);
        EXPECT_NEAR(rayleighCdfRef(mu), u, 2e-16 * 8) << u;
        EXPECT_NEAR(sampleRayleighCosTheta(1 - u), -mu, 1e-15) << u;  // symmetric
    }
}

TEST(Rayleigh, Chi2) {
    const auto r = phaseChi2(RayleighPhase(), 1, 21);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-9);
}

TEST(Rayleigh, SamplesConsistent) {
    checkSamples(RayleighPhase(), true);
    checkFiniteAtExtremes(RayleighPhase());
    EXPECT_EQ(PhaseFunction(RayleighPhase()).name(), "rayleigh");
}

}  // namespace
}  // namespace shvol
