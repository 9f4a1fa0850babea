#pragma once
/// \file Importance sampling of a zonal SH function p̃(μ) = Σ_{l<n} p_l y_l^0(μ), such as a phase
/// function fit, around an axis (Jarosz et al. 2009 §5, zonal case).
///
/// Only the m = 0 terms exist, so the hierarchical warp over (z, φ) separates: φ is uniform and z
/// is warped in 1D. A 1D hierarchical warp with leaf masses M_i = 2π·max(0, Σ_l p_l ∫_{bin i}
/// y_l^0 dz) over 2^D equal bins in z is exactly the inverse of the piecewise-constant CDF of the
/// clamped leaves (each level splits u by the left child's share and rescales it, which composes
/// to F⁻¹); so the warp is computed as that inverse, found in O(1) expected time with a guide
/// table (Chen & Asau 1974) instead of D halvings. tests/sampling/zonal_sh_sampler_test.cpp
/// checks it against the generic hierarchical warp.
///
/// The density of the samples is pdf(μ) = M_i / (ΣM · 2π Δz) on bin i — exact for the sampler;
/// clamped (negative) bins are never sampled.
#include <vector>

#include "shvol/core/math.h"
#include "shvol/sampling/hierarchical_warp.h"

namespace shvol {

class ZonalSHSampler {
  public:
    /// p: n zonal coefficients (p(μ) = Σ p_l y_l^0(μ)); depth: 2^depth bins in z (default 16).
    ZonalSHSampler(std::vector<double> p, int depth = 16);

    struct LocalSample {
        double cosTheta = 1, phi = 0, pdf = 0;  ///< pdf 0: the function has no positive mass
    };
    /// Warp around +z: direction and pdf only.
    LocalSample warpLocal(const Vec2& u) const;
    /// Warp around the unit axis `axis` (cos θ = axis·w): the direction, its density in *pdf.
    Vec3 warp(const Vec3& axis, const Vec2& u, double* pdf) const;
    /// warp(axis, u) with the reconstruction p̃(cos θ) (eval, O(n)) at its direction as the
    /// value (0 with a failed draw's pdf).
    SphereSample sample(const Vec3& axis, const Vec2& u) const;
    /// Density at cos θ (solid-angle measure).
    double pdf(double cosTheta) const;
    /// P(cos θ ≤ z) for a sample around +z (piecewise linear in z).
    double cdf(double z) const;
    /// The reconstruction p̃(cos θ) (O(n)).
    double eval(double cosTheta) const;

    int order() const { return int(p_.size()); }
    int depth() const { return depth_; }
    const std::vector<double>& coefficients() const { return p_; }
    /// ∫ max(0, p̃) dω as the sampler sees it (sum of clamped bins).
    double positiveMass() const { return total_; }
    /// Fraction of the bins whose mass was negative and clamped to 0.
    double clampedFraction() const { return clampedFraction_; }

  private:
    int bin(double z) const;
    std::vector<double> p_;
    int depth_, bins_;
    double binWidth_, total_ = 0, clampedFraction_ = 0;
    std::vector<double> cdf_;      ///< bins+1 entries, cdf_[0] = 0, cdf_[bins] = 1
    std::vector<double> density_;  ///< pdf per bin
    std::vector<int> guide_;       ///< guide_[j] = first bin i with cdf_[i+1] > j/G
};

}  // namespace shvol
