#include "shvol/sampling/density_peak.h"

#include <gtest/gtest.h>

#include <cmath>

#include "shvol/core/math.h"

namespace shvol {

// The maximum is found at either end, within a lobe far narrower than the even steps next to
// either end (10⁻⁶ rad wide, 2·10⁻⁶ rad away: the graded steps reach it), and in the middle.
TEST(DensityPeak, FindsLobesAtTheEndsAndNearThem) {
    EXPECT_NEAR(densityPeakOverIsotropic([](double) { return Inv4Pi; }, Pi), 1, 1e-15);
    const auto lobe = [](double at, double width) {
        return [=](double t) { return std::exp(-sqr((t - at) / width)); };
    };
    EXPECT_NEAR(densityPeakOverIsotropic(lobe(0, 1e-6), Pi), FourPi, 1e-12);
    EXPECT_NEAR(densityPeakOverIsotropic(lobe(0.5 * Pi, 1e-6), 0.5 * Pi), FourPi, 1e-12);
    EXPECT_GT(densityPeakOverIsotropic(lobe(2e-6, 1e-6), Pi), 0.9 * FourPi);
    EXPECT_GT(densityPeakOverIsotropic(lobe(Pi - 2e-6, 1e-6), Pi), 0.9 * FourPi);
    // (in the middle to its variation within an even step of π/4096: 0.14% for this one)
    EXPECT_GT(densityPeakOverIsotropic(lobe(1.0, 1e-2), Pi), 0.998 * FourPi);
}

}  // namespace shvol
