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
    // d = 1 − g + 2gu > 0, written for each sign of g as a sum of non-negative terms (1 − u is
    // exact for the samplers' u), so it does not cancel as |g| → 1.
    const double d = g >= 0 ? (1 - g) + 2 * g * u : (1 + g) - 2 * g * (1 - u);
    const double s = (1 - g * g) / d;
    const double oneMinusMu = (1 - g) * (1 - u) * (s + 1 - g) / d;
    const double onePlusMu = (1 + g) * u * (s + 1 + g) / d;
    const double mu = oneMinusMu <= onePlusMu ? 1 - oneMinusMu : onePlusMu - 1;
    return std::clamp(mu, -1.0, 1.0);
}

}  // namespace shvol
