#pragma once
/// \file Schlick's phase function, a cheap rational stand-in for Henyey–Greenstein (Blasi,
/// Le Saëc & Schlick 1993, "A Rendering Algorithm for Discrete Volume Density Objects",
/// Computer Graphics Forum 12(3)):
///   p(μ) = (1 − k²) / (4π (1 − kμ)²),  k ∈ (−1, 1),  ∫ p dω = 1,  μ = cos θ = wo·wi.
///
/// Sign convention: the literature writes the denominator both as (1 + k cos θ)² and as
/// (1 − k cos θ)², depending on whether θ is measured between the propagation directions or
/// between the incident direction pointing back towards the light and the scattered one. Here μ
/// is the cosine between the propagation directions before and after scattering (DESIGN.md), and
/// with (1 − kμ)² k > 0 scatters forward, like HG's g. k is not the mean cosine; Blasi et al.
/// match HG approximately with k ≈ 1.55g − 0.55g³.
#include "shvol/core/math.h"
#include "shvol/phase/phase_sample.h"

namespace shvol {

/// p(μ) = (1 − k²)/(4π(1 − kμ)²). 1 − kμ is evaluated as (1 − k) + k(1 − μ) for k ≥ 0 and
/// (1 + k) − k(1 + μ) for k < 0, sums of non-negative terms, so it stays accurate as |k| → 1.
double schlick(double cosTheta, double k);

/// Exact inverse of the CDF P(μ) = (1 − k)(1 + μ) / (2(1 − kμ)):
///   μ = (2u − 1 + k) / (1 − k + 2ku),
/// evaluated without cancellation through
///   1 + μ = 2u(1 + k)/d,  1 − μ = 2(1 − u)(1 − k)/d,  d = (1 − k)(1 − u) + (1 + k)u > 0,
/// taking whichever is smaller. \param u uniform in [0, 1]; result in [−1, 1].
double sampleSchlickCosTheta(double u, double k);

class SchlickPhase {
  public:
    static constexpr const char* kName = "schlick";
    /// \param k in (−1, 1); k > 0 forward.
    explicit SchlickPhase(double k) : k_(k) {}
    double k() const { return k_; }
    double eval(const Vec3& wo, const Vec3& wi) const { return schlick(wo.dot(wi), k_); }
    /// Exact sampler, so pdf = eval.
    double pdf(const Vec3& wo, const Vec3& wi) const { return eval(wo, wi); }
    /// cos θ = sampleSchlickCosTheta(u₁, k), φ = 2π u₂ around wo.
    PhaseSample sample(const Vec3& wo, const Vec2& u) const {
        const double cosTheta = sampleSchlickCosTheta(u.x(), k_);
        const Vec3 wi = Frame(wo).toWorld(sphericalDirection2Pi(cosTheta, u.y()));
        const double p = schlick(cosTheta, k_);
        return {wi, p, p};
    }

  private:
    double k_;
};

}  // namespace shvol
