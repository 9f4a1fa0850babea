#include "shvol/phase/piecewise_linear_1d.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "shvol/core/rng.h"
#include "shvol/sampling/chi2.h"

namespace shvol {
namespace {

TEST(PiecewiseLinear1D, EvalIntegralCdf) {
    const PiecewiseLinear1D d({0.0, 1.0, 3.0}, {1.0, 3.0, 0.0});
    EXPECT_DOUBLE_EQ(d.integral(), 2.0 + 3.0);
    EXPECT_DOUBLE_EQ(d.eval(0.5), 2.0);
    EXPECT_DOUBLE_EQ(d.eval(2.0), 1.5);
    EXPECT_EQ(d.eval(-0.1), 0.0);
    EXPECT_EQ(d.eval(3.1), 0.0);
    EXPECT_EQ(d.eval(std::nan("")), 0.0);
    EXPECT_DOUBLE_EQ(d.cdf(1.0), 0.4);
    EXPECT_DOUBLE_EQ(d.cdf(0.5), (0.5 * 1.0 + 0.25 * 0.5 * 2.0) / 5.0);
    EXPECT_EQ(d.cdf(3.0), 1.0);
}

TEST(PiecewiseLinear1D, SampleInvertsCdf) {
    // Rising, falling, flat, zero-ended and empty segments.
    const PiecewiseLinear1D d({-1.0, -0.5, 0.0, 0.2, 0.5, 0.9, 1.0},
                              {0.0, 0.0, 2.0, 2.0, 0.5, 0.0, 0.0});
    for (double u : {0.0, 1e-12, 0.01, 0.2, 0.37, 0.5, 0.66, 0.9, 0.999999, 1.0}) {
        const double x = d.sample(u);
        EXPECT_NEAR(d.cdf(x), u, 1e-13) << u;
        EXPECT_GE(x, -0.5) << u;  // never inside the empty first segment
        EXPECT_LE(x, 0.9) << u;   // nor the empty last one
        EXPECT_GT(d.pdf(x) + (u == 0 || u == 1), 0.0) << u;
    }
    // Monotone.
    double prev = -2;
    for (int i = 0; i <= 1000; ++i) {
        const double x = d.sample(i / 1000.0);
        EXPECT_GE(x, prev);
        prev = x;
    }
}

TEST(PiecewiseLinear1D, HistogramMatchesPdf) {
    const PiecewiseLinear1D d({0.0, 0.3, 1.0}, {0.1, 4.0, 1.0});
    const int bins = 20, n = 400000;
    std::vector<double> h(bins, 0), expected(bins);
    Rng rng(9, 9);
    for (int i = 0; i < n; ++i) ++h[std::min(bins - 1, int(d.sample(rng.uniform()) * bins))];
    for (int b = 0; b < bins; ++b)
        expected[b] = n * (d.cdf((b + 1.0) / bins) - d.cdf(double(b) / bins));
    const Chi2Result r = chi2TestCounts(h, expected);
    EXPECT_TRUE(r.passed) << r.report;
}

// A table that starts and ends with zeros: u = 0 and u = 1 (an RNG can return 0) must still give
// a point of positive density, or value/pdf would be 0/0 (found by review of the fuzzing work).
TEST(PiecewiseLinear1D, EndsOfTheUnitIntervalLandWhereThereIsMass) {
    const PiecewiseLinear1D f({0, 1, 2, 3, 4}, {0, 0, 1, 0, 0});
    for (double u : {0.0, 1.0, 1e-300, std::nextafter(1.0, 0.0)}) {
        const double x = f.sample(u);
        EXPECT_GT(f.pdf(x), 0) << "u " << u << " x " << x;
        EXPECT_GT(x, 1.0);
        EXPECT_LT(x, 3.0);
    }
}

// A zero between two lobes sits exactly on a cdf node; u on that node must still land where there
// is mass (found by the phase_csv fuzzer: a table 1, 0, 1 sampled at u = ½ returned pdf 0).
TEST(PiecewiseLinear1D, CdfNodeAtAZeroLandsWhereThereIsMass) {
    const PiecewiseLinear1D t({-1, 0, 1}, {1, 0, 1});
    for (double u : {0.5, std::nextafter(0.5, 0.0), std::nextafter(0.5, 1.0)}) {
        const double x = t.sample(u);
        EXPECT_GT(t.pdf(x), 0) << "u " << u << " x " << x;
        EXPECT_NEAR(x, 0, 1e-7);
    }
}

// A segment one double wide (a lobe of 10⁻⁶° in cos θ: cos 10⁻⁶° is the double below 1) holds no
// point but its ends: a sample rounded onto the end where f = 0 had value and pdf 0 (a quarter of
// them; helper 76's furnace rendered 0.007 for 1). Wider ones, a few doubles, lost fewer.
TEST(PiecewiseLinear1D, SegmentsAFewDoublesWideGiveNoZeroDensity) {
    for (int width : {1, 3, 68}) {
        double top = 1;
        for (int k = 0; k < width; ++k) top = std::nextafter(top, 2.0);
        for (const bool rising : {true, false}) {
            const PiecewiseLinear1D f = rising ? PiecewiseLinear1D({-1, 1, top}, {0, 0, 1})
                                               : PiecewiseLinear1D({-top, -1, 1}, {1, 0, 0});
            for (int k = 0; k < 4096; ++k) {
                const double u = (k + 0.5) / 4096, x = f.sample(u);
                ASSERT_GT(f.pdf(x), 0) << "width " << width << " u " << u << " x " << x;
                EXPECT_TRUE(rising ? x > 1 : x < -1) << x;
            }
        }
    }
}

TEST(PiecewiseLinear1D, RejectsBadInput) {
    EXPECT_THROW(PiecewiseLinear1D({0.0}, {1.0}), std::invalid_argument);
    EXPECT_THROW(PiecewiseLinear1D({0.0, 0.0}, {1.0, 1.0}), std::invalid_argument);
    EXPECT_THROW(PiecewiseLinear1D({0.0, 1.0}, {1.0, -1.0}), std::invalid_argument);
    EXPECT_THROW(PiecewiseLinear1D({0.0, 1.0}, {0.0, 0.0}), std::invalid_argument);
    EXPECT_THROW(PiecewiseLinear1D({0.0, 1.0}, {std::nan(""), 1.0}), std::invalid_argument);
}

}  // namespace
}  // namespace shvol
