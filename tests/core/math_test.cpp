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

// floatAtLeast and floatAtMost give the nearest float on their side of any double (the next float
// towards the value is past it), and a float itself.
TEST(Math, FloatAtLeastAndAtMostRoundOutward) {
    Rng rng(3, 1);
    for (int i = 0; i < 100000; ++i) {
        const double v = std::ldexp(rng.uniform(), int(rng.uniform() * 60) - 30);
        const float up = floatAtLeast(v), down = floatAtMost(v);
        ASSERT_GE(double(up), v) << v;
        ASSERT_LT(double(std::nextafter(up, -INFINITY)), v) << v;
        ASSERT_LE(double(down), v) << v;
        ASSERT_GT(double(std::nextafter(down, INFINITY)), v) << v;
        const float f = float(v);
        ASSERT_EQ(floatAtLeast(f), f);
        ASSERT_EQ(floatAtMost(f), f);
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

// cosSin2Pi(u) is within 3·10⁻¹⁶ of cos 2πu and sin 2πu evaluated in long double, at the quarter
// and eighth turns (where the quadrant changes), next to them, at the ends of [0, 1] and at random
// u of the samplers (multiples of 2⁻⁵³), and for u outside [0, 1]; it is a point of the unit
// circle.
TEST(Math, CosSin2PiMatchesLongDouble) {
    const long double twoPi = 6.283185307179586476925286766559L;
    std::vector<double> us = {0.0, 1.0, 0.5, 1 - 0x1p-53, 0x1p-53, -0.3, 2.75, 1e6 + 0.1};
    for (int k = 0; k <= 8; ++k)
        for (double u : {k / 8.0, std::nextafter(k / 8.0, -1.0), std::nextafter(k / 8.0, 2.0)})
            us.push_back(u);
    Rng rng(11, 11);
    for (int i = 0; i < 200000; ++i) us.push_back(rng.uniform());
    for (double u : us) {
        const Vec2 cs = cosSin2Pi(u);
        // The whole turns taken off first (exactly), or the reference loses digits at large u.
        const long double a = twoPi * ((long double)u - std::floor((long double)u));
        ASSERT_NEAR(cs.x(), double(std::cos(a)), 3e-16) << u;
        ASSERT_NEAR(cs.y(), double(std::sin(a)), 3e-16) << u;
        ASSERT_NEAR(cs.squaredNorm(), 1.0, 1e-15) << u;
    }
    EXPECT_EQ(cosSin2Pi(0.25), Vec2(0, 1));  // quarter turns are exact
    EXPECT_EQ(cosSin2Pi(0.5), Vec2(-1, 0));
}

}  // namespace shvol
