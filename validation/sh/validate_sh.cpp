// validate_sh: the experiments behind validation/sh/README.md. Writes CSV and markdown tables to
// validation/sh/results/ (or to argv[1]). Run through validation/sh/run.sh.
#include <Eigen/Geometry>
#include <boost/math/quadrature/tanh_sinh.hpp>
#include <boost/math/special_functions/gamma.hpp>
#include <boost/math/special_functions/legendre.hpp>
#include <boost/multiprecision/cpp_bin_float.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <string>
#include <vector>
#include "../../tests/sh/legendre_reference.h"

#include "shvol/core/rng.h"
#include "shvol/sh/hsh.h"
#include "shvol/sh/irradiance.h"
#include "shvol/sh/legendre.h"
#include "shvol/sh/sh_basis.h"
#include "shvol/sh/sh_integrals.h"
#include "shvol/sh/sh_projection.h"
#include "shvol/sh/sh_rotation.h"

using namespace shvol;
using namespace shvol::sh;

namespace {

std::string outDir;

std::ofstream open(const std::string& name) {
    std::ofstream f(outDir + "/" + name);
    if (!f) throw std::runtime_error("cannot write " + outDir + "/" + name);
    f.precision(10);
    return f;
}

// ---------------------------------------------------------------------------------------------
// 1. Gautron Figure 4: energy fraction (eq. 15) vs number of coefficients, Phong lobes.
void figure4() {
    auto f = open("fig4_energy.csv");
    f << "lobe,basis,order,coefficients,energy_fraction\n";
    struct Lobe {
        std::string name;
        double exponent, tiltDeg;
    };
    const std::vector<Lobe> lobes = {
        {"cos5_normal", 5, 0}, {"cos20_normal", 20, 0}, {"cos5_tilt45", 5, 45}};
    // Hemisphere rule in θ-friendly form: Gauss in z on [0,1] (f vanishes below the horizon).
    const SphereQuadrature q = hemisphereQuadrature(600, 1200);
    const int nMax = 12;
    for (const Lobe& L : lobes) {
        const double t = L.tiltDeg * Pi / 180;
        const Vec3 axis(std::sin(t), 0, std::cos(t));
        auto fn = [&](const Vec3& w) {
            return w.z() < 0 ? 0.0 : std::pow(std::max(0.0, w.dot(axis)), L.exponent);
        };
        const double total = squaredNorm(fn, q);
        const Eigen::VectorXd cs = projectSH(nMax, fn, q);
        const Eigen::VectorXd ch = projectHSH(nMax, fn, q);
        const Eigen::VectorXd es = energyFraction(cs, total), eh = energyFraction(ch, total);
        for (int n = 1; n <= nMax; ++n) {
            f << L.name << ",SH," << n << "," << n * n << "," << es[n * n - 1] << "\n";
            f << L.name << ",HSH," << n << "," << n * n << "," << eh[n * n - 1] << "\n";
        }
        std::printf("fig4 %-13s n=1..5  SH:", L.name.c_str());
        for (int n = 1; n <= 5; ++n) std::printf(" %.4f", es[n * n - 1]);
        std::printf("   HSH:");
        for (int n = 1; n <= 5; ++n) std::printf(" %.4f", eh[n * n - 1]);
        std::printf("\n");
    }
}

// ---------------------------------------------------------------------------------------------
// 2. The SH→HSH matrix for 3 bands, an independent check, and the paper's printed matrix.
void conversionMatrix() {
    const ShToHsh C(3, 3);
    const Eigen::MatrixXd D = C.dense();
    // Independent: explicit l ≤ 2 formulas (blog table for Y, Gautron eq. 8 with Appendix B
    // polynomials for H), tanh–sinh in z on [0, 1], φ integral analytic.
    const double pi = Pi;
    auto K = [&](int l, int m, double norm) {
        double r = 1;
        for (int k = l - m + 1; k <= l + m; ++k) r /= k;
        return std::sqrt((2 * l + 1) * r / norm);
    };
    auto P = [](int l, int m, double x) {  // Appendix B / blog, with Condon–Shortley
        const double s = std::sqrt(std::max(0.0, 1 - x * x));
        if (l == 0) return 1.0;
        if (l == 1) return m == 0 ? x : -s;
        if (m == 0) return 0.5 * (3 * x * x - 1);
        if (m == 1) return -3 * x * s;
        return 3 * (1 - x * x);
    };
    boost::math::quadrature::tanh_sinh<double> ts;
    Eigen::MatrixXd I = Eigen::MatrixXd::Zero(9, 9);
    for (int l = 0; l < 3; ++l)
        for (int m = -l; m <= l; ++m)
            for (int lp = 0; lp < 3; ++lp)
                for (int mp = -lp; mp <= lp; ++mp) {
                    if (m != mp) continue;
                    const int am = std::abs(m);
                    const double phiInt = am == 0 ? 2 * pi : pi;  // ∫cos² = ∫sin² = π
                    const double fac = (am == 0 ? 1.0 : 2.0);     // √2·√2 of eqs. 3 and 8
                    auto fz = [&](double z) {
                        return K(l, am, 2 * pi) * P(l, am, 2 * z - 1) * K(lp, am, 4 * pi) *
                               P(lp, am, z);
                    };
                    I(shIndex(l, m), shIndex(lp, mp)) = fac * phiInt * ts.integrate(fz, 0.0, 1.0);
                }
    const double printed[9][9] = {
        {0.71, 0, 0.41, 0, 0, 0, 0, 0, 0},    {0, 0.60, 0, 0, 0, 0.19, 0, 0, 0},
        {0.82, 0, 0.71, 0, 0, 0, 0.18, 0, 0}, {0, 0, 0, 0.60, 0, 0, 0, 0.19, 0},
        {0, 0, 0, 0, 0.53, 0, 0, 0, 0},       {0, 0.77, 0, 0, 0, 0.51, 0, 0, 0},
        {0.40, 0, 0.78, 0, 0, 0, 0.53, 0, 0}, {0, 0, 0, 0.77, 0, 0, 0, 0.51, 0},
        {0, 0, 0, 0, 0, 0, 0, 0, 0.53}};
    auto f = open("c_matrix_3.csv");
    f << "row_hsh_l,row_hsh_m,col_sh_l,col_sh_m,C_ours,C_independent,C_printed\n";
    auto md = open("c_matrix_3.md");
    md << "Rows: H_l^m (l,m) in flat order; columns: Y_l'^m' in flat order.\n\n";
    auto table = [&](const char* title, auto&& value) {
        md << "### " << title << "\n\n|   |";
        const char* lab[9] = {"0,0", "1,-1", "1,0", "1,1", "2,-2", "2,-1", "2,0", "2,1", "2,2"};
        for (int j = 0; j < 9; ++j) md << " Y" << lab[j] << " |";
        md << "\n|---|";
        for (int j = 0; j < 9; ++j) md << "---|";
        md << "\n";
        for (int i = 0; i < 9; ++i) {
            md << "| H" << lab[i] << " |";
            for (int j = 0; j < 9; ++j) {
                char b[32];
                std::snprintf(b, sizeof b, " %.4f |", value(i, j));
                md << b;
            }
            md << "\n";
        }
        md << "\n";
    };
    table("C from the definitions (eq. 18), this library", [&](int i, int j) { return D(i, j); });
    table("Printed in Gautron et al. 2004 §6.1", [&](int i, int j) { return printed[i][j]; });
    double maxDiffIndep = 0, maxDiffPrinted = 0;
    for (int i = 0; i < 9; ++i)
        for (int j = 0; j < 9; ++j) {
            maxDiffIndep = std::max(maxDiffIndep, std::fabs(D(i, j) - I(i, j)));
            maxDiffPrinted = std::max(maxDiffPrinted, std::fabs(D(i, j) - printed[i][j]));
            const int li = shBand(i), lj = shBand(j);
            f << li << "," << i - li * (li + 1) << "," << lj << "," << j - lj * (lj + 1) << ","
              << D(i, j) << "," << I(i, j) << "," << printed[i][j] << "\n";
        }
    char b[256];
    std::snprintf(b, sizeof b,
                  "max |C_ours − C_independent| = %.2e;  max |C_ours − C_printed| = %.3f\n",
                  maxDiffIndep, maxDiffPrinted);
    md << b;
    std::printf("C(3,3): (H00,Y00)=%.6f (H00,Y10)=%.6f (H10,Y00)=%.6f; %s", D(0, 0), D(0, 2),
                D(2, 0), b);
    // Hypothesis check: is the printed matrix our C with rows and columns swapped, i.e. the
    // "HSH→SH" direction ∫ Y_l^m H_l'^m'? Record the distance too.
    double maxT = 0;
    for (int i = 0; i < 9; ++i)
        for (int j = 0; j < 9; ++j) maxT = std::max(maxT, std::fabs(D(j, i) - printed[i][j]));
    std::snprintf(b, sizeof b, "max |C_oursᵀ − C_printed| = %.3f (transpose hypothesis)\n", maxT);
    md << "\n" << b;
}

// ---------------------------------------------------------------------------------------------
// 3. Rotation orthogonality and composition error vs l.

void rotationError() {
    const int n = 121;
    const int trials = 6;
    const RotationMethod methods[2] = {RotationMethod::IvanicRuedenberg,
                                       RotationMethod::EulerEigen};
    std::vector<double> orth[2], comp[2];
    double secs[2] = {0, 0};
    for (int k = 0; k < 2; ++k) {
        orth[k].assign(n, 0.0);
        comp[k].assign(n, 0.0);
        Rng rng(12, 3);
        for (int t = 0; t < trials; ++t) {
            const Eigen::Matrix3d A = uniformRandomRotation(rng), B = uniformRandomRotation(rng);
            const auto t0 = std::chrono::steady_clock::now();
            const ShRotation RA(n, A, methods[k]);
            secs[k] += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            const ShRotation RB(n, B, methods[k]), RAB(n, A * B, methods[k]);
            for (int l = 0; l < n; ++l) {
                const int kk = 2 * l + 1;
                orth[k][l] = std::max(orth[k][l], (RA.bands[l] * RA.bands[l].transpose() -
                                                   Eigen::MatrixXd::Identity(kk, kk))
                                                      .cwiseAbs()
                                                      .maxCoeff());
                comp[k][l] = std::max(
                    comp[k][l], (RA.bands[l] * RB.bands[l] - RAB.bands[l]).cwiseAbs().maxCoeff());
            }
        }
    }
    auto f = open("rotation_error.csv");
    f << "l,ir_max_abs_RRt_minus_I,ir_max_abs_RaRb_minus_Rab,eig_max_abs_RRt_minus_I,"
         "eig_max_abs_RaRb_minus_Rab\n";
    for (int l = 0; l < n; ++l)
        f << l << "," << orth[0][l] << "," << comp[0][l] << "," << orth[1][l] << "," << comp[1][l]
          << "\n";
    for (int k = 0; k < 2; ++k)
        std::printf(
            "rotation %s: max|RRT-I| l=10 %.2e l=30 %.2e l=60 %.2e l=100 %.2e l=120 %.2e;"
            " build n=121 %.3f s\n",
            k == 0 ? "IR   " : "Euler", orth[k][10], orth[k][30], orth[k][60], orth[k][100],
            orth[k][120], secs[k] / trials);
}

// ---------------------------------------------------------------------------------------------
// 4. Legendre accuracy vs l against 50-digit boost::math::legendre_p.
using Big = boost::multiprecision::cpp_bin_float_50;
double referenceN(int l, int m, double z) {
    const Big x(z);
    const Big p = boost::math::legendre_p(l, m, x);
    const Big ratio = boost::math::tgamma_ratio(Big(l - m + 1), Big(l + m + 1));
    return static_cast<double>(
        sqrt(Big(2 * l + 1) / (4 * boost::math::constants::pi<Big>()) * ratio) * p);
}

void legendreAccuracy() {
    auto f = open("legendre_accuracy.csv");
    f << "l,max_abs_err_over_envelope,max_rel_err_near_pole,eps_l_1.5\n";
    const std::vector<double> zs = {-1.0, -1.0 + 1e-12, -0.999999, -0.77,    -0.3,      0.0, 1e-12,
                                    0.5,  0.9,          0.999,     1 - 1e-9, 1 - 1e-12, 1.0};
    for (int l : {1, 2, 5, 10, 20, 50, 86, 100, 200, 300, 500, 700, 1000}) {
        std::vector<double> all(triSize(l + 1));
        double worst = 0, worstPole = 0;
        const double env = std::sqrt((2.0 * l + 1) / FourPi);
        for (double z : zs) {
            legendreNormalized(l + 1, z, all.data());
            for (int m : {0, 1, 2, 5, l / 4, l / 3, l / 2, (3 * l) / 4, l - 1, l}) {
                if (m < 0 || m > l) continue;
                const double ref = referenceN(l, m, z);
                const double got = all[triIndex(l, m)];
                worst = std::max(worst, std::fabs(got - ref) / env);
                if (std::fabs(z) >= 1 - 1e-9 && std::fabs(z) < 1 && std::fabs(ref) > 1e-290)
                    worstPole = std::max(worstPole, std::fabs(got / ref - 1));
            }
        }
        f << l << "," << worst << "," << worstPole << ","
          << 2.220446049250313e-16 * std::pow(l, 1.5) << "\n";
        if (l == 1000 || l == 100)
            std::printf("legendre l=%d: max|err|/env = %.2e, near-pole max rel err = %.2e\n", l,
                        worst, worstPole);
    }
}

// ---------------------------------------------------------------------------------------------
// 5. Legendre-integral accuracy vs n for several interval kinds, with and without the
//    narrow-interval switch. Reference: long double composite Gauss rule (as in the tests).
using shvol::sh::reference::referenceN;

// The 48-panel rule: finer than the tests' default, for the wider range of intervals here.
long double refJ(int l, int m, double z0, double z1) {
    return shvol::sh::reference::referenceJ(l, m, z0, z1, 48);
}

void integralAccuracy() {
    auto f = open("integral_accuracy.csv");
    f << "n,interval,z0,z1,max_err_switch,max_err_recurrence_only\n";
    struct Iv {
        const char* name;
        double z0, z1;
    };
    const std::vector<Iv> ivs = {{"wide[-1;1]", -1, 1},
                                 {"pole[0.9;1]", 0.9, 1},
                                 {"interior[-0.5;0.7]", -0.5, 0.7},
                                 {"w=1e-3", 0.5, 0.501},
                                 {"w=1e-6", 0.3, 0.3 + 1e-6},
                                 {"w=1e-10", 0.3, 0.3 + 1e-10},
                                 {"pole w=1e-10", 1 - 1e-10, 1},
                                 {"pole w=1e-12", -1, -1 + 1e-12},
                                 {"pole w=0.02", 0.98, 1},
                                 {"w=0.015", 0.2, 0.215}};
    // error measure: max over l < n, m ≤ l of |J − ref| / (env_l · min(1, z1 − z0)), i.e.
    // relative to the size the integral has when the integrand is of its typical magnitude.
    for (int n : {5, 10, 20, 50, 100}) {
        std::vector<double> J(triSize(n)), R(triSize(n));
        for (const Iv& iv : ivs) {
            legendreIntegrals(n, iv.z0, iv.z1, J.data());
            legendreIntegralsRecurrence(n, iv.z0, iv.z1, R.data());
            double e1 = 0, e2 = 0;
            for (int l = 0; l < n; ++l)
                for (int m = 0; m <= l; ++m) {
                    if (n >= 50 && !(l == n - 1 || l == n / 2) && l > 10) continue;
                    const double ref = (double)refJ(l, m, iv.z0, iv.z1);
                    const double sc =
                        std::sqrt((2.0 * l + 1) / FourPi) * std::min(1.0, iv.z1 - iv.z0);
                    e1 = std::max(e1, std::fabs(J[triIndex(l, m)] - ref) / sc);
                    e2 = std::max(e2, std::fabs(R[triIndex(l, m)] - ref) / sc);
                }
            f << n << "," << iv.name << "," << iv.z0 << "," << iv.z1 << "," << e1 << "," << e2
              << "\n";
        }
    }
    std::printf("integral accuracy written\n");
}

// ---------------------------------------------------------------------------------------------
// 6. HSH rotation through SH vs the number of SH bands; and C Cᵀ → I.
void hshRotation() {
    auto f = open("hsh_rotation.csv");
    f << "nHsh,nSh,rel_err_vs_rotated_truncation,rel_err_vs_rotated_function,max_abs_CCt_minus_I\n";
    const int nH = 6;
    const Vec3 a = sphericalDirection(std::cos(20 * Pi / 180), 0.4);
    const double c35 = std::cos(35 * Pi / 180);
    auto fn = [&](const Vec3& w) { return std::pow(std::max(0.0, w.dot(a) - c35), 3); };
    const Eigen::Matrix3d R = rotationZYZ(0.0, 15 * Pi / 180, 0.0);
    const Eigen::Matrix3d Rinv = R.transpose();
    const SphereQuadrature q = hemisphereQuadrature(300, 600);
    const Eigen::VectorXd h = projectHSH(nH, fn, q);
    const Eigen::VectorXd refTrue = projectHSH(
        nH, [&](const Vec3& w) { return fn(Rinv * w); }, q);
    const Eigen::VectorXd refTrunc = projectHSH(
        nH, [&](const Vec3& w) { return hshReconstruct(nH, h.data(), Rinv * w); }, q);
    for (int nS : {6, 8, 12, 16, 24, 32, 48, 64}) {
        const ShToHsh C(nH, nS);
        const Eigen::VectorXd got = hshRotate(C, ShRotation(nS, R), h);
        const Eigen::MatrixXd D = C.dense();
        const double cct =
            (D * D.transpose() - Eigen::MatrixXd::Identity(nH * nH, nH * nH)).cwiseAbs().maxCoeff();
        f << nH << "," << nS << "," << (got - refTrunc).norm() / refTrunc.norm() << ","
          << (got - refTrue).norm() / refTrue.norm() << "," << cct << "\n";
    }
    std::printf("hsh rotation written\n");
}

// ---------------------------------------------------------------------------------------------
// 7. A_l table.
void irradianceTable() {
    auto f = open("clamped_cosine.csv");
    f << "l,A_l\n";
    for (int l = 0; l <= 20; ++l) f << l << "," << clampedCosineCoeff(l) << "\n";
}

}  // namespace

int main(int argc, char** argv) {
    outDir = argc > 1 ? argv[1] : std::string(SHVOL_SOURCE_DIR) + "/validation/sh/results";
    const auto t0 = std::chrono::steady_clock::now();
    figure4();
    conversionMatrix();
    rotationError();
    legendreAccuracy();
    integralAccuracy();
    hshRotation();
    irradianceTable();
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("validate_sh done in %.1f s, results in %s\n", secs, outDir.c_str());
    return 0;
}
