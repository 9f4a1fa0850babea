// Rectangle integrals against adaptive Gauss–Kronrod quadrature in 50-digit arithmetic.
#include "shvol/sh/sh_integrals.h"

#include <gtest/gtest.h>

#include "sh/legendre_reference.h"

#include <boost/math/quadrature/gauss_kronrod.hpp>

#include <cmath>
#include <utility>
#include <vector>

#include "shvol/core/rng.h"
#include "shvol/sh/sh_basis.h"
#include "shvol/sh/sh_projection.h"

namespace {
using namespace shvol;
using namespace shvol::sh;

using reference::referenceN;

// 20-point Gauss–Legendre on [−1, 1] in long double (Newton on P_20), independent of the library.

using reference::referenceJ;

struct Interval {
    double z0, z1;
};
const std::vector<Interval> kIntervals = {
    {-1.0, 1.0},           {-1.0, -0.3},         {0.2, 1.0},     {0.9, 1.0},
    {-0.5, 0.7},           {0.5, 0.5 + 1e-3},    {0.99999, 1.0}, {0.3, 0.3 + 1e-10},
    {1.0 - 1e-10, 1.0},    {-1.0, -1.0 + 1e-12}, {0.0, 1e-9},    {-0.7, -0.7 + 3e-10},
    {0.999, 0.999 + 5e-10}};

// Error model (sh_integrals.h): relative to env·min(1, Δz), env = √((2l+1)/4π), the library's
// error is that of the Legendre values, ≈ ε·l^{3/2}, for wide intervals (recurrence) and narrow
// ones (θ-panel rule) alike. The test demands
//   |J − ref| ≤ 1e-13·|ref| + 4ε·(n+1)^{3/2}·env·min(1, z1−z0)
// for every l, m; narrow intervals therefore have to be accurate to their own size.
TEST(ShIntegrals, LegendreIntegralsMatchHighPrecisionQuadrature) {
    const double eps = 2.220446049250313e-16;
    for (int n : {21, 101}) {
        std::vector<double> J(triSize(n));
        for (const Interval& iv : kIntervals) {
            legendreIntegrals(n, iv.z0, iv.z1, J.data());
            std::vector<std::pair<int, int>> lm;
            if (n <= 21) {
                for (int l = 0; l < n; ++l)
                    for (int m = 0; m <= l; ++m) lm.push_back({l, m});
            } else {
                for (int l : {50, 99, 100})
                    for (int m : {0, 1, 2, 7, l / 2, l - 1, l}) lm.push_back({l, m});
            }
            for (auto [l, m] : lm) {
                const double ref = static_cast<double>(referenceJ(l, m, iv.z0, iv.z1));
                const double got = J[triIndex(l, m)];
                const double env = std::sqrt((2.0 * l + 1) / (4 * M_PI));
                const double tol = 1e-13 * std::fabs(ref) + 4 * eps * std::pow(n + 1.0, 1.5) * env *
                                                                std::min(1.0, iv.z1 - iv.z0);
                EXPECT_NEAR(got, ref, tol) << "n=" << n << " l=" << l << " m=" << m << " [" << iv.z0
                                           << ", " << iv.z1 << "]";
            }
        }
    }
}

// The fixed composite reference rule agrees with adaptive Gauss–Kronrod (61 points, long double,
// error target 1e-16 relative to env·Δz) on the same integrands.
TEST(ShIntegrals, ReferenceRuleAgreesWithAdaptiveQuadrature) {
    using GK = boost::math::quadrature::gauss_kronrod<long double, 61>;
    for (const Interval& iv : kIntervals) {
        for (auto lm : std::vector<std::pair<int, int>>{{7, 3}, {50, 0}, {100, 1}, {100, 100}}) {
            const int l = lm.first, m = lm.second;
            const long double a = iv.z0, b = iv.z1;
            long double adaptive;
            const long double env = std::sqrt((2.0L * l + 1) / (4 * 3.14159265358979323846264L));
            const long double scale = env * std::min(1.0L, b - a);
            if (b <= 0 && a < -0.5) continue;  // mirrored in referenceJ; covered by the +1 side
            if (1.0L - std::max(std::fabs(a), std::fabs(b)) > 1e-4L) {
                auto f = [&](long double z) {
                    return referenceN(l, m, z, std::sqrt((1.0L - z) * (1.0L + z)));
                };
                adaptive = GK::integrate(f, a, b, 10, 1e-16L * scale / (b - a));
            } else {
                auto g = [&](long double th) {
                    return referenceN(l, m, std::cos(th), std::sin(th)) * std::sin(th);
                };
                adaptive = GK::integrate(g, std::acos(b), std::acos(a), 10, 1e-16L);
            }
            EXPECT_NEAR((double)(referenceJ(l, m, iv.z0, iv.z1) / scale),
                        (double)(adaptive / scale), 1e-15)
                << l << " " << m << " [" << iv.z0 << ", " << iv.z1 << "]";
        }
    }
}

TEST(ShIntegrals, ZonalMatchesFull) {
    for (int n : {5, 30, 200}) {
        std::vector<double> J(triSize(n)), Z(n);
        for (const Interval& iv : kIntervals) {
            legendreIntegrals(n, iv.z0, iv.z1, J.data());
            legendreIntegralsZonal(n, iv.z0, iv.z1, Z.data());
            for (int l = 0; l < n; ++l)
                EXPECT_NEAR(Z[l], J[triIndex(l, 0)],
                            1e-14 * std::sqrt(2.0 * l + 1) + 1e-12 * std::fabs(J[triIndex(l, 0)]))
                    << n << " " << l << " " << iv.z0;
        }
    }
}

TEST(ShIntegrals, PhiIntegralsClosedForm) {
    const int n = 200;
    std::vector<double> C(n), S(n);
    for (auto [a, b] : std::vector<std::pair<double, double>>{
             {0.0, TwoPi}, {0.3, 1.9}, {5.0, 5.0 + 1e-9}, {0.0, 0.5 * Pi}, {1.0, 1.0 + 1e-3}}) {
        phiIntegrals(n, a, b, C.data(), S.data());
        for (int m = 0; m < n; ++m) {
            // reference in long double with the product form of the difference
            const long double h = 0.5L * ((long double)b - a), c = 0.5L * ((long double)a + b);
            const long double rc = m == 0 ? 2 * h : 2.0L / m * std::cos(m * c) * std::sin(m * h);
            const long double rs = m == 0 ? 0.0L : 2.0L / m * std::sin(m * c) * std::sin(m * h);
            const double scale = std::min(b - a, 2.0 / std::max(m, 1));
            EXPECT_NEAR(C[m], (double)rc, 1e-14 * scale * (1 + m * 0.01)) << m << " " << a;
            EXPECT_NEAR(S[m], (double)rs, 1e-14 * scale * (1 + m * 0.01)) << m << " " << a;
        }
    }
}

// ŷ_i over a partition of the sphere sums to ∫ y_i = √(4π) δ_i0, and matches the product rule on
// each rectangle (Gauss–Legendre in z × Gauss–Legendre in φ, exact for these trig polynomials).
TEST(ShIntegrals, RectangleIntegralsPartitionAndQuadrature) {
    const int n = 12;
    std::vector<double> out(n * n), sum(n * n, 0.0);
    const double zs[] = {-1.0, -0.6, 0.1, 0.1 + 1e-10, 0.8, 1.0};
    const double ps[] = {0.0, 1.0, 2.5, 4.0, TwoPi};
    for (int i = 0; i + 1 < 6; ++i)
        for (int j = 0; j + 1 < 5; ++j) {
            shRectIntegrals(n, zs[i], zs[i + 1], ps[j], ps[j + 1], out.data());
            std::vector<double> gz, wz, gp, wp;
            gaussLegendre(60, zs[i], zs[i + 1], gz, wz);
            gaussLegendre(60, ps[j], ps[j + 1], gp, wp);
            Eigen::VectorXd ref = Eigen::VectorXd::Zero(n * n);
            for (int a = 0; a < 60; ++a)
                for (int b = 0; b < 60; ++b)
                    ref += wz[a] * wp[b] * shEval(n, sphericalDirection(gz[a], gp[b]));
            for (int k = 0; k < n * n; ++k) {
                // odd m carry √(1−z²), not a polynomial: the z rule is only accurate away from ±1
                if (zs[i] > -1 && zs[i + 1] < 1)
                    EXPECT_NEAR(out[k], ref[k], 1e-13 * (1 + std::fabs(ref[k]))) << i << j << k;
                sum[k] += out[k];
            }
        }
    EXPECT_NEAR(sum[0], std::sqrt(4 * Pi), 1e-14);
    for (int k = 1; k < n * n; ++k) EXPECT_NEAR(sum[k], 0.0, 1e-14) << k;
}

TEST(ShIntegrals, NarrowRuleIntegratesPolynomials) {
    // ∫ z^k dz over narrow and pole-touching intervals, relative to 1e-14
    for (auto [a, b] : std::vector<std::pair<double, double>>{
             {0.3, 0.3 + 1e-10}, {1 - 1e-10, 1.0}, {-1.0, -1.0 + 1e-12}, {0.5, 0.5007}}) {
        for (int k = 0; k < 12; ++k) {
            double sum = 0.0;
            ASSERT_TRUE(forEachNarrowNode(
                20, a, b, 4, [&](double z, double, double w) { sum += w * std::pow(z, k); }));
            // (b^{k+1} − a^{k+1})/(k+1) = (b−a) Σ_j b^j a^{k−j} / (k+1), without cancellation
            long double sj = 0;
            for (int j = 0; j <= k; ++j)
                sj += std::pow((long double)b, j) * std::pow((long double)a, k - j);
            const long double ref = ((long double)b - (long double)a) * sj / (k + 1);
            EXPECT_NEAR(sum / (double)ref, 1.0, 1e-13) << a << " " << k;
        }
    }
}

}  // namespace
