#include "shvol/phase/henyey_greenstein.h"

#include <algorithm>
#include <cmath>

#include "shvol/core/math.h"

namespace shvol {

double henyeyGreenstein(double cosTheta, double g) {
    const double mu = std::clamp(cosTheta, -1.0, 1.0);
    const double base = g >= 0 ? sqr(1 - g) + 2 * g * (1 - mu) : sqr(1 + g) - 2 * g * (1 + mu);
    return (1 - g * g) / (FourPi * base * std::sqrt(base));
}

double henyeyGreensteinCdf(double cosTheta, double g) {
    const double mu = std::clamp(cosTheta, -1.0, 1.0);
    const double b = g >= 0 ? sqr(1 - g) + 2 * g * (1 - mu) : sqr(1 + g) - 2 * g * (1 + mu);
    const double s = std::sqrt(b);
    if (mu <= g) return std::clamp((1 - g) * (1 + mu) / (s * (1 + g + s)), 0.0, 1.0);
    return std::clamp(1 - (1 + g) * (1 - mu) / (s * (1 - g + s)), 0.0, 1.0);
}

double sampleHenyeyGreensteinCosTheta(double u, double g) {
    return HenyeyGreensteinSampler(g)(u).cosTheta;
}

}  // namespace shvol
