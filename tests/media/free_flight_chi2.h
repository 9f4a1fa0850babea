#pragma once
// The χ² of free-flight distances against P(t < x) = 1 − e^{−τ(x)}, shared by the tracking
// tests (tracking_test.cpp, trilinear_depth_test.cpp).
#include <gtest/gtest.h>

#include <boost/math/special_functions/gamma.hpp>

#include <algorithm>
#include <cmath>
#include <ostream>
#include <vector>

#include "shvol/media/tracking.h"

namespace shvol::test {

/// The χ² of free-flight distances: its statistic, degrees of freedom and p-value.
struct FreeFlightChi2 {
    double statistic = 0;
    int dof = 0;
    double pValue = 0;
    /// Whether the test passes as one of a family of `numTests` at α = 0.01 (Šidák, as
    /// chi2TestSphere).
    bool passes(int numTests) const { return pValue > 1 - std::pow(1 - 0.01, 1.0 / numTests); }
};

inline std::ostream& operator<<(std::ostream& os, const FreeFlightChi2& r) {
    return os << "chi2 " << r.statistic << ", dof " << r.dof << ", p " << r.pValue;
}

/// χ² over 20 equal-probability bins of u = (1 − e^{−τ(t)}) / (1 − e^{−τ(tEnd)}) for the n
/// distances t = flight(i), each in [0, tEnd) or NoCollision, plus a cell for the escapes
/// (probability e^{−τ(tEnd)}): pooled with the last bin when it expects fewer than 5, left out
/// where its probability is 0 (an escape then fails the test).
template <typename Tau, typename Flight>
FreeFlightChi2 freeFlightChi2(int n, double tEnd, const Tau& tau, Flight&& flight) {
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
    if (expected[bins] == 0) {
        EXPECT_EQ(observed[bins], 0) << "escapes where e^{-tau(tEnd)} = 0";
        observed.pop_back(), expected.pop_back();
    } else if (expected[bins] < 5) {
        observed[bins - 1] += observed[bins], expected[bins - 1] += expected[bins];
        observed.pop_back(), expected.pop_back();
    }
    FreeFlightChi2 r;
    for (size_t b = 0; b < observed.size(); ++b)
        r.statistic += (observed[b] - expected[b]) * (observed[b] - expected[b]) / expected[b];
    r.dof = int(observed.size()) - 1;
    r.pValue = boost::math::gamma_q(0.5 * r.dof, 0.5 * r.statistic);
    return r;
}

}  // namespace shvol::test
