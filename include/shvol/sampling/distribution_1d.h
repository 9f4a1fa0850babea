#pragma once
/// \file Piecewise-constant 1D distribution over [0, 1) (pbrt-v3 §13.3.1, "Sampling 1D
/// Functions"; pbrt-v4 PiecewiseConstant1D).
///
/// With n bins of width 1/n and values fᵢ ≥ 0:
///   integral  I = (1/n) Σ fᵢ,
///   pdf       p(x) = f_⌊xn⌋ / I,
///   CDF       Cᵢ = (1/(nI)) Σ_{j<i} f_j, C₀ = 0, Cₙ = 1,
///   inversion x = (i + (u − Cᵢ)/(Cᵢ₊₁ − Cᵢ)) / n with i the last index such that Cᵢ ≤ u.
/// If every fᵢ is zero the distribution behaves as the uniform one (p = 1) but integral() = 0,
/// so callers can detect that there is nothing to sample.
#include <vector>

namespace shvol {

class Distribution1D {
  public:
    /// \param f n non-negative bin values (negative or NaN values are treated as 0).
    Distribution1D(const double* f, int n);

    /// Continuous sample x ∈ [0, 1) by inverting the CDF (binary search).
    /// \param u uniform in [0, 1); values ≥ 1 are clamped below 1.
    /// \param pdf receives p(x) = f_i / I (> 0 unless all weights are 0, then 1).
    /// \param offset receives the bin index i; the bin never has zero weight.
    double sampleContinuous(double u, double* pdf, int* offset = nullptr) const;
    /// Discrete sample of a bin index with probability fᵢ / Σf (1/n if all zero).
    int sampleDiscrete(double u, double* pmf = nullptr) const;
    /// p(x) = f_⌊xn⌋ / I for x ∈ [0, 1) (x is clamped into the domain).
    double pdf(double x) const;
    /// Probability of bin i, fᵢ / Σf.
    double pmf(int i) const;
    /// I = (1/n) Σ fᵢ.
    double integral() const { return integral_; }
    int count() const { return int(func_.size()); }
    double func(int i) const { return func_[i]; }

  private:
    /// Index of the bin for u: the last i with cdf[i] ≤ u, moved to a non-zero bin if needed.
    int findBin(double u) const;

    std::vector<double> func_, cdf_;
    double integral_ = 0;
    bool allZero_ = true;
};

}  // namespace shvol
