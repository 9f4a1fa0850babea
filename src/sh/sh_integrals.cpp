#include "shvol/sh/sh_integrals.h"

#include <cmath>
#include <vector>

namespace shvol::sh {

namespace {

constexpr double kN00 = 0.28209479177387814;  // 1/√(4π)
constexpr int kMaxNarrowPanels = 4;

bool isNarrow(int n, double z0, double z1) {
    const double n1 = n + 1.0;
    return std::fabs(z1 - z0) < kNarrowCoef * n1 * std::sqrt(n1);
}

// Coefficients of the normalised DiDonato recurrences (see sh_integrals.h), tabulated for
// l < kBands: alpha (J_{l−2}^m factor), beta (boundary factor), diag (J_{l−2}^{l−2} factor).
struct IntegralTables {
    static constexpr int kBands = 160;
    std::vector<double> alpha, beta, diag;
};

inline double coefAlpha(int l, int m) {
    const double L = l, M = m;
    if (m >= l - 1) return 0.0;
    return (L - 2) / (L + 1) *
           std::sqrt((2 * L + 1) * (L + M - 1) * (L - M - 1) / ((2 * L - 3) * (L + M) * (L - M)));
}
inline double coefBeta(int l, int m) {
    const double L = l, M = m;
    return std::sqrt((2 * L + 1) * (2 * L - 1) / ((L + M) * (L - M))) / (L + 1);
}
inline double coefDiag(int l) {
    const double L = l;
    return 0.5 * std::sqrt(L * (2 * L + 1) * (2 * L - 1) / (L - 1)) / (L + 1);
}

const IntegralTables& integralTables() {
    static const IntegralTables* t = [] {
        auto* r = new IntegralTables;
        const int L = IntegralTables::kBands;
        r->alpha.assign(triSize(L), 0.0);
        r->beta.assign(triSize(L), 0.0);
        r->diag.assign(L, 0.0);
        for (int l = 1; l < L; ++l) {
            for (int m = 0; m < l; ++m) {
                r->alpha[triIndex(l, m)] = coefAlpha(l, m);
                r->beta[triIndex(l, m)] = coefBeta(l, m);
            }
            if (l >= 2) r->diag[l] = coefDiag(l);
        }
        return r;
    }();
    return *t;
}

// Writes into D[triIndex(l, m)] the bracketed boundary quantity that J_l^m needs, at z, with
// the given sign: (1−z²) N_{l−1}^m(z) for l > m, z N_l^l(z) on the diagonal.
void addBoundaryTerms(int n, double z, double sign, double* D, bool assign) {
    const double zc = std::clamp(z, -1.0, 1.0);
    const double s = std::sqrt((1.0 - zc) * (1.0 + zc));
    const double q = (1.0 - zc) * (1.0 + zc);
    forEachLegendre(n, zc, s, [&](int l, int m, double v) {
        const int d = triIndex(l, m);
        if (assign) {
            if (l == m) D[d] = sign * zc * v;
            if (l + 1 < n) D[triIndex(l + 1, m)] = sign * q * v;
        } else {
            if (l == m) D[d] += sign * zc * v;
            if (l + 1 < n) D[triIndex(l + 1, m)] += sign * q * v;
        }
    });
}

}  // namespace

void legendreIntegrals(int n, double z0, double z1, double* J) {
    if (n <= 0) return;
    if (isNarrow(n, z0, z1)) {
        for (int i = 0; i < triSize(n); ++i) J[i] = 0.0;
        const bool ok =
            forEachNarrowNode(n, z0, z1, kMaxNarrowPanels, [&](double z, double s, double wt) {
                forEachLegendre(n, z, s,
                                [&](int l, int m, double v) { J[triIndex(l, m)] += wt * v; });
            });
        if (ok) return;
    }
    legendreIntegralsRecurrence(n, z0, z1, J);
}

void legendreIntegralsRecurrence(int n, double z0, double z1, double* J) {
    if (n <= 0) return;
    // Boundary differences, then the normalised DiDonato recurrences in place (l ascending, so
    // J_{l−2}^m and J_{l−2}^{l−2} are final when J_l^m is formed).
    addBoundaryTerms(n, z1, 1.0, J, true);
    addBoundaryTerms(n, z0, -1.0, J, false);
    const double a = std::clamp(z0, -1.0, 1.0), b = std::clamp(z1, -1.0, 1.0);
    J[0] = kN00 * (z1 - z0);
    if (n == 1) return;
    {
        const double sa = std::sqrt((1.0 - a) * (1.0 + a)), sb = std::sqrt((1.0 - b) * (1.0 + b));
        J[triIndex(1, 1)] =
            -0.3454941494713355 * 0.5 * ((b * sb - a * sa) + (std::asin(b) - std::asin(a)));
    }
    const IntegralTables& T = integralTables();
    for (int l = 1; l < n; ++l) {
        const bool tab = l < IntegralTables::kBands;
        const int base = triIndex(l, 0), base2 = l >= 2 ? triIndex(l - 2, 0) : 0;
        for (int m = 0; m < l; ++m) {
            const double beta = tab ? T.beta[base + m] : coefBeta(l, m);
            double v = -beta * J[base + m];
            if (m < l - 1) v += (tab ? T.alpha[base + m] : coefAlpha(l, m)) * J[base2 + m];
            J[base + m] = v;
        }
        if (l >= 2) {
            const double c = tab ? T.diag[l] : coefDiag(l);
            J[base + l] = c * J[base2 + l - 2] + J[base + l] / (l + 1.0);
        }
    }
}

void legendreIntegralsZonal(int n, double z0, double z1, double* Z) {
    if (n <= 0) return;
    const detail::LegendreTables& T = detail::legendreTables();
    auto zonalValues = [&](double z, auto&& sink) {
        double p2 = kN00, p1 = std::sqrt(3.0) * z * kN00;
        sink(0, p2);
        if (n > 1) sink(1, p1);
        for (int l = 2; l < n; ++l) {
            const bool tab = l < detail::LegendreTables::kBands;
            const double a = tab ? T.a[triIndex(l, 0)] : legendreA(l, 0);
            const double b = tab ? T.b[triIndex(l, 0)] : legendreB(l, 0);
            const double p = a * (z * p1 - b * p2);
            p2 = p1;
            p1 = p;
            sink(l, p1);
        }
    };
    if (isNarrow(n, z0, z1)) {
        for (int l = 0; l < n; ++l) Z[l] = 0.0;
        const bool ok =
            forEachNarrowNode(n, z0, z1, kMaxNarrowPanels, [&](double z, double, double wt) {
                zonalValues(z, [&](int l, double v) { Z[l] += wt * v; });
            });
        if (ok) return;
    }
    const double a = std::clamp(z0, -1.0, 1.0), b = std::clamp(z1, -1.0, 1.0);
    const double qa = (1 - a) * (1 + a), qb = (1 - b) * (1 + b);
    // Z[l] temporarily holds [(1−z²) N_{l−1}^0]; l = 0 is set directly.
    zonalValues(b, [&](int l, double v) {
        if (l + 1 < n) Z[l + 1] = qb * v;
    });
    zonalValues(a, [&](int l, double v) {
        if (l + 1 < n) Z[l + 1] -= qa * v;
    });
    Z[0] = kN00 * (z1 - z0);
    const IntegralTables& IT = integralTables();
    for (int l = 1; l < n; ++l) {
        const bool tab = l < IntegralTables::kBands;
        double v = -(tab ? IT.beta[triIndex(l, 0)] : coefBeta(l, 0)) * Z[l];
        if (l >= 2) v += (tab ? IT.alpha[triIndex(l, 0)] : coefAlpha(l, 0)) * Z[l - 2];
        Z[l] = v;
    }
}

void phiIntegrals(int n, double phi0, double phi1, double* C, double* S) {
    if (n <= 0) return;
    const double h = 0.5 * (phi1 - phi0), c = 0.5 * (phi0 + phi1);
    C[0] = phi1 - phi0;
    S[0] = 0.0;
    const double cc = std::cos(c), sc = std::sin(c), ch = std::cos(h), sh = std::sin(h);
    double cmc = 1.0, smc = 0.0, cmh = 1.0, smh = 0.0;
    for (int m = 1; m < n; ++m) {
        double t = cmc * cc - smc * sc;
        smc = smc * cc + cmc * sc;
        cmc = t;
        t = cmh * ch - smh * sh;
        smh = smh * ch + cmh * sh;
        cmh = t;
        const double f = 2.0 * smh / m;
        C[m] = f * cmc;
        S[m] = f * smc;
    }
}

void shRectIntegrals(int n, double z0, double z1, double phi0, double phi1, double* out,
                     double* work) {
    double* J = work;
    double* C = work + triSize(n);
    double* S = C + n;
    legendreIntegrals(n, z0, z1, J);
    phiIntegrals(n, phi0, phi1, C, S);
    const double r2 = 1.4142135623730951;
    for (int l = 0; l < n; ++l) {
        const int c = l * (l + 1);
        const double* Jl = J + triIndex(l, 0);
        out[c] = Jl[0] * C[0];
        for (int m = 1; m <= l; ++m) {
            const double v = r2 * Jl[m];
            out[c + m] = v * C[m];
            out[c - m] = v * S[m];
        }
    }
}

void shRectIntegrals(int n, double z0, double z1, double phi0, double phi1, double* out) {
    if (n <= 64) {
        double work[rectIntegralsWorkSize(64)];
        shRectIntegrals(n, z0, z1, phi0, phi1, out, work);
    } else {
        thread_local std::vector<double> work;
        if (static_cast<int>(work.size()) < rectIntegralsWorkSize(n))
            work.resize(rectIntegralsWorkSize(n));
        shRectIntegrals(n, z0, z1, phi0, phi1, out, work.data());
    }
}

}  // namespace shvol::sh
