#pragma once
/// \file Result of sampling a phase function.
#include "shvol/core/math.h"

namespace shvol {

/// wi: new propagation direction (unit); value: p(wo·wi); pdf: density of wi over solid angle.
/// For the exact samplers in this module value == pdf; CornetteShanksPhase samples a tabulated
/// approximation, so there pdf is the sampler's own density and value/pdf ≈ 1 (unbiased).
struct PhaseSample {
    Vec3 wi;
    double value;
    double pdf;
};

}  // namespace shvol
