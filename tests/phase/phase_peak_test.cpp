#include "shvol/phase/phase_peak.h"

#include <gtest/gtest.h>

namespace shvol {

// Against the closed forms: HG peaks at a pole, (1 + |g|)/(1 − |g|)² over the isotropic value,
// also where the lobe is narrower than any even step (g = 0.999999); Rayleigh at 3/(8π) (1.5);
// the isotropic function is 1.
TEST(PhasePeak, MatchesTheClosedForms) {
    for (double g : {0.0, 0.5, 0.9, -0.9, 0.99, -0.999999}) {
        const double exact = (1 + std::abs(g)) / ((1 - std::abs(g)) * (1 - std::abs(g)));
        EXPECT_NEAR(peakOverIsotropic(PhaseFunction(HenyeyGreensteinPhase(g))), exact, 1e-9 * exact)
            << "g " << g;
    }
    EXPECT_NEAR(peakOverIsotropic(PhaseFunction(RayleighPhase())), 1.5, 1e-12);
    EXPECT_NEAR(peakOverIsotropic(PhaseFunction()), 1.0, 1e-12);
}

}  // namespace shvol
