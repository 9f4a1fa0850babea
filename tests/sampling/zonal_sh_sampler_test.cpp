#include "shvol/sampling/zonal_sh_sampler.h"

#include <gtest/gtest.h>

#include "shvol/core/rng.h"
#include "shvol/sampling/chi2.h"
#include "shvol/sampling/hierarchical_warp.h"
#include "shvol/sh/sh_basis.h"
#include "shvol/sh/sh_integrals.h"

namespace shvol {

namespace {
// Truncated Henyey–Greenstein: p_l = g^l √((2l+1)/4π).
std::vector<double> hg(double g, int n) {
    std::vector<double> p(n);
    for (int l = 0; l < n; ++l) p[l] = std::pow(g, l) * std::sqrt((2 * l + 1) / FourPi);
    return p;
}
const Vec3 kAxis = Vec3(-0.2, 0.7, 0.4).normalized();
/// Truncated HG lobes (g, order) that the chi-squared test and the cdf test share.
struct Case {
    double g;
    int n;
};
constexpr Case kCases[] = {{0.5, 8}, {0.9, 32}, {-0.7, 16}, {0.99, 8}};
}  // namespace

TEST(ZonalSHSampler, Chi2AroundAnOffAxisDirection) {
    for (const Case& c : kCases) {
        const ZonalSHSampler s(hg(c.g, c.n));
        Chi2Options opt;
        opt.numTests = 4;
        opt.seed = c.n;
        // Samples are drawn around kAxis and binned in kAxis's frame, where the expected cell
        // probabilities are exact: (φ1−φ0)/2π · (cdf(z1) − cdf(z0)).
        const Frame frame(kAxis);
        const Chi2Result r = chi2TestSphereCells(
            [&](Rng& rng) -> std::optional<Vec3> {
                const SphereSample x = s.sample(kAxis, rng.uniform2());
                if (!(x.pdf > 0)) return std::nullopt;
                EXPECT_NEAR(x.pdf, s.pdf(kAxis.dot(x.w)), 1e-12 * x.pdf);
                EXPECT_NEAR(x.value, s.eval(kAxis.dot(x.w)), 1e-12 * std::abs(x.value) + 1e-12);
                return frame.toLocal(x.w);
            },
            [&](double z0, double z1, double p0, double p1) {
                return (p1 - p0) / TwoPi * (s.cdf(z1) - s.cdf(z0));
            },
            opt);
        EXPECT_TRUE(r.passed) << "g " << c.g << " order " << c.n << "\n" << r.report;
        EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-4);
    }
}

// The chi-squared test above takes its cells from cdf(): here cdf() is tied to the claimed pdf
// (its derivative, 2π·pdf per unit of z, bin by bin: pdf is constant on each of the 2^depth bins)
// and to the function (each bin's mass ∝ ∫ p̃ dz over it where p̃ > 0 on the whole bin,
// integrated here by Simpson's rule), so neither can drift from what is sampled (helper 78).
// value/pdf of sample() estimates ∫ p̃ dω = √(4π) p_0 where no bin is clamped (every direction
// where p̃ has mass is sampled), within 5 standard errors over 100,000 samples.
TEST(ZonalSHSampler, SampleValueOverPdfEstimatesTheIntegral) {
    int tested = 0;
    for (const Case& c : kCases) {
        const ZonalSHSampler s(hg(c.g, c.n));
        if (s.clampedFraction() > 0) continue;
        ++tested;
        Rng rng(c.n, 3);
        double sum = 0, sum2 = 0;
        const int N = 100000;
        for (int i = 0; i < N; ++i) {
            const SphereSample x = s.sample(kAxis, rng.uniform2());
            ASSERT_GT(x.pdf, 0);
            const double r = x.value / x.pdf;
            sum += r, sum2 += r * r;
        }
        const double mean = sum / N, se = std::sqrt((sum2 / N - mean * mean) / (N - 1));
        const double integral = std::sqrt(FourPi) * s.coefficients()[0];
        EXPECT_NEAR(mean, integral, 5 * se + 1e-12) << c.g << " " << c.n;
        EXPECT_GT(se, 0);
    }
    EXPECT_GE(tested, 2);
}

TEST(ZonalSHSampler, CdfIsTheIntegralOfThePdfAndOfTheFunction) {
    for (const Case& c : kCases) {
        const int depth = 8, bins = 1 << depth;
        const ZonalSHSampler s(hg(c.g, c.n), depth);
        const double dz = 2.0 / bins;
        int compared = 0;
        for (int k = 0; k < bins; ++k) {
            const double z0 = -1 + k * dz, z1 = z0 + dz, mass = s.cdf(z1) - s.cdf(z0);
            EXPECT_NEAR(mass, TwoPi * s.pdf(z0 + 0.5 * dz) * dz, 1e-12)
                << "g " << c.g << " bin " << k;
            // Simpson's rule on 64 intervals of the bin (p̃ is a polynomial of degree < 32).
            double integral = 0, lowest = INFINITY;
            for (int i = 0; i <= 64; ++i) {
                const double f = s.eval(z0 + dz * i / 64);
                lowest = std::min(lowest, f);
                integral += f * (i == 0 || i == 64 ? 1 : i % 2 ? 4 : 2);
            }
            integral *= dz / 64 / 3;
            if (!(lowest > 0)) continue;
            ++compared;
            EXPECT_NEAR(mass, TwoPi * integral / s.positiveMass(), 1e-9 * mass + 1e-15)
                << "g " << c.g << " bin " << k;
        }
        EXPECT_GT(compared, bins / 4) << "g " << c.g;  // (truncated HG rings below 0)
    }
}

