#include <gtest/gtest.h>

#include <cmath>

#include "shvol/render/volume_path_integrator.h"

namespace shvol {

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
