#include "shvol/core/ray.h"

#include <gtest/gtest.h>

#include <vector>

#include "shvol/core/rng.h"

namespace shvol {

TEST(IntersectBox, HitAndMiss) {
    Ray r{{-5, 0.5, 0.5}, {1, 0, 0}};
    Interval iv = intersectBox(r, {0, 0, 0}, {1, 1, 1}, 1e30);
    EXPECT_DOUBLE_EQ(iv.t0, 5);
    EXPECT_DOUBLE_EQ(iv.t1, 6);
    Ray miss{{-5, 2, 0.5}, {1, 0, 0}};
    EXPECT_TRUE(intersectBox(miss, {0, 0, 0}, {1, 1, 1}, 1e30).empty());
}

TEST(IntersectBox, OriginInsideIsClippedToZero) {
    Ray r{{0.5, 0.5, 0.5}, Vec3(1, 1, 0).normalized()};
    Interval iv = intersectBox(r, {0, 0, 0}, {1, 1, 1}, 1e30);
    EXPECT_EQ(iv.t0, 0);
    EXPECT_NEAR(iv.t1, std::sqrt(0.5), 1e-12);
}

// Bounds3: all of space by default (every ray meets it), an inverted box is empty (no ray meets
// it, though the slab test alone would accept one), and a box is met only within [0, tMax].
TEST(Bounds3, EverywhereEmptyAndBox) {
    const Ray r{{0, 0, -5}, {0, 0, 1}};
    EXPECT_TRUE(Bounds3{}.isEverywhere());
    EXPECT_TRUE(Bounds3{}.hits(r, 1));
    const Bounds3 none{Vec3::Constant(INFINITY), Vec3::Constant(-INFINITY)};
    EXPECT_TRUE(none.empty());
    EXPECT_FALSE(none.hits(r, INFINITY));
    const Bounds3 box{Vec3(-1, -1, -1), Vec3(1, 1, 1)};
    EXPECT_FALSE(box.empty() || box.isEverywhere());
    EXPECT_TRUE(box.hits(r, 4.5));
    EXPECT_FALSE(box.hits(r, 3.5));
    EXPECT_FALSE(box.hits(Ray{{3, 0, -5}, {0, 0, 1}}, INFINITY));
}

// hits() answers rays from inside the box without the slab test: the same answer as the slab
// test (the slow reference) for every pairing of origins inside, on faces, edges and corners and
// outside with directions along the axes (zero components of either sign), random ones and NaN,
// for tMax of 0, negative, finite, infinite and NaN.
TEST(Bounds3, HitsFromInsideAgreesWithTheSlabTest) {
    const Bounds3 box{Vec3(-1, 0, 2), Vec3(1, 0.5, 3)};
    Rng rng(6, 6);
    std::vector<Vec3> origins = {box.lo,          box.hi,           Vec3(1, 0.25, 2.5),
                                 Vec3(0, 0.5, 3), Vec3(-1, 0, 2.5), Vec3(2, 0.25, 2.5)};
    std::vector<Vec3> dirs = {Vec3(1, 0, 0),       Vec3(-1, 0, 0),     Vec3(0, -1, 0),
                              Vec3(0, 0, 1),       Vec3(-0.0, 0, 1),   Vec3(0, -0.0, -1),
                              Vec3(-0.0, -0.0, 1), Vec3::Constant(NAN)};
    for (int i = 0; i < 300; ++i) {
        origins.push_back(
            box.lo + (box.hi - box.lo)
                         .cwiseProduct(Vec3(rng.uniform(), rng.uniform(), rng.uniform()) * 1.4 -
                                       Vec3::Constant(0.2)));
        dirs.push_back(sphericalDirection2Pi(2 * rng.uniform() - 1, rng.uniform()));
    }
    int inside = 0;
    for (const Vec3& o : origins)
        for (const Vec3& d : dirs)
            for (double tMax : {0.0, -1.0, 0.3, 5.0, double(INFINITY), double(NAN)}) {
                const Ray r{o, d};
                ASSERT_EQ(box.hits(r, tMax), !intersectBox(r, box.lo, box.hi, tMax).empty())
                    << o.transpose() << " | " << d.transpose() << " | " << tMax;
                inside +=
                    (o.array() >= box.lo.array()).all() && (o.array() <= box.hi.array()).all();
            }
    EXPECT_GT(inside, 1000);  // both branches were taken
    // Along a face, with either sign of zero across it: inside the closed box.
    for (double zero : {0.0, -0.0}) {
        EXPECT_FALSE(intersectBox(Ray{box.lo, Vec3(zero, 0, 1)}, box.lo, box.hi, 5).empty());
        EXPECT_FALSE(intersectBox(Ray{box.hi, Vec3(zero, 0, -1)}, box.lo, box.hi, 5).empty());
        EXPECT_TRUE(
            intersectBox(Ray{Vec3(1.5, 0, 2), Vec3(zero, 0, 1)}, box.lo, box.hi, 5).empty());
    }
}

TEST(IntersectSphere, ChordLength) {
    Ray r{{0, 0, -10}, {0, 0, 1}};
    Interval iv = intersectSphere(r, {0, 0, 0}, 2, 1e30);
    EXPECT_NEAR(iv.t0, 8, 1e-12);
    EXPECT_NEAR(iv.t1, 12, 1e-12);
    Ray inside{{0, 0, 0}, {1, 0, 0}};
    iv = intersectSphere(inside, {0, 0, 0}, 2, 1e30);
    EXPECT_EQ(iv.t0, 0);
    EXPECT_NEAR(iv.t1, 2, 1e-12);
}

TEST(Frame, IsOrthonormalForAllHemispheres) {
    for (Vec3 n : {Vec3(0, 0, 1), Vec3(0, 0, -1), Vec3(1, 2, 3).normalized(),
                   Vec3(-1e-9, 0, -1).normalized(), Vec3(0.3, -0.9, 0.1).normalized()}) {
        Frame f(n);
        EXPECT_NEAR(f.s.dot(f.t), 0, 1e-12);
        EXPECT_NEAR(f.s.dot(f.n), 0, 1e-12);
        EXPECT_NEAR(f.s.norm(), 1, 1e-12);
        EXPECT_NEAR(f.t.norm(), 1, 1e-12);
        EXPECT_NEAR((f.toWorld(f.toLocal(Vec3(0.2, 0.5, -0.7))) - Vec3(0.2, 0.5, -0.7)).norm(), 0,
                    1e-12);
        EXPECT_NEAR(f.s.cross(f.t).dot(f.n), 1, 1e-12);  // right-handed
    }
}

// The frame of a surface's tangent: x along the tangent's projection, at any angle to the normal
// and whatever the sign of n_z (Frame(n) alone turns by up to 90° where n_z changes sign).
TEST(Frame, FollowsTheTangentItIsGiven) {
    const Vec3 tangent(1, 0.2, 0.3);
    for (Vec3 n : {Vec3(0.6, 0.8, 1e-17), Vec3(0.6, 0.8, -1e-17), Vec3(0, 0, 1), Vec3(0, 0, -1),
                   Vec3(-0.3, 0.1, 0.9).normalized()}) {
        const Frame f(n, tangent);
        // s lies in the plane of n and the tangent, on the tangent's side, ⟂ n.
        EXPECT_NEAR(f.s.dot(n.cross(tangent)), 0, 1e-12) << n.transpose();
        EXPECT_GT(f.s.dot(tangent), 0) << n.transpose();
        EXPECT_NEAR(f.s.dot(f.n), 0, 1e-12);
        EXPECT_NEAR(f.t.norm(), 1, 1e-12);
        EXPECT_NEAR(f.s.cross(f.t).dot(f.n), 1, 1e-12);  // right-handed
    }
    // The two normals either side of z = 0 give (nearly) one frame.
    const Frame a(Vec3(0.6, 0.8, 1e-17), tangent), b(Vec3(0.6, 0.8, -1e-17), tangent);
    EXPECT_NEAR((a.s - b.s).norm(), 0, 1e-12);
    // A tangent 10⁻⁵ rad from the normal (above the threshold): still exactly ⟂ n.
    const Vec3 nz(0, 0.6, 0.8), near = (nz + Vec3(1e-5, 0, 0)).normalized();
    const Frame f(nz, near);
    EXPECT_NEAR(f.s.dot(nz), 0, 1e-15);
    EXPECT_NEAR(f.s.x(), 1, 1e-9);
    // A tangent along the normal: the second one, if given (a box's faces ⟂ its x axis), else
    // Frame(n).
    const Frame second(Vec3(0, 0, 1), Vec3(0, 0, 2), Vec3(0, 1, 0.5));
    EXPECT_NEAR((second.s - Vec3(0, 1, 0)).norm(), 0, 1e-15);
    const Frame along(Vec3(0, 0, 1), Vec3(0, 0, 2)), plain(Vec3(0, 0, 1));
    EXPECT_EQ(along.s, plain.s);
    EXPECT_EQ(along.t, plain.t);
}

}  // namespace shvol
