#pragma once
/// \file Piecewise-constant 2D distribution over [0, 1)² sampled as a marginal over rows times
/// a conditional within the row (pbrt-v3 §13.6.7, "Piecewise-Constant 2D Distributions").
///
/// With nu columns, nv rows and values f(u, v) = f[v·nu + u] ≥ 0:
///   p(u, v) = f / I,  I = (1/(nu·nv)) Σ f,
///   p(v) = (row integral of v) / I   (marginal),   p(u | v) = f(u, v) / (row integral of v).
/// The density returned is with respect to area on [0, 1)². An all-zero input behaves as the
/// uniform distribution (p = 1) with integral() = 0.
#include <vector>

#include "shvol/core/math.h"
#include "shvol/sampling/distribution_1d.h"

namespace shvol {

class Distribution2D {
  public:
    /// \param f nu·nv values, row-major: f[v·nu + u], v the row (image y), u the column.
    Distribution2D(const double* f, int nu, int nv);

    /// Sample a point (u, v) ∈ [0, 1)²: v from the marginal with u[1], then u from the
    /// conditional of that row with u[0]. \param pdf receives p(u, v) (area measure);
    /// \param cell, if given, the bin (column, row) the point lies in.
    Vec2 sampleContinuous(const Vec2& u, double* pdf, Eigen::Vector2i* cell = nullptr) const;
    /// p(u, v) = f(⌊u·nu⌋, ⌊v·nv⌋) / I.
    double pdf(const Vec2& p) const;
    /// I = mean of f.
    double integral() const { return marginal_.integral(); }
    int countU() const { return nu_; }
    int countV() const { return nv_; }

  private:
    int nu_, nv_;
    std::vector<Distribution1D> conditional_;
    Distribution1D marginal_;
};

}  // namespace shvol
