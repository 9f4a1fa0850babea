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

double Film::meanRelativeError() const {
    if (luminanceSumSq.empty()) return INFINITY;
    double n = 0, ySum = 0, ySumSq = 0, within = 0, dof = 0;
    for (size_t i = 0; i < pixels(); ++i) {
        const double k = count[i];
        if (k == 0) continue;
        const double s = luminance(Spectrum(sum[3 * i], sum[3 * i + 1], sum[3 * i + 2]));
        n += k, ySum += s, ySumSq += luminanceSumSq[i];
        if (k < 2) continue;
        // Σ (y − ȳ)² = Σ y² − (Σ y)²/k, never below 0 once rounded
        within += std::max(0.0, luminanceSumSq[i] - s * s / k);
        dof += k - 1;
    }
    if (n < 2 || !(ySum > 0)) return INFINITY;
    const double mean = ySum / n;
    // (from a quarter of the samples' degrees of freedom on: at 1 spp there are none within)
    const double variance =
        dof >= 0.25 * n ? within / dof : std::max(0.0, ySumSq / n - mean * mean) * n / (n - 1);
    return std::sqrt(variance / n) / mean;
}

double Film::meanRelativeErrorDof() const {
    if (!std::isfinite(meanRelativeError())) return INFINITY;
    double n = 0, dof = 0, within = 0, spread = 0;  // spread: Σ W_p² / d_p
    for (size_t i = 0; i < pixels(); ++i) {
        const double k = count[i];
        n += k;
        if (k < 2) continue;
        dof += k - 1;
        const double s = luminance(Spectrum(sum[3 * i], sum[3 * i + 1], sum[3 * i + 2])),
                     q = luminanceSumSq[i];
        const double w = std::max(0.0, q - s * s / k);
        // (Below the rounding of Σy² − (Σy)²/k, about k·ε·Σy²: equal samples not exactly
        // representable, 0.1 each, left one pixel's rounding holding all of ν's variance.)
        if (!(w > 1e-13 * k * q)) continue;
        within += w;
        spread += w * w / std::max(1.0, s * s / q);
    }
    if (dof < 0.25 * n || !(within > 0)) return INFINITY;  // (the spread of all samples: 1 spp)
    return within * within / spread;
}

uint32_t Film::minCount() const {
    return count.empty() ? 0 : *std::min_element(count.begin(), count.end());
}

uint32_t Film::maxCount() const {
    return count.empty() ? 0 : *std::max_element(count.begin(), count.end());
}

}  // namespace shvol
