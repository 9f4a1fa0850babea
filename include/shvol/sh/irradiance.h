#pragma once
/// \file Clamped-cosine convolution: irradiance from SH radiance (Ramamoorthi & Hanrahan 2001,
/// as summarised in sh-blog-irradiance-notes.md).
///
/// E(n) = ∫ L(ω) max(0, n·ω) dω = Σ_{l,m} Â_l L_l^m y_l^m(n), with
///   Â_l = 2π ∫_0^1 P_l(z) z dz:  Â_0 = π, Â_1 = 2π/3, Â_l = 0 for odd l > 1,
///   Â_l = 2π (−1)^{l/2−1} / ((l+2)(l−1)) · l! / (2^l ((l/2)!)²) for even l,
/// the central binomial factor computed by a ratio recurrence (no overflow at any l).
#include <Eigen/Core>

#include "shvol/core/math.h"

namespace shvol::sh {

/// Â_l (π, 2.094395, 0.785398, 0, −0.130900, 0, 0.049087, …).
double clampedCosineCoeff(int l);
/// E_l^m = Â_l L_l^m for an order-n radiance vector.
Eigen::VectorXd irradianceCoeffs(const Eigen::VectorXd& radiance);
/// E(normal) = Σ Â_l L_l^m y_l^m(normal).
double irradiance(const Eigen::VectorXd& radiance, const Vec3& normal);

}  // namespace shvol::sh
