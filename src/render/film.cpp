#include "shvol/render/film.h"

#include <algorithm>
#include <cmath>

namespace shvol {

Image Film::image() const {
    Image img(width, height);
    for (size_t i = 0; i < pixels(); ++i)
        for (int c = 0; c < 3; ++c)
            img.rgb[3 * i + c] = count[i] ? float(sum[3 * i + c] / count[i]) : 0.f;
    return img;
}

Image Film::standardError() const {
    Image img(width, height);
    for (size_t i = 0; i < pixels(); ++i) {
        const double n = count[i];
        if (sumSq.empty()) continue;
        if (n < 2) {
            for (int c = 0; c < 3; ++c) img.rgb[3 * i + c] = INFINITY;
            continue;
        }
        for (int c = 0; c < 3; ++c) {
            const double mean = sum[3 * i + c] / n, m2 = sumSq[3 * i + c] / n;
            // Samples beyond 10¹⁵⁴ overflow Σx² (inf − inf would make the variance 0): unknown.
            if (!std::isfinite(m2)) {
                img.rgb[3 * i + c] = INFINITY;
                continue;
            }
            const double var = std::max(0.0, m2 - mean * mean) * n / (n - 1);
            img.rgb[3 * i + c] = float(std::sqrt(var / n));
        }
    }
    return img;
}

namespace {
/// The sums meanRelativeError and meanRelativeErrorDof are made of, over the pixels in order.
struct PooledSpread {
    double n = 0, ySum = 0, ySumSq = 0;  ///< samples, Σ y, Σ y²
    double within = 0, dof = 0;          ///< Σ_p W_p and Σ_p (k_p − 1) over pixels of k_p ≥ 2
    double nuWithin = 0, nuSpread = 0;   ///< Σ W_p and Σ W_p²/d_p over pixels whose W_p counts
    /// Where pixels of two samples or more hold a quarter of the degrees of freedom or more, the
    /// spread within them is the error's (at 1 spp there are none within).
    bool fromWithin() const { return dof >= 0.25 * n; }
};
PooledSpread pooledSpread(const Film& f) {
    PooledSpread p;
    for (size_t i = 0; i < f.pixels(); ++i) {
        const double k = f.count[i];
        if (k == 0) continue;
        const double s = luminance(Spectrum(f.sum[3 * i], f.sum[3 * i + 1], f.sum[3 * i + 2])),
                     q = f.luminanceSumSq[i];
        p.n += k, p.ySum += s, p.ySumSq += q;
        if (k < 2) continue;
        // Σ (y − ȳ)² = Σ y² − (Σ y)²/k, never below 0 once rounded
        const double w = std::max(0.0, q - s * s / k);
        p.within += w, p.dof += k - 1;
        // (ν leaves out a W_p below the rounding of Σy² − (Σy)²/k, about k·ε·Σy²: equal samples
        // not exactly representable, 0.1 each, left one pixel's rounding holding all of ν's
        // variance. d_p is at most k − 1: Kish's count reaches k where every sample is equal,
        // and the variance of k samples about their own mean has k − 1 degrees of freedom;
        // helper 163.)
        if (!(w > 1e-13 * k * q)) continue;
        p.nuWithin += w;
        p.nuSpread += w * w / std::min(k - 1, std::max(1.0, s * s / q));
    }
    return p;
}
}  // namespace

double Film::meanRelativeError() const {
    if (luminanceSumSq.empty()) return INFINITY;
    const PooledSpread p = pooledSpread(*this);
    if (p.n < 2 || !(p.ySum > 0)) return INFINITY;
    const double mean = p.ySum / p.n;
    const double variance = p.fromWithin()
                                ? p.within / p.dof
                                : std::max(0.0, p.ySumSq / p.n - mean * mean) * p.n / (p.n - 1);
    return std::sqrt(variance / p.n) / mean;
}

double Film::meanRelativeErrorDof() const {
    if (luminanceSumSq.empty()) return INFINITY;
    const PooledSpread p = pooledSpread(*this);
    // (where meanRelativeError is finite and of the spread within pixels)
    if (p.n < 2 || !(p.ySum > 0) || !p.fromWithin() || !(p.nuWithin > 0)) return INFINITY;
    const double nu = p.nuWithin * p.nuWithin / p.nuSpread;
    return std::isfinite(nu) ? nu : INFINITY;  // (squares beyond the double range: unknown)
}

uint32_t Film::minCount() const {
    return count.empty() ? 0 : *std::min_element(count.begin(), count.end());
}

uint32_t Film::maxCount() const {
    return count.empty() ? 0 : *std::max_element(count.begin(), count.end());
}

}  // namespace shvol
