#include "shvol/phase/henyey_greenstein.h"

#include <algorithm>
#include <cmath>

#include "shvol/core/math.h"

namespace shvol {

namespace {
/// 1 + g² − 2gμ as a sum of non-negative terms.
double base(const AngleCosine& c, double g) {
    return g >= 0 ? sqr(1 - g) + 2 * g * c.oneMinusMu : sqr(1 + g) - 2 * g * c.onePlusMu;
}
}  // namespace

double henyeyGreenstein(const AngleCosine& c, double g) {
    const double b = base(c, g);
    return (1 - g * g) / (FourPi * b * std::sqrt(b));
}

double henyeyGreensteinCdf(const AngleCosine& c, double g) {
    const double s = std::sqrt(base(c, g));
    if (c.mu <= g) return std::clamp((1 - g) * c.onePlusMu / (s * (1 + g + s)), 0.0, 1.0);
    return std::clamp(1 - (1 + g) * c.oneMinusMu / (s * (1 - g + s)), 0.0, 1.0);
}

AngleCosine sampleHenyeyGreensteinAngle(double u, double g) {
    return HenyeyGreensteinSampler(g)(u).angle;
}

double sampleHenyeyGreensteinCosTheta(double u, double g) {
    return sampleHenyeyGreensteinAngle(u, g).mu;
}

}  // namespace shvol
