#include "shvol/core/math.h"

#include <gtest/gtest.h>

#include <cmath>

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

}  // namespace shvol
