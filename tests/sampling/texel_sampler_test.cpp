#include "shvol/sampling/texel_sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "shvol/core/rng.h"
#include "shvol/sampling/chi2.h"
#include "shvol/sampling/distribution_2d.h"

namespace shvol {
namespace {

// 4 columns × 3 rows, with a zero row and zero cells (as Distribution2D's tests).
const std::vector<double> kW = {1, 0,   2, 1,  //
                                0, 0,   0, 0,  //
                                3, 0.5, 0, 4.5};

std::vector<float> rgbOf(size_t texels) {
    std::vector<float> rgb;
    for (size_t i = 0; i < texels; ++i)
        for (int c = 0; c < 3; ++c) rgb.push_back(float(10 * i + c) + 0.25f);
    return rgb;
}

// Counts per texel against N·w/Σw (χ²), never a texel of weight 0, the draw's pdf exactly pdf()
// at its point, its point inside its texel, its RGB the texel's; and within each texel the point
// is uniform (mean offset ½ on both axes).
TEST(TexelSampler, DrawsEachTexelWithItsWeight) {
    const std::vector<float> rgb = rgbOf(kW.size());
    const TexelSampler s(kW.data(), rgb.data(), 4, 3);
    EXPECT_DOUBLE_EQ(s.integral(), 1.0);
    Rng rng(9, 3);
    std::vector<double> hist(kW.size(), 0), expected(kW.size());
    std::vector<Vec2> offsetSum(kW.size(), Vec2::Zero());
    const int n = 240000;
    for (int i = 0; i < n; ++i) {
        const TexelSampler::Draw d = s.sample(rng.uniform2());
        ASSERT_GE(d.uv.x(), 0.0);
        ASSERT_LT(d.uv.x(), 1.0);
        ASSERT_GE(d.uv.y(), 0.0);
        ASSERT_LT(d.uv.y(), 1.0);
        ASSERT_EQ(int(d.uv.x() * 4), d.x);
        ASSERT_EQ(int(d.uv.y() * 3), d.y);
        ASSERT_EQ(d.pdf, s.pdf(d.uv));
        ASSERT_GT(d.pdf, 0.0);
        const size_t t = size_t(d.y) * 4 + size_t(d.x);
        ASSERT_EQ(d.rgb[1], double(rgb[3 * t + 1]));
        ++hist[t];
        offsetSum[t] += Vec2(d.uv.x() * 4 - d.x, d.uv.y() * 3 - d.y);
    }
    for (size_t i = 0; i < kW.size(); ++i) expected[i] = n * kW[i] / 12.0;
    const Chi2Result r = chi2TestCounts(hist, expected);
    EXPECT_TRUE(r.passed) << r.report;
    for (size_t i = 0; i < kW.size(); ++i) {
        if (expected[i] == 0) {
            EXPECT_EQ(hist[i], 0) << i;
            continue;
        }
        const Vec2 mean = offsetSum[i] / hist[i];
        const double sigma = std::sqrt(1.0 / 12 / hist[i]);
        EXPECT_NEAR(mean.x(), 0.5, 5 * sigma) << i;
        EXPECT_NEAR(mean.y(), 0.5, 5 * sigma) << i;
    }
}

// The fast path against the slow reference: the density is Distribution2D's (inverting each
// row's CDF), on a sky-like image with a sun, at random points.
TEST(TexelSampler, PdfIsDistribution2DsPdf) {
    const int W = 64, H = 32;
    std::vector<double> w(size_t(W) * H);
    Rng rng(5, 2);
    for (double& x : w) x = rng.uniform() < 0.1 ? 0.0 : std::exp(-5 * rng.uniform());
    w[size_t(10) * W + 40] = 1e4;
    const TexelSampler s(w.data(), rgbOf(w.size()).data(), W, H);
    const Distribution2D reference(w.data(), W, H);
    EXPECT_NEAR(s.integral(), reference.integral(), 1e-15 * reference.integral());
    for (int i = 0; i < 10000; ++i) {
        const Vec2 uv = rng.uniform2();
        EXPECT_NEAR(s.pdf(uv), reference.pdf(uv), 1e-13 * reference.pdf(uv)) << uv.transpose();
    }
}

// u on or beyond the square's edges (and NaN) still draws a texel of weight, inside it.
TEST(TexelSampler, EdgesOfTheSquare) {
    const std::vector<double> even(12, 1.0);
    for (const std::vector<double>* w : {&kW, &even}) {
        const TexelSampler s(w->data(), rgbOf(12).data(), 4, 3);
        for (const Vec2& u :
             {Vec2(1, 1), Vec2(0, 0), Vec2(2, -1), Vec2(std::nan(""), 0.5), Vec2(0.5, std::nan("")),
              Vec2(std::nextafter(1.0, 0.0), std::nextafter(1.0, 0.0))}) {
            const TexelSampler::Draw d = s.sample(u);
            EXPECT_GT(d.pdf, 0.0) << u.transpose();
            EXPECT_EQ(d.pdf, s.pdf(d.uv)) << u.transpose();
            EXPECT_LT(d.uv.x(), 1.0) << u.transpose();
            EXPECT_LT(d.uv.y(), 1.0) << u.transpose();
        }
    }
}

TEST(TexelSampler, AllZeroDrawsNothing) {
    const std::vector<double> w(6, 0.0);
    const TexelSampler s(w.data(), rgbOf(6).data(), 3, 2);
    EXPECT_EQ(s.integral(), 0.0);
    EXPECT_EQ(s.sample({0.3, 0.7}).pdf, 0.0);
    EXPECT_EQ(s.pdf({0.3, 0.7}), 0.0);
    EXPECT_THROW(TexelSampler(w.data(), rgbOf(6).data(), 0, 2), std::exception);
}

}  // namespace
}  // namespace shvol
