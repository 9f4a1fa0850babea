#include "shvol/sh/irradiance.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "shvol/core/rng.h"
#include "shvol/sh/sh_basis.h"
#include "shvol/sh/sh_projection.h"

namespace {
using namespace shvol;
using namespace shvol::sh;

TEST(Irradiance, BlogConstants) {
    const double blog[7] = {3.141593, 2.094395, 0.785398, 0.0, -0.130900, 0.0, 0.049087};
    for (int l = 0; l < 7; ++l) EXPECT_NEAR(clampedCosineCoeff(l), blog[l], 1e-6) << l;
}

TEST(Irradiance, ConstantsMatchQuadrature) {
    // Â_l = 2π ∫_0^1 P_l(z) z dz, P_l = N_l^0 / √((2l+1)/4π); 40 Gauss points are exact here.
    const int n = 60;
    std::vector<double> x, w, y(n);
    gaussLegendre(40, 0.0, 1.0, x, w);
    std::vector<double> A(n, 0.0);
    for (size_t k = 0; k < x.size(); ++k) {
        shEvalZonal(n, x[k], y.data());
        for (int l = 0; l < n; ++l)
            A[l] += TwoPi * w[k] * x[k] * y[l] / std::sqrt((2 * l + 1) / FourPi);
    }
    for (int l = 0; l < n; ++l) EXPECT_NEAR(clampedCosineCoeff(l), A[l], 1e-13) << l;
    EXPECT_TRUE(std::isfinite(clampedCosineCoeff(100000)));
}

TEST(Irradiance, WhiteEnvironmentGivesPi) {
    Eigen::VectorXd L = Eigen::VectorXd::Zero(9);
    L[0] = std::sqrt(FourPi);  // L ≡ 1
    Rng rng(1, 1);
    for (int t = 0; t < 100; ++t) {
        const Vec3 nrm = sphericalDirection(2 * rng.uniform() - 1, TwoPi * rng.uniform());
        EXPECT_NEAR(irradiance(L, nrm), Pi, 1e-14);
    }
}

TEST(Irradiance, LinearRadianceIsExact) {
    // L(ω) = a·ω lies in band 1: E(n) = (2π/3) a·n exactly.
    const Vec3 a(0.3, -0.5, 0.8);
    const Eigen::VectorXd L = projectSH(
        3, [&](const Vec3& w) { return a.dot(w); }, sphereQuadratureForOrder(3));
    Rng rng(2, 1);
    for (int t = 0; t < 100; ++t) {
        const Vec3 nrm = sphericalDirection(2 * rng.uniform() - 1, TwoPi * rng.uniform());
        EXPECT_NEAR(irradiance(L, nrm), TwoPi / 3 * a.dot(nrm), 1e-14);
    }
}

}  // namespace
