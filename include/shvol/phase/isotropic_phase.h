#pragma once
/// \file Isotropic phase function p = 1/(4π).
#include "shvol/core/math.h"
#include "shvol/phase/phase_sample.h"
#include "shvol/sampling/warp.h"

namespace shvol {

class IsotropicPhase {
  public:
    static constexpr const char* kName = "isotropic";
    /// p(wo, wi) = 1/(4π).
    double eval(const Vec3& /*wo*/, const Vec3& /*wi*/) const { return Inv4Pi; }
    double pdf(const Vec3& /*wo*/, const Vec3& /*wi*/) const { return Inv4Pi; }
    /// Uniform sphere sample (sampleUniformSphere); value = pdf = 1/(4π).
    PhaseSample sample(const Vec3& /*wo*/, const Vec2& u) const {
        return {sampleUniformSphere(u), Inv4Pi, Inv4Pi};
    }
};

}  // namespace shvol
