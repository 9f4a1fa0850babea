#pragma once
/// \file Piecewise-linear 1D density with exact inverse-CDF sampling (the continuous analogue of
/// Distribution1D; pbrt-v4 §A.4.4 samples one linear segment the same way).
///
/// Nodes x₀ < x₁ < … < xₙ₋₁ with values fᵢ ≥ 0; between nodes f̃ is the linear interpolant
///   f̃(x) = (1 − s) fᵢ + s fᵢ₊₁,  s = (x − xᵢ)/hᵢ,  hᵢ = xᵢ₊₁ − xᵢ,
/// and f̃ = 0 outside [x₀, xₙ₋₁]. The integral is the trapezoid sum I = Σ hᵢ (fᵢ + fᵢ₊₁)/2 (exact
/// for f̃), the density is pdf(x) = f̃(x)/I and the CDF is piecewise quadratic.
///
/// Sampling picks segment i from the discrete CDF Cᵢ, rescales v = (u − Cᵢ)/(Cᵢ₊₁ − Cᵢ) and
/// solves the segment's quadratic  fᵢ s + (fᵢ₊₁ − fᵢ) s²/2 = v (fᵢ + fᵢ₊₁)/2  for s ∈ [0, 1] in the
/// cancellation-free form
///   s = v (fᵢ + fᵢ₊₁) / (fᵢ + √((1 − v) fᵢ² + v fᵢ₊₁²)),
/// which is the exact root (multiply the textbook root by its conjugate; the radicand is the
/// discriminant rewritten with Δ(fᵢ + fᵢ₊₁) = fᵢ₊₁² − fᵢ²), needs no special case for flat
/// segments (fᵢ = fᵢ₊₁ gives s = v) and never divides by zero for a segment of non-zero mass.
/// The sample's density is pdf(x) of the returned x, so value/pdf is exact.
#include <vector>

namespace shvol {

class PiecewiseLinear1D {
  public:
    PiecewiseLinear1D() = default;
    /// \param x at least 2 strictly increasing finite nodes.
    /// \param f one finite value ≥ 0 per node, not all zero.
    /// Throws std::invalid_argument otherwise (callers that read user data check first and give
    /// a better message).
    PiecewiseLinear1D(std::vector<double> x, std::vector<double> f);

    /// Unnormalised interpolant f̃(x); 0 outside [x₀, xₙ₋₁].
    double eval(double x) const;
    /// f̃(x) / I.
    double pdf(double x) const { return eval(x) / integral_; }
    /// ∫ f̃ dx.
    double integral() const { return integral_; }
    /// P(x) = ∫_{x₀}^{x} f̃ / I, in [0, 1].
    double cdf(double x) const;
    /// Exact inverse of cdf. \param u uniform in [0, 1) (clamped into [0, 1]).
    double sample(double u) const;

    const std::vector<double>& nodes() const { return x_; }
    const std::vector<double>& values() const { return f_; }

  private:
    /// Segment i with xᵢ ≤ x ≤ xᵢ₊₁ (x clamped into the domain).
    int segment(double x) const;

    std::vector<double> x_, f_, cdf_;  // cdf_[i] = P(xᵢ)
    double integral_ = 0;
};

}  // namespace shvol
