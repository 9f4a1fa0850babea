#pragma once
/// \file Russian roulette with a survival weight.
///
/// A path whose throughput β has its largest component m below the threshold θ survives with
/// probability q = m/θ and continues with β/q, whose largest component is θ; with m ≥ θ it
/// always continues (q = 1). E[β′] = q·β/q = β: unbiased for any θ > 0. This is the weight
/// cutoff of Monte Carlo particle transport: roulette below a cutoff weight, survivors carry a
/// survival weight. Each time the roulette plays, a survivor's largest component is set to θ,
/// so the weight cannot compound over bounces. The path tracer passes m of β·Π η² over its
/// refractions (pbrt-v4's etaScale), as refraction scales radiance by 1/η² without losing any
/// of it. θ = 1 is roulette on the throughput itself
/// (q = m, as pbrt-v4 plays it); Blender Cycles survives with q = min(1, √m)
/// (integrator/path_state.h, path_state_continuation_probability). Ratio tracking plays the
/// same rule on its transmittance estimate (media/tracking.h).
///
/// A smaller θ lets paths run longer before roulette: more time per path, less variance from
/// killing them. Under a constant sky every path ends in light, so the roulette on throughput
/// (θ = 1) turns each path's smooth weight αᵏ into a 0-or-1 draw; README ("Russian roulette")
/// has the measured efficiency of each choice.
#include <algorithm>

namespace shvol {

/// The survival probability q = min(1, m/θ) of a path whose throughput's largest component is
/// m ≥ 0, with threshold θ > 0. q = 0 for m = 0 (the path carries nothing).
inline double rouletteSurvival(double m, double threshold) {
    return std::min(1.0, m / threshold);
}

}  // namespace shvol
