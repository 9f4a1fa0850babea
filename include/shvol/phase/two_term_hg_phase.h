#pragma once
/// \file Two-term Henyey–Greenstein phase function: a mixture of a forward and a backward (or two
/// forward) HG lobes (Kattawar 1975, "A three-parameter analytic phase function for multiple
/// scattering calculations", JQSRT 15; pbrt-v4 keeps one lobe, Mitsuba's "hg" likewise):
///   p(μ) = w HG(μ; g₁) + (1 − w) HG(μ; g₂),  w ∈ [0, 1],  g₁, g₂ ∈ (−1, 1),
/// with HG from henyey_greenstein.h and μ = cos θ = wo·wi (g > 0 forward). Mean cosine
/// w g₁ + (1 − w) g₂. Each lobe is normalised, so ∫ p dω = 1.
///
/// Sampling: lobe 1 with probability w (u₁ < w, then reused as u₁/w), else lobe 2 (reused as
/// (u₁ − w)/(1 − w)), then the exact HG inverse CDF. The density of that sampler is the mixture
/// itself, so pdf = eval and value/pdf = 1.
#include <algorithm>

#include "shvol/core/math.h"
#include "shvol/phase/henyey_greenstein.h"
#include "shvol/phase/phase_sample.h"

namespace shvol {

/// w HG(μ; g₁) + (1 − w) HG(μ; g₂) (from the angle's complements: henyeyGreenstein).
inline double twoTermHenyeyGreenstein(const AngleCosine& c, double g1, double g2, double w) {
    return w * henyeyGreenstein(c, g1) + (1 - w) * henyeyGreenstein(c, g2);
}
inline double twoTermHenyeyGreenstein(double cosTheta, double g1, double g2, double w) {
    return twoTermHenyeyGreenstein(AngleCosine::of(cosTheta), g1, g2, w);
}

/// Samples μ, with its complements, from the mixture with one uniform number (lobe choice, then
/// the rescaled number).
inline AngleCosine sampleTwoTermHenyeyGreensteinAngle(double u, double g1, double g2, double w) {
    // w = 1 always takes lobe 1 (also for u = 1, where (u − w)/(1 − w) would be 0/0).
    if (u < w || w >= 1) return sampleHenyeyGreensteinAngle(std::min(u / w, 1.0), g1);
    return sampleHenyeyGreensteinAngle(std::clamp((u - w) / (1 - w), 0.0, 1.0), g2);
}
inline double sampleTwoTermHenyeyGreensteinCosTheta(double u, double g1, double g2, double w) {
    return sampleTwoTermHenyeyGreensteinAngle(u, g1, g2, w).mu;
}

class TwoTermHenyeyGreensteinPhase {
  public:
    static constexpr const char* kName = "two_term_hg";
    /// \param g1 first lobe, \param g2 second lobe, both in (−1, 1); \param w weight of the first
    /// lobe in [0, 1].
    TwoTermHenyeyGreensteinPhase(double g1, double g2, double w) : g1_(g1), g2_(g2), w_(w) {}
    double g1() const { return g1_; }
    double g2() const { return g2_; }
    double w() const { return w_; }
    double eval(const Vec3& wo, const Vec3& wi) const {
        return twoTermHenyeyGreenstein(AngleCosine::between(wo, wi), g1_, g2_, w_);
    }
    /// The sampler's density is the mixture: pdf = eval.
    double pdf(const Vec3& wo, const Vec3& wi) const { return eval(wo, wi); }
    PhaseSample sample(const Vec3& wo, const Vec2& u) const {
        const AngleCosine c = sampleTwoTermHenyeyGreensteinAngle(u.x(), g1_, g2_, w_);
        const Vec3 wi = Frame(wo).toWorld(sphericalDirection2Pi(c, u.y()));
        const double p = twoTermHenyeyGreenstein(c, g1_, g2_, w_);
        return {wi, p, p};
    }

  private:
    double g1_, g2_, w_;
};

}  // namespace shvol
