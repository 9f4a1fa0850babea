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
/// Rotates the HSH function h (n² coefficients, in place) by the angle φ about z: afterwards it
/// is f(R_z(−φ) ω). Exact, as the rotation only moves each band's cos mφ and sin mφ pair:
///   h′_{l,m} = h_{l,m} cos mφ − h_{l,−m} sin mφ,  h′_{l,−m} = h_{l,m} sin mφ + h_{l,−m} cos mφ.
void hshRotateZ(int n, double phi, double* h);

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

/// HSH rotation for the radiance cache, exact at the identity and continuous in R:
///   h′ = h + C (D(R) − I) E h,
/// with D the SH rotation of 2n bands (ShVectorRotation) and E h the SH projection of f̃ = Σ h_i H_i
/// extended below the horizon by its value there (only the m = 0 terms are non-zero at the
/// horizon, so the extension is one constant: E h = Cᵀh + s (v·h), v_i = H_i at the horizon and
/// s_j = ∫ Y_j over the lower hemisphere). It is C D E h (Gautron §4's rotation through SH, of the
/// held rather than the zero extension) plus the residual h − C E h that the truncation to 2n SH
/// bands loses, which the rotation leaves where it is. Through hshRotate (zero extension, no
/// residual) the step at the horizon is truncated even at R = I: a record of constant radiance
/// changed by 11% (n = 6) under any rotation however small, and the radiance cache switched
/// between that and the unrotated record at a normal difference of 10⁻¹². Against the projection
/// of the exactly rotated function (n = 6, tests/sh/hsh_test.cpp), relative L2 error at tilts of
/// 10⁻⁶ rad, 2°, 15°, 30° (through hshRotate in brackets):
///   constant radiance:               < 10⁻¹³ at every tilt  (0.11, 0.11, 0.26, 0.38)
///   e^{3(ω·d − 1)}, d 26° from n:    6.7·10⁻⁸, 0.0023, 0.016, 0.031  (0.018, 0.020, 0.037, 0.046)
///   the same, d 77° from n:          4.4·10⁻⁷, 0.015, 0.12, 0.21     (0.11, 0.11, 0.17, 0.26)
/// (first order in the tilt near the identity; beyond, mostly what the record does not know: the
/// radiance below its horizon). The cost is hshRotate's; the corrections of several records share
/// one C (addCorrection, then finish).
class HshRotation {
  public:
    explicit HshRotation(int n);
    int order() const { return n_; }
    /// SH coefficients per channel of the sums addCorrection builds ((2n)² of them).
    int shCount() const { return 4 * n_ * n_; }
    /// out[c·n² + j] = h′_j of channel c for h at h[c·n²], c < channels; R maps the function's
    /// frame to the new one (a direction v of the old frame is R·v in the new).
    void apply(const Eigen::Matrix3d& R, const double* h, double* out, int channels) const;
    /// sh[c·shCount() + k] += weight · ((D(R) − I) E h_c)_k for each channel.
    void addCorrection(const Eigen::Matrix3d& R, const double* h, double weight, double* sh,
                       int channels) const;
    /// out[c·n² + j] += (C sh_c)_j for each channel.
    void finish(const double* sh, double* out, int channels) const;

  private:
    int n_ = 0;
    ShToHsh C_;
    ShVectorRotation rotate_;
    std::vector<double> horizon_;  ///< v: H_i at the horizon (n²)
    std::vector<double> lowerSh_;  ///< s: ∫ Y_j over the lower hemisphere ((2n)²)
};

}  // namespace shvol::sh
