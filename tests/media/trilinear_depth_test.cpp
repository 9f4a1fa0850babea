// Regular tracking through a trilinear voxel grid: the cubic of one cell against the
// interpolation it stands for, the optical depth of whole rays against quadrature, and free
// flights and transmittance (alone and mixed with delta and ratio tracking) against the
// distribution the quadrature gives; at a density scale of 10¹² against a closed form.
#include "shvol/media/trilinear_depth.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "media/free_flight_chi2.h"
#include "shvol/core/rng.h"

namespace shvol {
namespace {

/// The χ² tests of free flights in this file: one family (Šidák).
constexpr int kFreeFlightChi2Tests = 4;

/// An n³ grid of voxels (index space, centres at 0 … n − 1), 0 outside.
struct Grid {
    int n;
    std::vector<float> v;
    float at(int x, int y, int z) const {
        if (x < 0 || y < 0 || z < 0 || x >= n || y >= n || z >= n) return 0;
        return v[(size_t(x) * n + y) * n + z];
    }
    void corners(int x, int y, int z, float c[8]) const {
        for (int i = 0; i < 8; ++i) c[i] = at(x + (i >> 2), y + ((i >> 1) & 1), z + (i & 1));
    }
    /// The trilinear interpolation at p, written out independently of TrilinearCubic.
    double rho(const Vec3& p) const {
        const int x = int(std::floor(p.x())), y = int(std::floor(p.y())),
                  z = int(std::floor(p.z()));
        const double fx = p.x() - x, fy = p.y() - y, fz = p.z() - z;
        double sum = 0;
        for (int a = 0; a < 2; ++a)
            for (int b = 0; b < 2; ++b)
                for (int k = 0; k < 2; ++k)
                    sum += at(x + a, y + b, z + k) * (a ? fx : 1 - fx) * (b ? fy : 1 - fy) *
                           (k ? fz : 1 - fz);
        return sum;
    }
};

/// A grid whose voxels are 0 with probability 1/2 and else uniform in [0, peak).
Grid randomGrid(int n, double peak, uint64_t seed) {
    Grid g{n, std::vector<float>(size_t(n) * n * n)};
    Rng rng(seed, 1);
    for (float& x : g.v) x = rng.uniform() < 0.5 ? 0.f : float(peak * rng.uniform());
    return g;
}

/// ∫_t0^t1 scale·ρ(o + t d) dt by 4-point Gauss–Legendre on `pieces` equal pieces (the
/// integrand is a cubic between kinks, so the error comes from the pieces with a kink).
double quadrature(const Grid& g, const Vec3& o, const Vec3& d, double t0, double t1, double scale,
                  int pieces = 20000) {
    const double x[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                         0.8611363115940526};
    const double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                         0.3478548451374538};
    const double h = (t1 - t0) / pieces;
    double sum = 0;
    for (int i = 0; i < pieces; ++i)
        for (int j = 0; j < 4; ++j) sum += w[j] * g.rho(o + (t0 + h * (i + 0.5 + 0.5 * x[j])) * d);
    return scale * sum * h / 2;
}

}  // namespace

// The cubic equals the trilinear interpolation along the segment, its integral the quadrature,
// and invertIntegral inverts it, also where the density is 0 on part of the segment.
TEST(TrilinearDepth, CubicIsTheInterpolationAlongTheSegment) {
    Rng rng(1, 2);
    for (int trial = 0; trial < 200; ++trial) {
        float v[8];
        for (float& x : v) x = trial % 4 == 0 && rng.uniform() < 0.7 ? 0.f : float(rng.uniform());
        const Vec3 q0(rng.uniform(), rng.uniform(), rng.uniform());
        const Vec3 q1(rng.uniform(), rng.uniform(), rng.uniform());
        const TrilinearCubic rho(v, q0, q1);
        Grid g{2, std::vector<float>(v, v + 8)};
        for (double s : {0.0, 0.25, 0.5, 0.9, 1.0})
            EXPECT_NEAR(rho(s), g.rho(q0 + s * (q1 - q0)), 1e-12) << trial;
        const double total = rho.integral(1);
        EXPECT_NEAR(total, quadrature(g, q0, q1 - q0, 0, 1, 1, 4), 1e-12) << trial;
        for (double f : {0.0, 1e-15, 1e-12, 1e-9, 0.3, 0.77, 1.0}) {
            const double s = rho.invertIntegral(f * total);
            EXPECT_GE(s, 0);
            EXPECT_LE(s, 1);
            EXPECT_NEAR(rho.integral(s), f * total, 1e-12 * f * total + 1e-16 * total)
                << trial << " " << f;
        }
    }
}

