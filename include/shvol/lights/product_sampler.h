#pragma once
/// \file Product importance sampling of a rotated zonal SH lobe × the sky (Jarosz, Carr & Jensen
/// 2009 §5.2, after Clarberg et al. 2005): one hierarchical warp through the sky's quadtree whose
/// child weights are the product of the lobe's integral over the child and the sky's average.
///
/// Lobe. A zonal function p̃(μ) = Σ_l p_l y_l^0(μ) around the unit axis ω₀ has the SH coefficients
///   c_l^m = √(4π/(2l+1)) · p_l · y_l^m(ω₀)                                    (zonal rotation)
/// (rotateZonal). Its integral over a (z, φ) cell is Σ c_l^m ŷ_l^m from the separable 1D
/// integrals of sampling/sh_cell_mass.h; the tables of ∫N_l^m dz and ∫cos/sin(mφ) dφ over the
/// 2^d intervals of every level d ≤ productDepth are built once (O(n²·2^D)).
///
/// Warp. At a node at level d the weight of child i is
///   w_i = max(0, ∫_child p̃) · max(0, sky_i)            for d < productDepth,
///   w_i = max(0, sky_i)                                   for d ≥ productDepth,
/// sky_i the child's sampling average from SkyHierarchy (a node below the sky's leaf level keeps
/// its leaf's average). Below productDepth the lobe is taken as constant over a node: a cell there
/// is narrower than 2π/2^D ≈ (π/n)/(2^D/(2n)), much finer than an order-n lobe's features, so
/// the product's shape barely changes while each level costs O(1) instead of O(n²). The descent
/// stops at max(sky levels, productDepth); the density is
///   pdf(ω) = Π_levels w_chosen / Σ w  ÷  leaf area,
/// exact for any ω (pdf() walks the same path), which is what MIS needs.
///
/// Holes. A child whose lobe integral is ≤ 0 (ringing of a low-order fit) or whose compressed sky
/// average is ≤ 0 gets no samples, although the true integrand may be positive there. The
/// mixture form sample(c, β, u) / pdf(c, β, ω) adds a share β of the sky-only sampler
/// (pdf = (1 − β) p_product + β p_sky) so that no direction with sky > 0 is left unsampled;
/// callers choose β > 0 exactly when holes are possible (see defensiveShare()).
#include <vector>

#include "shvol/lights/sky_hierarchy.h"

namespace shvol {

class ProductSampler {
  public:
    /// Largest lobe order (the caller's coefficient buffers hold kMaxOrder² doubles).
    static constexpr int kMaxOrder = 32;
    /// Share of the sky-only sampler in the mixture when holes are possible.
    static constexpr double kDefensiveFraction = 0.1;

    /// sky must outlive the sampler. productDepth < 0 chooses defaultProductDepth(order).
    ProductSampler(const SkyHierarchy& sky, int order, int productDepth = -1);

    /// Levels warped by the product: ⌈log2 n⌉ + 3 (a level-D cell is 2π/2^D wide in φ, ≤ 1/8
    /// of the 2π/n period of the lobe's highest band), clamped to [3, 9].
    static int defaultProductDepth(int order);

    /// c (n² doubles) = the zonal coefficients p (n doubles) rotated to the unit axis.
    void rotateZonal(const double* p, const Vec3& axis, double* c) const;

    /// Product warp of u ∈ [0, 1)² for the lobe c (pdf 0 if the product has no mass).
    WarpSample sample(const double* c, Vec2 u) const;
    /// Density of sample(c, ·) at a unit direction.
    double pdf(const double* c, const Vec3& w) const;
    /// Warps a point set through the product (stratification preserved).
    void sample(const double* c, const std::vector<Vec2>& u, std::vector<WarpSample>& out) const;

    /// Mixture with the sky-only sampler: share beta of sky.sample().
    WarpSample sample(const double* c, double beta, Vec2 u) const;
    double pdf(const double* c, double beta, const Vec3& w) const;
    /// β for a lobe: kDefensiveFraction when the lobe's reconstruction has a negative value
    /// (`lobeMinimum` < 0) or the sky is compressed, else 0.
    double defensiveShare(double lobeMinimum) const;

    int order() const { return n_; }
    int productDepth() const { return productDepth_; }
    /// Levels of the whole descent: max(sky levels, productDepth).
    int depth() const { return depth_; }
    const SkyHierarchy& sky() const { return sky_; }
    /// The four child weights of a node (for tests and the point-set warp).
    void childWeights(const double* c, const WarpNode& node, double skyAvg, double w[4]) const;

  private:
    /// Sky averages of a node's children during a descent.
    void skyChildren(int level, uint64_t skyNode, double skyAvg, double s[4]) const;

    const SkyHierarchy& sky_;
    int n_, productDepth_, depth_;
    /// Per level d = 1 … productDepth: ∫N_l^m dz over the 2^d z-intervals (triSize(n) each) and
    /// ∫cos/sin(mφ) dφ over the 2^d φ-intervals (n each).
    std::vector<std::vector<double>> J_, C_, S_;
};

}  // namespace shvol
