#pragma once
/// \file Fully normalised associated Legendre functions, stable for every l ≤ 1000 and z ∈ [−1, 1].
///
/// Convention (DESIGN.md): the Condon–Shortley phase (−1)^m is inside P_l^m, and the functions
/// returned here carry the spherical-harmonic normalisation
///
///   N_l^m(z) = K_l^m P_l^m(z),   K_l^m = √((2l+1)/(4π) · (l−m)!/(l+m)!),   0 ≤ m ≤ l,
///
/// (Gautron 2004 eq. 4; the N of the blog notes), so that the real SH of Jarosz 2009 eq. 1 are
/// y_l^0 = N_l^0(cos θ), y_l^m = √2 N_l^m cos(mφ), y_l^{−m} = √2 N_l^m sin(mφ), and
/// ∫_{−1}^{1} N_l^m(z)² dz = 1/(2π).
///
/// Method: the normalised three-term recurrences (as in geodesy, Holmes & Featherstone 2002,
/// J. Geodesy 76, written here for the 1/√(4π) normalisation)
///   N_0^0 = 1/√(4π),
///   N_m^m = −√((2m+1)/(2m)) · s · N_{m−1}^{m−1},              s = √(1−z²)   (sectoral),
///   N_{m+1}^m = √(2m+3) · z · N_m^m,
///   N_l^m = a_l^m (z N_{l−1}^m − b_l^m N_{l−2}^m),
///       a_l^m = √((4l²−1)/(l²−m²)),  b_l^m = √(((l−1)²−m²)/(4(l−1)²−1)).
/// The unnormalised forms overflow near l = 86; the normalised ones are bounded by √((2l+1)/4π).
/// The sectoral seeds s^m underflow near the poles even when N_l^m for l ≫ m is representable,
/// so each column is carried as an extended-range number (mantissa × 2^e, the "X-number" cure
/// of Fukushima 2012 / the 10^-280 scaling of Holmes & Featherstone): values are exact to
/// rounding until the very end, where 2^e is applied (and underflows only if the true value does).
///
/// Accuracy: the rounding error grows like ε·l^{3/2} relative to the envelope √((2l+1)/4π) (the
/// recurrence has a double characteristic root at z = ±1, so a rounding error grows linearly and
/// those errors add up as a random walk). Measured against 50-digit boost::math::legendre_p:
/// ≈ 1.2e-12 relative at l = 1000 (see validation/sh/README.md), tests assert ε·(l+10)^{3/2}.
#include <cstddef>

namespace shvol::sh {

/// Packed index of (l, m), 0 ≤ m ≤ l, in triangular arrays: l(l+1)/2 + m.
constexpr int triIndex(int l, int m) {
    return l * (l + 1) / 2 + m;
}
/// Size of a triangular array holding l = 0 … n−1.
constexpr int triSize(int n) {
    return n * (n + 1) / 2;
}

/// All N_l^m(z) for 0 ≤ m ≤ l < n into out[triIndex(l, m)] (triSize(n) doubles). No allocation.
/// z is clamped to [−1, 1]. s = √(1−z²) is computed as √((1−z)(1+z)) for accuracy at the poles.
void legendreNormalized(int n, double z, double* out);

/// Same, with s = sin θ supplied by the caller (for z = cos θ known with its sine, e.g. from a
/// direction vector, s = √(x²+y²) is more accurate than √(1−z²) near the poles).
void legendreNormalized(int n, double z, double s, double* out);

/// One value N_l^m(z), 0 ≤ m ≤ l (O(l) work).
double legendreNormalized(int l, int m, double z);

/// Column visitor used by the SH evaluation and integral code: for m = 0 … n−1 and l = m … n−1
/// calls f(l, m, N_l^m(z)) in that order. Inline so that the caller's loop body is fused.
template <class F>
void forEachLegendre(int n, double z, double s, F&& f);

/// The recurrence coefficients a_l^m, b_l^m (see the file comment).
double legendreA(int l, int m);
double legendreB(int l, int m);

}  // namespace shvol::sh

#include "shvol/sh/legendre_inl.h"
