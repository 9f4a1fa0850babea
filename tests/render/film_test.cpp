#include "shvol/render/film.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "shvol/core/math.h"

namespace shvol {

namespace {
/// A film of `pixels` grey pixels (luminance = value) with the given samples per pixel, and the
/// samples themselves, in pixel order.
struct Picture {
    Film film;
    std::vector<double> samples;
};
Picture picture(const std::vector<std::vector<double>>& perPixel) {
    Picture p{Film(int(perPixel.size()), 1), {}};
    for (size_t i = 0; i < perPixel.size(); ++i)
        for (double y : perPixel[i]) {
            for (int c = 0; c < 3; ++c) p.film.sum[3 * i + c] += y;
            p.film.luminanceSumSq[i] += y * y;
            ++p.film.count[i];
            p.samples.push_back(y);
        }
    return p;
}
/// `pixels` pixels of `samples` each, pixel i's alternating between mean_i ∓ spread, mean_i from
/// 0.5 to 1.5 across the pixels (the picture's contrast).
Picture contrast(int pixels, int samples, double spread) {
    std::vector<std::vector<double>> v(static_cast<size_t>(pixels));
    for (int i = 0; i < pixels; ++i)
        for (int k = 0; k < samples; ++k)
            v[size_t(i)].push_back(0.5 + double(i) / (pixels - 1) + (k % 2 ? spread : -spread));
    return picture(v);
}
/// The slow reference of the fallback: √(s²/n)/ȳ with s² the variance of all samples.
double ofAllSamples(const std::vector<double>& y) {
    const double n = double(y.size());
    double mean = 0, ss = 0;
    for (double v : y) mean += v / n;
    for (double v : y) ss += (v - mean) * (v - mean);
    return std::sqrt(ss / (n - 1) / n) / mean;
}
}  // namespace

// The image mean's standard error comes from the spread within pixels, not from the picture's
// contrast (helper 87): √(s²/n)/ȳ with s² the pooled within-pixel variance, here spread²·k/(k−1).
// It is the film's, summed in pixel order: no pass or thread enters it (helper 93).
TEST(Film, MeanRelativeErrorIsOfTheSpreadWithinPixels) {
    const int pixels = 100, samples = 16;
    const double n = pixels * samples, spread = 0.01;
    const double s2 = spread * spread * samples / (samples - 1);
    EXPECT_NEAR(contrast(pixels, samples, spread).film.meanRelativeError(), std::sqrt(s2 / n),
                1e-12);
    // No spread within pixels: no error but rounding (Σy² − (Σy)²/k), however strong the
    // contrast (the variance of all samples would give about √(1/12 / n) here, 0.72%).
    EXPECT_LT(contrast(pixels, samples, 0).film.meanRelativeError(), 1e-8);
    // One sample per pixel: nothing within; the variance of all samples, larger, not ∞.
    const Picture one = contrast(pixels, 1, spread);
    EXPECT_NEAR(one.film.meanRelativeError(), ofAllSamples(one.samples), 1e-12);
    // A pixel of two equal samples among pixels of one is no estimate of the spread (it would
    // give 0; helper 90): below a quarter of the degrees of freedom, all samples' variance.
    std::vector<std::vector<double>> mixed;
    for (int i = 0; i < pixels; ++i) mixed.push_back({0.5 + double(i) / (pixels - 1)});
    mixed[0] = {1, 1};
    const Picture m = picture(mixed);
    EXPECT_NEAR(m.film.meanRelativeError(), ofAllSamples(m.samples), 1e-12);
    // Unknown squares (a checkpoint without them), or no light: ∞.
    Picture unknown = contrast(pixels, samples, spread);
    unknown.film.luminanceSumSq.clear();
    EXPECT_EQ(unknown.film.meanRelativeError(), INFINITY);
    EXPECT_EQ(Film(4, 4).meanRelativeError(), INFINITY);
}

namespace {
/// The slow reference of meanRelativeErrorDof, from the samples: each pixel's sum of squared
/// deviations about its own mean, and its Kish count (Σy)²/Σy².
double dofOfSamples(const std::vector<std::vector<double>>& perPixel) {
    double num = 0, den = 0;
    for (const std::vector<double>& y : perPixel) {
        double mean = 0, sum = 0, sq = 0, w = 0;
        for (double v : y) mean += v / double(y.size()), sum += v, sq += v * v;
        for (double v : y) w += (v - mean) * (v - mean);
        if (y.size() < 2 || w == 0) continue;
        num += w;
        den += w * w / std::min(double(y.size()) - 1, std::max(1.0, sum * sum / sq));
    }
    return num * num / den;
}
}  // namespace

// The degrees of freedom of the stated error (helper 162): many where every pixel's samples
// spread alike, about one where one pixel's single rare sample holds the variance (a heavy tail),
// whatever the number of samples. Against the slow reference from the samples.
TEST(Film, MeanRelativeErrorDofFallsUnderAHeavyTail) {
    const int pixels = 100, samples = 16;
    std::vector<std::vector<double>> even(pixels), tail(pixels, std::vector<double>(samples, 1.0));
    for (int i = 0; i < pixels; ++i)
        for (int k = 0; k < samples; ++k) even[size_t(i)].push_back(1 + 0.01 * ((k * 7 + i) % 5));
    tail[17][3] = 1000;  // one sample in 1600
    tail[60][9] = 2;     // and a little spread elsewhere
    for (const auto* v : {&even, &tail})
        EXPECT_NEAR(picture(*v).film.meanRelativeErrorDof(), dofOfSamples(*v),
                    1e-9 * dofOfSamples(*v));
    EXPECT_GT(picture(even).film.meanRelativeErrorDof(), 1000);
    // Every pixel spread alike about a mean far above the spread: Satterthwaite's ν is the
    // nominal pixels × (k − 1), 1500 (Kish's count, 15.9, is capped at k − 1).
    std::vector<std::vector<double>> alike(pixels);
    for (int i = 0; i < pixels; ++i)
        for (int k = 0; k < samples; ++k) alike[size_t(i)].push_back(k % 2 ? 1.25 : 1.0);
    EXPECT_NEAR(picture(alike).film.meanRelativeErrorDof(), pixels * (samples - 1), 1e-9);
    EXPECT_LT(picture(tail).film.meanRelativeErrorDof(), 1.1);
    // At one sample per pixel the error is of all samples: no within-pixel figure (∞); so
    // without squares, and where no pixel spreads (an error of 0 stated by nothing).
    EXPECT_EQ(contrast(pixels, 1, 0.01).film.meanRelativeErrorDof(), INFINITY);
    Picture unknown = picture(even);
    unknown.film.luminanceSumSq.clear();
    EXPECT_EQ(unknown.film.meanRelativeErrorDof(), INFINITY);
    EXPECT_EQ(picture(std::vector<std::vector<double>>(pixels, std::vector<double>(samples, 1.0)))
                  .film.meanRelativeErrorDof(),
              INFINITY);
    // Nor where the spread is the sums' rounding (0.3 is not a double: Σy² − (Σy)²/k is not 0).
    const Picture tenths = picture(std::vector<std::vector<double>>(pixels, {0.3, 0.3, 0.3}));
    const Film& f = tenths.film;
    const double s = luminance(Spectrum(f.sum[0], f.sum[1], f.sum[2]));
    EXPECT_GT(f.luminanceSumSq[0] - s * s / 3, 0.0);  // (the case)
    EXPECT_EQ(f.meanRelativeErrorDof(), INFINITY);
}

}  // namespace shvol
