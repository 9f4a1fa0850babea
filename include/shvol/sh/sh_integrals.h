#pragma once
/// \file Integrals of the SH basis over (z, φ) rectangles (Jarosz 2009 §4.1, eqs. 7–17).
///
///   ŷ_l^m = ∫_{z0}^{z1} ∫_{φ0}^{φ1} y_l^m dφ dz = J_l^{|m|} · √2 {∫cos(mφ) | ∫sin(|m|φ)} dφ,
///   J_l^m = ∫_{z0}^{z1} N_l^m(z) dz   (N from legendre.h, the 1/√(4π)-normalised functions).
///
/// Legendre integrals: the DiDonato recurrences of Jarosz Algorithm 1 (eqs. 9–13) overflow at
/// high l because they run on the unnormalised P_l^m. Multiplying eq. 9 by K_l^m gives, for
/// 0 ≤ m < l (derived here; checked against quadrature in tests/sh/sh_integrals_test.cpp),
///   J_l^m = (l−2)/(l+1) · √((2l+1)(l+m−1)(l−m−1) / ((2l−3)(l+m)(l−m))) · J_{l−2}^m
///           − 1/(l+1) · √((2l+1)(2l−1) / ((l+m)(l−m))) · [(1−z²) N_{l−1}^m(z)]_{z0}^{z1}
/// (the first term vanishes for m = l−1), and eq. 10 becomes, for l ≥ 2,
///   J_l^l = ( ½√(l(2l+1)(2l−1)/(l−1)) · J_{l−2}^{l−2} + [z N_l^l(z)]_{z0}^{z1} ) / (l+1),
/// seeded with J_0^0 = N_0^0 (z1−z0) (eq. 11) and, with the Condon–Shortley sign that Jarosz's
/// eq. 13 omits, J_1^1 = −√(3/8π) · ½ [z√(1−z²) + asin z]_{z0}^{z1}. All coefficients are O(1)
/// and the J_{l−2} factor is < 1, so errors do not grow with l. Errors are absolute, on the scale
/// env·min(1, z1−z0): an integral that is itself far smaller (m > 0 next to a pole, where
/// N_l^m ∝ (1−z²)^{m/2}) is not resolved to its own relative precision.
///
/// Narrow intervals: the bracketed differences cancel catastrophically when z1 − z0 is small
/// (their absolute error is a few ε·env, i.e. ≈ ε/(z1−z0) relative). When z1 − z0 <
/// kNarrowCoef·(n+1)^{3/2} the integrals are instead computed by 2-, 4- or 8-point Gauss–Legendre
/// panels in θ (z = cos θ, dz = sin θ dθ), with one panel per radian/(n+1) of θ: the integrand
/// N_l^m(cos θ) sin θ is a trigonometric polynomial of degree ≤ n, so the rule is exact to
/// rounding, including intervals touching z = ±1 (where a rule in z would meet the √(1−z²) branch
/// point). The θ width is computed from the chord, 2 asin(½ (z1−z0) √(1 + ((z0+z1)/(s0+s1))²)),
/// without cancellation.
#include <algorithm>
#include <cmath>

#include "shvol/sh/legendre.h"

