#pragma once
/// \file Rotation of real SH coefficient vectors.
///
/// Convention (DESIGN.md): rotating f by R means f′(ω) = f(R⁻¹ω), so a lobe around +z rotated
/// by R points along R·ẑ. Coefficients transform band by band, f′_l = R^l f_l.
///
/// Method: Ivanic & Ruedenberg, J. Phys. Chem. 100 (1996) 6342, with the corrections of
/// J. Phys. Chem. A 102 (1998) 9099: R^l is built from R^{l−1} and R^1 by the u·U + v·V + w·W
/// recursion (Table 2 / eqs. 8.1–8.7 of the 1998 version). IR's real harmonics carry no
/// Condon–Shortley phase; ours do, so y_l^m = (−1)^m S_lm and R^l_{mm′} = (−1)^{m+m′} R^l_{IR,mm′}.
/// R^1 in IR's basis is R permuted to (y, z, x) order. Orthogonality error vs l is measured in
/// validation/sh (≈ ε·l growth; see README.md there).
#include <Eigen/Core>
#include <vector>

#include "shvol/core/math.h"

namespace shvol::sh {

/// Per-band rotation matrices for order n.
struct ShRotation {
    int n = 0;
    /// bands[l] is (2l+1)×(2l+1), row/column index m + l.
    std::vector<Eigen::MatrixXd> bands;

    ShRotation() = default;
    /// Builds R^0 … R^{n−1} for the 3×3 rotation R (f′(ω) = f(R⁻¹ω)).
    ShRotation(int n, const Eigen::Matrix3d& R);

    /// out = R in (n² doubles each; in ≠ out).
    void apply(const double* in, double* out) const;
    Eigen::VectorXd apply(const Eigen::VectorXd& in) const;
    /// The n²×n² block-diagonal matrix.
    Eigen::MatrixXd matrix() const;
};

/// Zonal fast path: coefficients of p(μ) = Σ p_l y_l^0(μ), rotated so that its axis +z goes to
/// the unit vector d:  f_l^m = √(4π/(2l+1)) p_l y_l^m(d)  (the addition theorem). p has n
/// entries, out n². No allocation for n ≤ 64.
void rotateZonal(int n, const double* p, const Vec3& d, double* out);
Eigen::VectorXd rotateZonal(const Eigen::VectorXd& p, const Vec3& d);

/// A rotation taking +z to the unit vector d (the shortest-arc one; any rotation with R·ẑ = d
/// gives the same rotated zonal function).
Eigen::Matrix3d rotationTo(const Vec3& d);
/// R = Rz(α) Ry(β) Rz(γ) (the ZYZ Euler convention of Gautron §4).
Eigen::Matrix3d rotationZYZ(double alpha, double beta, double gamma);

}  // namespace shvol::sh
