#pragma once
// Inline part of legendre.h: the fused column recurrence. Include legendre.h, not this file.
#include <cmath>

namespace shvol::sh {

namespace detail {
/// Precomputed recurrence coefficients for l < kTableBands (computed once, thread-safe).
struct LegendreTables {
    static constexpr int kBands = 160;
    double a[kBands * (kBands + 1) / 2];
    double b[kBands * (kBands + 1) / 2];
    double sect[kBands];  // √((2m+1)/(2m)), m ≥ 1
    double next[kBands];  // √(2m+3)
};
const LegendreTables& legendreTables();
}  // namespace detail

template <class F>
void forEachLegendre(int n, double z, double s, F&& f) {
    const detail::LegendreTables& T = detail::legendreTables();
    constexpr int kTab = detail::LegendreTables::kBands;
    constexpr int kShift = 400;
    constexpr double kBig = 0x1p400, kSmall = 0x1p-400;  // 2^±kShift
    double pm = 0.28209479177387814;  // N_0^0 = 1/√(4π); sectoral N_m^m = pm · 2^pe
    int pe = 0;
    for (int m = 0; m < n; ++m) {
        if (m > 0) {
            pm *= -(m < kTab ? T.sect[m] : std::sqrt((2.0 * m + 1.0) / (2.0 * m))) * s;
            if (pm != 0.0 && std::fabs(pm) < kSmall) {
                pm *= kBig;
                pe -= kShift;
            }
        }
        int e = pe;
        double p2 = pm;
        f(m, m, e == 0 ? p2 : std::ldexp(p2, e));
        if (m + 1 >= n) break;
        double p1 = (m < kTab ? T.next[m] : std::sqrt(2.0 * m + 3.0)) * z * p2;
        f(m + 1, m, e == 0 ? p1 : std::ldexp(p1, e));
        if (e == 0 && n <= kTab) {
            // The common column: unscaled and tabulated throughout, the same arithmetic without
            // the tests per value (the product sampler's lobe rotation spent 24% of an order-32
            // render here; helper 169).
            for (int l = m + 2, i = (m + 2) * (m + 3) / 2 + m; l < n; i += ++l) {
                const double p = T.a[i] * (z * p1 - T.b[i] * p2);
                p2 = p1;
                p1 = p;
                f(l, m, p1);
            }
            continue;
        }
        for (int l = m + 2; l < n; ++l) {
            double a, b;
            if (l < kTab) {
                const int i = l * (l + 1) / 2 + m;
                a = T.a[i];
                b = T.b[i];
            } else {
                const double ll = l, mm = m;
                a = std::sqrt((4.0 * ll * ll - 1.0) / ((ll - mm) * (ll + mm)));
                b = std::sqrt(((ll - 1.0 - mm) * (ll - 1.0 + mm)) /
                              (4.0 * (ll - 1.0) * (ll - 1.0) - 1.0));
            }
            const double p = a * (z * p1 - b * p2);
            p2 = p1;
            p1 = p;
            if (e < 0 && std::fabs(p1) > kBig) {
                p1 *= kSmall;
                p2 *= kSmall;
                e += kShift;
            }
            f(l, m, e == 0 ? p1 : std::ldexp(p1, e));
        }
    }
}

}  // namespace shvol::sh