// The optical depth of whole rays through a random 8³ grid equals quadrature: oblique rays in
// both directions along every axis, rays along an axis (two components 0) and in a face plane,
// rays starting on cell boundaries and outside the grid; spend() stops where the depth reaches
// the budget.
TEST(TrilinearDepth, DepthAndSpendMatchQuadrature) {
    const Grid g = randomGrid(8, 1.0, 3);
    Rng rng(5, 6);
    std::vector<std::pair<Vec3, Vec3>> rays = {
        {{-1, 3.5, 4.2}, {1, 0, 0}},         {{9, 3, 4}, {-1, 0, 0}},
        {{2, 2, -2}, Vec3(0, 0.6, 0.8)},     {{3, 3, 3}, Vec3(-1, -2, 0.5).normalized()},
        {{-0.5, -0.5, -0.5}, Vec3(1, 1, 1)},  // not unit: t has the caller's units
    };
    for (int i = 0; i < 20; ++i) {
        const Vec3 o = Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 12 - Vec3::Constant(2);
        const Vec3 d = Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
        rays.push_back({o, d.normalized()});
    }
    for (const auto& [o, d] : rays) {
        const double scale = 2.5, t1 = 15;
        const TrilinearDepth depth(o, d, scale, g);
        TrackingCounters c;
        const double tau = depth.depth(0, t1, c);
        const double ref = quadrature(g, o, d, 0, t1, scale);
        EXPECT_NEAR(tau, ref, 1e-7 * (1 + ref)) << o.transpose() << " | " << d.transpose();
        // Two halves add up; spend() with a budget of half the depth stops where τ = τ/2.
        EXPECT_NEAR(depth.depth(0, 6, c) + depth.depth(6, t1, c), tau, 1e-12 * (1 + tau));
        if (tau > 0) {
            double e = tau / 2, t = -1;
            ASSERT_TRUE(depth.spend(0, t1, &e, &t, c));
            EXPECT_NEAR(quadrature(g, o, d, 0, t, scale), tau / 2, 1e-7 * (1 + tau));
            e = 2 * tau;  // more than the ray holds: spent, no collision
            EXPECT_FALSE(depth.spend(0, t1, &e, &t, c));
            EXPECT_NEAR(e, tau, 1e-12 * (1 + tau));
        }
    }
}

// A budget of exactly 0 (rounding can leave one) ends no flight where σ_t is 0: along the line
// y = z = 2 of a grid whose only voxel is at (3, 3, 3), the cells around x = 2 … 4 have that voxel
// as a corner but the interpolation is 0 on the whole line; past them the budget is still 0.
TEST(TrilinearDepth, ZeroBudgetNeedsDensity) {
    Grid g{6, std::vector<float>(216, 0.f)};
    g.v[(3 * 6 + 3) * 6 + 3] = 1;
    const TrilinearDepth depth(Vec3(0, 2, 2), Vec3(1, 0, 0), 1e6, g);
    TrackingCounters c;
    double e = 0, t = -1;
    EXPECT_FALSE(depth.spend(0, 6, &e, &t, c));
    EXPECT_EQ(e, 0);
    EXPECT_EQ(t, -1);
    EXPECT_EQ(depth.depth(0, 6, c), 0);
}

namespace {
/// Segments of the ray o + t d over [0, tEnd): pieces of the given lengths, each with the
/// majorant scale·(largest voxel), σ_min = 0.
struct Pieces {
    std::vector<double> lengths;
    double sigmaMaj;
    template <typename Visit>
    void operator()(Visit&& visit) const {
        double t = 0;
        for (double l : lengths) {
            if (!visit(t, t + l, sigmaMaj, 0.0)) return;
            t += l;
        }
    }
};

/// Regular tracking on every segment, however thin.
struct Always {
    const TrilinearDepth<Grid>& inner;
    bool preferred(double, double, double) const { return true; }
    bool spend(double t0, double t1, double* e, double* t, TrackingCounters& c) const {
        return inner.spend(t0, t1, e, t, c);
    }
    double depth(double t0, double t1, TrackingCounters& c, double stop) const {
        return inner.depth(t0, t1, c, stop);
    }
};

/// τ(t) along o + t d on [0, tEnd], interpolated in a table of quadratures at 20 001 points.
auto tauTable(const Grid& g, const Vec3& o, const Vec3& d, double scale, double tEnd) {
    constexpr int m = 20000;
    std::vector<double> tau(m + 1, 0.0);
    for (int i = 0; i < m; ++i)
        tau[i + 1] = tau[i] + quadrature(g, o, d, tEnd * i / m, tEnd * (i + 1) / m, scale, 1);
    return [tau, tEnd](double t) {
        const double x = std::clamp(t / tEnd * m, 0.0, double(m) - 1e-9);
        const int j = int(x);
        return tau[j] + (x - j) * (tau[j + 1] - tau[j]);
    };
}
}  // namespace

