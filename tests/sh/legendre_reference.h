#pragma once
// The long-double Legendre reference shared by tests/sh and validation/sh.
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

}  // namespace shvol::sh::reference
