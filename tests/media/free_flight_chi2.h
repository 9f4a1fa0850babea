#pragma once
// The χ² of free-flight distances against P(t < x) = 1 − e^{−τ(x)}, shared by the tracking
// tests (homogeneous_medium_test.cpp, tracking_test.cpp, trilinear_depth_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "shvol/media/tracking.h"
#include "shvol/sampling/chi2.h"

namespace shvol::test {

/// χ² over 20 equal-probability bins of u = (1 − e^{−τ(t)}) / (1 − e^{−τ(tEnd)}) for the n
/// distances t = flight(i), each in [0, tEnd) or NoCollision, plus a cell for the escapes
/// (probability e^{−τ(tEnd)}), by chi2TestCounts (pooling below 5; a test of a family of
/// `numTests`, α = 0.01 with Šidák). Where e^{−τ(tEnd)} = 0 an escape fails the test.
template <typename Tau, typename Flight>
Chi2Result freeFlightChi2(int n, double tEnd, const Tau& tau, Flight&& flight, int numTests) {
    const int bins = 20;
    const double escape = std::exp(-tau(tEnd));
    std::vector<double> observed(bins + 1, 0), expected(bins + 1, n * (1 - escape) / bins);
    expected[bins] = n * escape;
    for (int i = 0; i < n; ++i) {
        const double t = flight(i);
        if (t == NoCollision) {
            ++observed[bins];
            continue;
        }
        EXPECT_GE(t, 0);
        EXPECT_LT(t, tEnd);
        const double u = (1 - std::exp(-tau(t))) / (1 - escape);  // ∈ [0, 1)
        ++observed[std::clamp(int(u * bins), 0, bins - 1)];
    }
    Chi2Options opt;
    opt.numTests = numTests;
    return chi2TestCounts(observed, expected, opt, [&](size_t b) {
        return b == size_t(bins) ? std::string("escapes") : "bin " + std::to_string(b) + " of u";
    });
}

}  // namespace shvol::test
