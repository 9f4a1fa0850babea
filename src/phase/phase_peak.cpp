#include "shvol/phase/phase_peak.h"

#include "shvol/sampling/density_peak.h"

namespace shvol {

double peakOverIsotropic(const PhaseFunction& phase) {
    return densityPeakOverIsotropic(
        [&](double theta) { return phase.evalAngle(AngleCosine::ofAngle(theta)); }, Pi);
}

}  // namespace shvol
