#include <gtest/gtest.h>

#include <cmath>

#include "shvol/render/volume_path_integrator.h"

namespace shvol {

namespace {
/// Counters of `pixels` pixels of `samples` each in `passes` equal passes, pixel i's samples
/// alternating between mean_i − spread and mean_i + spread, mean_i from 0.5 to 1.5 across the
/// pixels.
PathCounters picture(int pixels, int samples, double spread, int passes = 1) {
    PathCounters c;
    for (int i = 0; i < pixels; ++i) {
        const double mean = 0.5 + double(i) / (pixels - 1);
        for (int p = 0, k = 0; p < passes; ++p) {
            PixelMoments m;
            for (int j = 0; j < samples / passes; ++j, ++k)
                m.add(mean + (k % 2 ? spread : -spread));
            c.add(m);
            c.paths += uint64_t(samples / passes);
        }
    }
    return c;
}
}  // namespace

// The image mean's standard error comes from the spread within pixels, not from the picture's
// contrast (helper 87): √(s²/n)/ȳ with s² the pooled within-pixel variance, here spread²·k/(k−1).
TEST(PathCounters, ImageMeanRelativeErrorIsOfTheSpreadWithinPixels) {
    const int pixels = 100, samples = 16;
    const double n = pixels * samples, spread = 0.01;
    const double s2 = spread * spread * samples / (samples - 1);
    EXPECT_NEAR(picture(pixels, samples, spread).imageMeanRelativeError(), std::sqrt(s2 / n) / 1.0,
                1e-12);
    // No spread within pixels: no error but rounding (Σy² − (Σy)²/k), however strong the
    // contrast (the variance of all samples would give about √(1/12 / n) here, 0.72%).
    EXPECT_LT(picture(pixels, samples, 0).imageMeanRelativeError(), 1e-8);
    // Passes of two samples each: the same spread, pooled over 8 passes.
    const double s2Pairs = spread * spread * 2;
    EXPECT_NEAR(picture(pixels, samples, spread, 8).imageMeanRelativeError(),
                std::sqrt(s2Pairs / n), 1e-12);
    // Passes of one sample (--checkpoint-interval 0): the variance of all samples, larger, not ∞
    // (helper 88); 0.007295977757824748 from the samples themselves, in Python (helper 90: the
    // test only asked for more than 10× the within-pixel value).
    EXPECT_NEAR(picture(pixels, samples, spread, 16).imageMeanRelativeError(), 0.007295977757824748,
                1e-12);
    // One pass of two equal samples among passes of one is no estimate of the spread (it gave
    // 0; helper 90): the variance of all samples stays.
    PathCounters mixed = picture(pixels, samples, spread, 16);
    PixelMoments twice;
    twice.add(1), twice.add(1);
    mixed.add(twice), mixed.paths += 2;
    EXPECT_NEAR(mixed.imageMeanRelativeError(), 0.0073, 1e-4);
    // Passes of four: most samples of a pixel pass do enter the within-pixel spread.
    EXPECT_NEAR(picture(pixels, samples, spread, 4).imageMeanRelativeError(),
                std::sqrt(spread * spread * 4 / 3 / n), 1e-12);
    // No light: nothing to be relative to.
    EXPECT_EQ(PathCounters{}.imageMeanRelativeError(), INFINITY);
}

// The share of paths cut by max_depth that is exceeded with 95% confidence: the Poisson lower
// bound of the count, λ with P(N ≥ k | λ) = 0.05 (for k = 1, −ln 0.95), over the paths.
TEST(PathCounters, TruncatedShareLowerBound) {
    EXPECT_EQ(truncatedShareLowerBound(0, 100), 0.0);
    EXPECT_EQ(truncatedShareLowerBound(3, 0), 0.0);
    EXPECT_NEAR(truncatedShareLowerBound(1, 768), -std::log(0.95) / 768, 1e-15);
    // P(N ≥ 5 | λ) = 1 − e^{−λ} Σ_{j<5} λ^j/j! is 0.05 at the bound.
    const double lambda = truncatedShareLowerBound(5, 1);
    double below = 0, term = std::exp(-lambda);
    for (int j = 0; j < 5; ++j) below += term, term *= lambda / (j + 1);
    EXPECT_NEAR(1 - below, 0.05, 1e-12);
    // Below 0.1% for one path of 768 (chance), above for five of 1536 and for nine of nine.
    EXPECT_LT(truncatedShareLowerBound(1, 768), 1e-3);
    EXPECT_GT(truncatedShareLowerBound(5, 1536), 1e-3);
    EXPECT_GT(truncatedShareLowerBound(9, 9), 0.5);
}

}  // namespace shvol