// The guide-table inverse CDF is the 1D hierarchical warp: compare with the generic warp driven by
// on-the-fly zonal integrals. The function must be non-negative: with negative regions the fast
// sampler clamps leaves while the on-the-fly warp clamps per level, a legitimate difference.
TEST(ZonalSHSampler, MatchesGenericHierarchicalWarp) {
    // (g, order, depth): the order-6 lobe at depth 10, and sharp lobes at high orders at the
    // default depth 16 (helper 92: only the first was compared). Each truncated lobe is lifted
    // by its most negative value (on 20,001 cosines) and 1% of its peak, so it is ≥ 0.
    const struct {
        double g;
        int n, depth;
    } cases[] = {{0.6, 6, 10}, {0.9, 32, 16}, {0.97, 96, 16}};
    for (const auto& c : cases) {
        auto p = hg(c.g, c.n);
        std::vector<double> y(c.n);
        double lo = 0, hi = 0;
        for (int i = 0; i <= 20000; ++i) {
            sh::shEvalZonal(c.n, -1 + i / 10000.0, y.data());
            double f = 0;
            for (int l = 0; l < c.n; ++l) f += p[l] * y[l];
            lo = std::min(lo, f), hi = std::max(hi, f);
        }
        p[0] += (0.01 * hi - lo) * std::sqrt(FourPi);
        const ZonalSHSampler fast(p, c.depth);
        std::vector<double> Z(c.n);
        auto children = [&](const WarpNode& node, double m4[4]) {
            for (int r = 0; r < 2; ++r) {
                sh::legendreIntegralsZonal(c.n, r ? node.zMid() : node.z0,
                                           r ? node.z1 : node.zMid(), Z.data());
                double m = 0;
                for (int l = 0; l < c.n; ++l) m += p[l] * Z[l];
                m4[2 * r] = m4[2 * r + 1] = m * 0.5 * (node.phi1 - node.phi0);
            }
        };
        Rng rng(4, uint64_t(c.n));
        for (int i = 0; i < 5000; ++i) {
            const Vec2 u = rng.uniform2();
            // The generic warp splits φ at every level too; a uniform-in-φ target leaves
            // φ = 2πu.y.
            const WarpSample slow = hierarchicalWarp(children, c.depth, u);
            const ZonalSHSampler::LocalSample f = fast.warpLocal(u);
            ASSERT_NEAR(f.cosTheta, slow.z, 1e-9) << "order " << c.n;
            ASSERT_NEAR(f.phi, slow.phi, 1e-9) << "order " << c.n;
            ASSERT_NEAR(f.pdf, slow.pdf, 1e-9 * slow.pdf) << "order " << c.n;
        }
    }
}

// g = ±0.99 at low order rings strongly negative: no NaN, pdf normalised, negative bins unsampled.
TEST(ZonalSHSampler, ExtremeAnisotropyAtLowOrder) {
    for (double g : {0.99, -0.99}) {
        for (int n : {2, 3, 5, 8}) {
            const auto p = hg(g, n);
            const ZonalSHSampler s(p);
            double integral = 0;
            const int bins = 1 << s.depth();
            for (int i = 0; i < bins; ++i)
                integral += s.pdf(-1 + (i + 0.5) * 2.0 / bins) * TwoPi * 2.0 / bins;
            EXPECT_NEAR(integral, 1.0, 1e-9) << g << " " << n;
            if (n >= 3) {
                EXPECT_GT(s.clampedFraction(), 0.0) << "order " << n << " should ring negative";
            }
            Rng rng(n, 1);
            for (int i = 0; i < 20000; ++i) {
                const auto x = s.warpLocal(rng.uniform2());
                ASSERT_TRUE(std::isfinite(x.cosTheta));
                ASSERT_GT(x.pdf, 0);
                ASSERT_GE(s.eval(x.cosTheta), -1e-9 * std::abs(p[0]) - 1e-3 * s.pdf(x.cosTheta))
                    << "sampled a negative region";
            }
        }
    }
}

TEST(ZonalSHSampler, EvalIsTheReconstruction) {
    const auto p = hg(0.8, 12);
    const ZonalSHSampler s(p);
    for (double mu : {-1.0, -0.3, 0.0, 0.5, 0.999, 1.0}) {
        // Σ g^l (2l+1)/(4π) P_l(μ) with Bonnet's recurrence for the Legendre polynomials.
        double series = 0, Pm2 = 0, Pm1 = 0;
        for (int l = 0; l < 12; ++l) {
            const double P = l == 0   ? 1.0
                             : l == 1 ? mu
                                      : ((2 * l - 1) * mu * Pm1 - (l - 1) * Pm2) / l;
            Pm2 = Pm1, Pm1 = P;
            series += std::pow(0.8, l) * (2 * l + 1) / FourPi * P;
        }
        EXPECT_NEAR(s.eval(mu), series, 1e-12) << mu;
    }
}

}  // namespace shvol
