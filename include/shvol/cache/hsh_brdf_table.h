#pragma once
/// \file HSH coefficients of a cosine-weighted BRDF for a grid of outgoing directions (Gautron et
/// al. 2004 §5 and §6.2, "BRDF Representation").
///
/// For each outgoing direction ω_o of the local frame (+z the normal), the coefficients of
/// g(ω_i) = f(ω_o, ω_i) cos θ_i over the upper hemisphere,
///   c_i(ω_o) = ∫_{H²} f(ω_o, ω_i) cos θ_i H_i(ω_i) dω_i          (Gautron eq. 17, premultiplied),
/// so that the outgoing radiance of an incoming radiance with HSH coefficients λ is L_o = Σ λ_i
/// c_i. ω_o is tabulated on an R × R grid of the parabolic parametrisation of Heidrich & Seidel
/// 1999,
///   (u, v) = (ω_x, ω_y) / (1 + ω_z) ∈ unit disk,
/// with grid nodes outside the disk taken at its rim, and c is interpolated bilinearly.
/// Lambert, Phong and Ward are linear in their reflectances, f = ρ_d f_d + ρ_s f_s, so the table
/// holds the scalar coefficients of f_d (one vector: they do not depend on ω_o) and of f_s per
/// node, and RGB coefficients are ρ_d c_d + ρ_s c_s. The integrals use a Gauss–Legendre × uniform
/// hemisphere rule fine enough for the lobe (hemisphereQuadrature in sh/hsh.h).
#include <memory>
#include <string>
#include <vector>

#include "shvol/core/math.h"
#include "shvol/surfaces/bsdf.h"

namespace shvol {

class HshBrdfTable {
  public:
    /// Whether a BSDF can be tabulated (and its surfaces cached): lambert, phong and ward.
    static bool supports(const Bsdf& bsdf) {
        return bsdf.type == BsdfType::Lambert || bsdf.type == BsdfType::Phong ||
               bsdf.type == BsdfType::Ward;
    }
    /// \param bsdf lambert, phong or ward (others: shvol::Error). \param order n (n² coefficients).
    /// \param resolution R, outgoing directions per side of the parabolic grid.
    HshBrdfTable(const Bsdf& bsdf, int order, int resolution = 32);
    /// Whether two supported BSDFs have the same lobes up to their reflectances (type, exponent,
    /// roughness, and a specular part in both or neither), so that one's table serves the other's
    /// with the reflectances changed: the projections do not depend on them.
    static bool sameLobes(const Bsdf& a, const Bsdf& b);
    /// The table of `bsdf` from that of another BSDF of the same lobes (sameLobes; others are an
    /// Error): its coefficients and errors with bsdf's reflectances, equal to those of
    /// HshBrdfTable(bsdf, …) (tested), sharing the other's specular projections rather than
    /// computing res² of them again.
    HshBrdfTable(const HshBrdfTable& sameLobe, const Bsdf& bsdf);
    int order() const { return n_; }
    int size() const { return n_ * n_; }
    /// RGB coefficients c(ω_o) for a local ω_o with z > 0: out[k·n² + i] for channel k.
    void coefficients(const Vec3& wo, double* out) const;
    /// The same for a world direction ω_o, in the HSH frame `base` (z the normal: the frame of a
    /// radiance cache record's λ) rather than the lobe's own, `own` (the same normal; a surface's
    /// Frame(n, tangent, tangentY)), turned by φ about the normal from `base`: an anisotropic
    /// lobe's coefficients are turned back by sh::hshRotateZ (other lobes are the same in every
    /// frame about the normal).
    void coefficients(const Frame& base, const Frame& own, const Vec3& wo, double* out) const;
    /// The fraction of ∫ g² the order-n projection misses (1 − Gautron eq. 15), averaged over the
    /// grid's outgoing directions, for the specular part (the diffuse part's, if it has no
    /// specular part or its ρ_s is 0).
    double projectionError() const { return projectionError_; }
    /// How far a point light's reflection can be from the lobe's: the largest, over the grid's
    /// outgoing directions within acos(0.2) = 78.5° of the normal (as albedoError), of
    ///   max_{ω_i} |g(ω_i) − P_n g(ω_i)| / max_{ω_i} g(ω_i)
    /// at the table's quadrature nodes ω_i (the specular part's; the diffuse part's for lambert).
    /// A record's λ is the projection P_n L of its incoming radiance, and Σ λ_i c_i = ∫ P_n L g =
    /// ∫ L P_n g, so light from a small source in direction ω_i is reflected by P_n g(ω_i): a
    /// highlight off by up to this fraction of the lobe's peak, too dark at the peak where the
    /// truncation rounds it off, and rings (clamped at 0) in its tail. It can be large where the
    /// energy fraction projectionError is small (Phong 30 at order 8: 0.22 against 0.082; an
    /// audit found its highlight under a small lamp 7.9% dark and its dim edges 88%, helper
    /// 105). Lambert's cos θ_i is held exactly from order 2.
    double peakError() const { return peakError_; }
    /// The largest relative error, over the grid's outgoing directions within acos(0.2) = 78.5°
    /// of the normal, of the specular part's directional albedo as the table gives it (what a
    /// cached surface reflects of uniform light) against the lobe's own, found by importance
    /// sampling the BSDF on a 16 × 16 stratified grid (0 for lambert). The quadrature cannot see
    /// a lobe narrower than its nodes' spacing: Ward α = 10⁻⁴ came out black (albedo error 1)
    /// with a projection error of 0.008, α = 0.003 up to 7× too bright, and projection errors
    /// did not tell these from the broad lobes the table holds. At order 8 (test
    /// HshBrdfTable.AlbedoErrorFindsLobesTheQuadratureMisses): Ward α ≥ 0.1 and Phong ≤ 1000
    /// within 1%; Ward α ≤ 0.03 and Phong ≥ 10⁴ off by 86% or more. Nearer the horizon the
    /// quadrature and the sampled estimate of Ward's 1/√(cos θ_o cos θ_i) disagree even for a
    /// lobe held well elsewhere (α = 0.2: 125% at the rim, 0.14% above 78.5°), so those
    /// directions are left out of the check.
    double albedoError() const { return albedoError_; }
    static constexpr double kAlbedoCheckCos = 0.2;
    /// Bytes of the coefficients, the specular ones included however many tables share them.
    size_t memoryBytes() const;

  private:
    int n_, res_;
    std::vector<double> diffuse_;  ///< n² coefficients of f_d cos θ_i
    /// res² × n² coefficients of f_s cos θ_i (null without a specular lobe), shared by the tables
    /// of the same lobes
    std::shared_ptr<const std::vector<double>> specular_;
    Bsdf lobes_;  ///< the BSDF tabulated (its lobes are the table's; sameLobes)
    double projectionError_ = 0, peakError_ = 0, albedoError_ = 0;
};

/// A surface's BRDF table's errors (projectionError and peakError), under the surface's name.
struct BrdfTableErrors {
    std::string surface;
    double projection = 0, peak = 0;
};

/// Parabolic map of Heidrich & Seidel 1999 and its inverse, for directions with z ≥ 0.
Vec2 parabolicFromDirection(const Vec3& w);
Vec3 directionFromParabolic(const Vec2& uv);

}  // namespace shvol
