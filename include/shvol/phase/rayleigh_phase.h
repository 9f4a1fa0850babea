#pragma once
/// \file Rayleigh phase function (scattering by particles much smaller than the wavelength,
/// unpolarised light; Chandrasekhar 1950, "Radiative Transfer", §I.17):
///   p(μ) = 3/(16π) (1 + μ²),  ∫ p dω = 1,  μ = cos θ = wo·wi.
/// Symmetric in μ, so the direction convention does not matter; mean cosine 0.
#include "shvol/core/math.h"
#include "shvol/phase/phase_sample.h"

namespace shvol {

/// p(μ) = 3/(16π)(1 + μ²), μ clamped to [−1, 1].
double rayleigh(double cosTheta);

/// Exact inverse of the CDF P(μ) = ∫_{−1}^{μ} 2π p dμ′ = (μ³ + 3μ + 4)/8 (Frisvad 2011,
/// "Importance sampling the Rayleigh phase function", JOSA A 28(12)). P(μ) = u is the depressed
/// cubic μ³ + 3μ − q = 0 with q = 8u − 4, which has one real root (Cardano):
///   μ = A − 1/A,  A = ∛(q/2 + √(q²/4 + 1)).
/// Evaluated for |q| (A ≥ 1, no cancellation inside the cube root) and given the sign of q
/// (the root is odd in q). \param u uniform in [0, 1]; result in [−1, 1].
double sampleRayleighCosTheta(double u);

class RayleighPhase {
  public:
    static constexpr const char* kName = "rayleigh";
    double eval(const Vec3& wo, const Vec3& wi) const { return rayleigh(wo.dot(wi)); }
    /// Exact sampler, so pdf = eval.
    double pdf(const Vec3& wo, const Vec3& wi) const { return eval(wo, wi); }
    /// cos θ = sampleRayleighCosTheta(u₁), φ = 2π u₂ around wo.
    PhaseSample sample(const Vec3& wo, const Vec2& u) const {
        const double cosTheta = sampleRayleighCosTheta(u.x());
        const Vec3 wi = Frame(wo).toWorld(sphericalDirection2Pi(cosTheta, u.y()));
        const double p = rayleigh(cosTheta);
        return {wi, p, p};
    }
};

}  // namespace shvol
