#pragma once
/// \file Hemispherical harmonics (Gautron et al. 2004, eqs. 5–9), SH→HSH conversion (eq. 18) and
/// HSH rotation through SH (§4, first method).
///
/// H_l^m(θ, φ) = √2 K_l^m P_l^{|m|}(2cos θ − 1) Φ_m(φ) with Φ_m as in the SH (√2 cos, √2 sin, 1),
/// i.e. K̃_l^m = √2 K_l^m (eq. 9), on the upper hemisphere z = cos θ ∈ [0, 1] of the local frame.
/// In terms of legendre.h: H_l^m(z, φ) = √2 N_l^{|m|}(2z−1) Φ_m(φ), with the shifted sine
/// √(1 − (2z−1)²) = 2√(z(1−z)). Orthonormal on the hemisphere; flat index l(l+1)+m as for SH.
#include <Eigen/Core>
#include <vector>

#include "shvol/core/math.h"
#include "shvol/sh/sh_projection.h"
#include "shvol/sh/sh_rotation.h"

namespace shvol::sh {

/// All H_i(ω), i < n², into out (n² doubles). ω a unit vector with z ≥ 0 (z is clamped to
/// [0, 1]). No allocation.
void hshEval(int n, const Vec3& w, double* out);
Eigen::VectorXd hshEval(int n, const Vec3& w);
/// Σ_i h_i H_i(ω) for z ≥ 0 (0 below the horizon).
double hshReconstruct(int n, const double* h, const Vec3& w);

/// nz Gauss–Legendre points in z ∈ [0, 1] × nphi uniform points in φ. Products H_i H_j of order
/// n are polynomials of degree ≤ 2n−2 in z, so nz ≥ n, nphi ≥ 2n is exact for them.
SphereQuadrature hemisphereQuadrature(int nz, int nphi);

/// h_i = ∫_{H²} f H_i dω (Gautron eq. 17/21) by the hemisphere rule q. F: double(const Vec3&).
template <class F>
Eigen::VectorXd projectHSH(int n, F&& f, const SphereQuadrature& q) {
    Eigen::VectorXd c = Eigen::VectorXd::Zero(n * n);
    Eigen::VectorXd y(n * n);
    for (size_t i = 0; i < q.z.size(); ++i)
        for (int j = 0; j < q.nphi; ++j) {
            const Vec3 w = q.direction(static_cast<int>(i), j);
            hshEval(n, w, y.data());
            c += (q.weight(static_cast<int>(i)) * f(w)) * y;
        }
    return c;
}

/// The SH→HSH change of basis C of Gautron eq. 18, C_{(l,m),(l′,m′)} = ∫_{H²} H_l^m Y_{l′}^{m′} dω,
/// for nHsh HSH bands and nSh SH bands (non-square when nSh ≠ nHsh). Nonzero only for m = m′,
/// so it is stored as one block per |m| (the ±m blocks are equal):
///   blocks[|m|](l − |m|, l′ − |m|) = 2π √2 ∫_0^1 N_l^{|m|}(2z−1) N_{l′}^{|m|}(z) dz.
/// The z integral is done with z = t² (which removes the √z branch point of odd |m| at the
/// horizon) by Gauss–Legendre in t with nHsh + nSh + 40 points: exact for even |m| (a polynomial
/// in t) and converged to rounding for odd |m| (analytic on [0, 1]); checked by independent
/// quadrature in tests and in validation/sh.
struct ShToHsh {
    int nHsh = 0, nSh = 0;
    std::vector<Eigen::MatrixXd> blocks;  // blocks[am]: (nHsh−am)×(nSh−am), am < min(nHsh, nSh)

    ShToHsh() = default;
    ShToHsh(int nHsh, int nSh);
    /// HSH coefficients (nHsh²) of the restriction to the hemisphere of the SH function sh (nSh²).
    Eigen::VectorXd toHsh(const Eigen::VectorXd& sh) const;
    void toHsh(const double* sh, double* h) const;  ///< the same, without allocating
    /// SH coefficients (nSh²) of the HSH function h (nHsh²) extended by zero below the horizon:
    /// Cᵀ h (the projection, so it is exact; the truncation to nSh bands is the only loss).
    Eigen::VectorXd toSh(const Eigen::VectorXd& h) const;
    void toSh(const double* h, double* sh) const;  ///< the same, without allocating
    /// The dense nHsh² × nSh² matrix C.
    Eigen::MatrixXd dense() const;
};

/// HSH rotation through SH (Gautron §4, first method): h′ = C · R_SH · Cᵀ h, with nSh ≥ nHsh SH
/// bands in the middle. Whatever the rotation moves below the horizon is dropped by the final
/// projection. Accuracy is that of the SH representation of the zero-extended function; see
/// tests/sh/hsh_test.cpp and validation/sh for measured errors vs nSh.
Eigen::VectorXd hshRotate(const ShToHsh& C, const ShRotation& R, const Eigen::VectorXd& h);
/// The same as one nHsh² × nHsh² matrix C R Cᵀ (for rotating many vectors).
Eigen::MatrixXd hshRotationMatrix(const ShToHsh& C, const ShRotation& R);

/// HSH rotation by quadrature, continuous at the identity (what the radiance cache uses):
///   h′_j = Σ_q w_q f̃(R⁻¹ω_q) H_j(ω_q)
/// over the hemisphere rule of n × 2n points (hemisphereQuadrature), with f̃ = Σ h_i H_i extended
/// below the horizon by its value at the horizon point of the same azimuth. The rule integrates
/// f̃ H_j exactly where f̃ is not extended, so R = I returns h to rounding, and h′ moves
/// continuously with R. Through SH (hshRotate), the zero extension's step at the horizon is
/// truncated to 2n bands even at R = I: a record of constant radiance changed by 11% (n = 6) under
/// any rotation, however small, and the radiance cache switched between that and the unrotated
/// record at a normal difference of 10⁻¹². Against the projection of the exactly rotated
/// function (n = 6; tests/sh/hsh_test.cpp), relative L2 error by tilt 10⁻⁶ rad, 2°, 15°, 30°:
///   constant:                          10⁻¹⁵ throughout        (through SH: 0.11, 0.11, 0.26,
///   0.38) e^{3(ω·d − 1)}, d 26° from n:      1.2·10⁻⁹, 0.004, 0.022, 0.032  (0.018, 0.020, 0.037,
///   0.046) the same, d 77° from n:            1.3·10⁻⁸, 0.030, 0.17, 0.24    (0.11, 0.11, 0.17,
///   0.26)
/// (the rest is what the record does not know: the radiance below its horizon).
class HshRotation {
  public:
    HshRotation() = default;
    explicit HshRotation(int n);
    int order() const { return n_; }
    /// out[c·n² + j] = h′_j of channel c for h at h[c·n²], c < channels; R maps the function's
    /// frame to the new one (a direction v of the old frame is R·v in the new). out must not
    /// overlap h.
    void apply(const Eigen::Matrix3d& R, const double* h, double* out, int channels) const;

  private:
    int n_ = 0;
    std::vector<Vec3> nodes_;
    std::vector<double> weights_;
    std::vector<double> basis_;  ///< H_j(ω_q) at q·n² + j
};

}  // namespace shvol::sh
