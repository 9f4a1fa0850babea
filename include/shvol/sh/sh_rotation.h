#pragma once
/// \file Rotation of real SH coefficient vectors.
///
/// Convention (DESIGN.md): rotating f by R means f′(ω) = f(R⁻¹ω), so a lobe around +z rotated
/// by R points along R·ẑ. Coefficients transform band by band, f′_l = R^l f_l.
///
/// Methods (see RotationMethod): Ivanic & Ruedenberg, J. Phys. Chem. 100 (1996) 6342, with the
/// corrections of J. Phys. Chem. A 102 (1998) 9099: R^l is built from R^{l−1} and R^1 by the u·U +
/// v·V + w·W recursion (in the corrected form of the 1998 note). IR's real harmonics carry no
/// Condon–Shortley phase; ours do, so y_l^m = (−1)^m S_lm and R^l_{mm′} = (−1)^{m+m′} R^l_{IR,mm′}.
/// R^1 in IR's basis is R permuted to (y, z, x) order. IR's rounding errors grow ×10 per ~10
/// bands beyond l ≈ 35, so high bands use a backward-stable Euler/eigen construction instead
/// (RotationMethod; errors vs l for both in validation/sh/README.md §5).
#include <Eigen/Core>
#include <vector>

#include "shvol/core/math.h"

namespace shvol::sh {

/// How the band matrices are built.
enum class RotationMethod {
    /// Ivanic–Ruedenberg recursion: O(l²) per band, accurate to ~1e-13 up to l ≈ 40, but its
    /// rounding errors grow about ×10 per 10 bands beyond (measured: 9e-12 at l = 60, 5e-8 at
    /// l = 100, 3e-6 at l = 120; validation/sh/results/rotation_error.csv).
    IvanicRuedenberg,
    /// Euler ZYZ: D(R) = Z(α) Y(β) Z(γ), with Y(β) = Re(V e^{−iβΛ} V^H) from the (cached)
    /// eigen-decomposition of the real-basis matrix of the angular-momentum operator L_y (whose
    /// eigenvalues are the integers −l … l), and Z the exact 2×2 (m, −m) rotations. Backward
    /// stable (error ≈ ε·l); O(l³) per band. Near gimbal lock R is first multiplied by a fixed
    /// 90° x-rotation so that the Euler angles stay well conditioned.
    EulerEigen,
    /// IR for l < kRotationIrBands, EulerEigen above.
    Auto
};
inline constexpr int kRotationIrBands = 32;

/// Per-band rotation matrices for order n.
struct ShRotation {
    int n = 0;
    /// bands[l] is (2l+1)×(2l+1), row/column index m + l.
    std::vector<Eigen::MatrixXd> bands;

    ShRotation() = default;
    /// Builds R^0 … R^{n−1} for the 3×3 rotation R (f′(ω) = f(R⁻¹ω)).
    ShRotation(int n, const Eigen::Matrix3d& R, RotationMethod method = RotationMethod::Auto);

    /// out = R in (n² doubles each; in ≠ out).
    void apply(const double* in, double* out) const;
    Eigen::VectorXd apply(const Eigen::VectorXd& in) const;
    /// The n²×n² block-diagonal matrix.
    Eigen::MatrixXd matrix() const;
};

/// Rotation of coefficient vectors by many different R without building band matrices, for
/// loops that rotate each vector once (the radiance cache's lookups). R is written as the ZYZ
/// product Rz(α) Ry(β) Rz(γ) and Ry(β) = Rx(−90°) Rz(β) Rx(90°), so that per band
///   D^l(R) = Z^l(α) X^lᵀ Z^l(β) X^l Z^l(γ),   X^l = D^l(Rx(90°)),
/// with X^l built once and Z^l the 2×2 (m, −m) rotations by mα: the zxzxz rotation of Kautz,
/// Sloan & Snyder 2002, "Fast, Arbitrary BRDF Shading for Low-Frequency Lighting Using
/// Spherical Harmonics". Per band two products of fixed sparse matrices (about 1/4 of X^l's
/// entries are nonzero) with the vectors instead of building R's band matrix by the
/// Ivanic–Ruedenberg recursion (both O(l²) per band, a constant factor apart): 6.5–6.7× as fast
/// for 16 bands and three vectors (build/bench_sh, ShRotateVectors, two runs; 4.7–5.7× with X^l
/// dense). The angles are found without the
/// ill-conditioning of Euler angles near β = 0 (a small tilt and any twist, what neighbouring
/// frames differ by): α and β from R·ẑ, then γ from what is left once the tilt
/// Rz(α) Ry(β) Rz(−α) is taken out. Agrees with ShRotation's matrices within 1e-12 for 16
/// bands (tests/sh/sh_rotation_test.cpp).
class ShVectorRotation {
  public:
    explicit ShVectorRotation(int n);
    int bands() const { return n_; }
    /// out_j = D(R) in_j for `count` vectors of n² coefficients stored one after another
    /// (in = out allowed).
    void apply(const Eigen::Matrix3d& R, const double* in, double* out, int count) const;

  private:
    /// A band matrix by rows, its nonzero entries only: row i is col/val[start[i] … start[i+1]).
    struct SparseBand {
        std::vector<int> start, col;
        std::vector<double> val;
    };
    static SparseBand sparse(const Eigen::MatrixXd& m);
    int n_;
    /// D^l(Rx(90°)) and its transpose, l < n. About 3/4 of their entries are zero (241 of 961
    /// are not at l = 15); a third of the zeros come out of the construction as rounding noise
    /// below 4e-16, so entries below 1e-13 are dropped.
    std::vector<SparseBand> x_, xt_;
};

/// Zonal fast path: coefficients of p(μ) = Σ p_l y_l^0(μ), rotated so that its axis +z goes to
/// the unit vector d:  f_l^m = √(4π/(2l+1)) p_l y_l^m(d)  (the addition theorem). p has n
/// entries, out n². No allocation; accurate to the Legendre accuracy at any order (l ≤ 1000).
void rotateZonal(int n, const double* p, const Vec3& d, double* out);
Eigen::VectorXd rotateZonal(const Eigen::VectorXd& p, const Vec3& d);

/// A rotation taking +z to the direction of d (the shortest-arc one, Rodrigues' formula about
/// ẑ × d; for d along −z a half turn about x; any rotation with R·ẑ = d gives the same rotated
/// zonal function).
Eigen::Matrix3d rotationTo(const Vec3& d);
/// R = Rz(α) Ry(β) Rz(γ) (the ZYZ Euler convention of Gautron §4).
Eigen::Matrix3d rotationZYZ(double alpha, double beta, double gamma);

}  // namespace shvol::sh
