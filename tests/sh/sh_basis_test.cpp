#include "shvol/sh/sh_basis.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "shvol/core/rng.h"
#include "shvol/sh/legendre.h"
#include "shvol/sh/sh_projection.h"

namespace {
using namespace shvol;
using namespace shvol::sh;

Vec3 randomDir(Rng& rng) {
    const double z = 2 * rng.uniform() - 1, phi = TwoPi * rng.uniform();
    return sphericalDirection(z, phi);
}

// The l ≤ 2 table of sh-blog-irradiance-notes.md, transcribed literally (signs included).
TEST(ShBasis, ReproducesBlogTable) {
    Rng rng(7, 1);
    for (int t = 0; t < 100; ++t) {
        const Vec3 w = randomDir(rng);
        const double x = w.x(), y = w.y(), z = w.z(), pi = M_PI;
        const double ref[9] = {std::sqrt(1 / (4 * pi)),
                               -std::sqrt(3 / (4 * pi)) * y,
                               std::sqrt(3 / (4 * pi)) * z,
                               -std::sqrt(3 / (4 * pi)) * x,
                               std::sqrt(15 / (4 * pi)) * x * y,
                               -std::sqrt(15 / (4 * pi)) * y * z,
                               std::sqrt(5 / (16 * pi)) * (3 * z * z - 1),
                               -std::sqrt(15 / (4 * pi)) * z * x,
                               std::sqrt(15 / (16 * pi)) * (x * x - y * y)};
        double fast[9], rec[9];
        shEvalFast(3, w, fast);
        shEvalRecurrence(3, w, rec);
        for (int i = 0; i < 9; ++i) {
            EXPECT_NEAR(fast[i], ref[i], 1e-15) << i;
            EXPECT_NEAR(rec[i], ref[i], 1e-15) << i;
        }
    }
}

TEST(ShBasis, FastPathMatchesRecurrence) {
    Rng rng(11, 1);
    for (int t = 0; t < 1000; ++t) {
        Vec3 w = randomDir(rng);
        if (t == 0) w = Vec3(0, 0, 1);
        if (t == 1) w = Vec3(0, 0, -1);
        if (t == 2) w = Vec3(1, 0, 0);
        for (int n = 1; n <= kShFastMaxOrder; ++n) {
            double fast[25], rec[25];
            shEvalFast(n, w, fast);
            shEvalRecurrence(n, w, rec);
            for (int i = 0; i < n * n; ++i) EXPECT_NEAR(fast[i], rec[i], 2e-15) << n << " " << i;
        }
    }
}

TEST(ShBasis, SingleAndZonalMatchAll) {
    Rng rng(3, 1);
    const int n = 25;
    std::vector<double> y(n * n), zon(n);
    for (int t = 0; t < 20; ++t) {
        const Vec3 w = randomDir(rng);
        shEval(n, w, y.data());
        shEvalZonal(n, w.z(), zon.data());
        for (int l = 0; l < n; ++l) {
            EXPECT_NEAR(zon[l], y[shIndex(l, 0)], 1e-13);
            for (int m = -l; m <= l; ++m)
                EXPECT_NEAR(shEvalSingle(l, m, w), y[shIndex(l, m)], 1e-12) << l << " " << m;
        }
    }
}

TEST(ShBasis, ZAxisValuesAndHighOrderFinite) {
    const int n = 1000;
    std::vector<double> y(n * n);
    for (const Vec3& w :
         {Vec3(0, 0, 1), Vec3(0, 0, -1), Vec3(1e-12, 0, 1).normalized(), Vec3(0.6, 0.8, 0.0)}) {
        shEval(n, w, y.data());
        for (int i = 0; i < n * n; ++i) ASSERT_TRUE(std::isfinite(y[i])) << i;
    }
    shEval(n, Vec3(0, 0, 1), y.data());
    for (int l = 0; l < n; ++l)
        for (int m = -l; m <= l; ++m) {
            const double expect = m == 0 ? std::sqrt((2.0 * l + 1) / (4 * M_PI)) : 0.0;
            ASSERT_NEAR(y[shIndex(l, m)], expect, 1e-12 * (l + 1)) << l << " " << m;
        }
}

// Orthonormality ∫ y_i y_j dω = δ_ij by the exact product rule, to 1e-12.
TEST(ShBasis, OrthonormalOnTheSphere) {
    for (int n : {4, 12, 30}) {
        const SphereQuadrature q = sphereQuadratureForOrder(n);
        Eigen::MatrixXd Y(q.size(), n * n);
        Eigen::VectorXd w(q.size());
        int k = 0;
        for (size_t i = 0; i < q.z.size(); ++i)
            for (int j = 0; j < q.nphi; ++j, ++k) {
                Eigen::VectorXd y = shEval(n, q.direction(int(i), j));
                Y.row(k) = y.transpose();
                w[k] = q.weight(int(i));
            }
        const Eigen::MatrixXd G = Y.transpose() * w.asDiagonal() * Y;
        const double err = (G - Eigen::MatrixXd::Identity(n * n, n * n)).cwiseAbs().maxCoeff();
        EXPECT_LT(err, 1e-12) << "n=" << n;
    }
}

TEST(ShBasis, FlatIndex) {
    EXPECT_EQ(shIndex(0, 0), 0);
    EXPECT_EQ(shIndex(1, -1), 1);
    EXPECT_EQ(shIndex(2, 2), 8);
    for (int i = 0; i < 10000; ++i) {
        const int l = shBand(i);
        EXPECT_TRUE(l * l <= i && i < (l + 1) * (l + 1));
    }
}

}  // namespace
