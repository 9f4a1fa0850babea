#pragma once
/// \file A float RGB image in row-major order, row 0 at the top.
#include <vector>

#include "shvol/core/math.h"

namespace shvol {

struct Image {
    int width = 0, height = 0;
    std::vector<float> rgb;  ///< 3·width·height floats

    Image() = default;
    Image(int w, int h) : width(w), height(h), rgb(size_t(3) * w * h, 0.f) {}
    Spectrum at(int x, int y) const {
        const float* p = &rgb[3 * (size_t(y) * width + x)];
        return {p[0], p[1], p[2]};
    }
    void set(int x, int y, const Spectrum& s) {
        float* p = &rgb[3 * (size_t(y) * width + x)];
        p[0] = float(s[0]), p[1] = float(s[1]), p[2] = float(s[2]);
    }
};

/// Per-channel summary of an image: mean, minimum and maximum over the finite values (NaN for a
/// channel without one: they read 0, a value the image did not have; helper 68), and the number
/// of non-finite values (which never enter the other three).
struct ImageStatistics {
    Spectrum mean = Spectrum::Zero(), min = Spectrum::Zero(), max = Spectrum::Zero();
    long long nonFinite = 0;
};
ImageStatistics imageStatistics(const Image& image);

}  // namespace shvol
