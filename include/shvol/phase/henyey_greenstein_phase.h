#pragma once
/// \file Henyey–Greenstein phase function object: a thin wrapper over henyey_greenstein.h.
///
/// Convention (DESIGN.md): wo is the propagation direction before scattering (the incoming ray's
/// direction), wi the direction after, cos θ = wo·wi; g > 0 samples wi near wo.
#include "shvol/core/math.h"
#include "shvol/phase/henyey_greenstein.h"
#include "shvol/phase/phase_sample.h"

namespace shvol {

class HenyeyGreensteinPhase {
  public:
    static constexpr const char* kName = "hg";
    /// \param g asymmetry parameter in (−1, 1).
    explicit HenyeyGreensteinPhase(double g) : g_(g), sampler_(g) {}
    double g() const { return g_; }
    /// p(wo·wi) = henyeyGreenstein(wo·wi, g), from the complements of wo·wi.
    double eval(const Vec3& wo, const Vec3& wi) const {
        return henyeyGreenstein(AngleCosine::between(wo, wi), g_);
    }
    /// Exact sampler, so pdf = eval.
    double pdf(const Vec3& wo, const Vec3& wi) const { return eval(wo, wi); }
    /// cos θ and its density from HenyeyGreensteinSampler(u₁), φ = 2π u₂,
    /// wi = Frame(wo).toWorld(ω(cos θ, φ)) with sin θ from the complements of cos θ.
    PhaseSample sample(const Vec3& wo, const Vec2& u) const {
        const HenyeyGreensteinSampler::Sample s = sampler_(u.x());
        const Vec3 wi = Frame(wo).toWorld(sphericalDirection2Pi(s.angle, u.y()));
        return {wi, s.pdf, s.pdf};
    }

  private:
    double g_;
    HenyeyGreensteinSampler sampler_;
};

}  // namespace shvol
