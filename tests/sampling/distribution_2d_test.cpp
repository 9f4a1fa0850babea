#include "shvol/sampling/distribution_2d.h"

#include <gtest/gtest.h>

#include <vector>

#include "shvol/core/rng.h"
#include "shvol/sampling/chi2.h"

namespace shvol {
namespace {

// 4 columns × 3 rows, with a zero row and zero cells.
const std::vector<double> kF = {1, 0,   2, 1,  //
                                0, 0,   0, 0,  //
                                3, 0.5, 0, 4.5};

TEST(Distribution2D, PdfIntegratesToOne) {
    Distribution2D d(kF.data(), 4, 3);
    EXPECT_DOUBLE_EQ(d.integral(), 12.0 / 12.0);
    double sum = 0;
    for (int v = 0; v < 3; ++v)
        for (int u = 0; u < 4; ++u) sum += d.pdf({(u + 0.5) / 4, (v + 0.5) / 3}) / 12.0;
    EXPECT_NEAR(sum, 1.0, 1e-15);
    EXPECT_DOUBLE_EQ(d.pdf({0.9, 0.9}), 4.5);
}

TEST(Distribution2D, SamplesMatchPdfAndAvoidZeroCells) {
    Distribution2D d(kF.data(), 4, 3);
    Rng rng(9, 3);
    std::vector<double> hist(12, 0), expected(12);
    const int n = 240000;
    for (int i = 0; i < n; ++i) {
        double pdf;
        const Vec2 p = d.sampleContinuous(rng.uniform2(), &pdf);
        ASSERT_GE(p.x(), 0.0);
        ASSERT_LT(p.x(), 1.0);
        ASSERT_GE(p.y(), 0.0);
        ASSERT_LT(p.y(), 1.0);
        EXPECT_NEAR(pdf, d.pdf(p), 1e-12 * pdf);
        ASSERT_GT(pdf, 0.0);
        ++hist[int(p.y() * 3) * 4 + int(p.x() * 4)];
    }
    for (int i = 0; i < 12; ++i) {
        expected[i] = n * kF[i] / 12.0;
        if (expected[i] == 0) EXPECT_EQ(hist[i], 0) << i;
    }
    const Chi2Result r = chi2TestCounts(hist, expected);
    EXPECT_TRUE(r.passed) << r.report;
}

TEST(Distribution2D, InverseConsistency) {
    // Within a cell, the sample moves linearly with u: u[0] maps onto the row's CDF.
    const std::vector<double> f = {1, 3};  // 2 columns, 1 row
    Distribution2D d(f.data(), 2, 1);
    double pdf;
    Vec2 p = d.sampleContinuous({0.125, 0.5}, &pdf);
    EXPECT_NEAR(p.x(), 0.25, 1e-15);
    EXPECT_NEAR(p.y(), 0.5, 1e-15);
    EXPECT_DOUBLE_EQ(pdf, 0.5);
    p = d.sampleContinuous({0.625, 0.5}, &pdf);
    EXPECT_NEAR(p.x(), 0.75, 1e-15);
    EXPECT_DOUBLE_EQ(pdf, 1.5);
}

TEST(Distribution2D, AllZeroIsUniformWithZeroIntegral) {
    const std::vector<double> f(6, 0.0);
    Distribution2D d(f.data(), 3, 2);
    EXPECT_EQ(d.integral(), 0.0);
    double pdf;
    const Vec2 p = d.sampleContinuous({0.3, 0.7}, &pdf);
    EXPECT_NEAR(p.x(), 0.3, 1e-15);
    EXPECT_NEAR(p.y(), 0.7, 1e-15);
    EXPECT_EQ(pdf, 1.0);
}

}  // namespace
}  // namespace shvol