// Free flights follow P(t < x) = 1 − e^{−τ(x)} with regular tracking on every segment, on some
// (mixed with delta tracking on the others: the budget left is carried across) and on none;
// ratio-tracked transmittance has the mean e^{−τ}. On a ray through a sparse grid (half its
// voxels 0, the rest up to 0.4, scale 2) with a loose majorant σ_maj = 16, so that regular
// tracking is preferred on the pieces longer than 0.41 (kRegularTrackingLookupsPerCell = 4 per
// cell, ‖d‖₁ = 1.53 cells per unit) and the pieces of 0.3 are delta- and ratio-tracked.
TEST(TrilinearDepth, FreeFlightsAndTransmittanceMixedWithTracking) {
    const Grid g = randomGrid(10, 0.4, 7);
    const Vec3 o(-0.5, 2.3, 1.7), d = Vec3(1, 0.45, 0.3).normalized();
    const double scale = 2;
    const Pieces pieces{{0.3, 4.0, 0.3, 6.0, 0.7}, 16};
    const double tEnd = 11.3, T = std::exp(-quadrature(g, o, d, 0, tEnd, scale));
    ASSERT_GT(T, 0.02);
    ASSERT_LT(T, 0.5);
    auto sigmaT = [&](double t) { return scale * g.rho(o + t * d); };
    const auto tau = tauTable(g, o, d, scale, tEnd);
    for (int mode = 0; mode < 3; ++mode) {  // regular tracking where preferred, nowhere, always
        const TrilinearDepth exact(o, d, scale, g);
        Rng rng(11, uint64_t(mode));
        TrackingCounters c;
        const Always always{exact};
        const auto x2 = test::freeFlightChi2(
            40000, tEnd, tau,
            [&](int) {
                return mode == 2 ? deltaTrack(pieces, sigmaT, rng, c, nullptr, always)
                       : mode == 1
                           ? deltaTrack(pieces, sigmaT, rng, c, nullptr, NoRegularTracking{})
                           : deltaTrack(pieces, sigmaT, rng, c, nullptr, exact);
            },
            kFreeFlightChi2Tests);
        EXPECT_TRUE(x2.passed) << "mode " << mode << ": " << x2.report;
        EXPECT_EQ(c.exactCells > 0, mode != 1) << mode;
        EXPECT_EQ(c.densityLookups > 0, mode != 2) << mode;
        double s = 0, s2 = 0;
        const int n = 40000;
        for (int i = 0; i < n; ++i) {
            const double t = mode == 2   ? ratioTrack(pieces, sigmaT, rng, c, always)
                             : mode == 1 ? ratioTrack(pieces, sigmaT, rng, c, NoRegularTracking{})
                                         : ratioTrack(pieces, sigmaT, rng, c, exact);
            s += t, s2 += t * t;
        }
        const double mean = s / n, se = std::sqrt(std::max(0.0, s2 / n - mean * mean) / n);
        EXPECT_NEAR(mean, T, 5 * se + 1e-9) << "mode " << mode;
    }
}

// At density scale 10¹² a free flight entering a voxel that ramps up from 0 ends within it at a
// few cells' cost, distributed as the closed form says: along the x axis through a single voxel
// of value v at (3, 2, 2), ρ = v·(x − 2) on [2, 3], so τ(x) = k v (x − 2)²/2 with k = 10¹²
// (χ² of 1 − e^{−τ(t)}), and delta tracking would need ~10¹² tentative collisions per flight.
TEST(TrilinearDepth, ThickRampCostsAFewCells) {
    Grid g{6, std::vector<float>(216, 0.f)};
    const float v = 0.75f;
    g.v[(3 * 6 + 2) * 6 + 2] = v;
    const double k = 1e12;
    const Vec3 o(0, 2, 2), d(1, 0, 0);
    const Pieces pieces{{8.0}, k * v};
    auto sigmaT = [&](double t) { return k * g.rho(o + t * d); };
    const TrilinearDepth exact(o, d, k, g);
    Rng rng(13, 14);
    TrackingCounters c;
    const int n = 20000;
    // τ on [0, 3], where every flight ends; past it only e^{−τ(8)} = 0 (no escapes) matters.
    auto tau = [&](double t) {
        const double x = std::clamp(t - 2, 0.0, 1.0);
        return k * v * x * x / 2;
    };
    const auto x2 = test::freeFlightChi2(
        n, 8.0, tau,
        [&](int) {
            const double t = deltaTrack(pieces, sigmaT, rng, c, nullptr, exact);
            EXPECT_GT(t, 2);
            EXPECT_LT(t, 3);
            return t;
        },
        kFreeFlightChi2Tests);
    EXPECT_EQ(x2.dof, 19);  // (no escape cell: e^{-τ(8)} = 0)
    EXPECT_TRUE(x2.passed) << x2.report;
    EXPECT_EQ(c.densityLookups, 0u);
    EXPECT_LE(c.exactCells, uint64_t(3 * n));  // cells [0,1], [1,2], [2,3] along x
    // Transmittance across the voxel is 0 (τ = k v / 2 ≈ 3.75·10¹¹) at the same cost.
    TrackingCounters ct;
    EXPECT_EQ(ratioTrack(pieces, sigmaT, rng, ct, exact), 0.0);
    EXPECT_LE(ct.exactCells, 3u);
}

}  // namespace shvol
