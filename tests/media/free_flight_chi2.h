#pragma once
// The χ² of free-flight distances against P(t < x) = 1 − e^{−τ(x)}, shared by the tracking
// tests (tracking_test.cpp, trilinear_depth_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "shvol/media/tracking.h"

namespace shvol::test {

/// χ² over 20 equal-probability bins of u = (1 − e^{−τ(t)}) / (1 − e^{−τ(tEnd)}) for the n
/// distances t = flight(i), each in [0, tEnd) or NoCollision, plus a cell for the escapes
/// (probability e^{−τ(tEnd)}); where that probability is 0 the cell is left out and an escape
/// fails the test. Degrees of freedom: 20 with the escape cell, 19 without.
template <typename Tau, typename Flight>
double freeFlightChi2(int n, double tEnd, const Tau& tau, Flight&& flight) {
    const int bins = 20;
    const double escape = std::exp(-tau(tEnd));
    std::vector<int> hist(bins + 1, 0);
    for (int i = 0; i < n; ++i) {
        const double t = flight(i);
        if (t == NoCollision) {
            ++hist[bins];
            continue;
        }
        EXPECT_GE(t, 0);
        EXPECT_LT(t, tEnd);
        const double u = (1 - std::exp(-tau(t))) / (1 - escape);  // ∈ [0, 1)
        ++hist[std::clamp(int(u * bins), 0, bins - 1)];
    }
    double chi2 = 0;
    for (int b = 0; b <= bins; ++b) {
        const double expected = n * (b < bins ? (1 - escape) / bins : escape);
        if (expected > 0)
            chi2 += (hist[b] - expected) * (hist[b] - expected) / expected;
        else
            EXPECT_EQ(hist[b], 0) << "escapes where e^{-tau(tEnd)} = 0";
    }
    return chi2;
}

}  // namespace shvol::test
