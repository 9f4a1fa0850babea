#include "shvol/core/rng.h"

#include <gtest/gtest.h>

namespace shvol {

TEST(Rng, SameKeySameSequence) {
    Rng a = Rng::forSample(7, 123, 4), b = Rng::forSample(7, 123, 4);
    for (int i = 0; i < 100; ++i) EXPECT_EQ(a.nextU32(), b.nextU32());
}

TEST(Rng, DifferentKeysDiffer) {
    Rng a = Rng::forSample(7, 123, 4), b = Rng::forSample(7, 123, 5), c = Rng::forSample(8, 123, 4);
    int sameB = 0, sameC = 0;
    for (int i = 0; i < 100; ++i) {
        const uint32_t x = a.nextU32();
        sameB += x == b.nextU32();
        sameC += x == c.nextU32();
    }
    EXPECT_LT(sameB, 3);
    EXPECT_LT(sameC, 3);
}

TEST(Rng, UniformInUnitIntervalWithCorrectMean) {
    Rng r(1, 2);
    double sum = 0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        const double u = r.uniform();
        ASSERT_GE(u, 0.0);
        ASSERT_LT(u, 1.0);
        sum += u;
    }
    // Mean of U(0,1) is 1/2 with standard error 1/sqrt(12 n) ≈ 6.5e-4; allow 5 sigma.
    EXPECT_NEAR(sum / n, 0.5, 5 * std::sqrt(1.0 / (12.0 * n)));
}

}  // namespace shvol
