#include "shvol/phase/phase_peak.h"

#include <algorithm>

#include "shvol/phase/zonal_fit.h"

namespace shvol {

double peakOverIsotropic(const PhaseFunction& phase) {
    double peak = 0;
    const auto at = [&](double theta) {
        peak = std::max(peak, phase.evalAngle(AngleCosine::ofAngle(theta)));
    };
    for (const double theta : gradedThetaEdges()) at(theta);
    constexpr int kSteps = 4096;
    for (int i = 0; i <= kSteps; ++i) at(Pi * i / kSteps);
    return FourPi * peak;
}

}  // namespace shvol
