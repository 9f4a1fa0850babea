#include "shvol/sampling/distribution_1d.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "shvol/core/rng.h"
#include "shvol/sampling/chi2.h"

namespace shvol {
namespace {

TEST(Distribution1D, IntegralAndPdfIntegratesToOne) {
    const std::vector<double> f = {1, 0, 3, 0, 0, 4};
    Distribution1D d(f.data(), int(f.size()));
    EXPECT_EQ(d.count(), 6);
    EXPECT_DOUBLE_EQ(d.integral(), 8.0 / 6.0);
    double sum = 0;
    for (int i = 0; i < d.count(); ++i) sum += d.pdf((i + 0.5) / d.count()) / d.count();
    EXPECT_NEAR(sum, 1.0, 1e-15);
    EXPECT_DOUBLE_EQ(d.pdf(0.99), 4 / (8.0 / 6.0));
    EXPECT_EQ(d.pdf(0.2), 0.0);
}

TEST(Distribution1D, ContinuousSampleInvertsTheCdf) {
    const std::vector<double> f = {1, 2, 0, 5};
    Distribution1D d(f.data(), 4);
    // CDF at bin edges: 0, 1/8, 3/8, 3/8, 1.
    double pdf;
    int off;
    double x = d.sampleContinuous(0.0625, &pdf, &off);  // half way through bin 0
    EXPECT_EQ(off, 0);
    EXPECT_NEAR(x, 0.125, 1e-15);
    EXPECT_DOUBLE_EQ(pdf, 0.5);
    x = d.sampleContinuous(0.375, &pdf, &off);  // exactly at the start of bin 3, skips bin 2
    EXPECT_EQ(off, 3);
    EXPECT_NEAR(x, 0.75, 1e-15);
    EXPECT_DOUBLE_EQ(pdf, 2.5);
    // Consistency: the CDF of the returned x equals u.
    Rng rng(1, 2);
    for (int i = 0; i < 10000; ++i) {
        const double u = rng.uniform();
        x = d.sampleContinuous(u, &pdf, &off);
        ASSERT_GE(x, 0.0);
        ASSERT_LT(x, 1.0);
        double cdf = 0;
        for (int j = 0; j < off; ++j) cdf += f[j] / 8.0;
        cdf += (x * 4 - off) * f[off] / 8.0;
        EXPECT_NEAR(cdf, u, 1e-12);
        EXPECT_EQ(pdf, d.pdf(x));
        EXPECT_GT(pdf, 0.0);
    }
}

// The guide-table search (findBin) finds the bin the binary search of the whole CDF finds, for
// random u and for the values where it could err: the guide cells' edges k/n and the CDF's own
// values, each with its neighbours one ulp away; on spiky, sparse, all-zero and tiny tables.
TEST(Distribution1D, GuideTableFindsTheBinTheFullSearchFinds) {
    Rng rng(7, 3);
    std::vector<std::vector<double>> tables = {{1}, {0}, {1, 2, 0, 5}, {0, 0, 0, 3, 0}};
    std::vector<double> spike(1024, 1e-6);  // a sun among faint sky texels
    spike[700] = 1e6, spike[701] = 5e5;
    tables.push_back(spike);
    std::vector<double> sparse(777, 0.0);  // not a power of two, mostly empty
    for (int i = 0; i < 777; i += 37) sparse[i] = rng.uniform();
    tables.push_back(sparse);
    std::vector<double> random(333);
    for (double& v : random) v = rng.uniform() < 0.2 ? 0.0 : -std::log(1 - rng.uniform());
    tables.push_back(random);
    for (const std::vector<double>& f : tables) {
        const Distribution1D d(f.data(), int(f.size()));
        const int n = d.count();
        std::vector<double> us;
        for (int i = 0; i < 20000; ++i) us.push_back(rng.uniform());
        double c = 0;
        for (int i = 0; i <= n; ++i) {
            us.push_back(double(i) / n);
            if (i < n) us.push_back(c / (d.integral() * n)), c += d.func(i);
        }
        for (size_t i = 0, m = us.size(); i < m; ++i)
            for (double u : {std::nextafter(us[i], 0.0), std::nextafter(us[i], 1.0)})
                us.push_back(u);
        for (double u : us) {
            if (!(u >= 0 && u < 1)) continue;
            ASSERT_EQ(d.findBin(u), d.findBinBySearch(u)) << "n " << n << ", u " << u;
        }
    }
}

TEST(Distribution1D, ZeroWeightBinsAreNeverSampled) {
    const std::vector<double> f = {0, 0, 1, 0, 0, 2, 0, 0};
    Distribution1D d(f.data(), 8);
    const double us[] = {
        0.0, 1e-300, 1.0 / 3, std::nextafter(1.0 / 3, 0.0), 0.5, std::nextafter(1.0, 0.0),
        1.0, 1.5};
    for (double u : us) {
        double pdf, pmf;
        int off;
        const double x = d.sampleContinuous(u, &pdf, &off);
        EXPECT_TRUE(off == 2 || off == 5) << u;
        EXPECT_GT(pdf, 0.0) << u;
        EXPECT_GT(d.pdf(x), 0.0) << u;
        EXPECT_LT(x, 1.0);
        const int k = d.sampleDiscrete(u, &pmf);
        EXPECT_TRUE(k == 2 || k == 5) << u;
        EXPECT_NEAR(pmf, f[k] / 3.0, 1e-15);
    }
}

TEST(Distribution1D, DiscreteFrequencies) {
    const std::vector<double> f = {1, 0, 2, 7};
    Distribution1D d(f.data(), 4);
    std::vector<double> hist(4, 0), expected(4);
    Rng rng(5, 1);
    const int n = 200000;
    for (int i = 0; i < n; ++i) ++hist[d.sampleDiscrete(rng.uniform())];
    EXPECT_EQ(hist[1], 0);
    for (int i = 0; i < 4; ++i) {
        expected[i] = n * f[i] / 10.0;
        EXPECT_DOUBLE_EQ(d.pmf(i), f[i] / 10.0);
    }
    const Chi2Result r = chi2TestCounts(hist, expected);
    EXPECT_TRUE(r.passed) << r.report;
}

TEST(Distribution1D, AllZeroBehavesUniform) {
    const std::vector<double> f = {0, 0, 0, 0};
    Distribution1D d(f.data(), 4);
    EXPECT_EQ(d.integral(), 0.0);
    double pdf, pmf;
    int off;
    const double x = d.sampleContinuous(0.6, &pdf, &off);
    EXPECT_NEAR(x, 0.6, 1e-15);
    EXPECT_EQ(off, 2);
    EXPECT_EQ(pdf, 1.0);
    EXPECT_EQ(d.pdf(0.3), 1.0);
    EXPECT_EQ(d.sampleDiscrete(0.99, &pmf), 3);
    EXPECT_DOUBLE_EQ(pmf, 0.25);
}

TEST(Distribution1D, SingleBinAndTinyWeights) {
    const double one = 3.0;
    Distribution1D d(&one, 1);
    double pdf;
    EXPECT_NEAR(d.sampleContinuous(0.25, &pdf), 0.25, 1e-15);
    EXPECT_EQ(pdf, 1.0);
    const std::vector<double> f = {1e-300, 1.0, 1e-300};
    Distribution1D t(f.data(), 3);
    int off;
    t.sampleContinuous(0.0, &pdf, &off);
    EXPECT_GT(pdf, 0.0);
    t.sampleContinuous(std::nextafter(1.0, 0.0), &pdf, &off);
    EXPECT_GT(pdf, 0.0);
}

}  // namespace
}  // namespace shvol
