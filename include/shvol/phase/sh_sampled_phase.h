#pragma once
/// \file A phase function importance-sampled through its zonal SH fit (Jarosz et al. 2009).
///
/// Two uses, one interface:
///  - Evaluate::Exact (default): eval is the underlying phase function p; the zonal SH sampler of
///    p's order-n fit only supplies directions and their pdf, so f/pdf is an unbiased weight
///    whatever the fit's quality — provided the pdf is positive wherever p is. Where the fit rings
///    negative its bins are clamped and never sampled although p > 0 there (HG g = 0.99 at
///    order 4 loses 0.8% of its mass that way), so when any bin is clamped the sampler is mixed
///    with a uniform one, pdf = (1 − α) pdf_SH + α/(4π), α = kDefensiveFraction (defensive
///    importance sampling, Hesterberg 1995).
///  - Evaluate::Reconstruction: the fit itself is the phase function,
///      p_SH(μ) = max(0, p̃(μ)) / C,   C = ∫ max(0, p̃) dω (as the sampler's clamped bins see it),
///    non-negative and normalised; sampling is then nearly proportional to it (f/pdf ≈ 1).
#include <memory>
#include <string>

#include "shvol/core/math.h"
#include "shvol/phase/phase_sample.h"
#include "shvol/phase/zonal_fit.h"

namespace shvol {

class PhaseFunction;
class ZonalSHSampler;

class SHSampledPhase {
  public:
    static constexpr const char* kName = "sh";
    /// Uniform share α of the defensive mixture (Exact use with clamped bins only).
    static constexpr double kDefensiveFraction = 0.02;
    enum class Evaluate { Exact, Reconstruction };

    /// Fits `base` at `order` bands with `window` and builds a zonal sampler with 2^depth bins.
    SHSampledPhase(const PhaseFunction& base, int order, SHWindow window = SHWindow::Hann,
                   Evaluate evaluate = Evaluate::Exact, int depth = 16);

    double eval(const Vec3& wo, const Vec3& wi) const;
    double pdf(const Vec3& wo, const Vec3& wi) const;
    PhaseSample sample(const Vec3& wo, const Vec2& u) const;

    const ZonalFit& fit() const { return *fit_; }
    const ZonalSHSampler& sampler() const { return *sampler_; }
    const PhaseFunction& base() const { return *base_; }
    Evaluate evaluate() const { return evaluate_; }
    /// α: kDefensiveFraction when the mixture is on, else 0.
    double defensiveFraction() const { return alpha_; }

  private:
    double evalCos(double mu) const;
    std::shared_ptr<const PhaseFunction> base_;
    std::shared_ptr<const ZonalFit> fit_;
    std::shared_ptr<const ZonalSHSampler> sampler_;
    Evaluate evaluate_;
    double norm_ = 1, alpha_ = 0;
};

}  // namespace shvol
