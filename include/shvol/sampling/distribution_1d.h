#pragma once
/// \file Piecewise-constant 1D distribution over [0, 1) (pbrt-v3 §13.3.1, "Sampling 1D
/// Functions"; pbrt-v4 PiecewiseConstant1D).
///
/// With n bins of width 1/n and values fᵢ ≥ 0:
///   integral  I = (1/n) Σ fᵢ,
///   pdf       p(x) = f_⌊xn⌋ / I,
///   CDF       Cᵢ = (1/(nI)) Σ_{j<i} f_j, C₀ = 0, Cₙ = 1,
///   inversion x = (i + (u − Cᵢ)/(Cᵢ₊₁ − Cᵢ)) / n with i the last index such that Cᵢ ≤ u.
/// That i is found through a guide table (the cutpoint method, Chen & Asau 1974; Devroye 1986,
/// §III.2.4): gₖ = the last i with Cᵢ ≤ k/n for k = 0 … n, so for k/n ≤ u < (k+1)/n the bin lies
/// in [gₖ, gₖ₊₁] and a search of that range (about two entries on average) replaces the binary
/// search of the whole CDF, whose ~log₂ n reads miss the cache on large tables (a sky's rows).
/// If every fᵢ is zero the distribution behaves as the uniform one (p = 1) but integral() = 0,
/// so callers can detect that there is nothing to sample.
#include <vector>

namespace shvol {

class Distribution1D {
  public:
    /// \param f n non-negative bin values (negative or NaN values are treated as 0).
    Distribution1D(const double* f, int n);

    /// Continuous sample x ∈ [0, 1) by inverting the CDF (binary search).
    /// \param u uniform in [0, 1); values ≥ 1 are clamped below 1, negative ones and NaN to 0.
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

    /// The bin of u ∈ [0, 1): the last i with Cᵢ ≤ u (moved to a bin of non-zero weight if
    /// rounding lands on an empty one), found through the guide table.
    int findBin(double u) const;
    /// The same by a binary search of the whole CDF: the slow reference of findBin, for tests.
    int findBinBySearch(double u) const;

  private:
    /// Moves i, the last index with Cᵢ ≤ u, into [0, n − 1] and onto a bin of non-zero weight.
    int validBin(int i) const;
    /// The last i in [first, last) with Cᵢ ≤ u, or first − 1 if none is (C is non-decreasing).
    int lastAtMost(int first, int last, double u) const;

    std::vector<double> func_, cdf_;
    std::vector<int> guide_;  ///< gₖ for k = 0 … n
    double integral_ = 0;
    bool allZero_ = true;
};

/// The point (i + du)/n of bin i ∈ [0, n) at du ∈ [0, 1], moved by the last bits it needs to lie
/// in bin i as ⌊x n⌋ (clamped to n − 1) finds it, and below 1: so that a pdf looked up at the
/// point is the bin's.
double pointInBin(int i, double du, int n);

}  // namespace shvol
