#include "shvol/sh/sh_rotation.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>
#include <complex>
#include <memory>
#include <mutex>

#include "shvol/sh/sh_basis.h"

namespace shvol::sh {

namespace {

// Ivanic–Ruedenberg helper P (1998 errata form). R1 is band 1 (3×3, index m+1), Rp band l−1.
inline double irP(int i, int l, int a, int b, const Eigen::MatrixXd& R1,
                  const Eigen::MatrixXd& Rp) {
    const double ri1 = R1(i + 1, 2), rim1 = R1(i + 1, 0), ri0 = R1(i + 1, 1);
    const int o = l - 1;
    if (b == l) return ri1 * Rp(a + o, 2 * l - 2) - rim1 * Rp(a + o, 0);
    if (b == -l) return ri1 * Rp(a + o, 0) + rim1 * Rp(a + o, 2 * l - 2);
    return ri0 * Rp(a + o, b + o);
}

}  // namespace

namespace {

// Ivanic–Ruedenberg bands 0 … n−1 (Condon–Shortley adapted).
std::vector<Eigen::MatrixXd> irBands(int n, const Eigen::Matrix3d& R) {
    std::vector<Eigen::MatrixXd> bands(std::max(n, 0));
    if (n <= 0) return bands;
    bands[0] = Eigen::MatrixXd::Ones(1, 1);
    if (n == 1) return bands;
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
        // u, v, w = (row factor in m) / √d(m′): tabulate both so the inner loop has no sqrt.
        std::vector<double> colInv(2 * l + 1), rowU(2 * l + 1), rowV(2 * l + 1), rowW(2 * l + 1);
        for (int mp = -l; mp <= l; ++mp)
            colInv[mp + l] = 1.0 / std::sqrt((std::abs(mp) == l) ? (2.0 * l) * (2.0 * l - 1.0)
                                                                 : double(l + mp) * double(l - mp));
        for (int m = -l; m <= l; ++m) {
            const int am = std::abs(m);
            rowU[m + l] = std::sqrt(double(l + m) * double(l - m));
            rowV[m + l] = 0.5 *
                          std::sqrt((m == 0 ? 2.0 : 1.0) * double(l + am - 1) * double(l + am)) *
                          (m == 0 ? -1.0 : 1.0);
            rowW[m + l] = m == 0 ? 0.0 : -0.5 * std::sqrt(double(l - am - 1) * double(l - am));
        }
        for (int m = -l; m <= l; ++m) {
            for (int mp = -l; mp <= l; ++mp) {
                const double ci = colInv[mp + l];
                const double u = rowU[m + l] * ci, v = rowV[m + l] * ci, w = rowW[m + l] * ci;
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
                if ((std::abs(m) + std::abs(mp)) & 1)
                    bands[l](m + l, mp + l) = -ir[l](m + l, mp + l);
    }
    return bands;
}

// Eigen-decomposition of the real-basis matrix of L_y for band l (cached): L_y = V Λ V^H.
struct LyEigen {
    Eigen::MatrixXcd V;
    Eigen::VectorXd lambda;
};

const LyEigen& lyEigen(int l) {
    static std::mutex mu;
    static std::vector<std::unique_ptr<LyEigen>> cache;
    std::lock_guard<std::mutex> lock(mu);
    if (static_cast<int>(cache.size()) <= l) cache.resize(l + 1);
    if (cache[l]) return *cache[l];
    using C = std::complex<double>;
    const int k = 2 * l + 1;
    const C I(0.0, 1.0);
    // Complex basis |l m⟩ (Condon–Shortley): L± |m⟩ = √(l(l+1) − m(m±1)) |m±1⟩, L_y = (L+ − L−)/2i.
    Eigen::MatrixXcd Lc = Eigen::MatrixXcd::Zero(k, k);
    const double ll = l * (l + 1.0);
    for (int m = -l; m <= l; ++m) {
        if (m + 1 <= l) Lc(m + 1 + l, m + l) = std::sqrt(ll - m * (m + 1.0)) / (2.0 * I);
        if (m - 1 >= -l) Lc(m - 1 + l, m + l) = -std::sqrt(ll - m * (m - 1.0)) / (2.0 * I);
    }
    // Real basis: y^m = (Y^m + (−1)^m Y^{−m})/√2, y^{−m} = (Y^m − (−1)^m Y^{−m})/(i√2), m > 0.
    Eigen::MatrixXcd U = Eigen::MatrixXcd::Zero(k, k);
    const double r = 1.0 / std::sqrt(2.0);
    U(l, l) = 1.0;
    for (int m = 1; m <= l; ++m) {
        const double sg = (m & 1) ? -1.0 : 1.0;
        U(m + l, m + l) = r;
        U(m + l, -m + l) = sg * r;
        U(-m + l, m + l) = r / I;
        U(-m + l, -m + l) = -sg * r / I;
    }
    const Eigen::MatrixXcd Lr = U.conjugate() * Lc * U.transpose();
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXcd> es(0.5 * (Lr + Lr.adjoint()));
    auto e = std::make_unique<LyEigen>();
    e->V = es.eigenvectors();
    e->lambda = es.eigenvalues().array().round();  // exactly the integers −l … l
    cache[l] = std::move(e);
    return *cache[l];
}

// cs[2m], cs[2m + 1] = cos(m·a), sin(m·a) for m < count.
void cosSinMultiples(double a, int count, double* cs) {
    for (int m = 0; m < count; ++m) cs[2 * m] = std::cos(m * a), cs[2 * m + 1] = std::sin(m * a);
}

// D^l(Rz(a)) applied from the left to the band-l rows of M, in place, with cs from
// cosSinMultiples(a, ≥ l + 1): rows (m, −m) → (c·row_m − s·row_−m, s·row_m + c·row_−m).
void zRows(Eigen::Ref<Eigen::MatrixXd> M, int l, const double* cs) {
    for (int m = 1; m <= l; ++m) {
        const double c = cs[2 * m], s = cs[2 * m + 1];
        for (Eigen::Index j = 0; j < M.cols(); ++j) {
            const double p = M(l + m, j), q = M(l - m, j);
            M(l + m, j) = c * p - s * q, M(l - m, j) = s * p + c * q;
        }
    }
}

// D^l(Rz(a)) applied from the left (rows) or right (columns) of M, in place.
void zLeft(Eigen::MatrixXd& M, int l, double a) {
    std::vector<double> cs(2 * size_t(l + 1));
    cosSinMultiples(a, l + 1, cs.data());
    zRows(M, l, cs.data());
}
void zRight(Eigen::MatrixXd& M, int l, double a) {
    for (int m = 1; m <= l; ++m) {
        const double c = std::cos(m * a), s = std::sin(m * a);
        const Eigen::VectorXd cp = M.col(m + l), cm = M.col(-m + l);
        M.col(m + l) = c * cp + s * cm;
        M.col(-m + l) = -s * cp + c * cm;
    }
}

// D^l(Ry(b)) = Re(V e^{−ibΛ} V^H).
Eigen::MatrixXd yBand(int l, double b) {
    const LyEigen& e = lyEigen(l);
    Eigen::VectorXcd ph(e.lambda.size());
    for (Eigen::Index i = 0; i < ph.size(); ++i) ph[i] = std::polar(1.0, -b * e.lambda[i]);
    return (e.V * ph.asDiagonal() * e.V.adjoint()).real();
}

// ZYZ Euler angles of R = Rz(α) Ry(β) Rz(γ), for R away from gimbal lock (|R22| ≤ 0.9).
void eulerZYZ(const Eigen::Matrix3d& R, double& a, double& b, double& g) {
    b = std::atan2(std::hypot(R(0, 2), R(1, 2)), R(2, 2));
    a = std::atan2(R(1, 2), R(0, 2));
    g = std::atan2(R(2, 1), -R(2, 0));
}

}  // namespace

static std::vector<Eigen::MatrixXd> eulerEigenBands(int n, const Eigen::Matrix3d& R, int lStart) {
    std::vector<Eigen::MatrixXd> bands(std::max(n, 0));
    // Near gimbal lock (|R22| > 0.5) write R = R′ Q⁻¹ with Q = Rx(−90°), so that R′ = R Q is far
    // from it (|R′22| = |R21| ≤ 0.87), and D(R) = D(R′) D(Rx(90°)), Rx(90°) =
    // Rz(−90°)Ry(90°)Rz(90°).
    const bool lock = std::fabs(R(2, 2)) > 0.5;
    Eigen::Matrix3d Rp = R;
    if (lock) Rp = R * Eigen::AngleAxisd(-0.5 * Pi, Vec3::UnitX()).toRotationMatrix();
    double a, b, g;
    eulerZYZ(Rp, a, b, g);
    for (int l = std::max(lStart, 0); l < n; ++l) {
        Eigen::MatrixXd D = yBand(l, b);
        zLeft(D, l, a);
        zRight(D, l, g);
        if (lock) {
            Eigen::MatrixXd X = yBand(l, 0.5 * Pi);
            zLeft(X, l, -0.5 * Pi);
            zRight(X, l, 0.5 * Pi);
            D = D * X;
        }
        bands[l] = std::move(D);
    }
    return bands;
}

ShRotation::ShRotation(int n_, const Eigen::Matrix3d& R, RotationMethod method) : n(n_) {
    if (method == RotationMethod::IvanicRuedenberg) {
        bands = irBands(n, R);
    } else if (method == RotationMethod::EulerEigen) {
        bands = eulerEigenBands(n, R, 0);
    } else {
        const int nIr = std::min(n, kRotationIrBands);
        bands = irBands(nIr, R);
        if (n > nIr) {
            std::vector<Eigen::MatrixXd> hi = eulerEigenBands(n, R, nIr);
            bands.resize(n);
            for (int l = nIr; l < n; ++l) bands[l] = std::move(hi[l]);
        }
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

ShVectorRotation::SparseBand ShVectorRotation::sparse(const Eigen::MatrixXd& m) {
    SparseBand b;
    for (Eigen::Index i = 0; i < m.rows(); ++i) {
        b.start.push_back(int(b.col.size()));
        for (Eigen::Index j = 0; j < m.cols(); ++j)
            if (std::fabs(m(i, j)) > 1e-13) b.col.push_back(int(j)), b.val.push_back(m(i, j));
    }
    b.start.push_back(int(b.col.size()));
    return b;
}

ShVectorRotation::ShVectorRotation(int n) : n_(n) {
    const ShRotation x(n, Eigen::AngleAxisd(0.5 * Pi, Vec3::UnitX()).toRotationMatrix());
    for (const Eigen::MatrixXd& band : x.bands) {
        x_.push_back(sparse(band));
        xt_.push_back(sparse(band.transpose()));
    }
}

void ShVectorRotation::apply(const Eigen::Matrix3d& R, const double* in, double* out,
                             int count) const {
    // α, β from the image of ẑ (any α will do when β = 0), then the twist γ from the rest.
    const double dx = R(0, 2), dy = R(1, 2), dz = R(2, 2);
    const double alpha = dx == 0 && dy == 0 ? 0.0 : std::atan2(dy, dx);
    const double beta = std::atan2(std::hypot(dx, dy), dz);
    const Eigen::Matrix3d tilt =
        (Eigen::AngleAxisd(alpha, Vec3::UnitZ()) * Eigen::AngleAxisd(beta, Vec3::UnitY()) *
         Eigen::AngleAxisd(-alpha, Vec3::UnitZ()))
            .toRotationMatrix();
    const Eigen::Matrix3d twist = tilt.transpose() * R;  // Rz(α + γ), to rounding
    const double gamma = std::atan2(twist(1, 0), twist(0, 0)) - alpha;
    // cos and sin of m·a for m < n, for the three angles.
    const int n = n_;
    thread_local std::vector<double> trig;
    trig.resize(6 * size_t(std::max(n, 1)));
    const double angles[3] = {alpha, beta, gamma};
    for (int k = 0; k < 3; ++k) cosSinMultiples(angles[k], n, &trig[2 * size_t(k) * n]);
    // Z^l of angle k on the band's coefficients of every vector.
    auto z = [&](int k, int l, Eigen::Ref<Eigen::MatrixXd> v) {
        zRows(v, l, &trig[2 * size_t(k) * n]);
    };
    // Scratch for one band of every vector, sized once for the widest band (no allocation per
    // band or call).
    thread_local std::vector<double> scratch;
    const size_t widest = size_t(std::max(2 * n - 1, 1)) * std::max(count, 1);
    if (scratch.size() < 2 * widest) scratch.resize(2 * widest);
    const size_t nn = size_t(n) * n;
    // out = M in for every column, over M's nonzero entries: each entry is read once for all
    // columns, and the columns' sums are independent chains (three for an RGB record).
    auto multiply = [count](const SparseBand& M, const auto& in, auto& out) {
        constexpr int kChains = 3;
        const Eigen::Index stride = in.outerStride();
        for (size_t i = 0; i + 1 < M.start.size(); ++i)
            for (int j0 = 0; j0 < count; j0 += kChains) {
                const int m = std::min(kChains, count - j0);
                double s[kChains] = {0, 0, 0};
                for (int p = M.start[i]; p < M.start[i + 1]; ++p) {
                    const double a = M.val[p];
                    const double* x = &in(M.col[p], j0);
                    for (int j = 0; j < kChains; ++j)
                        if (j < m) s[j] += a * x[j * stride];
                }
                for (int j = 0; j < m; ++j) out(Eigen::Index(i), j0 + j) = s[j];
            }
    };
    for (int l = 0; l < n; ++l) {
        const int k = 2 * l + 1;
        Eigen::Map<Eigen::MatrixXd> v(scratch.data(), k, count),
            w(scratch.data() + widest, k, count);
        for (int j = 0; j < count; ++j)
            v.col(j) = Eigen::Map<const Eigen::VectorXd>(in + j * nn + l * l, k);
        z(2, l, v);
        multiply(x_[l], v, w);
        z(1, l, w);
        multiply(xt_[l], w, v);
        z(0, l, v);
        for (int j = 0; j < count; ++j)
            Eigen::Map<Eigen::VectorXd>(out + j * nn + l * l, k) = v.col(j);
    }
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

// Rodrigues' formula about v = ẑ × d = (−y, x, 0) with cos θ = c = d_z:
// R = I + [v]× + [v]×² / (1 + c), [v]×² = v vᵀ − |v|² I. For c < 0, 1/(1 + c) is taken as
// (1 − c)/(x² + y²), which does not cancel. (Eigen's Quaternion::FromTwoVectors gives the same
// rotation but instantiates a JacobiSVD for the antiparallel case: a third of this file's
// compile time.)
Eigen::Matrix3d rotationTo(const Vec3& dIn) {
    const Vec3 d = dIn.normalized();
    const double x = d.x(), y = d.y(), c = d.z(), s = x * x + y * y;
    if (!(s > 0))  // ±z: the identity, or a half turn about x
        return Eigen::Matrix3d(Vec3(1, c >= 0 ? 1 : -1, c >= 0 ? 1 : -1).asDiagonal());
    const double k = c >= 0 ? 1 / (1 + c) : (1 - c) / s;
    Eigen::Matrix3d R;
    R << 1 - x * x * k, -x * y * k, x,  //
        -x * y * k, 1 - y * y * k, y,   //
        -x, -y, c;
    return R;
}

Eigen::Matrix3d rotationZYZ(double alpha, double beta, double gamma) {
    return (Eigen::AngleAxisd(alpha, Vec3::UnitZ()) * Eigen::AngleAxisd(beta, Vec3::UnitY()) *
            Eigen::AngleAxisd(gamma, Vec3::UnitZ()))
        .toRotationMatrix();
}

}  // namespace shvol::sh
