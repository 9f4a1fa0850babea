#include "shvol/core/image_metrics.h"

#include <gtest/gtest.h>

#include <cmath>

#include "shvol/core/error.h"
#include "shvol/core/rng.h"

namespace shvol {

// Hand-computed: two pixels, errors (1, −1, 0.5) and (0, 2, −0.5) against r = (1, 0, 2), (0, 1, 1).
TEST(ImageMetrics, HandComputedValues) {
    Image r(2, 1), x(2, 1);
    r.set(0, 0, Spectrum(1, 0, 2)), r.set(1, 0, Spectrum(0, 1, 1));
    x.set(0, 0, Spectrum(2, -1, 2.5)), x.set(1, 0, Spectrum(0, 3, 0.5));
    const ImageMetrics m = imageMetrics(x, r);
    EXPECT_EQ(m.values, 6);
    EXPECT_DOUBLE_EQ(m.rmse, std::sqrt((1 + 1 + 0.25 + 0 + 4 + 0.25) / 6));
    EXPECT_DOUBLE_EQ(m.mae, (1 + 1 + 0.5 + 0 + 2 + 0.5) / 6);
    EXPECT_DOUBLE_EQ(m.bias, 2.0 / 6);
    EXPECT_NEAR(m.relMse, (1 / 1.01 + 1 / 0.01 + 0.25 / 4.01 + 0 + 4 / 1.01 + 0.25 / 1.01) / 6,
                1e-12);
    // The interval is over the 2 pixels' mean differences (0.5/3 and 1.5/3): a pixel's channels
    // share its paths, so they are not independent values.
    const double d0 = 0.5 / 3, d1 = 1.5 / 3, mean = (d0 + d1) / 2;
    const double var = (d0 - mean) * (d0 - mean) + (d1 - mean) * (d1 - mean);  // /(2 − 1)
    EXPECT_NEAR(m.biasHalfWidth95, 1.96 * std::sqrt(var / 2), 1e-12);
    EXPECT_THROW(imageMetrics(Image(3, 1), r), Error);
}

// The z-test passes an unbiased noisy image with the right standard errors, and fails one
// shifted by 10 standard errors in a single pixel.
TEST(ImageMetrics, ZTest) {
    Image r(32, 32), x(32, 32), se(32, 32), zero(32, 32);
    Rng rng(3, 4);
    for (int y = 0; y < 32; ++y)
        for (int i = 0; i < 32; ++i) {
            r.set(i, y, Spectrum::Constant(1));
            se.set(i, y, Spectrum::Constant(0.1));
            // Box–Muller normal deviates
            Spectrum v;
            for (int c = 0; c < 3; ++c) {
                const Vec2 u = rng.uniform2();
                v[c] = 1 + 0.1 * std::sqrt(-2 * std::log(1 - u.x())) * std::cos(TwoPi * u.y());
            }
            x.set(i, y, v);
        }
    ZTest t = zTest(x, se, r, zero);
    EXPECT_TRUE(t.passed) << t.minP << " < " << t.threshold;
    EXPECT_EQ(t.tested, 32 * 32 * 3);
    x.set(5, 5, Spectrum(2, 1, 1));
    t = zTest(x, se, r, zero);
    EXPECT_FALSE(t.passed);
}

// The reference's standard error counts as the image's does: a difference of 0.5 is 4 standard
// errors of an image of σ 0.125 against an exact reference (p = 6·10⁻⁵, failing at α = 0.01),
// and 0.97 of √(0.125² + 0.5²) against a reference of σ 0.5 (p = 0.33). Every other z-test here
// has an exact reference, so dropping its term passed (helper 118).
TEST(ImageMetrics, ZTestCountsTheReferencesStandardError) {
    Image x(1, 1), r(1, 1), sx(1, 1), sr(1, 1), zero(1, 1);
    // (all exact in float32; both values' float step is 2⁻²³)
    x.set(0, 0, Spectrum::Constant(1.5));
    r.set(0, 0, Spectrum::Constant(1.0));
    sx.set(0, 0, Spectrum::Constant(0.125));
    sr.set(0, 0, Spectrum::Constant(0.5));
    const double ulp = std::ldexp(1.0, -23), rounding = 2 * ulp * ulp / 12;
    const auto p = [&](double variance) {
        return std::erfc(0.5 / std::sqrt(variance + rounding) / std::sqrt(2.0));
    };
    ZTest t = zTest(x, sx, r, sr);
    EXPECT_TRUE(t.passed);
    EXPECT_EQ(t.tested, 3);
    EXPECT_NEAR(t.minP, p(0.125 * 0.125 + 0.5 * 0.5), 1e-12);
    t = zTest(x, sx, r, zero);
    EXPECT_FALSE(t.passed);
    EXPECT_NEAR(t.minP, p(0.125 * 0.125), 1e-15);
}

// Values with (almost) no noise, such as pixels of constant sky, differ by the float32 rounding
// of their storage: one float step passes (with σ = 2.6·10⁻⁹, the audit's case, p underflowed
// to 0), a hundred steps do not.
TEST(ImageMetrics, ZTestAllowsTheFloatRoundingOfStoredValues) {
    Image r(1, 1), x(1, 1), se(1, 1), zero(1, 1);
    const float one = 1.0f, next = std::nextafter(one, 2.0f);
    r.set(0, 0, Spectrum::Constant(one));
    se.set(0, 0, Spectrum::Constant(2.6e-9));
    x.set(0, 0, Spectrum(next, one, one));
    EXPECT_TRUE(zTest(x, se, r, zero).passed) << zTest(x, se, r, zero).minP;
    EXPECT_TRUE(zTest(x, zero, r, zero).passed);
    x.set(0, 0, Spectrum(one + 100 * (next - one), one, one));
    EXPECT_FALSE(zTest(x, se, r, zero).passed);
    EXPECT_EQ(zTest(x, se, r, zero).tested, 3);
    // Values equal in both and without noise are not tested (they would loosen the level).
    EXPECT_EQ(zTest(x, zero, x, zero).tested, 0);
}

}  // namespace shvol
