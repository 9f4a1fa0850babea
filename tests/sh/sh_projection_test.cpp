#include "shvol/sh/sh_projection.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "shvol/core/rng.h"
#include "shvol/sh/sh_integrals.h"
#include "shvol/sh/sh_rotation.h"

namespace {
using namespace shvol;
using namespace shvol::sh;

TEST(ShProjection, GaussLegendreIsExactForDegree2kMinus1) {
    for (int k : {1, 2, 5, 17, 100, 1000}) {
        std::vector<double> x, w;
        gaussLegendre(k, -1.0, 1.0, x, w);
        double sw = 0;
        for (double v : w) sw += v;
        EXPECT_NEAR(sw, 2.0, 1e-13) << k;
        for (int d : {2 * k - 2, 2 * k - 1}) {
            if (d < 0 || d > 60) continue;
            double s = 0;
            for (int i = 0; i < k; ++i) s += w[i] * std::pow(x[i], d);
            EXPECT_NEAR(s, d % 2 ? 0.0 : 2.0 / (d + 1), 1e-14) << k << " " << d;
        }
        for (int i = 1; i < k; ++i) EXPECT_LT(x[i - 1], x[i]);
    }
}

TEST(ShProjection, BandLimitedRoundTripAndEnergy) {
    const int n = 10;
    Rng rng(4, 1);
    Eigen::VectorXd c(n * n);
    for (int i = 0; i < n * n; ++i) c[i] = 2 * rng.uniform() - 1;
    auto f = [&](const Vec3& w) { return shReconstruct(n, c.data(), w); };
    const SphereQuadrature q = sphereQuadratureForOrder(n);
    const Eigen::VectorXd p = projectSH(n, f, q);
    EXPECT_LT((p - c).cwiseAbs().maxCoeff(), 1e-13);
    const Eigen::VectorXd e = energyFraction(p, squaredNorm(f, q));
    EXPECT_NEAR(e[n * n - 1], 1.0, 1e-13);
    EXPECT_NEAR(e[0], c[0] * c[0] / c.squaredNorm(), 1e-13);
}

// Henyey–Greenstein has p_l = g^l √((2l+1)/4π) (DESIGN.md); far beyond graphics orders.
TEST(ShProjection, ZonalHenyeyGreensteinToHighOrder) {
    for (auto [g, n, nz] :
         {std::tuple{0.5, 60, 200}, std::tuple{0.9, 400, 1500}, std::tuple{0.98, 1800, 4000}}) {
        auto hg = [g = g](double mu) {
            return (1 - g * g) / (FourPi * std::pow(1 + g * g - 2 * g * mu, 1.5));
        };
        const Eigen::VectorXd p = projectZonal(n, hg, nz);
        for (int l = 0; l < n; ++l) {
            const double ref = std::pow(g, l) * std::sqrt((2 * l + 1) / FourPi);
            ASSERT_NEAR(p[l], ref, 1e-11 * std::sqrt(2 * l + 1.0)) << g << " " << l;
        }
        // The rectangle integrals of the expansion over a partition of the sphere sum to 1,
        // and the zonal integral over [z, 1] matches the HG cumulative distribution.
        std::vector<double> Z(n);
        const double z0 = 0.9;
        legendreIntegralsZonal(n, z0, 1.0, Z.data());
        double mass = 0;
        for (int l = 0; l < n; ++l) mass += TwoPi * p[l] * Z[l];
        const double cdf =
            (1 - g * g) / (2 * g) * (1 / (1 - g) - 1 / std::sqrt(1 + g * g - 2 * g * z0));
        ASSERT_LT(std::pow(g, n) * n, 1e-12);  // the expansion has converged
        EXPECT_NEAR(mass, cdf, 1e-11) << g;
        // rotated to an arbitrary axis, the coefficients stay finite and the peak is p(1)
        const Vec3 d = Vec3(0.3, -0.2, 0.9).normalized();
        const Eigen::VectorXd r = rotateZonal(p, d);
        ASSERT_TRUE(r.allFinite());
    }
}

}  // namespace
