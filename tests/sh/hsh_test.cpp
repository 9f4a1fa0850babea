#include "shvol/sh/hsh.h"

#include <gtest/gtest.h>

#include <boost/math/quadrature/tanh_sinh.hpp>
#include <cmath>
#include <vector>

#include "shvol/core/rng.h"
#include "shvol/sh/legendre.h"
#include "shvol/sh/sh_basis.h"

namespace {
using namespace shvol;
using namespace shvol::sh;

TEST(Hsh, OrthonormalOnTheHemisphere) {
    for (int n : {3, 10, 20}) {
        const SphereQuadrature q = hemisphereQuadrature(n, 2 * n);
        Eigen::MatrixXd Y(q.size(), n * n);
        Eigen::VectorXd w(q.size());
        int k = 0;
        for (size_t i = 0; i < q.z.size(); ++i)
            for (int j = 0; j < q.nphi; ++j, ++k) {
                Y.row(k) = hshEval(n, q.direction(int(i), j)).transpose();
                w[k] = q.weight(int(i));
            }
        const Eigen::MatrixXd G = Y.transpose() * w.asDiagonal() * Y;
        EXPECT_LT((G - Eigen::MatrixXd::Identity(n * n, n * n)).cwiseAbs().maxCoeff(), 1e-12) << n;
    }
}

// Gautron eq. 8 written out for l ≤ 2 with P from Appendix B (P_l^m(2z−1)) and eq. 9.
TEST(Hsh, MatchesEquation8) {
    const double pi = M_PI;
    for (double z : {0.0, 0.1, 0.5, 0.93, 1.0})
        for (double phi : {0.0, 0.7, 2.9, 5.5}) {
            const Vec3 w = sphericalDirection(z, phi);
            const double u = 2 * z - 1, s = std::sqrt(std::max(0.0, 1 - u * u));
            auto K = [&](int l, int m) {
                double r = 1;
                for (int k = l - m + 1; k <= l + m; ++k) r /= k;
                return std::sqrt((2 * l + 1) * r / (2 * pi));
            };
            const double r2 = std::sqrt(2.0);
            const double ref[9] = {K(0, 0),
                                   r2 * K(1, 1) * std::sin(phi) * (-s),
                                   K(1, 0) * u,
                                   r2 * K(1, 1) * std::cos(phi) * (-s),
                                   r2 * K(2, 2) * std::sin(2 * phi) * 3 * s * s,
                                   r2 * K(2, 1) * std::sin(phi) * (-3 * u * s),
                                   K(2, 0) * 0.5 * (3 * u * u - 1),
                                   r2 * K(2, 1) * std::cos(phi) * (-3 * u * s),
                                   r2 * K(2, 2) * std::cos(2 * phi) * 3 * s * s};
            double h[9];
            hshEval(3, w, h);
            for (int i = 0; i < 9; ++i)
                EXPECT_NEAR(h[i], ref[i], 1e-14) << z << " " << phi << " " << i;
        }
}

// Near the normal the terms with m ≠ 0 scale with s = √(1 − (2z − 1)²) = 2√(z(1 − z)), and z
// rounds the polar angle away (at θ = 10⁻⁹, z = 1 exactly): s must come from the direction's
// x and y, 1 − z = (x² + y²)/(1 + z). Reference: s = 2√(cos θ)·√2·sin(θ/2) from θ itself. From
// the rounded z, H_1^{±1} was 0 at θ = 10⁻⁹ and 0.76% off at 10⁻⁷.
TEST(Hsh, AccurateNearTheNormal) {
    for (double theta : {1e-9, 1e-7, 1e-5, 1e-3})
        for (double phi : {0.3, 4.0}) {
            const Vec3 w(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi),
                         std::cos(theta));
            const double s = 2 * std::sqrt(std::cos(theta)) * std::sqrt(2.0) * std::sin(theta / 2);
            const double K11 = std::sqrt(3 / (4 * M_PI)), r2 = std::sqrt(2.0);
            double h[4];
            hshEval(2, w, h);
            // H_1^{−1} and H_1^1: √2 K_1^1 (−s) sin φ and cos φ (MatchesEquation8).
            EXPECT_NEAR(h[1], -r2 * K11 * s * std::sin(phi), 1e-12 * r2 * K11 * s) << theta;
            EXPECT_NEAR(h[3], -r2 * K11 * s * std::cos(phi), 1e-12 * r2 * K11 * s) << theta;
        }
}