namespace shvol::sh {

/// Switch to quadrature when z1 − z0 < kNarrowCoef · (n+1)^{3/2} (and ≤ 4 panels are needed).
inline constexpr double kNarrowCoef = 2e-5;

/// J_l^m = ∫_{z0}^{z1} N_l^m(z) dz for 0 ≤ m ≤ l < n into J[triIndex(l, m)] (triSize(n)
/// doubles). z0, z1 ∈ [−1, 1] (z0 > z1 gives the signed integral). No allocation.
/// Accuracy, with env = √((2l+1)/4π) (validation/sh/README.md §2, n ≤ 100, 10 interval kinds):
/// |error| ≤ 2.5e-13 · env · min(1, z1−z0), down to widths of 1e-12 and at the poles. Model: the
/// recurrence's absolute error is a few ε·env whatever the width (so ≈ ε/(z1−z0) relative), hence
/// the switch to the narrow rule, whose error is that of the Legendre values (≈ ε·l^{3/2}).
/// For very high n the rule is skipped when it would need more than 4 panels, and the
/// recurrence's ε/(z1−z0) behaviour applies there.
void legendreIntegrals(int n, double z0, double z1, double* J);

/// The recurrence alone, without the narrow-interval switch (for validation: shows the
/// cancellation that the switch avoids).
void legendreIntegralsRecurrence(int n, double z0, double z1, double* J);

/// The zonal subset Z_l = ∫_{z0}^{z1} y_l^0(z) dz = J_l^0, l < n, into Z (n doubles); costs
/// O(n) (O(n) per panel in the narrow case). No allocation.
void legendreIntegralsZonal(int n, double z0, double z1, double* Z);

/// φ integrals (Jarosz eq. 14) for m = 0 … n−1: C[m] = ∫_{φ0}^{φ1} cos(mφ) dφ and
/// S[m] = ∫_{φ0}^{φ1} sin(mφ) dφ, written without cancellation as
///   C[m] = (2/m) cos(mφc) sin(mh),  S[m] = (2/m) sin(mφc) sin(mh),  φc = (φ0+φ1)/2, h = (φ1−φ0)/2,
/// where cos(mφc), sin(mφc), sin(mh) come from the multiple-angle recurrences (Jarosz eqs. 15–16,
/// in their complex-rotation form) seeded by a single sin/cos pair each. No allocation.
void phiIntegrals(int n, double phi0, double phi1, double* C, double* S);

/// Doubles of workspace needed by shRectIntegrals.
constexpr int rectIntegralsWorkSize(int n) {
    return n * (n + 1) / 2 + 2 * n;
}

/// ŷ_i = ∫_{z0}^{z1} ∫_{φ0}^{φ1} y_i dφ dz for i < n² into out (Jarosz eq. 17). work must hold
/// rectIntegralsWorkSize(n) doubles. No allocation.
void shRectIntegrals(int n, double z0, double z1, double phi0, double phi1, double* out,
                     double* work);
/// Same, with an internal workspace (on the stack for n ≤ 64, else a per-thread buffer).
void shRectIntegrals(int n, double z0, double z1, double phi0, double phi1, double* out);

/// Visits the nodes of the narrow-interval rule on [z0, z1]: f(z, s, weight) with s = √(1−z²)
/// and Σ weight·g(z) ≈ ∫_{z0}^{z1} g(z) dz, exact to rounding for g(cos θ) sin θ a trigonometric
/// polynomial of degree ≤ n (Gauss–Legendre panels in θ, ⌈(n+1)Δθ⌉ of them, 2–8 points each).
/// Returns false without calling f when more than maxPanels panels would be needed.
template <class F>
bool forEachNarrowNode(int n, double z0, double z1, int maxPanels, F&& f) {
    // Gauss–Legendre rules on [−1, 1] with 2, 4 and 8 points (positive half; symmetric).
    static constexpr double x2[1] = {0.5773502691896258};
    static constexpr double w2[1] = {1.0};
    static constexpr double x4[2] = {0.3399810435848563, 0.8611363115940526};
    static constexpr double w4[2] = {0.6521451548625461, 0.3478548451374538};
    static constexpr double x8[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                                     0.9602898564975363};
    static constexpr double w8[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                                     0.1012285362903763};
    const double s0 = std::sqrt((1.0 - z0) * (1.0 + z0)), s1 = std::sqrt((1.0 - z1) * (1.0 + z1));
    const double w = z1 - z0;
    if (w == 0.0) return true;
    const double ss = s0 + s1;
    const double ratio = ss > 0.0 ? (z0 + z1) / ss : 0.0;
    const double dth =
        2.0 * std::asin(std::min(1.0, 0.5 * std::fabs(w) * std::sqrt(1.0 + ratio * ratio)));
    const int panels = std::max(1, static_cast<int>(std::ceil((n + 1) * dth)));
    if (panels > maxPanels) return false;
    // Points per panel: the k-point rule's relative error for e^{iνu} over a panel of width Δ is
    // about x^{2k} (k!)⁴ / ((2k+1)((2k)!)³), x = νΔ ≤ 1; below 1e-17 for k = 2 when
    // x ≤ 4.6e-4, k = 4 when x ≤ 0.1, k = 8 when x ≤ 1.
    const double x = (n + 1) * dth / panels;
    const int half = x <= 4.6e-4 ? 1 : (x <= 0.1 ? 2 : 4);
    const double* gx = half == 1 ? x2 : (half == 2 ? x4 : x8);
    const double* gw = half == 1 ? w2 : (half == 2 ? w4 : w8);
    // θ runs from θ(upper z) to θ(upper z) + dth; u is the offset from θ(upper z).
    const double sign = w > 0 ? 1.0 : -1.0;
    const double zt = w > 0 ? z1 : z0, st = w > 0 ? s1 : s0;
    const double hp = 0.5 * dth / panels;
    for (int p = 0; p < panels; ++p) {
        const double uc = (2 * p + 1) * hp;
        for (int k = 0; k < 2 * half; ++k) {
            const double u = uc + (k < half ? -gx[k] : gx[k - half]) * hp;
            const double cu = std::cos(u), su = std::sin(u);
            const double z = zt * cu - st * su;
            const double s = st * cu + zt * su;
            f(z, s, sign * gw[k < half ? k : k - half] * hp * s);
        }
    }
    return true;
}

}  // namespace shvol::sh
