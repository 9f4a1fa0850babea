#include "shvol/sampling/density_peak.h"

#include <algorithm>

#include "shvol/core/math.h"

namespace shvol {

double densityPeakOverIsotropic(const std::function<double(double theta)>& p, double thetaMax) {
    double peak = std::max(p(0), p(thetaMax));
    for (double t = 1e-7; t < thetaMax; t *= 1.25) peak = std::max({peak, p(t), p(thetaMax - t)});
    constexpr int kSteps = 4096;
    for (int i = 1; i < kSteps; ++i) peak = std::max(peak, p(thetaMax * i / kSteps));
    return FourPi * peak;
}

}  // namespace shvol
