#include "shvol/sh/irradiance.h"

#include <cmath>

#include "shvol/sh/sh_basis.h"

namespace shvol::sh {

double clampedCosineCoeff(int l) {
    if (l == 0) return Pi;
    if (l == 1) return TwoPi / 3.0;
    if (l % 2 == 1) return 0.0;
    // r_l = l! / (2^l ((l/2)!)²), r_0 = 1, r_{k} = r_{k−2} (k−1) / k  (k even)
    double r = 1.0;
    for (int k = 2; k <= l; k += 2) r *= (k - 1.0) / k;
    const double sign = ((l / 2 - 1) % 2 == 0) ? 1.0 : -1.0;
    return TwoPi * sign / ((l + 2.0) * (l - 1.0)) * r;
}

Eigen::VectorXd irradianceCoeffs(const Eigen::VectorXd& L) {
    Eigen::VectorXd E(L.size());
    const int n = static_cast<int>(std::lround(std::sqrt(double(L.size()))));
    for (int l = 0; l < n; ++l) {
        const double a = clampedCosineCoeff(l);
        for (int i = l * l; i < (l + 1) * (l + 1); ++i) E[i] = a * L[i];
    }
    return E;
}

double irradiance(const Eigen::VectorXd& L, const Vec3& normal) {
    const int n = static_cast<int>(std::lround(std::sqrt(double(L.size()))));
    const Eigen::VectorXd E = irradianceCoeffs(L);
    return shReconstruct(n, E.data(), normal);
}

}  // namespace shvol::sh
