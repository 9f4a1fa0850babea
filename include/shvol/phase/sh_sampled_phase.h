#pragma once
/// \file A phase function importance-sampled through its zonal SH fit (Jarosz et al. 2009).
///
/// Two uses, one interface:
///  - Evaluate::Reconstruction (default; `evaluate: sh`): the fit itself is the phase function,
///    described below; every phase sample has weight f/pdf = 1.
///  - Evaluate::Exact: eval is the underlying phase function p; the zonal SH sampler of
///    p's order-n fit only supplies directions and their pdf, so f/pdf is an unbiased weight
///    whatever the fit's quality — provided the pdf is positive wherever p is. Where the fit rings
///    negative its bins are clamped and never sampled although p > 0 there (HG g = 0.99 at
///    order 4 loses 0.8% of its mass that way), so when any bin is clamped the sampler is mixed
///    with a uniform one, pdf = (1 − α) pdf_SH + α/(4π), α = kDefensiveFraction (defensive
///    importance sampling, Hesterberg 1995).
///
/// The reconstruction is the phase function, in the form the sampler
///    draws it: the reconstruction averaged over each of the 2^depth z-bins, clamped at 0 and
///    normalised, p_SH(μ) = max(0, ∫_bin p̃ dz) / (Δz · C), C = Σ_bins max(0, ∫_bin p̃) · 2π.
///    It is exactly normalised, sampled exactly (f/pdf = 1) and has no region that is evaluated
///    but never sampled. (The pointwise max(0, p̃)/C differs from it in bins that straddle a zero
///    of p̃; at depth 4 that made ∫p = 1.049 for HG 0.99 at order 8, and left unsampled mass.)
///    At the default depth 16 the two agree to ~1e−6.
///
/// Why Reconstruction is the default. In the Exact use E[p/pdf] = 1 but the second moment
/// m₂ = E[(p/pdf)²] = ∫ p²/pdf dω exceeds 1 wherever pdf ≠ p, and along a path of k scattering
/// events the weight's second moment is m₂^k. In an albedo-1 furnace with optical depths in the
/// hundreds (validation/hardcases/) HG g = 0.9 at order 16 with Hann rendered a mean of 0.87 and
/// a darkest pixel of 0.06 at 256 spp (the product of weights is almost always small and rarely
/// huge, and Russian roulette ends the small ones), g = 0.99 a mean of 0.76; the Reconstruction
/// renders 1.000 ± 0.001 with no pixel below 0.92. m₂ is computed here by quadrature and
/// reported (`shvol phase fit`, the stats JSON, a warning when it exceeds 1.01).
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
    /// The range of sh_depth, the sampler's 2^depth z-bins.
    static constexpr int kMinDepth = 4, kMaxDepth = 22;
    /// Uniform share α of the defensive mixture (Exact use with clamped bins only).
    static constexpr double kDefensiveFraction = 0.02;
    enum class Evaluate { Exact, Reconstruction };

    /// Fits `base` as `request` asks (order and window may be automatic, see zonal_fit.h) and
    /// builds a zonal sampler with 2^depth bins.
    SHSampledPhase(const PhaseFunction& base, const ZonalFitRequest& request,
                   Evaluate evaluate = Evaluate::Reconstruction, int depth = 16);
    /// The same with an explicit order and window.
    SHSampledPhase(const PhaseFunction& base, int order, SHWindow window = SHWindow::Hann,
                   Evaluate evaluate = Evaluate::Reconstruction, int depth = 16);

    double eval(const Vec3& wo, const Vec3& wi) const;
    double pdf(const Vec3& wo, const Vec3& wi) const;
    PhaseSample sample(const Vec3& wo, const Vec2& u) const;

    const ZonalFit& fit() const { return *fit_; }
    const ZonalSHSampler& sampler() const { return *sampler_; }
    const PhaseFunction& base() const { return *base_; }
    Evaluate evaluate() const { return evaluate_; }
    /// α: kDefensiveFraction when the mixture is on, else 0.
    double defensiveFraction() const { return alpha_; }
    /// m₂ = E[(f/pdf)²] = ∫ f²/pdf dω of one phase sample: exactly 1 for Reconstruction; for
    /// Exact, Gauss–Legendre quadrature in θ over the union of the sampler's z-bins (where pdf is
    /// constant) and gradedThetaEdges() (where p is peaked); +∞ if p > 0 where pdf = 0.
    double weightSecondMoment() const { return m2_; }
    /// A render is flagged when m₂ > this (m₂^k then exceeds 2.7 after 100 bounces).
    static constexpr double kUnreliableSecondMoment = 1.01;
    /// The relative L2 error of the phase function rendered, eval, against the wrapped one p:
    /// (∫ (eval − p)² dω / ∫ p² dω)^{1/2}, by the quadrature of weightSecondMoment(). 0 for
    /// Exact; for Reconstruction the error of the fit as the sampler draws it, averaged over
    /// the z-bins, clamped and normalised, which the fit's own error (fit().relativeL2Error,
    /// what "order": "auto" meets) does not see: HG 0.9 at sh_depth 4 renders a lobe averaged
    /// over 16 bins (error 0.88 for a fit of 0.0098), and HG 0.999 at order 256, half of its
    /// bins clamped, sends three quarters of its light outside the forward cone (0.993 for 0.952;
    /// helper 62's audit).
    double renderedRelativeL2Error() const { return renderedError_; }
    /// ∫ p dω of the wrapped function by the quadrature of weightSecondMoment() (which the fit's
    /// own nodes resemble): 1 to within 10⁻⁶ wherever that quadrature sees the whole function.
    /// Far from 1, the function has structure finer than its nodes, and the fit, m₂ and the
    /// rendered error are blind to it. The nodes end at a table's corners, so a table hides only
    /// where μ's rounding makes it a staircase in θ (a spike rising from 0 at 0° to its peak at
    /// 10⁻⁶° and back to 0 at 2·10⁻⁶°: 0.951; 0 before the corners, helper 94).
    double quadratureMass() const { return quadratureMass_; }
    /// A render is flagged when |quadratureMass() − 1| exceeds this.
    static constexpr double kBlindQuadrature = 1e-3;

  private:
    double baseCos(double mu) const;  ///< the wrapped function at cos θ = mu
    double evalCos(double mu) const;
    double pdfCos(double mu) const;
    /// Calls node(p, pdf, w) at the nodes of a quadrature over the sphere, ∫ g dω ≈ Σ w·g(p, pdf):
    /// Gauss–Legendre (4 points) in θ on each interval between the union of the sampler's z-bin
    /// edges (where pdf is constant, and given at the interval's midpoint) and
    /// gradedThetaEdges(corners) (where p is peaked, and the base's corners).
    template <typename Node>
    void forEachNode(const std::vector<double>& corners, Node&& node) const;
    /// Sets quadratureMass_ and m2_ (Exact) or renderedError_ (Reconstruction), by forEachNode
    /// with the base's corners.
    void checkByQuadrature(const std::vector<double>& corners);
    std::shared_ptr<const PhaseFunction> base_;
    std::shared_ptr<const ZonalFit> fit_;
    std::shared_ptr<const ZonalSHSampler> sampler_;
    Evaluate evaluate_;
    double alpha_ = 0, m2_ = 1, renderedError_ = 0, quadratureMass_ = 0;
};

}  // namespace shvol
