#include "shvol/core/image_metrics.h"

#include <cmath>
#include <limits>

#include "shvol/core/error.h"

namespace shvol {

namespace {
void checkSizes(const Image& a, const Image& b, const char* what) {
    if (a.width != b.width || a.height != b.height)
        throw Error(std::string(what) + " is " + std::to_string(a.width) + "x" +
                    std::to_string(a.height) + ", the reference " + std::to_string(b.width) + "x" +
                    std::to_string(b.height));
}
}  // namespace

ImageMetrics imageMetrics(const Image& x, const Image& reference) {
    checkSizes(x, reference, "the image");
    ImageMetrics m;
    const size_t n = x.rgb.size();
    // d, d2: sums over pixels of a pixel's mean difference over its channels, and its square.
    double se = 0, rel = 0, ae = 0, d = 0, d2 = 0;
    for (size_t p = 0; p < n / 3; ++p) {
        double pixel = 0;
        for (size_t i = 3 * p; i < 3 * p + 3; ++i) {
            const double r = reference.rgb[i], e = double(x.rgb[i]) - r;
            if (!std::isfinite(e)) {
                se = rel = ae = std::numeric_limits<double>::infinity();
                continue;
            }
            se += e * e, rel += e * e / (r * r + 1e-2), ae += std::abs(e), pixel += e / 3;
        }
        d += pixel, d2 += pixel * pixel;
    }
    m.values = (long long)n;
    if (n == 0) return m;
    const double pixels = double(n / 3);
    m.rmse = std::sqrt(se / n), m.relMse = rel / n, m.mae = ae / n, m.bias = d / pixels;
    const double var = pixels > 1 ? std::max(0.0, (d2 - d * d / pixels) / (pixels - 1)) : 0.0;
    m.biasHalfWidth95 = 1.96 * std::sqrt(var / pixels);
    return m;
}

ZTest zTest(const Image& x, const Image& xStdErr, const Image& reference, const Image& refStdErr,
            double alpha) {
    checkSizes(x, reference, "the image");
    checkSizes(xStdErr, x, "the image's standard error");
    checkSizes(refStdErr, reference, "the reference's standard error");
    ZTest t;
    // The spacing of float32 values at v: x and r were rounded to it when stored (EXR).
    const auto ulp = [](float v) {
        const float a = std::abs(v);
        return double(std::nextafter(a, std::numeric_limits<float>::infinity())) - double(a);
    };
    for (size_t i = 0; i < x.rgb.size(); ++i) {
        const double sx = xStdErr.rgb[i], sr = refStdErr.rgb[i], ux = ulp(x.rgb[i]),
                     ur = ulp(reference.rgb[i]);
        const double s = std::sqrt(sx * sx + sr * sr + (ux * ux + ur * ur) / 12);
        const double e = double(x.rgb[i]) - reference.rgb[i];
        if (e == 0 && sx == 0 && sr == 0) continue;  // equal and noiseless (black void): no test
        if (!(s > 0)) {
            if (e != 0) t.minP = 0, ++t.tested;  // a difference where neither has noise
            continue;
        }
        ++t.tested;
        t.minP = std::min(t.minP, std::erfc(std::abs(e / s) / std::sqrt(2.0)));
    }
    t.threshold = t.tested ? sidakThreshold(alpha, double(t.tested)) : 0.0;
    t.passed = t.minP >= t.threshold;
    return t;
}

}  // namespace shvol