// C from its definition by an independent integrator (tanh–sinh on z ∈ [0, 1], which copes with
// the √z branch point of odd m at the horizon), φ integral analytic (2π for equal m).
TEST(Hsh, ConversionMatrixMatchesIndependentQuadrature) {
    const int nH = 5, nS = 9;
    const ShToHsh C(nH, nS);
    const Eigen::MatrixXd D = C.dense();
    boost::math::quadrature::tanh_sinh<double> ts;
    for (int l = 0; l < nH; ++l)
        for (int m = -l; m <= l; ++m)
            for (int lp = 0; lp < nS; ++lp)
                for (int mp = -lp; mp <= lp; ++mp) {
                    double ref = 0.0;
                    if (m == mp) {
                        const int am = std::abs(m);
                        auto f = [&](double z) {
                            return std::sqrt(2.0) * legendreNormalized(l, am, 2 * z - 1) *
                                   legendreNormalized(lp, am, z);
                        };
                        ref = TwoPi * ts.integrate(f, 0.0, 1.0);
                    }
                    EXPECT_NEAR(D(shIndex(l, m), shIndex(lp, mp)), ref, 1e-13)
                        << l << " " << m << " " << lp << " " << mp;
                }
    // The two entries quoted in the issue (the paper prints 0.71 and 0.41).
    const ShToHsh C3(3, 3);
    EXPECT_NEAR(C3.dense()(0, 0), std::sqrt(0.5), 1e-15);                         // (H_0^0, Y_0^0)
    EXPECT_NEAR(C3.dense()(0, 2), std::sqrt(3.0) / (2 * std::sqrt(2.0)), 1e-15);  // (H_0^0, Y_1^0)
    EXPECT_NEAR(C3.dense()(2, 0), 0.0, 1e-15);  // (H_1^0, Y_0^0): ∫(2z−1)dz = 0; printed 0.82
}

// hshRotateZ(φ) turns a function about the normal: h′ evaluated at R_z(φ)ω is h at ω, for every
// band and order; φ = 2π is the identity.
TEST(Hsh, RotationAboutTheNormal) {
    const int n = 6;
    std::vector<double> h(n * n), turned;
    for (int i = 0; i < n * n; ++i) h[i] = std::sin(1.3 * i + 0.4);
    for (double phi : {0.3, -2.1, 2 * Pi}) {
        turned = h;
        hshRotateZ(n, phi, turned.data());
        for (double z : {0.05, 0.5, 0.97})
            for (double az : {0.1, 2.5, 5.0})
                EXPECT_NEAR(hshReconstruct(n, turned.data(), sphericalDirection(z, az + phi)),
                            hshReconstruct(n, h.data(), sphericalDirection(z, az)), 1e-13)
                    << phi << " " << z << " " << az;
    }
    for (int i = 0; i < n * n; ++i) EXPECT_NEAR(turned[i], h[i], 1e-13);  // (after φ = 2π)
}

TEST(Hsh, ConversionRoundTripOfAnShFunctionRestricted) {
    // A zonal SH function of order 3 is a polynomial of degree 2 in z; on the hemisphere the m = 0
    // HSH of order 3 span the same polynomials (P_l(2z−1)), so toHsh reproduces it exactly.
    // (Not so for m ≠ 0: H_1^1 ∝ √(z(1−z)) cos φ while y_1^1 ∝ √(1−z²) cos φ.)
    const int n = 3;
    Eigen::VectorXd c = Eigen::VectorXd::Zero(n * n);
    for (int l = 0; l < n; ++l) c[shIndex(l, 0)] = std::cos(1.7 * l + 0.3);
    const ShToHsh C(n, n);
    const Eigen::VectorXd h = C.toHsh(c);
    for (double z : {0.05, 0.4, 0.99})
        for (double phi : {0.2, 3.0}) {
            const Vec3 w = sphericalDirection(z, phi);
            EXPECT_NEAR(hshReconstruct(n, h.data(), w), shReconstruct(n, c.data(), w), 1e-13);
        }
}

