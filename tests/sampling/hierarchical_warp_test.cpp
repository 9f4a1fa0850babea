#include "shvol/sampling/hierarchical_warp.h"

#include <gtest/gtest.h>

#include "shvol/core/rng.h"
#include "shvol/sampling/chi2.h"

namespace shvol {

namespace {
// f(z, φ) = 1 + 0.5 z + 0.4 cos φ ≥ 0.1, integrated exactly over a cell.
double mass(double z0, double z1, double p0, double p1) {
    return (z1 - z0) * (p1 - p0) + 0.25 * (z1 * z1 - z0 * z0) * (p1 - p0) +
           0.4 * (z1 - z0) * (std::sin(p1) - std::sin(p0));
}
double density(double z, double phi) {
    return (1 + 0.5 * z + 0.4 * std::cos(phi)) / FourPi;
}
void children(const WarpNode& n, double c[4]) {
    for (int r = 0; r < 2; ++r)
        for (int k = 0; k < 2; ++k) {
            const WarpNode ch = n.child(r, k);
            c[2 * r + k] = mass(ch.z0, ch.z1, ch.phi0, ch.phi1);
        }
}
double radicalInverse2(uint32_t i) {
    i = (i << 16) | (i >> 16);
    i = ((i & 0x55555555u) << 1) | ((i & 0xAAAAAAAAu) >> 1);
    i = ((i & 0x33333333u) << 2) | ((i & 0xCCCCCCCCu) >> 2);
    i = ((i & 0x0F0F0F0Fu) << 4) | ((i & 0xF0F0F0F0u) >> 4);
    i = ((i & 0x00FF00FFu) << 8) | ((i & 0xFF00FF00u) >> 8);
    return i * 0x1p-32;
}
}  // namespace

// Deep enough, the warp's piecewise-constant density approaches the target; its pdf is exactly
// the density of the samples (chi²) and agrees with hierarchicalPdf.
TEST(HierarchicalWarp, MatchesTargetAndOwnPdf) {
    const int depth = 10;
    Rng rng(1, 1);
    for (int i = 0; i < 2000; ++i) {
        const WarpSample s = hierarchicalWarp(children, depth, rng.uniform2());
        ASSERT_GT(s.pdf, 0);
        // On a leaf of size Δz × Δφ the warp's density is the leaf mean of f, which differs from
        // f at a point of the leaf by at most (0.5 Δz + 0.4 Δφ)/(4π).
        const double bound = (0.5 * 2.0 / (1 << depth) + 0.4 * TwoPi / (1 << depth)) / FourPi;
        EXPECT_NEAR(s.pdf, density(s.z, s.phi), bound);
        EXPECT_NEAR(hierarchicalPdf(children, depth, s.z, s.phi), s.pdf, 1e-12 * s.pdf);
    }
    const Chi2Result r = chi2TestSphereCells(
        [](Rng& g) {
            return std::optional<Vec3>(hierarchicalWarp(children, depth, g.uniform2()).direction());
        },
        [](double z0, double z1, double p0, double p1) {
            return hierarchicalProbability(children, depth, z0, z1, p0, p1);
        });
    // On a rectangle made of whole leaves the probability is the target's own, to rounding.
    const double p0 = TwoPi * 128 / 1024, p1 = TwoPi * 384 / 1024;
    EXPECT_NEAR(hierarchicalProbability(children, depth, -1, 0.25, p0, p1),
                mass(-1, 0.25, p0, p1) / mass(-1, 1, 0, TwoPi), 1e-12);
    EXPECT_TRUE(r.passed) << r.report;
}

TEST(HierarchicalWarp, UniformTargetIsIdentity) {
    auto uniform = [](const WarpNode& n, double c[4]) {
        for (int i = 0; i < 4; ++i) c[i] = n.area() / 4;
    };
    Rng rng(2, 2);
    for (int i = 0; i < 1000; ++i) {
        const Vec2 u = rng.uniform2();
        const WarpSample s = hierarchicalWarp(uniform, 12, u);
        EXPECT_NEAR(s.z, -1 + 2 * u.x(), 1e-12);
        EXPECT_NEAR(s.phi, TwoPi * u.y(), 1e-12);
        // The leaf width φ1 − φ0 is a difference of numbers ~2^12 times larger: relative rounding
        // up to about 2^12 ε.
        EXPECT_NEAR(s.pdf, Inv4Pi, 4096 * 4e-16 * Inv4Pi);
    }
}

// Warping a whole point set gives the same images as warping each point, and a Hammersley set
// stays stratified: its counts per cell are far closer to the expected counts than random points'.
TEST(HierarchicalWarp, PointSetsPreserveStratification) {
    const int N = 4096, depth = 8, cells = 16;
    std::vector<Vec2> ham(N), rnd(N);
    Rng rng(3, 3);
    for (int i = 0; i < N; ++i)
        ham[i] = Vec2((i + 0.5) / N, radicalInverse2(i)), rnd[i] = rng.uniform2();
    std::vector<WarpSample> wh(N), wr(N);
    hierarchicalWarpPoints(children, depth, ham.data(), N, wh.data());
    hierarchicalWarpPoints(children, depth, rnd.data(), N, wr.data());
    for (int i = 0; i < N; ++i) {
        const WarpSample one = hierarchicalWarp(children, depth, ham[i]);
        ASSERT_EQ(one.z, wh[i].z);
        ASSERT_EQ(one.phi, wh[i].phi);
        ASSERT_EQ(one.pdf, wh[i].pdf);
    }
    std::vector<double> expected(cells * cells);
    for (int a = 0; a < cells; ++a)
        for (int b = 0; b < cells; ++b)
            expected[a * cells + b] = N *
                                      mass(-1 + 2.0 * a / cells, -1 + 2.0 * (a + 1) / cells,
                                           TwoPi * b / cells, TwoPi * (b + 1) / cells) /
                                      FourPi;
    auto chi2Stat = [&](const std::vector<WarpSample>& w) {  // χ² per degree of freedom
        std::vector<double> count(cells * cells, 0);
        for (const auto& s : w)
            ++count[std::min(cells - 1, int((s.z + 1) / 2 * cells)) * cells +
                    std::min(cells - 1, int(s.phi / TwoPi * cells))];
        const Chi2Result r = chi2TestCounts(count, expected);  // (12 cells expecting < 5 pooled)
        return r.statistic / r.dof;
    };
    const double stratified = chi2Stat(wh), random = chi2Stat(wr);
    EXPECT_LT(stratified, 0.2) << "random: " << random;
    EXPECT_GT(random, 0.5);
}

TEST(HierarchicalWarp, ZeroMassGivesInvalidSamples) {
    auto zero = [](const WarpNode&, double c[4]) { c[0] = c[1] = c[2] = c[3] = -1; };
    EXPECT_EQ(hierarchicalWarp(zero, 4, Vec2(0.3, 0.3)).pdf, 0);
    EXPECT_EQ(hierarchicalPdf(zero, 4, 0.0, 1.0), 0);
}

}  // namespace shvol
