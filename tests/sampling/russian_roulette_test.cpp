#include "shvol/sampling/russian_roulette.h"

#include <gtest/gtest.h>

namespace shvol {

// Below the threshold a path survives with probability m/θ and carries θ; above it, it always
// continues; θ = 1 is roulette on the throughput itself.
TEST(RussianRoulette, SurvivalFollowsTheThreshold) {
    for (double theta : {1e-6, 0.05, 0.25, 1.0})
        for (double m : {0.0, 1e-300, 1e-9, 1e-3, 0.1, 0.2499, 0.25, 0.6, 0.999, 1.0, 3.0}) {
            SCOPED_TRACE("theta " + std::to_string(theta) + " m " + std::to_string(m));
            const double q = rouletteSurvival(m, theta);
            EXPECT_GE(q, 0.0);
            EXPECT_LE(q, 1.0);
            if (m >= theta) {
                EXPECT_EQ(q, 1.0);
                continue;
            }
            EXPECT_DOUBLE_EQ(q, m / theta);
            if (m == 0) {
                EXPECT_EQ(q, 0.0);  // nothing to carry: the path ends
                continue;
            }
            // The survivor's largest component is θ.
            EXPECT_NEAR(m / q, theta, 1e-15 * theta);
            if (theta == 1.0) EXPECT_EQ(q, m);
        }
}

}  // namespace shvol
