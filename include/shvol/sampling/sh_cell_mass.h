#pragma once
/// \file The mass of an SH expansion over a (z, φ) cell from separable 1D integrals (Jarosz,
/// Carr & Jensen 2009, eqs. 3 and 17), shared by the SH sampler and the product sampler.
///
/// With J_l^m = ∫ N_l^m dz over the cell's z-interval (sh_integrals.h) and C[m], S[m] = ∫ cos(mφ),
/// ∫ sin(mφ) dφ over its φ-interval, the mass of f̃ = Σ f_l^m y_l^m over the cell is
///   M = A[0]·C[0] + √2 Σ_{m≥1} (A[m]·C[m] + B[m]·S[m]),
///   A[m] = Σ_{l≥m} f_l^m J_l^m,  B[m] = Σ_{l≥m} f_l^{−m} J_l^m,
/// so one z-interval costs O(n²) (weightByCoefficients) and each φ-interval then O(n) (cellMass).
#include "shvol/sh/legendre.h"

namespace shvol {

/// A[m], B[m] (n doubles each) of the coefficients f (n², flat index l(l+1)+m) for one
/// z-interval whose Legendre integrals are J (triSize(n), index triIndex(l, m)).
inline void weightByCoefficients(int n, const double* f, const double* J, double* A, double* B) {
    for (int m = 0; m < n; ++m) A[m] = B[m] = 0;
    for (int l = 0; l < n; ++l) {
        const double* Jl = J + sh::triIndex(l, 0);
        const int c = l * (l + 1);
        A[0] += f[c] * Jl[0];
        for (int m = 1; m <= l; ++m) {
            A[m] += f[c + m] * Jl[m];
            B[m] += f[c - m] * Jl[m];
        }
    }
}

/// The cell mass M from A, B and one φ-interval's C, S.
inline double cellMass(int n, const double* A, const double* B, const double* C, const double* S) {
    constexpr double Sqrt2 = 1.4142135623730951;
    double s = 0;
    for (int m = 1; m < n; ++m) s += A[m] * C[m] + B[m] * S[m];
    return A[0] * C[0] + Sqrt2 * s;
}

}  // namespace shvol
