#include "shvol/phase/rayleigh_phase.h"

#include <algorithm>
#include <cmath>

namespace shvol {

double rayleigh(double cosTheta) {
    const double mu = std::clamp(cosTheta, -1.0, 1.0);
    return 3.0 / (16.0 * Pi) * (1 + mu * mu);
}

double sampleRayleighCosTheta(double u) {
    const double q = 8 * std::clamp(u, 0.0, 1.0) - 4;
    const double h = 0.5 * std::abs(q);
    const double A = std::cbrt(h + std::sqrt(h * h + 1));  // ≥ 1
    const double mu = A - 1 / A;
    return std::clamp(std::copysign(mu, q), -1.0, 1.0);
}

}  // namespace shvol
