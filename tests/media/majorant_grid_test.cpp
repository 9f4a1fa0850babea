#include "shvol/media/majorant_grid.h"

#include <gtest/gtest.h>

#include "shvol/core/ray.h"
#include "shvol/core/rng.h"

namespace shvol {

TEST(MajorantGrid, ExpandMarksOverlappingCells) {
    MajorantGrid g(Vec3(0, 0, 0), Vec3(8, 8, 8), Eigen::Vector3i(4, 4, 4));
    g.expand(Vec3(1.5, 1.5, 1.5), Vec3(2.5, 2.5, 2.5), 3.0);
    for (int z = 0; z < 4; ++z)
        for (int y = 0; y < 4; ++y)
            for (int x = 0; x < 4; ++x) {
                const bool in = x <= 1 && y <= 1 && z <= 1;
                EXPECT_EQ(g.cell(x, y, z), in ? 3.0 : 0.0) << x << y << z;
            }
    g.expand(Vec3(0, 0, 0), Vec3(0.1, 0.1, 0.1), 1.0);
    EXPECT_EQ(g.cell(0, 0, 0), 3.0);  // max, not overwrite
    EXPECT_EQ(g.maxValue(), 3.0);
}

// Bounds are kept in float, rounded outward (floatAtLeast, floatAtMost): a value that is no
// float still has its bounds on the right side.
TEST(MajorantGrid, BoundsRoundOutwardToFloat) {
    MajorantGrid g(Vec3(0, 0, 0), Vec3(2, 1, 1), Eigen::Vector3i(2, 1, 1));
    // The nearest floats of 0.7 and 0.1 lie below and above them: on the wrong side.
    g.expand(Vec3(0.2, 0.2, 0.2), Vec3(0.4, 0.4, 0.4), 0.7);
    g.setMinimum({0.1, 0.0});
    EXPECT_GE(g.cell(0, 0, 0), 0.7);
    EXPECT_EQ(g.cell(0, 0, 0), double(floatAtLeast(0.7)));
    EXPECT_EQ(g.maxValue(), double(floatAtLeast(0.7)));
    int dense = 0;  // segments through the cell with density: the walk must meet it once
    g.traverse(Vec3(-1, 0.5, 0.5), Vec3(1, 0, 0), 0, 10, [&](double, double, double m, double mn) {
        if (m > 0) {
            ++dense;
            EXPECT_TRUE(mn <= 0.1 && mn > 0.0999999) << mn;
        }
        return true;
    });
    EXPECT_EQ(dense, 1);
}

// Segments must tile the clipped ray interval in order, and each segment's majorant must be the
// value of the cell containing every point of it (checked at random points).
TEST(MajorantGrid, TraversalMatchesBruteForce) {
    const Eigen::Vector3i res(5, 3, 7);
    MajorantGrid g(Vec3(-1, -2, 0), Vec3(4, 1, 7), res);
    Rng rng(5, 5);
    for (int z = 0; z < res.z(); ++z)
        for (int y = 0; y < res.y(); ++y)
            for (int x = 0; x < res.x(); ++x) {
                const Vec3 lo = Vec3(-1 + x, -2 + y, z) + Vec3::Constant(0.25);
                g.expand(lo, lo + Vec3::Constant(0.5), 1 + rng.uniform());
            }
    auto cellAt = [&](const Vec3& p) {
        const Vec3 q = p - Vec3(-1, -2, 0);
        return g.cell(std::clamp(int(std::floor(q.x())), 0, 4),
                      std::clamp(int(std::floor(q.y())), 0, 2),
                      std::clamp(int(std::floor(q.z())), 0, 6));
    };
    for (int i = 0; i < 2000; ++i) {
        const Vec3 o(-3 + 9 * rng.uniform(), -4 + 7 * rng.uniform(), -2 + 11 * rng.uniform());
        Vec3 d = Vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5);
        if (i % 10 == 0) d = Vec3(1, 0, 0) * (i % 20 == 0 ? 1 : -1);  // axis-parallel rays
        d.normalize();
        const Interval box = intersectBox(Ray{o, d}, g.lower(), g.upper(), 100);
        double prev = NAN, first = NAN, covered = 0;
        g.traverse(o, d, 0, 100, [&](double t0, double t1, double m, double) {
            EXPECT_LT(t0, t1);
            if (std::isnan(first)) first = t0;
            if (!std::isnan(prev)) EXPECT_NEAR(t0, prev, 1e-9);
            prev = t1;
            covered += t1 - t0;
            for (double f : {0.1, 0.5, 0.9})
                EXPECT_EQ(m, cellAt(o + (t0 + f * (t1 - t0)) * d)) << "ray " << i;
            // ... and up to 10⁻⁷ from either end: a walk whose boundaries were all shifted by
            // a little (under 10% of a segment) passed the points above (helper 118).
            if (t1 - t0 > 3e-7)
                for (double t : {t0 + 1e-7, t1 - 1e-7})
                    EXPECT_EQ(m, cellAt(o + t * d)) << "ray " << i << " at " << t;
            return true;
        });
        if (box.empty()) {
            EXPECT_EQ(covered, 0) << "ray " << i;
        } else {
            EXPECT_NEAR(first, box.t0, 1e-9) << "ray " << i;
            EXPECT_NEAR(prev, box.t1, 1e-9) << "ray " << i;
            EXPECT_NEAR(covered, box.t1 - box.t0, 1e-9) << "ray " << i;
        }
    }
}

