#include "shvol/sh/hsh.h"

#include <algorithm>
#include <cmath>

#include "shvol/sh/legendre.h"

namespace shvol::sh {

void hshEval(int n, const Vec3& w, double* out) {
    const double x = w.x(), y = w.y();
    const double z = std::clamp(w.z(), 0.0, 1.0);
    const double s = std::sqrt(x * x + y * y);
    const double c1 = s > 0.0 ? x / s : 1.0;
    const double s1 = s > 0.0 ? y / s : 0.0;
    const double zs = 2.0 * z - 1.0;  // shifted argument (Gautron eq. 6)
    // √(1 − (2z−1)²) = 2√(z(1 − z)), with 1 − z = (x² + y²)/(1 + z) for a unit w: near the
    // normal z rounds the polar angle away (z = 1 exactly at θ = 10⁻⁹), x and y keep it.
    const double ss = 2.0 * s * std::sqrt(z / (1.0 + z));
    const double r2 = 1.4142135623730951, two = 2.0;  // √2 (K̃ = √2 K) and √2·√2
    double cm = 1.0, sm = 0.0;
    int mCur = 0;
    forEachLegendre(n, zs, ss, [&](int l, int m, double v) {
        if (m != mCur) {
            const double c = cm * c1 - sm * s1;
            sm = sm * c1 + cm * s1;
            cm = c;
            mCur = m;
        }
        if (m == 0) {
            out[l * (l + 1)] = r2 * v;
        } else {
            const double tv = two * v;
            out[l * (l + 1) + m] = tv * cm;
            out[l * (l + 1) - m] = tv * sm;
        }
    });
}

void hshRotateZ(int n, double phi, double* h) {
    for (int m = 1; m < n; ++m) {
        const double c = std::cos(m * phi), s = std::sin(m * phi);
        for (int l = m; l < n; ++l) {
            double& a = h[l * (l + 1) + m];  // cos mφ
            double& b = h[l * (l + 1) - m];  // sin mφ
            const double a2 = a * c - b * s;
            b = a * s + b * c;
            a = a2;
        }
    }
}

Eigen::VectorXd hshEval(int n, const Vec3& w) {
    Eigen::VectorXd v(n * n);
    hshEval(n, w, v.data());
    return v;
}

double hshReconstruct(int n, const double* h, const Vec3& w) {
    if (w.z() < 0.0) return 0.0;
    const Eigen::VectorXd y = hshEval(n, w);
    return Eigen::Map<const Eigen::VectorXd>(h, n * n).dot(y);
}

SphereQuadrature hemisphereQuadrature(int nz, int nphi) {
    return sphereQuadrature(nz, nphi, 0.0, 1.0);
}

HshRotation::HshRotation(int n)
    : n_(n), C_(n, 2 * n), rotate_(2 * n), horizon_(size_t(n) * n), lowerSh_(size_t(4) * n * n) {
    hshEval(n, Vec3(1, 0, 0), horizon_.data());  // (m ≠ 0 terms vanish at the horizon)
    // ∫ Y_j over z ∈ [−1, 0]: Y_j is a polynomial of degree < 2n in z times its azimuth factor,
    // which integrates to 0 unless m = 0; 2n Gauss points in z and 4n in φ are exact.
    const SphereQuadrature lower = sphereQuadrature(2 * n, 4 * n, -1.0, 0.0);
    std::vector<double> y(lowerSh_.size());
    for (size_t i = 0; i < lower.z.size(); ++i)
        for (int j = 0; j < lower.nphi; ++j) {
            shEval(2 * n, lower.direction(int(i), j), y.data());
            for (size_t k = 0; k < y.size(); ++k) lowerSh_[k] += lower.weight(int(i)) * y[k];
        }
}

void HshRotation::addCorrection(const Eigen::Matrix3d& R, const double* h, double weight,
                                double* sh, int channels) const {
    const int nn = n_ * n_, ns = shCount();
    thread_local std::vector<double> held, rotated;
    held.resize(size_t(channels) * ns);
    rotated.resize(held.size());
    for (int c = 0; c < channels; ++c) {
        const double* hc = h + size_t(c) * nn;
        double* e = &held[size_t(c) * ns];
        C_.toSh(hc, e);
        double atHorizon = 0;
        for (int i = 0; i < nn; ++i) atHorizon += horizon_[i] * hc[i];
        for (int k = 0; k < ns; ++k) e[k] += atHorizon * lowerSh_[k];
    }
    rotate_.apply(R, held.data(), rotated.data(), channels);
    for (size_t k = 0; k < held.size(); ++k) sh[k] += weight * (rotated[k] - held[k]);
}

void HshRotation::finish(const double* sh, double* out, int channels) const {
    const int nn = n_ * n_, ns = shCount();
    thread_local std::vector<double> h;
    h.resize(nn);
    for (int c = 0; c < channels; ++c) {
        C_.toHsh(sh + size_t(c) * ns, h.data());
        for (int i = 0; i < nn; ++i) out[size_t(c) * nn + i] += h[i];
    }
}

void HshRotation::apply(const Eigen::Matrix3d& R, const double* h, double* out,
                        int channels) const {
    std::copy(h, h + size_t(channels) * n_ * n_, out);
    std::vector<double> sh(size_t(channels) * shCount(), 0.0);
    addCorrection(R, h, 1, sh.data(), channels);
    finish(sh.data(), out, channels);
}

ShToHsh::ShToHsh(int nH, int nS) : nHsh(nH), nSh(nS) {
    const int mMax = std::min(nH, nS);
    blocks.resize(mMax);
    for (int am = 0; am < mMax; ++am) blocks[am] = Eigen::MatrixXd::Zero(nH - am, nS - am);
    std::vector<double> t, wt;
    gaussLegendre(nH + nS + 40, 0.0, 1.0, t, wt);
    std::vector<double> a(triSize(nH)), b(triSize(nS));
    const double f = TwoPi * 1.4142135623730951;
    for (size_t k = 0; k < t.size(); ++k) {
        const double z = t[k] * t[k];
        const double wz = wt[k] * 2.0 * t[k];  // dz = 2t dt
        // Shifted: argument 2z−1 with sine 2√(z(1−z)) = 2t√(1−t²); unshifted: z, √(1−z²).
        legendreNormalized(nH, 2.0 * z - 1.0, 2.0 * t[k] * std::sqrt((1.0 - t[k]) * (1.0 + t[k])),
                           a.data());
        legendreNormalized(nS, z, std::sqrt((1.0 - z) * (1.0 + z)), b.data());
        for (int am = 0; am < mMax; ++am)
            for (int l = am; l < nH; ++l) {
                const double al = f * wz * a[triIndex(l, am)];
                for (int lp = am; lp < nS; ++lp)
                    blocks[am](l - am, lp - am) += al * b[triIndex(lp, am)];
            }
    }
}

void ShToHsh::toHsh(const double* sh, double* h) const {
    std::fill(h, h + nHsh * nHsh, 0.0);
    for (int am = 0; am < static_cast<int>(blocks.size()); ++am)
        for (int sgn : {1, -1}) {
            if (am == 0 && sgn < 0) continue;
            const int m = sgn * am;
            for (int l = am; l < nHsh; ++l) {
                double s = 0.0;
                for (int lp = am; lp < nSh; ++lp)
                    s += blocks[am](l - am, lp - am) * sh[lp * (lp + 1) + m];
                h[l * (l + 1) + m] = s;
            }
        }
}

Eigen::VectorXd ShToHsh::toHsh(const Eigen::VectorXd& sh) const {
    Eigen::VectorXd h(nHsh * nHsh);
    toHsh(sh.data(), h.data());
    return h;
}

void ShToHsh::toSh(const double* h, double* sh) const {
    std::fill(sh, sh + nSh * nSh, 0.0);
    for (int am = 0; am < static_cast<int>(blocks.size()); ++am)
        for (int sgn : {1, -1}) {
            if (am == 0 && sgn < 0) continue;
            const int m = sgn * am;
            for (int lp = am; lp < nSh; ++lp) {
                double s = 0.0;
                for (int l = am; l < nHsh; ++l)
                    s += blocks[am](l - am, lp - am) * h[l * (l + 1) + m];
                sh[lp * (lp + 1) + m] = s;
            }
        }
}

Eigen::VectorXd ShToHsh::toSh(const Eigen::VectorXd& h) const {
    Eigen::VectorXd sh(nSh * nSh);
    toSh(h.data(), sh.data());
    return sh;
}

Eigen::MatrixXd ShToHsh::dense() const {
    Eigen::MatrixXd C = Eigen::MatrixXd::Zero(nHsh * nHsh, nSh * nSh);
    for (int am = 0; am < static_cast<int>(blocks.size()); ++am)
        for (int sgn : {1, -1}) {
            if (am == 0 && sgn < 0) continue;
            const int m = sgn * am;
            for (int l = am; l < nHsh; ++l)
                for (int lp = am; lp < nSh; ++lp)
                    C(l * (l + 1) + m, lp * (lp + 1) + m) = blocks[am](l - am, lp - am);
        }
    return C;
}

Eigen::VectorXd hshRotate(const ShToHsh& C, const ShRotation& R, const Eigen::VectorXd& h) {
    return C.toHsh(R.apply(C.toSh(h)));
}

Eigen::MatrixXd hshRotationMatrix(const ShToHsh& C, const ShRotation& R) {
    const Eigen::MatrixXd D = C.dense();
    return D * R.matrix() * D.transpose();
}

}  // namespace shvol::sh
