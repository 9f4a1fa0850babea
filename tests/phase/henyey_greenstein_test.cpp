#include "shvol/phase/henyey_greenstein.h"

#include <gtest/gtest.h>

#include <cmath>

#include "shvol/core/math.h"
#include "shvol/core/rng.h"
#include "shvol/phase/cornette_shanks_phase.h"
#include "shvol/phase/henyey_greenstein_phase.h"
#include "shvol/phase/two_term_hg_phase.h"
#include "shvol/sampling/chi2.h"
#include "shvol/sampling/warp.h"

namespace shvol {
namespace {

// Reference p(μ) written straight from the formula.
double hgRef(double mu, double g) {
    return (1 - g * g) / (FourPi * std::pow(1 + g * g - 2 * g * mu, 1.5));
}
// Reference CDF P(μ) = (1 − g²)/(2g) [ (1 + g² − 2gμ)^{-1/2} − 1/(1 + g) ].
double hgCdfRef(double mu, double g) {
    return (1 - g * g) / (2 * g) * (1 / std::sqrt(1 + g * g - 2 * g * mu) - 1 / (1 + g));
}

TEST(HenyeyGreenstein, MatchesFormula) {
    for (double g : {-0.9, -0.3, 0.0, 0.2, 0.8})
        for (double mu : {-1.0, -0.5, 0.0, 0.3, 0.99, 1.0})
            EXPECT_NEAR(henyeyGreenstein(mu, g), hgRef(mu, g), 1e-13 * hgRef(mu, g))
                << g << " " << mu;
    EXPECT_DOUBLE_EQ(henyeyGreenstein(0.3, 0.0), Inv4Pi);
}

TEST(HenyeyGreenstein, ForwardForPositiveG) {
    EXPECT_GT(henyeyGreenstein(1.0, 0.5), henyeyGreenstein(-1.0, 0.5));
    EXPECT_LT(henyeyGreenstein(1.0, -0.5), henyeyGreenstein(-1.0, -0.5));
}

TEST(HenyeyGreenstein, IntegratesToOne) {
    for (double g : {-0.99, -0.9, -0.5, 0.0, 0.3, 0.7, 0.9, 0.99}) {
        // ∫ p dω = 2π ∫_{-1}^{1} p(μ) dμ, integrated over the sphere with the chi² quadrature.
        const double I =
            integrateOverSphere([g](const Vec3& w) { return henyeyGreenstein(w.z(), g); });
        EXPECT_NEAR(I, 1.0, 1e-6) << "g = " << g;
    }
}

TEST(HenyeyGreenstein, SamplerInvertsCdf) {
    for (double g : {-0.95, -0.5, -1e-2, 0.1, 0.6, 0.95}) {
        for (double u : {0.0, 1e-6, 0.1, 0.25, 0.5, 0.75, 0.9, 1 - 1e-6}) {
            const double mu = sampleHenyeyGreensteinCosTheta(u, g);
            EXPECT_NEAR(hgCdfRef(mu, g), u, 1e-10) << "g = " << g << " u = " << u;
        }
        EXPECT_DOUBLE_EQ(sampleHenyeyGreensteinCosTheta(0.0, g), -1.0);
        // u → 1 gives μ → 1 (1 − μ is O(1 − u), larger for g < 0 where the density at μ = 1 is
        // small).
        EXPECT_NEAR(sampleHenyeyGreensteinCosTheta(std::nextafter(1.0, 0.0), g), 1.0, 1e-12);
    }
}

TEST(HenyeyGreenstein, CdfMatchesFormulaAndInvertsTheSampler) {
    for (double g : {-0.9, -0.3, 0.2, 0.8})
        for (double mu : {-1.0, -0.5, 0.0, 0.3, 0.99, 1.0})
            EXPECT_NEAR(henyeyGreensteinCdf(mu, g), hgCdfRef(mu, g), 1e-13) << g << " " << mu;
    for (double mu : {-1.0, 0.0, 0.4})
        EXPECT_NEAR(henyeyGreensteinCdf(mu, 0.0), (1 + mu) / 2, 1e-16);
    for (double g : {-0.999, -0.5, 0.0, 0.3, 0.9, 0.999})
        for (double u : {0.0, 1e-9, 0.1, 0.5, 0.9, 1 - 1e-9, 1.0})
            EXPECT_NEAR(henyeyGreensteinCdf(sampleHenyeyGreensteinCosTheta(u, g), g), u, 1e-9)
                << g << " " << u;
}

TEST(HenyeyGreenstein, SamplerNearZeroG) {
    // g = 0 is exactly uniform in μ; tiny g stays within O(g) of it and inverts its own CDF.
    for (double u : {0.0, 0.2, 0.5, 0.9})
        EXPECT_NEAR(sampleHenyeyGreensteinCosTheta(u, 0.0), 2 * u - 1, 1e-15);
    for (double g : {1e-5, -1e-5, 1e-9}) {
        for (double u : {0.05, 0.3, 0.5, 0.8}) {
            const double mu = sampleHenyeyGreensteinCosTheta(u, g);
            EXPECT_NEAR(mu, 2 * u - 1, 4 * std::abs(g));
            // The closed-form CDF is still accurate enough in double for |g| ≥ 1e-5.
            if (std::abs(g) >= 1e-5) EXPECT_NEAR(hgCdfRef(mu, g), u, 1e-9);
        }
    }
    // The first-order shift: E[μ] = g, so μ(u) − (2u − 1) is proportional to g.
    const double d1 = sampleHenyeyGreensteinCosTheta(0.5, 1e-5),
                 d2 = sampleHenyeyGreensteinCosTheta(0.5, 2e-5);
    EXPECT_GT(d1, 0.0);
    EXPECT_NEAR(d2 / d1, 2.0, 1e-4);
}

TEST(HenyeyGreenstein, StableForExtremeG) {
    Rng rng(11, 0);
    for (double g : {0.999999, -0.999999, 0.0, 1e-12}) {
        for (int i = 0; i < 20000; ++i) {
            const double u = rng.uniform();
            const double mu = sampleHenyeyGreensteinCosTheta(u, g);
            ASSERT_TRUE(std::isfinite(mu));
            ASSERT_GE(mu, -1.0);
            ASSERT_LE(mu, 1.0);
            const double p = henyeyGreenstein(mu, g);
            ASSERT_TRUE(std::isfinite(p)) << g << " " << u;
            ASSERT_GT(p, 0.0) << g << " " << u;
        }
    }
    // Peak and tail values for g → 1 from the cancellation-free form.
    const double g = 0.999999;
    const double peak = (1 + g) / (FourPi * sqr(1 - g));  // p(1) = (1 − g²)/(4π(1 − g)³)
    EXPECT_NEAR(henyeyGreenstein(1.0, g), peak, 1e-9 * peak);
    const double tail = (1 - g) / (FourPi * sqr(1 + g));  // p(−1)
    EXPECT_NEAR(henyeyGreenstein(-1.0, g), tail, 1e-9 * tail);
}

TEST(HenyeyGreenstein, MeanCosineIsG) {
    // E[μ] = g for HG, estimated from the sampler.
    Rng rng(4, 4);
    for (double g : {-0.7, 0.0, 0.4, 0.9}) {
        const int n = 200000;
        double sum = 0, sum2 = 0;
        for (int i = 0; i < n; ++i) {
            const double mu = sampleHenyeyGreensteinCosTheta(rng.uniform(), g);
            sum += mu, sum2 += mu * mu;
        }
        const double mean = sum / n, var = sum2 / n - mean * mean;
        EXPECT_NEAR(mean, g, 5 * std::sqrt(var / n)) << g;
    }
}

// HenyeyGreensteinSampler's closed-form density against the formula, henyeyGreenstein at the
// sampled μ (whose own accuracy the CDF tests above check: sampleHenyeyGreensteinCosTheta is the
// sampler's μ), as far as μ's rounding allows: an error δμ changes p by 3|g|δμ/b relative,
// b = 1 + g² − 2gμ ≥ (1 − |g|)², which is 3.3·10⁻¹² at |g| = 0.99 for δμ = 2⁻⁵³ (hence 4·10⁻¹²).
// At |g| → 1 that bound is useless; the ends are checked against the exact values p(∓1) instead.
TEST(HenyeyGreenstein, SamplerDensityIsTheFormulaAtTheSampledCosine) {
    Rng rng(12, 12);
    for (double g : {-0.99, -0.7, -1e-9, 0.0, 1e-9, 0.3, 0.8, 0.99}) {
        const HenyeyGreensteinSampler sampler(g);
        for (int i = 0; i < 20000; ++i) {
            const double u = i < 2 ? double(i) : rng.uniform();
            const HenyeyGreensteinSampler::Sample s = sampler(u);
            ASSERT_NEAR(s.pdf, henyeyGreenstein(s.angle.mu, g), 4e-12 * s.pdf) << g << " " << u;
        }
    }
    for (double g : {0.999999, -0.999999}) {
        const HenyeyGreensteinSampler sampler(g);
        EXPECT_EQ(sampler(0.0).angle.mu, -1.0);
        EXPECT_EQ(sampler(1.0).angle.mu, 1.0);
        const double pBack = (1 - g) / (FourPi * sqr(1 + g)),  // p(−1)
            pFront = (1 + g) / (FourPi * sqr(1 - g));          // p(1)
        EXPECT_NEAR(sampler(0.0).pdf, pBack, 1e-14 * pBack);
        EXPECT_NEAR(sampler(1.0).pdf, pFront, 1e-14 * pFront);
        // p is monotonic in μ: every sample lies between the two.
        const double lo = std::min(pBack, pFront), hi = std::max(pBack, pFront);
        for (int i = 0; i < 20000; ++i) {
            const HenyeyGreensteinSampler::Sample s = sampler(rng.uniform());
            ASSERT_TRUE(std::isfinite(s.pdf)) << g;
            ASSERT_LE(s.pdf, hi * (1 + 1e-14)) << g;
            ASSERT_GE(s.pdf, lo * (1 - 1e-14)) << g;
        }
    }
}

// Near |g| = 1 the lobe is narrower than the rounding of μ = wo·wi (at g = 0.999999 its width
// 1 − μ ~ 10⁻¹² is 10⁴ ulps of μ): eval, pdf and sample() work from the angle's complements
// instead, and agree with the density at the exact angle between the returned unit vectors
// (long double: 1 − μ = 2 sin²(θ/2), θ = atan2(|wo × wi|, wo·wi)). From the rounded μ they
// were off by up to 1.3·10⁻³ (the reference's own error is about 10⁻¹⁹/(1 − |μ|)). Also for the
// two-term mixture and Cornette–Shanks (whose pdf is HG's times a table).
TEST(HenyeyGreenstein, NarrowLobesAreEvaluatedFromTheAngle) {
    auto exactHg = [](const Vec3& a, const Vec3& b, double g) {
        using LD = long double;
        const LD cx = LD(a.y()) * b.z() - LD(a.z()) * b.y(),
                 cy = LD(a.z()) * b.x() - LD(a.x()) * b.z(),
                 cz = LD(a.x()) * b.y() - LD(a.y()) * b.x();
        const LD dot = LD(a.x()) * b.x() + LD(a.y()) * b.y() + LD(a.z()) * b.z();
        const LD theta = std::atan2(std::sqrt(cx * cx + cy * cy + cz * cz), dot);
        const LD oneMinusMu = 2 * sqr(std::sin(theta / 2)),
                 onePlusMu = 2 * sqr(std::cos(theta / 2));
        const LD base = g >= 0 ? sqr(1 - LD(g)) + 2 * LD(g) * oneMinusMu
                               : sqr(1 + LD(g)) - 2 * LD(g) * onePlusMu;
        return double((1 - LD(g) * g) /
                      (4 * 3.14159265358979323846264338327950288L * base * std::sqrt(base)));
    };
    Rng rng(21, 21);
    for (double g : {0.99, 0.9999, 0.999999, -0.999999}) {
        const HenyeyGreensteinPhase hg(g);
        double worstEval = 0, worstSample = 0;
        for (int i = 0; i < 20000; ++i) {
            const Vec3 wo = sampleUniformSphere(rng.uniform2());
            const PhaseSample s = hg.sample(wo, rng.uniform2());
            const double exact = exactHg(wo, s.wi, g);
            worstEval = std::max(worstEval, std::abs(hg.pdf(wo, s.wi) / exact - 1));
            worstSample = std::max(worstSample, std::abs(s.pdf / exact - 1));
        }
        SCOPED_TRACE(g);
        // Measured: 1.1·10⁻¹¹ and 1.8·10⁻¹⁰ at |g| = 0.999999 (the sample's direction is rounded
        // in its frame, an error of about 10⁻¹⁶ rad in an angle of about 10⁻⁶).
        EXPECT_LT(worstEval, 1e-9);
        EXPECT_LT(worstSample, 1e-8);
    }
    const TwoTermHenyeyGreensteinPhase two(0.999999, -0.999999, 0.7);
    const CornetteShanksPhase cs(0.999999);
    double worstTwo = 0, worstCs = 0;
    for (int i = 0; i < 20000; ++i) {
        const Vec3 wo = sampleUniformSphere(rng.uniform2());
        const PhaseSample s = two.sample(wo, rng.uniform2());
        const double exact = 0.7 * exactHg(wo, s.wi, 0.999999) + 0.3 * exactHg(wo, s.wi, -0.999999);
        worstTwo = std::max(worstTwo, std::abs(two.pdf(wo, s.wi) / exact - 1));
        const PhaseSample c = cs.sample(wo, rng.uniform2());
        worstCs = std::max(worstCs, std::abs(cs.pdf(wo, c.wi) / c.pdf - 1));
    }
    EXPECT_LT(worstTwo, 1e-9);  // measured 1.1·10⁻¹¹
    EXPECT_LT(worstCs, 1e-8);   // measured 2.0·10⁻¹⁰ (1.3·10⁻³ from the rounded μ)
}

}  // namespace
}  // namespace shvol