// HSH rotation through SH for rotations that keep the function above the horizon. The function:
// a smooth cap f(ω) = max(0, ω·a − cos 35°)³ with a at 20° from the normal, rotated by 15° about
// y (its support stays within 70° of the normal). h = order-6 HSH projection of f, f̃ = Σ h_i H_i.
// What the method computes, as nSh → ∞, is the HSH projection of f̃∘R⁻¹ (f̃ extended by zero
// below the horizon): the error against that must fall with nSh. Stated tolerance (measured,
// see validation/sh/results/hsh_rotation.csv): relative L2 error < 3e-3 at nSh = 24 and < 3e-4
// at nSh = 48. Against the projection of the exactly rotated f, the error cannot fall below the
// basis' own loss (HSH spaces are not closed under rotation); that is checked to stay < 5e-2.
TEST(Hsh, RotationThroughShKeepsFunctionsAboveTheHorizon) {
    const int nH = 6;
    const Vec3 a = sphericalDirection(std::cos(20 * Pi / 180), 0.4);
    const double c35 = std::cos(35 * Pi / 180);
    auto f = [&](const Vec3& w) { return std::pow(std::max(0.0, w.dot(a) - c35), 3); };
    const Eigen::Matrix3d R = rotationZYZ(0.0, 15 * Pi / 180, 0.0);
    const Eigen::Matrix3d Rinv = R.transpose();
    const SphereQuadrature q = hemisphereQuadrature(200, 400);
    const Eigen::VectorXd h = projectHSH(nH, f, q);
    const Eigen::VectorXd refTrue = projectHSH(
        nH, [&](const Vec3& w) { return f(Rinv * w); }, q);
    const Eigen::VectorXd refTrunc = projectHSH(
        nH, [&](const Vec3& w) { return hshReconstruct(nH, h.data(), Rinv * w); }, q);
    double prev = 1e9;
    for (int nS : {12, 24, 48}) {
        const Eigen::VectorXd got = hshRotate(ShToHsh(nH, nS), ShRotation(nS, R), h);
        const double err = (got - refTrunc).norm() / refTrunc.norm();
        const double errTrue = (got - refTrue).norm() / refTrue.norm();
        std::printf("nS=%d relative error %.3e (vs rotated f: %.3e)\n", nS, err, errTrue);
        EXPECT_LT(err, prev) << nS;
        if (nS == 24) EXPECT_LT(err, 3e-3);
        if (nS == 48) EXPECT_LT(err, 3e-4);
        EXPECT_LT(errTrue, 5e-2);
        prev = err;
    }
}

// HshRotation against its definition, h′ = h + C (D(R) − I) E h, evaluated by quadrature alone
// (none of its matrices: C, the SH rotation D, the horizon values v and lower-hemisphere
// integrals s): E h is the SH projection (2n bands) of f̃ = Σ h_i H_i held below the horizon at
// its value there; D E h the projection of (Σ (E h)_k Y_k)∘R⁻¹; C the HSH projection over the
// upper hemisphere. Upper-hemisphere integrals take z = u², Gauss–Legendre in u: an HSH function
// of odd m carries √z, which the substitution makes u, so that the products the integrals take
// (of equal m, the others vanish in φ) are smooth in u (in z, the quadrature converged as a
// power). Arbitrary coefficients and the cache test's field, at tilts about a skew axis.
TEST(Hsh, RotationForTheCacheMatchesItsDefinitionByQuadrature) {
    const int n = 6, nSh = 2 * n, nH = n * n, nY = nSh * nSh;
    struct Node {
        Vec3 w;
        double weight;
    };
    std::vector<Node> upper, lower, whole;
    const SphereQuadrature gu = sphereQuadrature(64, 1, 0.0, 1.0);  // (its z: nodes u in [0, 1])
    const int nphi = 64;
    for (size_t i = 0; i < gu.z.size(); ++i)
        for (int j = 0; j < nphi; ++j) {
            const double u = gu.z[i], phi = (j + 0.5) * TwoPi / nphi;
            upper.push_back({sphericalDirection(u * u, phi), gu.wz[i] * 2 * u * TwoPi / nphi});
        }
    const auto addNodes = [&](std::vector<Node>& out, const SphereQuadrature& q) {
        for (size_t i = 0; i < q.z.size(); ++i)
            for (int j = 0; j < q.nphi; ++j)
                out.push_back({q.direction(int(i), j), q.weight(int(i))});
    };
    addNodes(lower, sphereQuadrature(32, nphi, -1.0, 0.0));
    addNodes(whole, sphereQuadrature(32, nphi));
    const auto yOf = [&](const Vec3& w) { return shEval(nSh, w); };
    const Vec3 dir = Vec3(0.9, 0, 0.2).normalized();
    const SphereQuadrature fine = hemisphereQuadrature(96, 192);
    Eigen::VectorXd fieldH = projectHSH(
        n, [&](const Vec3& w) { return std::exp(3 * (w.dot(dir) - 1)); }, fine);
    Eigen::VectorXd randomH(nH);
    Rng rng(11, 2);
    for (int i = 0; i < nH; ++i) randomH[i] = rng.uniform() - 0.5;
    const HshRotation rotation(n);
    for (const Eigen::VectorXd& h : {fieldH, randomH})
        for (const double degrees : {2.0, 30.0, 120.0}) {
            const Eigen::Matrix3d R =
                Eigen::AngleAxisd(degrees * Pi / 180, Vec3(1, 0.3, -0.4).normalized())
                    .toRotationMatrix();
            const double atHorizon = hshReconstruct(n, h.data(), Vec3(1, 0, 0));
            Eigen::VectorXd e = Eigen::VectorXd::Zero(nY), De = Eigen::VectorXd::Zero(nY);
            for (const Node& q : upper) e += q.weight * hshReconstruct(n, h.data(), q.w) * yOf(q.w);
            for (const Node& q : lower) e += q.weight * atHorizon * yOf(q.w);
            for (const Node& q : whole) De += q.weight * yOf(R.transpose() * q.w).dot(e) * yOf(q.w);
            const Eigen::VectorXd d = De - e;
            Eigen::VectorXd expected = h;
            for (const Node& q : upper) expected += q.weight * yOf(q.w).dot(d) * hshEval(n, q.w);
            Eigen::VectorXd got(nH);
            rotation.apply(R, h.data(), got.data(), 1);
            EXPECT_LT((got - expected).norm(), 1e-12 * h.norm())
                << degrees << "°: " << (got - expected).norm() / h.norm();
        }
}

