#include "shvol/sh/sh_rotation.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "shvol/core/rng.h"
#include "shvol/sh/sh_basis.h"
#include "shvol/sh/sh_projection.h"

namespace {
using namespace shvol;
using namespace shvol::sh;

TEST(ShRotation, IdentityAndOrthogonality) {
    const int n = 20;
    ShRotation I(n, Eigen::Matrix3d::Identity());
    for (int l = 0; l < n; ++l)
        EXPECT_LT(
            (I.bands[l] - Eigen::MatrixXd::Identity(2 * l + 1, 2 * l + 1)).cwiseAbs().maxCoeff(),
            1e-15);
    Rng rng(5, 1);
    for (int t = 0; t < 10; ++t) {
        ShRotation R(n, uniformRandomRotation(rng));
        for (int l = 0; l < n; ++l) {
            const Eigen::MatrixXd E = R.bands[l] * R.bands[l].transpose() -
                                      Eigen::MatrixXd::Identity(2 * l + 1, 2 * l + 1);
            EXPECT_LT(E.cwiseAbs().maxCoeff(), 1e-13) << l;
        }
    }
}

TEST(ShRotation, Composition) {
    const int n = 16;
    Rng rng(6, 1);
    for (int t = 0; t < 10; ++t) {
        const Eigen::Matrix3d A = uniformRandomRotation(rng), B = uniformRandomRotation(rng);
        ShRotation RA(n, A), RB(n, B), RAB(n, A * B);
        for (int l = 0; l < n; ++l)
            EXPECT_LT((RA.bands[l] * RB.bands[l] - RAB.bands[l]).cwiseAbs().maxCoeff(), 1e-13);
    }
}

// f′(ω) = f(R⁻¹ω): project f′ by the exact quadrature and compare with R·f.
// Rotated coefficients against the rotated function projected again by quadrature (the slow
// reference), below and above l = 32, where the band matrices come from Euler angles and eigen
// decompositions instead of the Ivanic–Ruedenberg recurrence (every m, not only the zonal column
// of HighOrderStaysAccurate).
void agreesWithReprojection(int n, int rotations, double tolerance) {
    Rng rng(8, 1);
    const SphereQuadrature q = sphereQuadratureForOrder(n);
    for (int t = 0; t < rotations; ++t) {
        Eigen::VectorXd c(n * n);
        for (int i = 0; i < n * n; ++i) c[i] = 2 * rng.uniform() - 1;
        const Eigen::Matrix3d R = uniformRandomRotation(rng);
        const Eigen::Matrix3d Rinv = R.transpose();
        const Eigen::VectorXd ref = projectSH(
            n, [&](const Vec3& w) { return shReconstruct(n, c.data(), Rinv * w); }, q);
        const Eigen::VectorXd got = ShRotation(n, R).apply(c);
        EXPECT_LT((got - ref).cwiseAbs().maxCoeff(), tolerance) << "n " << n << ", rotation " << t;
    }
}

TEST(ShRotation, AgreesWithReprojection) {
    agreesWithReprojection(9, 5, 1e-12);
    agreesWithReprojection(48, 2, 1e-11);
}

// The convention pinned: a lobe around +z rotated by R peaks along R·ẑ, and the zonal fast path
// agrees with the full rotation.
TEST(ShRotation, ZonalLobePointsAlongRz) {
    const int n = 12;
    const double g = 0.8;
    Eigen::VectorXd p(n);
    for (int l = 0; l < n; ++l) p[l] = std::pow(g, l) * std::sqrt((2 * l + 1) / FourPi);  // HG
    const Eigen::Matrix3d R = rotationZYZ(0.3, 1.1, -0.4);
    const Vec3 d = R * Vec3(0, 0, 1);
    const Eigen::VectorXd full = ShRotation(n, R).apply(zonalToSH(p));
    const Eigen::VectorXd fast = rotateZonal(p, d);
    EXPECT_LT((full - fast).cwiseAbs().maxCoeff(), 1e-13);
    double peak = 0;
    for (int l = 0; l < n; ++l) peak += p[l] * std::sqrt((2 * l + 1) / FourPi);
    EXPECT_NEAR(shReconstruct(n, full.data(), d), peak, 1e-12);
    Rng rng(9, 1);
    for (int t = 0; t < 2000; ++t) {
        const Vec3 w = sphericalDirection(2 * rng.uniform() - 1, TwoPi * rng.uniform());
        EXPECT_LE(shReconstruct(n, full.data(), w), peak + 1e-12);
    }
    // A not-pointing-at-d check: the value at −d is the backward value of the lobe.
    double back = 0;
    for (int l = 0; l < n; ++l) back += p[l] * std::sqrt((2 * l + 1) / FourPi) * (l % 2 ? -1 : 1);
    EXPECT_NEAR(shReconstruct(n, full.data(), -d), back, 1e-12);
}

// The two constructions agree where IR is accurate, including rotations at and near gimbal lock.
TEST(ShRotation, EulerEigenAgreesWithIvanicRuedenberg) {
    const int n = 25;
    Rng rng(21, 1);
    std::vector<Eigen::Matrix3d> rs = {
        Eigen::Matrix3d::Identity(),       rotationZYZ(0.7, 0.0, 0.2),
        rotationZYZ(0.7, 1e-9, 0.2),       rotationZYZ(0.1, Pi, 0.0),
        rotationZYZ(-2.0, Pi - 1e-7, 1.3), rotationZYZ(0.0, 0.5 * Pi, 0.0)};
    for (int t = 0; t < 10; ++t) rs.push_back(uniformRandomRotation(rng));
    for (const Eigen::Matrix3d& R : rs) {
        const ShRotation a(n, R, RotationMethod::IvanicRuedenberg);
        const ShRotation b(n, R, RotationMethod::EulerEigen);
        for (int l = 0; l < n; ++l)
            EXPECT_LT((a.bands[l] - b.bands[l]).cwiseAbs().maxCoeff(), 1e-13) << l;
    }
}

// Beyond where IR loses accuracy (l ≥ 60), the default construction stays orthogonal,
// composes, and agrees with the addition theorem for a zonal lobe.
TEST(ShRotation, HighOrderStaysAccurate) {
    const int n = 121;
    Rng rng(22, 1);
    const Eigen::Matrix3d A = uniformRandomRotation(rng), B = uniformRandomRotation(rng);
    const ShRotation RA(n, A), RB(n, B), RAB(n, A * B);
    for (int l : {40, 60, 90, 120}) {
        const int k = 2 * l + 1;
        EXPECT_LT((RA.bands[l] * RA.bands[l].transpose() - Eigen::MatrixXd::Identity(k, k))
                      .cwiseAbs()
                      .maxCoeff(),
                  1e-12)
            << l;
        EXPECT_LT((RA.bands[l] * RB.bands[l] - RAB.bands[l]).cwiseAbs().maxCoeff(), 1e-12) << l;
    }
    Eigen::VectorXd p(n);
    for (int l = 0; l < n; ++l) p[l] = std::pow(0.95, l) * std::sqrt((2 * l + 1) / FourPi);
    const Eigen::VectorXd full = RA.apply(zonalToSH(p));
    const Eigen::VectorXd fast = rotateZonal(p, A * Vec3(0, 0, 1));
    EXPECT_LT((full - fast).cwiseAbs().maxCoeff(), 1e-12);
}

// The fast path for vectors against the band matrices, on random rotations and on those where
// Euler angles are ill-conditioned: identity, a pure twist, tiny tilts with a twist (what
// neighbouring radiance cache frames differ by), β = π, and β near π; for one vector, three
// (an RGB record, its sums done side by side) and five (more than are summed side by side).
void agreesWithShRotation(int count) {
    const int n = 16;
    const ShVectorRotation fast(n);
    Rng rng(31, 1);
    std::vector<Eigen::Matrix3d> rs = {
        Eigen::Matrix3d::Identity(),       rotationZYZ(0.7, 0.0, 0.2),
        rotationZYZ(0.7, 1e-9, 0.2),       rotationZYZ(2.5, 1e-14, -1.1),
        rotationZYZ(-2.0, 3e-4, 2.9),      rotationZYZ(0.1, Pi, 0.0),
        rotationZYZ(-2.0, Pi - 1e-7, 1.3), rotationZYZ(0.0, 0.5 * Pi, 0.0)};
    for (int t = 0; t < 20; ++t) rs.push_back(uniformRandomRotation(rng));
    Eigen::MatrixXd in(n * n, count);
    for (Eigen::Index i = 0; i < in.size(); ++i) in.data()[i] = 2 * rng.uniform() - 1;
    for (size_t r = 0; r < rs.size(); ++r) {
        const ShRotation slow(n, rs[r]);
        Eigen::MatrixXd out(n * n, count);
        fast.apply(rs[r], in.data(), out.data(), count);
        for (int j = 0; j < count; ++j)
            EXPECT_LT((out.col(j) - slow.apply(Eigen::VectorXd(in.col(j)))).cwiseAbs().maxCoeff(),
                      1e-12)
                << "rotation " << r << ", vector " << j << " of " << count;
        // In place, as the radiance cache uses it.
        Eigen::MatrixXd same = in;
        fast.apply(rs[r], same.data(), same.data(), count);
        EXPECT_EQ(same, out) << "rotation " << r;
    }
}

TEST(ShVectorRotation, AgreesWithShRotation) {
    for (int count : {1, 3, 5}) agreesWithShRotation(count);
}

// rotationTo's closed form against Eigen's shortest-arc quaternion, over directions that include
// the poles and directions within 1e-9 rad of -z, where 1/(1 + cos θ) would cancel.
TEST(ShRotation, RotationToIsTheShortestArc) {
    std::vector<Vec3> ds = {Vec3(0, 0, 1),        Vec3(1, 0, 0),         Vec3(0, -1, 0),
                            Vec3(1e-9, 0, -1),    Vec3(-3e-9, 2e-9, -1), Vec3(1e-300, 0, -1),
                            Vec3(0.3, -0.2, -0.9)};
    Rng rng(11, 3);
    for (int i = 0; i < 200; ++i)
        ds.push_back(2 * Vec3(rng.uniform(), rng.uniform(), rng.uniform()) - Vec3::Ones());
    for (const Vec3& d0 : ds) {
        const Vec3 d = d0.normalized();
        const Eigen::Matrix3d R = rotationTo(d0);
        EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 4e-15) << d.transpose();
        EXPECT_NEAR(R.determinant(), 1.0, 4e-15) << d.transpose();
        EXPECT_LT((R * Vec3(0, 0, 1) - d).norm(), 4e-15) << d.transpose();
        const Eigen::Matrix3d Q =
            Eigen::Quaterniond::FromTwoVectors(Vec3(0, 0, 1), d).toRotationMatrix();
        if (d.z() > -1 + 1e-6) EXPECT_LT((R - Q).norm(), 1e-13) << d.transpose();
    }
    EXPECT_LT((rotationTo(Vec3(0, 0, -2)) * Vec3(0, 0, 1) - Vec3(0, 0, -1)).norm(), 1e-15);
}

TEST(ShRotation, EulerZYZ) {
    const Eigen::Matrix3d R = rotationZYZ(0.0, 0.5 * Pi, 0.0);
    EXPECT_LT((R * Vec3(0, 0, 1) - Vec3(1, 0, 0)).norm(), 1e-15);
    EXPECT_LT((rotationTo(Vec3(0, 0, -1)) * Vec3(0, 0, 1) - Vec3(0, 0, -1)).norm(), 1e-15);
}

}  // namespace
