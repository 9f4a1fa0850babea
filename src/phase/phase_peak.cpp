#include "shvol/phase/phase_peak.h"

#include <algorithm>

#include "shvol/sampling/density_peak.h"

namespace shvol {

double peakOverIsotropic(const PhaseFunction& phase) {
    const auto p = [&](double theta) { return phase.evalAngle(AngleCosine::ofAngle(theta)); };
    // A table peaks at one of its nodes, which the fixed angles need not meet (a ring 10⁻⁵° wide
    // at 37.123°, 10⁷ times the isotropic value, read as 0; helper 115).
    double peak = densityPeakOverIsotropic(p, Pi);
    for (double theta : phase.corners()) peak = std::max(peak, FourPi * p(theta));
    return peak;
}

}  // namespace shvol
