#pragma once
/// \file The peak of a phase function over the isotropic value, 4π·max_θ p(θ): a light sample
/// drawn without regard to the phase function meets the lobe about once in that many draws.
#include "shvol/phase/phase_function.h"

namespace shvol {

/// 4π·max_θ p(θ) by densityPeakOverIsotropic over θ ∈ [0, π]: exact for lobes peaked at a pole
/// (HG: (1 + |g|)/(1 − |g|)²). 1 for the isotropic phase function.
double peakOverIsotropic(const PhaseFunction& phase);

}  // namespace shvol
