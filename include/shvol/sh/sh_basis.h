#pragma once
/// \file Real spherical harmonics y_l^m: evaluation of all n² basis functions at a direction.
///
/// Convention (DESIGN.md, Jarosz 2009 eq. 1 with the Condon–Shortley phase inside P_l^m):
///   y_l^0 = N_l^0(cos θ),  y_l^m = √2 N_l^m(cos θ) cos(mφ),  y_l^{−m} = √2 N_l^m(cos θ) sin(mφ),
/// with N_l^m from legendre.h, so that y_1^{−1} = −√(3/4π) y, y_1^0 = √(3/4π) z,
/// y_1^1 = −√(3/4π) x (the l ≤ 2 table of sh-blog-irradiance-notes.md, signs included).
/// Flat index i = l(l+1)+m; "order n" = n bands l = 0 … n−1 = n² coefficients.
#include <Eigen/Core>

#include "shvol/core/math.h"

namespace shvol::sh {

/// Flat index of y_l^m (Jarosz 2009 §3.1).
constexpr int shIndex(int l, int m) {
    return l * (l + 1) + m;
}
/// Number of coefficients of order n.
constexpr int shSize(int n) {
    return n * n;
}
/// Band l of a flat index i.
int shBand(int i);

/// Largest order served by the hard-coded fast path.
inline constexpr int kShFastMaxOrder = 5;

/// All y_i(ω), i < n², into out (n² doubles). ω must be a unit vector. No allocation.
/// Uses the hard-coded polynomials for n ≤ kShFastMaxOrder, the recurrence otherwise.
void shEval(int n, const Vec3& w, double* out);
/// The general path: Legendre column recurrence × multiple-angle recurrence for cos mφ, sin mφ
/// (cos φ = x/s, sin φ = y/s with s = √(x²+y²); φ = 0 at the poles). Any n (tested to 1000).
void shEvalRecurrence(int n, const Vec3& w, double* out);
/// The fast path: Cartesian polynomials for l ≤ 4 (n ≤ 5). Tested against shEvalRecurrence.
void shEvalFast(int n, const Vec3& w, double* out);
/// Convenience: returns the n² values.
Eigen::VectorXd shEval(int n, const Vec3& w);
/// One basis function y_l^m(ω).
double shEvalSingle(int l, int m, const Vec3& w);

/// Zonal functions y_l^0(z) = N_l^0(z), l < n, into out (n doubles). No allocation.
void shEvalZonal(int n, double z, double* out);

/// Σ_i c_i y_i(ω): evaluates an order-n SH expansion (reconstruction, Jarosz eq. 2).
double shReconstruct(int n, const double* coeffs, const Vec3& w);
inline double shReconstruct(const Eigen::VectorXd& c, int n, const Vec3& w) {
    return shReconstruct(n, c.data(), w);
}

}  // namespace shvol::sh
