#pragma once
// The long-double Legendre and Legendre-integral references shared by tests/sh and
// validation/sh.
#include <algorithm>
#include <cmath>

namespace shvol::sh::reference {

// Independent long-double reference: the textbook unnormalised recurrence (Gautron eqs. 27–29,
// no overflow for l ≤ 100 in long double's range) times K_l^m, with sin θ supplied exactly.
inline long double referenceN(int l, int m, long double z, long double s) {
    long double pmm = 1.0L;
    for (int k = 1; k <= m; ++k) pmm *= -(2.0L * k - 1.0L) * s;
    long double p = pmm;
    if (l > m) {
        long double p2 = pmm, p1 = z * (2.0L * m + 1.0L) * pmm;
        for (int ll = m + 2; ll <= l; ++ll) {
            const long double t = ((2.0L * ll - 1.0L) * z * p1 - (ll + m - 1.0L) * p2) / (ll - m);
            p2 = p1;
            p1 = t;
        }
        p = p1;
    }
    long double ratio = 1.0L;  // (l−m)!/(l+m)!
    for (int k = l - m + 1; k <= l + m; ++k) ratio /= k;
    return std::sqrt((2.0L * l + 1.0L) / (4.0L * 3.14159265358979323846264338327950288L) * ratio) *
           p;
}

/// 20-point Gauss–Legendre nodes and weights on [−1, 1] in long double (Newton on P_20),
/// independent of the library's gaussLegendre.
struct GL20 {
    long double x[20], w[20];
    GL20() {
        const int k = 20;
        for (int i = 0; i < k; ++i) {
            long double t =
                std::cos(3.14159265358979323846264338327950288L * (i + 0.75L) / (k + 0.5L));
            long double dp = 0;
            for (int it = 0; it < 50; ++it) {
                long double p0 = 1, p1 = t;
                for (int j = 2; j <= k; ++j) {
                    const long double p2 = ((2 * j - 1) * t * p1 - (j - 1) * p0) / j;
                    p0 = p1;
                    p1 = p2;
                }
                dp = k * (t * p1 - p0) / (t * t - 1);
                const long double dt = p1 / dp;
                t -= dt;
                if (std::fabs(dt) < 1e-19L) break;
            }
            x[i] = t;
            w[i] = 2 / ((1 - t * t) * dp * dp);
        }
    }
};

// ∫_{z0}^{z1} N_l^m(z) dz by a composite rule (`panels` panels × 20 Gauss points, default 32) in
// long double: in z when the interval stays 1e-4 away from the poles (the integrand is analytic
// there), else in θ (z = cos θ: a trigonometric polynomial of degree l+1; θ is small near the
// poles, so it is represented to full relative precision). Both rules are exact to long-double
// rounding for l ≤ 100.
inline long double referenceJ(int l, int m, double z0, double z1, int panels = 32) {
    // Near z = −1 use N_l^m(−z) = (−1)^(l+m) N_l^m(z): θ is then small and exact in long double.
    if (z1 <= 0.0 && z0 < -0.5)
        return ((l + m) % 2 ? -1.0L : 1.0L) * referenceJ(l, m, -z1, -z0, panels);
    static const GL20 gl;
    const long double a = z0, b = z1;
    const bool inZ = 1.0L - std::max(std::fabs(a), std::fabs(b)) > 1e-4L;
    const long double lo = inZ ? a : std::acos(b), hi = inZ ? b : std::acos(a);
    const long double h = (hi - lo) / panels;
    long double sum = 0;
    for (int p = 0; p < panels; ++p) {
        const long double c = lo + (p + 0.5L) * h;
        for (int i = 0; i < 20; ++i) {
            const long double t = c + 0.5L * h * gl.x[i];
            long double v;
            if (inZ)
                v = referenceN(l, m, t, std::sqrt((1.0L - t) * (1.0L + t)));
            else
                v = referenceN(l, m, std::cos(t), std::sin(t)) * std::sin(t);
            sum += gl.w[i] * 0.5L * h * v;
        }
    }
    return sum;
}

}  // namespace shvol::sh::reference
