#pragma once
/// \file Cornette–Shanks phase function (Cornette & Shanks 1992, "Physically reasonable analytic
/// expression for the single-scattering phase function", Applied Optics 31(16)), an HG-like lobe
/// that tends to Rayleigh as g → 0:
///   p(μ) = 3/(8π) (1 − g²)(1 + μ²) / ((2 + g²)(1 + g² − 2gμ)^{3/2}),  g ∈ (−1, 1),
/// with μ = cos θ = wo·wi and g > 0 forward. (g is a shape parameter; the mean cosine is
/// 3g(4 + g²)/(5(2 + g²)), not g.)
///
/// Normalisation: p = HG(μ; g) · c (1 + μ²) with c = 3/(2(2 + g²)). Since HG's Legendre moments
/// are gˡ, E_HG[μ²] = (1 + 2g²)/3, so ∫ p dω = c (1 + (1 + 2g²)/3) = c · 2(2 + g²)/3 = 1 exactly;
/// no numerical normalisation is needed (the tests check it by quadrature).
///
/// Sampling: the CDF has no simple inverse. Warping by HG's exact CDF, t = P_HG(μ) in [0, 1],
/// turns p into the density r(t) = c (1 + μ(t)²) over t, smooth and bounded in [c, 2c] for
/// every g (the peak is absorbed by the warp). r is tabulated at kTableSize + 1 nodes uniform in t
/// merged with kTableSize + 1 nodes uniform in μ (mapped to t = P_HG(μ); for |g| → 1 the whole back
/// hemisphere occupies a tiny interval of t, where μ(t) changes fast), sampled exactly as a
/// piecewise-linear density r̃ (PiecewiseLinear1D) and mapped back through
/// sampleHenyeyGreensteinCosTheta. The density of
/// that sampler over the sphere is
///   pdf(μ) = r̃(P_HG(μ)) · HG(μ; g),
/// which is what pdf() and sample() return; value = p(μ), so value/pdf = r/r̃ ≈ 1 (within the
/// tabulation error of r: segments are bisected until r̃ matches r to 1e-5 at their midpoints, and
/// the tests measure max |value/pdf − 1| ≈ 1.1e-5 for |g| ≤ 0.999) and the estimator is unbiased.
#include <memory>

#include "shvol/core/math.h"
#include "shvol/phase/henyey_greenstein.h"
#include "shvol/phase/phase_sample.h"
#include "shvol/phase/piecewise_linear_1d.h"

namespace shvol {

/// p(μ) = HG(μ; g) · 3(1 + μ²)/(2(2 + g²)), the closed form above (accurate as |g| → 1 through
/// henyeyGreenstein's cancellation-free base and the angle's complements).
double cornetteShanks(const AngleCosine& c, double g);
inline double cornetteShanks(double cosTheta, double g) {
    return cornetteShanks(AngleCosine::of(cosTheta), g);
}

class CornetteShanksPhase {
  public:
    static constexpr const char* kName = "cornette_shanks";
    static constexpr int kTableSize = 256;  ///< nodes per family (uniform in t, uniform in μ)
    /// \param g in (−1, 1); g > 0 forward.
    explicit CornetteShanksPhase(double g);
    double g() const { return g_; }
    double eval(const Vec3& wo, const Vec3& wi) const {
        return cornetteShanks(AngleCosine::between(wo, wi), g_);
    }
    /// r̃(P_HG(μ)) HG(μ; g): the density of sample(), close to but not equal to eval.
    double pdf(const Vec3& wo, const Vec3& wi) const;
    /// t = r̃⁻¹(u₁), cos θ = sampleHenyeyGreensteinCosTheta(t, g), φ = 2π u₂ around wo.
    PhaseSample sample(const Vec3& wo, const Vec2& u) const;
    /// r̃ over t ∈ [0, 1] (for tests and diagnostics).
    const PiecewiseLinear1D& warpedTable() const { return *warped_; }

  private:
    double g_;
    HenyeyGreensteinSampler hg_;
    std::shared_ptr<const PiecewiseLinear1D> warped_;  // r̃ over t ∈ [0, 1]; shared by copies
};

}  // namespace shvol
