#pragma once
/// \file The peak of a phase function over the isotropic value, 4π·max_θ p(θ): a light sample
/// drawn without regard to the phase function meets the lobe about once in that many draws.
#include "shvol/phase/phase_function.h"

namespace shvol {

/// 4π·max_θ p(θ), the maximum taken over θ = 0, π, the graded edges of gradedThetaEdges() (steps
/// of 1.25× from 10⁻⁷ rad at either pole) and 4096 even steps between: exact for lobes peaked at a
/// pole (HG: (1 + |g|)/(1 − |g|)²), and for others to the lobe's variation within a step.
/// 1 for the isotropic phase function.
double peakOverIsotropic(const PhaseFunction& phase);

}  // namespace shvol
