#include "shvol/sh/sh_rotation.h"

#include <Eigen/Geometry>
#include <cmath>

#include "shvol/sh/sh_basis.h"

namespace shvol::sh {

namespace {

// Ivanic–Ruedenberg helper P (1998 errata form). R1 is band 1 (3×3, index m+1), Rp band l−1.
inline double irP(int i, int l, int a, int b, const Eigen::MatrixXd& R1, const Eigen::MatrixXd& Rp) {
    const double ri1 = R1(i + 1, 2), rim1 = R1(i + 1, 0), ri0 = R1(i + 1, 1);
    const int o = l - 1;
    if (b == l) return ri1 * Rp(a + o, 2 * l - 2) - rim1 * Rp(a + o, 0);
    if (b == -l) return ri1 * Rp(a + o, 0) + rim1 * Rp(a + o, 2 * l - 2);
    return ri0 * Rp(a + o, b + o);
}

}  // namespace

ShRotation::ShRotation(int n_, const Eigen::Matrix3d& R) : n(n_) {
    bands.resize(std::max(n, 0));
    if (n <= 0) return;
    bands[0] = Eigen::MatrixXd::Ones(1, 1);
    if (n == 1) return;
    // Band 1 in IR's basis (∝ y, z, x): R1 = P R Pᵀ with P picking rows (y, z, x).
    const int p[3] = {1, 2, 0};
    Eigen::MatrixXd R1(3, 3);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) R1(i, j) = R(p[i], p[j]);
    std::vector<Eigen::MatrixXd> ir(n);
    ir[0] = bands[0];
    ir[1] = R1;
    for (int l = 2; l < n; ++l) {
        const Eigen::MatrixXd& Rp = ir[l - 1];
        Eigen::MatrixXd Rl(2 * l + 1, 2 * l + 1);
        for (int m = -l; m <= l; ++m) {
            const int am = std::abs(m);
            for (int mp = -l; mp <= l; ++mp) {
                const double d = (std::abs(mp) == l) ? (2.0 * l) * (2.0 * l - 1.0)
                                                     : double(l + mp) * double(l - mp);
                const double u = std::sqrt(double(l + m) * double(l - m) / d);
                const double v = 0.5 * std::sqrt((m == 0 ? 2.0 : 1.0) * double(l + am - 1) *
                                                 double(l + am) / d) *
                                 (m == 0 ? -1.0 : 1.0);
                const double w = m == 0 ? 0.0
                                        : -0.5 * std::sqrt(double(l - am - 1) * double(l - am) / d);
                double val = 0.0;
                if (u != 0.0) val += u * irP(0, l, m, mp, R1, Rp);
                if (v != 0.0) {
                    double V;
                    if (m == 0) {
                        V = irP(1, l, 1, mp, R1, Rp) + irP(-1, l, -1, mp, R1, Rp);
                    } else if (m > 0) {
                        const bool d1 = (m == 1);
                        V = irP(1, l, m - 1, mp, R1, Rp) * (d1 ? std::sqrt(2.0) : 1.0) -
                            (d1 ? 0.0 : irP(-1, l, -m + 1, mp, R1, Rp));
                    } else {
                        const bool d1 = (m == -1);
                        V = (d1 ? 0.0 : irP(1, l, m + 1, mp, R1, Rp)) +
                            irP(-1, l, -m - 1, mp, R1, Rp) * (d1 ? std::sqrt(2.0) : 1.0);
                    }
                    val += v * V;
                }
                if (w != 0.0) {
                    double W;
                    if (m > 0)
                        W = irP(1, l, m + 1, mp, R1, Rp) + irP(-1, l, -m - 1, mp, R1, Rp);
                    else
                        W = irP(1, l, m - 1, mp, R1, Rp) - irP(-1, l, -m + 1, mp, R1, Rp);
                    val += w * W;
                }
                Rl(m + l, mp + l) = val;
            }
        }
        ir[l] = std::move(Rl);
    }
    // Condon–Shortley: R_{mm'} (−1)^{m+m'}.
    for (int l = 1; l < n; ++l) {
        bands[l] = ir[l];
        for (int m = -l; m <= l; ++m)
            for (int mp = -l; mp <= l; ++mp)
                if ((std::abs(m) + std::abs(mp)) & 1) bands[l](m + l, mp + l) = -ir[l](m + l, mp + l);
    }
}

void ShRotation::apply(const double* in, double* out) const {
    for (int l = 0; l < n; ++l) {
        const int k = 2 * l + 1, o = l * l;
        Eigen::Map<const Eigen::VectorXd> x(in + o, k);
        Eigen::Map<Eigen::VectorXd> y(out + o, k);
        y.noalias() = bands[l] * x;
    }
}

Eigen::VectorXd ShRotation::apply(const Eigen::VectorXd& in) const {
    Eigen::VectorXd out(n * n);
    apply(in.data(), out.data());
    return out;
}

Eigen::MatrixXd ShRotation::matrix() const {
    Eigen::MatrixXd M = Eigen::MatrixXd::Zero(n * n, n * n);
    for (int l = 0; l < n; ++l) M.block(l * l, l * l, 2 * l + 1, 2 * l + 1) = bands[l];
    return M;
}

void rotateZonal(int n, const double* p, const Vec3& d, double* out) {
    shEval(n, d, out);
    for (int l = 0; l < n; ++l) {
        const double f = std::sqrt(FourPi / (2.0 * l + 1.0)) * p[l];
        for (int i = l * l; i < (l + 1) * (l + 1); ++i) out[i] *= f;
    }
}

Eigen::VectorXd rotateZonal(const Eigen::VectorXd& p, const Vec3& d) {
    const int n = static_cast<int>(p.size());
    Eigen::VectorXd out(n * n);
    rotateZonal(n, p.data(), d, out.data());
    return out;
}

Eigen::Matrix3d rotationTo(const Vec3& d) {
    return Eigen::Quaterniond::FromTwoVectors(Vec3(0, 0, 1), d.normalized()).toRotationMatrix();
}

Eigen::Matrix3d rotationZYZ(double alpha, double beta, double gamma) {
    return (Eigen::AngleAxisd(alpha, Vec3::UnitZ()) * Eigen::AngleAxisd(beta, Vec3::UnitY()) *
            Eigen::AngleAxisd(gamma, Vec3::UnitZ()))
        .toRotationMatrix();
}

}  // namespace shvol::sh
