#pragma once
/// \file Drawing a texel of a W × H image with probability ∝ a weight w(x, y), and a point in
/// it, from one 32-byte record per texel that also holds the texel's RGB: the sampler of image
/// skies (Environment), whose draws are bound by memory latency on a large sky.
///
/// The row by inverting the marginal over rows (Distribution1D: H entries, small enough to stay
/// in the cache), the texel in the row by an alias table (sampling/alias_table.h) whose columns
/// live in the texels' records. A draw reads the record of column j and, when the alias is
/// taken, the alias's record, which holds the weight (for the pdf) and the RGB (for the caller):
/// under a sky whose sun holds most of the weight the aliases mostly point into the few sun
/// texels, which stay in the cache. Inverting each row's CDF instead (Distribution2D, the
/// reference) reads a guide entry, the CDF, the weight and the image: dependent misses.
///
/// Over (u, v) ∈ [0, 1)² (u = (x + du)/W, v = (y + dv)/H) the density is
///   p(u, v) = w(x, y) / I,  I = (1/(W H)) Σ w,
/// and the same formula serves sample() and pdf(), so they agree to the last bit. Weights ≤ 0 or
/// NaN count as 0 and are never drawn. All weights 0: integral() = 0 and nothing can be drawn.
#include <array>
#include <vector>

#include "shvol/core/math.h"
#include "shvol/sampling/distribution_1d.h"

namespace shvol {

class TexelSampler {
  public:
    /// \param weights W·H weights, row-major (weights[y·W + x]); \param rgb 3·W·H floats in the
    /// same order, handed back with each draw.
    TexelSampler(const double* weights, const float* rgb, int width, int height);

    struct Draw {
        Vec2 uv;       ///< the point in [0, 1)², inside texel (x, y)
        int x, y;      ///< the texel
        double pdf;    ///< p(uv) over [0, 1)² (0 when nothing can be drawn)
        Spectrum rgb;  ///< the texel's RGB as given (float to double)
    };
    /// A draw from u ∈ [0, 1)²: u[1] picks the row, u[0] the texel in it.
    Draw sample(const Vec2& u) const;
    /// p(uv) = w(⌊u W⌋, ⌊v H⌋) / I (uv clamped into the square).
    double pdf(const Vec2& uv) const;
    /// I, the mean weight.
    double integral() const { return marginal_.integral() / width_; }
    int width() const { return width_; }
    int height() const { return height_; }

  private:
    /// The same from weights already cleaned (≥ 0, finite), W·H of them.
    TexelSampler(const std::vector<double>& weights, const float* rgb, int width, int height);
    /// A texel's record: its alias column, its weight and its RGB, 32 bytes.
    struct Record {
        double q;  ///< the alias column's threshold
        double weight;
        int alias;  ///< the column's alias, in the same row
        std::array<float, 3> rgb;
    };
    static_assert(sizeof(Record) == 32);
    int width_, height_;
    std::vector<Record> records_;  ///< row-major
    Distribution1D marginal_;      ///< over rows, of the row sums
    double invIntegral_ = 0;
};

}  // namespace shvol
