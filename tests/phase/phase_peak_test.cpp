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

// A table peaks at a node: a ring 10⁻⁵° wide at 37.123°, which the fixed angles of the search miss
// (it read 0 and the warning for render.mis "none" said nothing; helper 115), peaks at its value
// there, 4π · 1 / (2π ∫ f dμ) with ∫ f dμ = (cos 37.12299° − cos 37.12301°) / 2.
TEST(PhasePeak, TablesPeakAtANode) {
    const double a = 37.12299 * Pi / 180, b = 37.12301 * Pi / 180;
    const double exact = 2 / ((std::cos(a) - std::cos(b)) / 2);
    const PhaseFunction ring(TabulatedPhase({0, 37.12299, 37.123, 37.12301, 180}, {0, 0, 1, 0, 0}));
    EXPECT_NEAR(peakOverIsotropic(ring), exact, 1e-6 * exact);
    // Sampled by its SH fit and evaluated exactly, it is still the table that peaks there.
    const PhaseFunction sampled(
        SHSampledPhase(ring, 32, SHWindow::Hann, SHSampledPhase::Evaluate::Exact));
    EXPECT_NEAR(peakOverIsotropic(sampled), exact, 1e-6 * exact);
}

}  // namespace shvol
