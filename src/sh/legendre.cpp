#include "shvol/sh/legendre.h"

#include <algorithm>
#include <cmath>

namespace shvol::sh {

double legendreA(int l, int m) {
    const double ll = l, mm = m;
    return std::sqrt((4.0 * ll * ll - 1.0) / ((ll - mm) * (ll + mm)));
}

double legendreB(int l, int m) {
    const double ll = l, mm = m;
    return std::sqrt(((ll - 1.0 - mm) * (ll - 1.0 + mm)) / (4.0 * (ll - 1.0) * (ll - 1.0) - 1.0));
}

namespace detail {
static LegendreTables makeTables() {
    LegendreTables t{};
    constexpr int L = LegendreTables::kBands;
    for (int l = 0; l < L; ++l)
        for (int m = 0; m <= l; ++m) {
            const int i = l * (l + 1) / 2 + m;
            t.a[i] = (l >= m + 2) ? legendreA(l, m) : 0.0;
            t.b[i] = (l >= m + 2) ? legendreB(l, m) : 0.0;
        }
    t.sect[0] = 0.0;
    for (int m = 1; m < L; ++m) t.sect[m] = std::sqrt((2.0 * m + 1.0) / (2.0 * m));
    for (int m = 0; m < L; ++m) t.next[m] = std::sqrt(2.0 * m + 3.0);
    return t;
}

const LegendreTables& legendreTables() {
    static const LegendreTables* tables = new LegendreTables(makeTables());
    return *tables;
}
}  // namespace detail

void legendreNormalized(int n, double z, double s, double* out) {
    forEachLegendre(n, z, s, [out](int l, int m, double v) { out[triIndex(l, m)] = v; });
}

void legendreNormalized(int n, double z, double* out) {
    z = std::clamp(z, -1.0, 1.0);
    legendreNormalized(n, z, std::sqrt((1.0 - z) * (1.0 + z)), out);
}

double legendreNormalized(int l, int m, double z) {
    z = std::clamp(z, -1.0, 1.0);
    const double s = std::sqrt((1.0 - z) * (1.0 + z));
    // Sectoral diagonal, then the column, with the extended-range scaling of forEachLegendre.
    constexpr int kShift = 400;
    const double kBig = std::ldexp(1.0, kShift), kSmall = std::ldexp(1.0, -kShift);
    double pm = 0.28209479177387814;
    int e = 0;
    for (int k = 1; k <= m; ++k) {
        pm *= -std::sqrt((2.0 * k + 1.0) / (2.0 * k)) * s;
        if (pm != 0.0 && std::fabs(pm) < kSmall) {
            pm *= kBig;
            e -= kShift;
        }
    }
    if (l == m) return std::ldexp(pm, e);
    double p2 = pm, p1 = std::sqrt(2.0 * m + 3.0) * z * pm;
    for (int ll = m + 2; ll <= l; ++ll) {
        const double p = legendreA(ll, m) * (z * p1 - legendreB(ll, m) * p2);
        p2 = p1;
        p1 = p;
        if (e < 0 && std::fabs(p1) > kBig) {
            p1 *= kSmall;
            p2 *= kSmall;
            e += kShift;
        }
    }
    return std::ldexp(p1, e);
}

}  // namespace shvol::sh