// HshRotation (what the radiance cache rotates records with) against the projection of the
// exactly rotated function, at order 6, for constant radiance and for e^{3(ω·d − 1)} with d at
// 26° and at 77° from the normal, rotated about x by 10⁻⁶ rad to 30°: exact for the constant,
// continuous at the identity (the error at 10⁻⁶ rad is the tilt's own effect), within the
// measured errors (hsh.h's table, with a margin of 1.5) and below those of the rotation through
// SH with the zero extension (hshRotate) at every tilt. The table is the method's own output,
// so its bound only guards the documented figures; that the method computes what hsh.h defines
// is RotationForTheCacheMatchesItsDefinitionByQuadrature's to check (helper 118).
TEST(Hsh, RotationForTheCacheIsContinuousAndCloserThanThroughSh) {
    const int n = 6;
    const SphereQuadrature fine = hemisphereQuadrature(96, 192);
    const HshRotation rotation(n);
    const Vec3 dirs[] = {Vec3(0.3, 0.1, 0.9).normalized(), Vec3(0.9, 0, 0.2).normalized()};
    const double degrees[] = {1e-6 * 180 / Pi, 2, 15, 30};
    // Measured relative L2 errors per field and tilt (hsh.h).
    const double measured[3][4] = {
        {1e-13, 1e-13, 1e-13, 1e-13}, {6.7e-8, 0.0023, 0.016, 0.031}, {4.4e-7, 0.015, 0.12, 0.21}};
    for (int field = 0; field < 3; ++field) {
        auto f = [&](const Vec3& w) {
            return field == 0 ? 1.0 : std::exp(3 * (w.dot(dirs[field - 1]) - 1));
        };
        const Eigen::VectorXd h = projectHSH(n, f, fine);
        Eigen::VectorXd same(n * n);
        rotation.apply(Eigen::Matrix3d::Identity(), h.data(), same.data(), 1);
        EXPECT_LT((same - h).norm(), 1e-14 * h.norm()) << field;
        for (int k = 0; k < 4; ++k) {
            const double a = degrees[k] * Pi / 180;
            Eigen::Matrix3d R;
            R << 1, 0, 0, 0, std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a);
            const Eigen::VectorXd truth = projectHSH(
                n, [&](const Vec3& w) { return f(R.transpose() * w); }, fine);
            Eigen::VectorXd got(n * n);
            rotation.apply(R, h.data(), got.data(), 1);
            const Eigen::VectorXd throughSh = hshRotate(ShToHsh(n, 2 * n), ShRotation(2 * n, R), h);
            const double err = (got - truth).norm() / truth.norm();
            SCOPED_TRACE("field " + std::to_string(field) + ", " + std::to_string(degrees[k]) +
                         "°");
            EXPECT_LT(err, 1.5 * measured[field][k]);
            EXPECT_LT(err, (throughSh - truth).norm() / truth.norm());
        }
    }
}

}  // namespace