TEST(MajorantGrid, VisitorCanStopTheWalk) {
    MajorantGrid g(Vec3(0, 0, 0), Vec3(4, 1, 1), Eigen::Vector3i(4, 1, 1));
    int visits = 0;
    g.traverse(Vec3(-1, 0.5, 0.5), Vec3(1, 0, 0), 0, 100, [&](double, double, double, double) {
        ++visits;
        return visits < 2;
    });
    EXPECT_EQ(visits, 2);
}

// A coarsened grid holds what expand() gives a grid built directly with cells twice as large
// (aligned with the fine cells, an odd resolution rounding up), over the fine grid's box: its
// last cells reach beyond it, and no walk goes there.
TEST(MajorantGrid, CoarsenedEqualsDirectBuild) {
    const Vec3 lo(-1, -2, 0);
    const Eigen::Vector3i res(5, 3, 7), half(3, 2, 4);
    MajorantGrid fine(lo, lo + res.cast<double>(), res);
    MajorantGrid direct(lo, lo + 2 * half.cast<double>(), half);
    Rng rng(8, 1);
    for (int i = 0; i < 40; ++i) {
        const Vec3 a = lo + Vec3(5 * rng.uniform(), 3 * rng.uniform(), 7 * rng.uniform());
        const Vec3 b = a + 1.5 * Vec3(rng.uniform(), rng.uniform(), rng.uniform());
        const double v = rng.uniform();
        fine.expand(a, b, v);
        direct.expand(a, b, v);
    }
    const MajorantGrid coarse = fine.coarsened();
    ASSERT_EQ(coarse.resolution(), half);
    EXPECT_EQ(coarse.upper(), fine.upper());
    EXPECT_NE(coarse.upper(), direct.upper());
    double tEnd = 0;
    coarse.traverse(lo - Vec3(1, 1, 1), Vec3(1, 1, 1), 0, INFINITY,
                    [&](double, double t1, double, double) { return tEnd = t1, true; });
    EXPECT_DOUBLE_EQ(tEnd, 4);  // out through y = lo.y + 3, not lo.y + 4 (the coarse cells' t = 5)
    for (int z = 0; z < half.z(); ++z)
        for (int y = 0; y < half.y(); ++y)
            for (int x = 0; x < half.x(); ++x)
                EXPECT_EQ(coarse.cell(x, y, z), direct.cell(x, y, z)) << x << y << z;
}

// The cost of a line is segmentCost per cell crossed plus scale·∫ cellMax dt, t measured in
// units of the direction's length.
TEST(MajorantGrid, TrackingCostCountsSegmentsAndOpticalDepth) {
    MajorantGrid g(Vec3(0, 0, 0), Vec3(4, 1, 1), Eigen::Vector3i(4, 1, 1));
    for (int x = 1; x < 4; ++x) g.expand(Vec3(x + 0.4, 0.4, 0.4), Vec3(x + 0.6, 0.6, 0.6), x);
    // Along x with |d| = 2: four segments of Δt = 0.5 with majorants 0, 1, 2, 3.
    const std::vector<std::pair<Vec3, Vec3>> line{{Vec3(0.5, 0.5, 0.5), Vec3(2, 0, 0)}};
    EXPECT_NEAR(g.trackingCost(line, 3.0, 0.25), 4 * 0.25 + 3.0 * 6 * 0.5, 1e-12);
    // A line missing the grid costs nothing; the mean is over all lines.
    const std::vector<std::pair<Vec3, Vec3>> two{line[0], {Vec3(0.5, 5, 0.5), Vec3(1, 0, 0)}};
    EXPECT_NEAR(g.trackingCost(two, 3.0, 0.25), 0.5 * (1 + 9), 1e-12);
}

}  // namespace shvol
