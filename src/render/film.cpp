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

uint32_t Film::minCount() const {
    return count.empty() ? 0 : *std::min_element(count.begin(), count.end());
}

uint32_t Film::maxCount() const {
    return count.empty() ? 0 : *std::max_element(count.begin(), count.end());
}

}  // namespace shvol
