// Normalised associated Legendre functions against boost::math::legendre_p evaluated in 50-digit
// binary floating point (boost::multiprecision), l ≤ 1000, including |z| within 1e-12 of 1.
#include "shvol/sh/legendre.h"

#include <gtest/gtest.h>

#include <boost/math/special_functions/gamma.hpp>
#include <boost/math/special_functions/legendre.hpp>
#include <boost/multiprecision/cpp_bin_float.hpp>
#include <cmath>
#include <vector>

namespace {
using shvol::sh::legendreNormalized;
using shvol::sh::triIndex;
using shvol::sh::triSize;
using Big = boost::multiprecision::cpp_bin_float_50;

// N_l^m(z) = √((2l+1)/4π · (l−m)!/(l+m)!) P_l^m(z), P with the Condon–Shortley phase (boost's).
double referenceN(int l, int m, double z) {
    const Big x(z);
    const Big p = boost::math::legendre_p(l, m, x);
    const Big ratio = boost::math::tgamma_ratio(Big(l - m + 1), Big(l + m + 1));
    const Big k = sqrt(Big(2 * l + 1) / (4 * boost::math::constants::pi<Big>()) * ratio);
    return static_cast<double>(k * p);
}

// Error model (legendre.h): rounding errors of the three-term recurrence grow like ε·l^{3/2}
// (a random walk of the linear growth caused by the double characteristic root at z = ±1).
constexpr double kEps = 2.220446049250313e-16;

const std::vector<double> kZ = {-1.0,   -1.0 + 1e-12, -0.999999,  -0.77,       -0.3,
                                -1e-12, 0.0,          1e-12,      0.1,         0.5,
                                0.9,    0.999,        1.0 - 1e-9, 1.0 - 1e-12, 1.0};

TEST(Legendre, LowOrderClosedForms) {
    const double z = 0.3, s = std::sqrt(1 - z * z), k = 1.0 / std::sqrt(4 * M_PI);
    EXPECT_NEAR(legendreNormalized(0, 0, z), k, 1e-16);
    EXPECT_NEAR(legendreNormalized(1, 0, z), std::sqrt(3.0) * k * z, 1e-16);
    EXPECT_NEAR(legendreNormalized(1, 1, z), -std::sqrt(1.5) * k * s, 1e-16);  // √(3/2)·P_1^1/…
    EXPECT_NEAR(legendreNormalized(2, 2, z), std::sqrt(5.0 / 24.0) * k * 3 * s * s, 1e-15);
}

TEST(Legendre, MatchesMultiprecisionReferenceUpTo1000) {
    const std::vector<int> ls = {2, 5, 10, 31, 60, 85, 86, 87, 100, 200, 500, 999, 1000};
    double worst = 0.0;
    for (int l : ls) {
        std::vector<double> all(triSize(l + 1));
        const std::vector<int> ms = {0, 1, 2, l / 3, l / 2, (9 * l) / 10, l - 1, l};
        for (double z : kZ) {
            legendreNormalized(l + 1, z, all.data());
            for (int m : ms) {
                if (m < 0 || m > l) continue;
                const double ref = referenceN(l, m, z);
                const double got = all[triIndex(l, m)];
                ASSERT_TRUE(std::isfinite(got)) << l << " " << m << " " << z;
                EXPECT_EQ(got, legendreNormalized(l, m, z)) << "single-value path " << l << m;
                // Oscillatory region: error relative to the envelope √((2l+1)/4π); the values
                // themselves must also be relatively exact when they are not near a root.
                const double env = std::sqrt((2.0 * l + 1.0) / (4 * M_PI));
                const double err = std::fabs(got - ref);
                const double tol = kEps * std::pow(l + 10.0, 1.5) * env;
                EXPECT_LE(err, tol) << "l=" << l << " m=" << m << " z=" << z << " ref=" << ref;
                if (ref != 0.0 && std::fabs(ref) >= 1e-300) worst = std::max(worst, err / env);
            }
        }
    }
    RecordProperty("worst_abs_error_over_envelope", std::to_string(worst));
}

// Near the poles, beyond the largest root, the functions are monotone in l and tiny for large m:
// here the extended-range recurrence must give every representable value to a small relative
// error, where a plain recurrence underflows its sectoral seed to zero.
TEST(Legendre, RelativeAccuracyNearPoles) {
    for (double z : {1.0 - 1e-12, -1.0 + 1e-12, 1.0 - 1e-9}) {
        for (int l : {100, 300, 1000}) {
            std::vector<double> all(triSize(l + 1));
            legendreNormalized(l + 1, z, all.data());
            for (int m : {1, 2, 5, 10, 20, 40, 60, 80, 100}) {
                if (m > l) continue;
                const double ref = referenceN(l, m, z);
                if (std::fabs(ref) < 1e-290) continue;  // below double's normal range
                const double got = all[triIndex(l, m)];
                EXPECT_NEAR(got / ref, 1.0, kEps * std::pow(l + 10.0, 1.5))
                    << l << " " << m << " " << z;
            }
        }
    }
}

TEST(Legendre, FiniteAndBoundedEverywhere) {
    const int n = 1001;
    std::vector<double> all(triSize(n));
    for (double z : kZ) {
        legendreNormalized(n, z, all.data());
        for (int l = 0; l < n; ++l) {
            const double bound = std::sqrt((2.0 * l + 1.0) / (4 * M_PI)) * (1 + 1e-10);
            for (int m = 0; m <= l; ++m) {
                const double v = all[triIndex(l, m)];
                ASSERT_TRUE(std::isfinite(v)) << l << " " << m << " " << z;
                ASSERT_LE(std::fabs(v), bound) << l << " " << m << " " << z;
            }
        }
        if (std::fabs(z) == 1.0)
            for (int l = 1; l < n; ++l) EXPECT_EQ(all[triIndex(l, 1)], 0.0);
    }
}

TEST(Legendre, EndpointValues) {
    // N_l^0(±1) = (±1)^l √((2l+1)/4π)
    for (int l = 0; l <= 1000; l += 37) {
        const double v = std::sqrt((2.0 * l + 1.0) / (4 * M_PI));
        const double tol = kEps * std::pow(l + 10.0, 1.5) * v;
        EXPECT_NEAR(legendreNormalized(l, 0, 1.0), v, tol);
        EXPECT_NEAR(legendreNormalized(l, 0, -1.0), (l % 2 ? -v : v), tol);
    }
}

}  // namespace
