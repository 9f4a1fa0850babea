#include "shvol/sh/sh_basis.h"

#include <cmath>
#include <vector>

#include "shvol/sh/legendre.h"

namespace shvol::sh {

int shBand(int i) {
    int l = static_cast<int>(std::sqrt(static_cast<double>(i)));
    while (l * l > i) --l;
    while ((l + 1) * (l + 1) <= i) ++l;
    return l;
}

void shEvalRecurrence(int n, const Vec3& w, double* out) {
    const double x = w.x(), y = w.y(), z = w.z();
    const double s = std::sqrt(x * x + y * y);
    const double c1 = s > 0.0 ? x / s : 1.0;
    const double s1 = s > 0.0 ? y / s : 0.0;
    const double r2 = 1.4142135623730951;
    // cos(mφ), sin(mφ) by complex multiplication (the rotation form of Jarosz eqs. 15–16, whose
    // rounding error grows like m·ε instead of m²·ε near φ = 0, π).
    double cm = 1.0, sm = 0.0;
    int mCur = 0;
    forEachLegendre(n, z, s, [&](int l, int m, double v) {
        if (m != mCur) {  // new column
            const double c = cm * c1 - sm * s1;
            sm = sm * c1 + cm * s1;
            cm = c;
            mCur = m;
        }
        if (m == 0) {
            out[l * (l + 1)] = v;
        } else {
            const double rv = r2 * v;
            out[l * (l + 1) + m] = rv * cm;
            out[l * (l + 1) - m] = rv * sm;
        }
    });
}

void shEvalFast(int n, const Vec3& w, double* out) {
    const double x = w.x(), y = w.y(), z = w.z();
    out[0] = 0.28209479177387814;  // 1/(2√π); constants are √2 K_l^m × the P_l^m prefactor
    if (n <= 1) return;
    out[1] = -0.4886025119029199 * y;  // √(3/4π)
    out[2] = 0.4886025119029199 * z;
    out[3] = -0.4886025119029199 * x;
    if (n <= 2) return;
    const double xx = x * x, yy = y * y, zz = z * z;
    out[4] = 1.0925484305920792 * x * y;  // √(15/4π)
    out[5] = -1.0925484305920792 * y * z;
    out[6] = 0.31539156525252005 * (3.0 * zz - 1.0);  // √(5/16π)
    out[7] = -1.0925484305920792 * x * z;
    out[8] = 0.5462742152960396 * (xx - yy);  // √(15/16π)
    if (n <= 3) return;
    out[9] = -0.5900435899266435 * y * (3.0 * xx - yy);    // √(35/32π)
    out[10] = 2.890611442640554 * x * y * z;               // √(105/4π)
    out[11] = -0.4570457994644658 * y * (5.0 * zz - 1.0);  // √(21/32π)
    out[12] = 0.3731763325901154 * z * (5.0 * zz - 3.0);   // √(7/16π)
    out[13] = -0.4570457994644658 * x * (5.0 * zz - 1.0);
    out[14] = 1.445305721320277 * z * (xx - yy);  // √(105/16π)
    out[15] = -0.5900435899266435 * x * (xx - 3.0 * yy);
    if (n <= 4) return;
    // l = 4: √2 K_4^m P_4^m with P_4^1 = −(5/2)(7z³−3z)s, P_4^2 = (15/2)(7z²−1)s²,
    // P_4^3 = −105 z s³, P_4^4 = 105 s⁴, and s^m (cos mφ, sin mφ) written in x, y.
    const double z2 = 7.0 * zz;
    out[16] = 2.5033429417967050 * x * y * (xx - yy);  // 4·0.62583…
    out[17] = -1.7701307697799307 * z * y * (3.0 * xx - yy);
    out[18] = 0.94617469575756 * x * y * (z2 - 1.0);  // 2·0.47308…
    out[19] = -0.6690465435572892 * y * z * (z2 - 3.0);
    out[20] = 0.10578554691520431 * (35.0 * zz * zz - 30.0 * zz + 3.0);
    out[21] = -0.6690465435572892 * x * z * (z2 - 3.0);
    out[22] = 0.47308734787878 * (xx - yy) * (z2 - 1.0);
    out[23] = -1.7701307697799307 * z * x * (xx - 3.0 * yy);
    out[24] = 0.6258357354491763 * (xx * xx - 6.0 * xx * yy + yy * yy);
}

void shEval(int n, const Vec3& w, double* out) {
    if (n <= kShFastMaxOrder)
        shEvalFast(n, w, out);
    else
        shEvalRecurrence(n, w, out);
}

Eigen::VectorXd shEval(int n, const Vec3& w) {
    Eigen::VectorXd v(n * n);
    shEval(n, w, v.data());
    return v;
}

double shEvalSingle(int l, int m, const Vec3& w) {
    const double x = w.x(), y = w.y(), z = w.z();
    const double s = std::sqrt(x * x + y * y);
    const int am = m < 0 ? -m : m;
    const double v = legendreNormalized(l, am, z);
    if (m == 0) return v;
    const double phi = std::atan2(y, x);
    (void)s;
    return 1.4142135623730951 * v * (m > 0 ? std::cos(am * phi) : std::sin(am * phi));
}

void shEvalZonal(int n, double z, double* out) {
    if (n <= 0) return;
    const double k0 = 0.28209479177387814;
    out[0] = k0;
    if (n == 1) return;
    out[1] = std::sqrt(3.0) * z * k0;
    const detail::LegendreTables& T = detail::legendreTables();
    for (int l = 2; l < n; ++l) {
        const bool tab = l < detail::LegendreTables::kBands;
        const double a = tab ? T.a[triIndex(l, 0)] : legendreA(l, 0);
        const double b = tab ? T.b[triIndex(l, 0)] : legendreB(l, 0);
        out[l] = a * (z * out[l - 1] - b * out[l - 2]);
    }
}

double shReconstruct(int n, const double* c, const Vec3& w) {
    double buf[256];
    std::vector<double> big;
    double* y = buf;
    if (n * n > 256) {
        big.resize(n * n);
        y = big.data();
    }
    shEval(n, w, y);
    double sum = 0.0;
    for (int i = 0; i < n * n; ++i) sum += c[i] * y[i];
    return sum;
}

}  // namespace shvol::sh
