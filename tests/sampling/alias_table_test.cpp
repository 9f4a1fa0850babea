#include "shvol/sampling/alias_table.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "shvol/core/rng.h"

namespace shvol {
namespace {

std::vector<double> normalised(const std::vector<double>& w) {
    // Through w / max w, so that the sum of weights near 1e308 stays finite.
    double top = 0;
    for (double x : w) top = x > top && std::isfinite(x) ? x : top;
    double sum = 0;
    for (double x : w) sum += x > 0 && std::isfinite(x) ? x / top : 0;
    std::vector<double> p;
    for (double x : w) p.push_back(x > 0 && std::isfinite(x) ? x / top / sum : 0);
    return p;
}

// The sum P(i) = (qᵢ + Σ_{a_j = i} (1 − q_j))/n against wᵢ/Σw, to `relative` of the larger of wᵢ/Σw
// and 1/n (rounding accumulates in the bins that many columns alias), and what a table must never
// do.
void expectDrawsTheWeights(const std::vector<double>& w, double relative) {
    const std::vector<AliasColumn> t = buildAliasTable(w.data(), int(w.size()));
    ASSERT_EQ(t.size(), w.size());
    const std::vector<double> P = aliasTableProbabilities(t), want = normalised(w);
    for (size_t i = 0; i < w.size(); ++i) {
        EXPECT_NEAR(P[i], want[i], relative * std::max(want[i], 1.0 / double(w.size())))
            << "bin " << i;
        EXPECT_GE(t[i].q, 0.0);
        EXPECT_LE(t[i].q, 1.0);
        ASSERT_GE(t[i].alias, 0);
        ASSERT_LT(t[i].alias, int(w.size()));
        if (want[i] == 0) EXPECT_EQ(t[i].q, 0.0) << "a bin of weight 0 is kept, bin " << i;
        if (t[i].q < 1) EXPECT_GT(want[size_t(t[i].alias)], 0.0) << "alias of bin " << i;
    }
}

TEST(AliasTable, DrawsEachBinWithItsWeight) {
    expectDrawsTheWeights({1, 0, 2, 1, 0, 0, 3, 0.5, 0, 4.5}, 1e-14);
    expectDrawsTheWeights({7}, 0);
    expectDrawsTheWeights({1, 1, 1, 1}, 0);
    // Negative, NaN and infinite weights count as 0.
    expectDrawsTheWeights({-1, 2, std::nan(""), 1, std::numeric_limits<double>::infinity()}, 1e-14);
    // A sun: one bin with almost all of the weight among 4096 dim ones, and a wide range.
    std::vector<double> sky(4096);
    Rng rng(3, 1);
    for (double& x : sky) x = rng.uniform() < 0.2 ? 0.0 : std::exp(-20 * rng.uniform());
    sky[1234] = 1e7;
    expectDrawsTheWeights(sky, 1e-14);
}

TEST(AliasTable, AllZeroKeepsEveryColumn) {
    const std::vector<double> w(5, 0.0);
    const std::vector<AliasColumn> t = buildAliasTable(w.data(), 5);
    for (int i = 0; i < 5; ++i) {
        EXPECT_EQ(t[size_t(i)].q, 1.0);
        EXPECT_EQ(t[size_t(i)].alias, i);
    }
    EXPECT_THROW(buildAliasTable(w.data(), 0), std::exception);
}

// aliasDraw over a fine grid of u: the share of u landing in each bin is its probability, and
// the position in the bin is uniform (its mean over the bin's u is ½, its range [0, 1)).
TEST(AliasTable, DrawMapsTheUnitIntervalOntoTheBins) {
    const std::vector<double> w = {1, 0, 2, 1, 0, 0, 3, 0.5, 0, 4.5};
    const std::vector<AliasColumn> t = buildAliasTable(w.data(), int(w.size()));
    const std::vector<double> want = normalised(w);
    const int n = int(w.size()), m = 1 << 20;
    std::vector<double> count(w.size(), 0), duSum(w.size(), 0);
    for (int k = 0; k < m; ++k) {
        const AliasDraw d = aliasDraw((k + 0.5) / m, n, [&](int j) { return t[size_t(j)]; });
        ASSERT_GE(d.bin, 0);
        ASSERT_LT(d.bin, n);
        ASSERT_GE(d.du, 0.0);
        ASSERT_LT(d.du, 1.0);
        count[size_t(d.bin)] += 1;
        duSum[size_t(d.bin)] += d.du;
    }
    for (size_t i = 0; i < w.size(); ++i) {
        // Each column splits into at most two intervals of u: a few grid steps of error.
        EXPECT_NEAR(count[i] / m, want[i], 4.0 / m) << "bin " << i;
        if (count[i] > 0) EXPECT_NEAR(duSum[i] / count[i], 0.5, 1e-3) << "bin " << i;
    }
    // u at the ends of [0, 1), beyond them and NaN: a bin of weight, du in [0, 1); also where the
    // last column keeps its own bin (q = 1), which u = 1 unclamped would turn into 0/0.
    const std::vector<double> even = {1, 1, 1, 1};
    const std::vector<AliasColumn> te = buildAliasTable(even.data(), 4);
    ASSERT_EQ(te[3].q, 1.0);
    for (double u : {0.0, std::nextafter(1.0, 0.0), 1.0, -0.5, 2.0, std::nan("")}) {
        const AliasDraw d = aliasDraw(u, n, [&](int j) { return t[size_t(j)]; });
        EXPECT_GT(want[size_t(d.bin)], 0.0) << u;
        EXPECT_GE(d.du, 0.0) << u;
        EXPECT_LT(d.du, 1.0) << u;
        const AliasDraw de = aliasDraw(u, 4, [&](int j) { return te[size_t(j)]; });
        EXPECT_GE(de.du, 0.0) << u;
        EXPECT_LT(de.du, 1.0) << u;
    }
}

// Weights at the ends of the double range: a sum that would overflow, subnormal weights.
TEST(AliasTable, ExtremeWeights) {
    expectDrawsTheWeights({1e308, 0, 1e308, 5e307}, 1e-14);
    expectDrawsTheWeights({4.9e-324, 0, 1e-320, 0}, 1e-14);
}

}  // namespace
}  // namespace shvol
