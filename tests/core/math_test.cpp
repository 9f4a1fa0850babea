#include "shvol/core/math.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "shvol/core/rng.h"

namespace shvol {

// floorToInt agrees with std::floor on integers, on their neighbours one ulp away, on signed
// zeros and on random values of every magnitude below 2³¹.
TEST(Math, FloorToIntMatchesFloor) {
    for (double k : {0.0, -0.0, 1.0, -1.0, 7.0, -8.0, 2147483646.0, -2147483647.0})
        for (double x :
             {k, std::nextafter(k, -INFINITY), std::nextafter(k, INFINITY), k + 0.5, k - 0.5})
            if (std::abs(x) < 2147483647.0) ASSERT_EQ(floorToInt(x), int(std::floor(x))) << x;
    Rng rng(8, 8);
    for (int i = 0; i < 100000; ++i) {
        const double x = (rng.uniform() - 0.5) * std::ldexp(1.0, int(rng.nextU32() % 32));
        ASSERT_EQ(floorToInt(x), int(std::floor(x))) << x;
    }
}

// exponentialVariate(u) = −log1p(−u) to within 2 ulp for the numbers the samplers give
// (multiples of 2⁻⁵³ in [0, 1)), tiny and close to 1 included.
TEST(Math, ExponentialVariateMatchesLog1p) {
    Rng rng(9, 9);
    std::vector<double> us = {0.0, 0x1p-53, 0x1p-40, 0.5, 1 - 0x1p-53, 1 - 0x1p-30};
    for (int i = 0; i < 100000; ++i)  // uniform, and small multiples of 2⁻⁵³
        us.push_back(i % 2 ? rng.uniform() : double(rng.nextU32() >> (i % 32)) * 0x1p-53);
    for (double u : us) {
        const double want = -std::log1p(-u);
        ASSERT_NEAR(exponentialVariate(u), want, 2 * 0x1p-52 * want) << u;
    }
}

// cosSin gives what std::cos and std::sin give (its comment says: the same values).
TEST(Math, CosSinMatchesCosAndSin) {
    Rng rng(10, 10);
    for (int i = 0; i < 100000; ++i) {
        const double phi = (rng.uniform() - 0.5) * (i % 2 ? TwoPi : 1e4);
        const Vec2 cs = cosSin(phi);
        ASSERT_EQ(cs.x(), std::cos(phi)) << phi;
        ASSERT_EQ(cs.y(), std::sin(phi)) << phi;
    }
}

}  // namespace shvol
