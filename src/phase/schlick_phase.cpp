#include "shvol/phase/schlick_phase.h"

#include <algorithm>
#include <cmath>

namespace shvol {

double schlick(double cosTheta, double k) {
    const double mu = std::clamp(cosTheta, -1.0, 1.0);
    const double base = k >= 0 ? (1 - k) + k * (1 - mu) : (1 + k) - k * (1 + mu);
    return (1 - k * k) / (FourPi * base * base);
}

double sampleSchlickCosTheta(double u, double k) {
    u = std::clamp(u, 0.0, 1.0);
    const double d = (1 - k) * (1 - u) + (1 + k) * u;
    const double onePlusMu = 2 * u * (1 + k) / d;
    const double oneMinusMu = 2 * (1 - u) * (1 - k) / d;
    const double mu = onePlusMu <= oneMinusMu ? onePlusMu - 1 : 1 - oneMinusMu;
    return std::clamp(mu, -1.0, 1.0);
}

}  // namespace shvol
