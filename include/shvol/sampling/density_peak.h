#pragma once
/// \file The peak of a direction density symmetric about an axis, over the uniform sphere's:
/// 4π·max_θ p(θ). A light sample drawn without regard to p meets p's lobe about once in that many
/// draws (the warning for render.mis "none": phase/phase_peak.h, surfaces/bsdf.h).
#include <functional>

namespace shvol {

/// 4π·max p(θ) over θ ∈ [0, θmax], p given as a function of θ: the maximum over both ends, steps
/// of 1.25× from 10⁻⁷ rad away from either end (lobes far narrower than any even step) and 4096
/// even steps between. Exact for lobes peaked at an end, and for others to their variation within
/// a step.
double densityPeakOverIsotropic(const std::function<double(double theta)>& p, double thetaMax);

}  // namespace shvol
