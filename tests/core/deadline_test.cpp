#include "shvol/core/deadline.h"

#include <gtest/gtest.h>

#include <cmath>

namespace shvol {

namespace {

using Clock = std::chrono::steady_clock;

/// Seconds from `start` until d.passed(), polled; +inf if it has not passed within `bound` s.
double secondsUntilPassed(const Deadline& d, Clock::time_point start, double bound) {
    while (!d.passed()) {
        if (std::chrono::duration<double>(Clock::now() - start).count() > bound) return INFINITY;
        std::this_thread::sleep_for(std::chrono::microseconds(100));
    }
    return std::chrono::duration<double>(Clock::now() - start).count();
}

}  // namespace

// Not before its time, and then (within a generous bound: a loaded host may wake it late).
TEST(Deadline, PassesAtItsTimeAndNotBefore) {
    const Clock::time_point start = Clock::now();
    const Deadline d(start, 0.02);
    const double at = secondsUntilPassed(d, start, 30);
    EXPECT_GE(at, 0.02);
    EXPECT_LT(at, 30);
}

// A limit that came before the deadline was made passes at once.
TEST(Deadline, ALimitInThePastPasses) {
    const Clock::time_point start = Clock::now() - std::chrono::seconds(2);
    const Deadline d(start, 1);
    EXPECT_LT(secondsUntilPassed(d, Clock::now(), 30), 30);
}

// No limit (0, negative, NaN, +inf) never passes; a far one is not waited for by the destructor
// (the test would hang until ctest's timeout).
TEST(Deadline, NoLimitNeverPasses) {
    for (const double seconds : {0.0, -1.0, double(NAN), double(INFINITY), 1e9, 1e300}) {
        const Deadline d(Clock::now(), seconds);
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
        EXPECT_FALSE(d.passed()) << seconds;
    }
}

}  // namespace shvol
