#include "shvol/render/phase_weight_moments.h"

#include <gtest/gtest.h>

#include "shvol/core/rng.h"

namespace shvol {

// E[m₂^k] from the bins: a lower bound of the paths' own mean, within the bin's factor e^(1/16)
// of it, over paths merged from two sets; the last bin holds everything beyond ln m₂^k = 8.
TEST(PhaseWeightMoments, MeanLowerBoundBracketsThePathsMean) {
    PhaseWeightMoments a, b;
    Rng rng(5, 1);
    double sum = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        const double lnM2k = 3 * rng.uniform() * rng.uniform();  // below the last bin
        sum += std::exp(lnM2k);
        (i % 2 ? a : b).add(lnM2k);
    }
    a.add(b);
    ASSERT_EQ(a.count(), uint64_t(n));
    const double mean = sum / n, bound = a.meanLowerBound();
    EXPECT_LE(bound, mean);
    EXPECT_GE(bound, mean * std::exp(-PhaseWeightMoments::kBin));
    EXPECT_EQ(PhaseWeightMoments{}.meanLowerBound(), 1.0);
    EXPECT_EQ(a.shareFrom(0), 1.0);

    PhaseWeightMoments c;
    c.add(0.0);
    c.add(1.0);    // bin 16: e
    c.add(500.0);  // beyond: counted in the last bin, at e^8
    EXPECT_NEAR(c.meanLowerBound(), (1 + std::exp(1.0) + std::exp(8.0)) / 3, 1e-9);
    EXPECT_NEAR(c.shareFrom(16), 2.0 / 3, 1e-15);
    EXPECT_EQ(c.paths[PhaseWeightMoments::kBins - 1], 1u);
}

}  // namespace shvol
