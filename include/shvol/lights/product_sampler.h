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
/// is at most 2π/2^D wide, a quarter of the period of the lobe's highest band, so
/// the product's shape barely changes while each level costs O(1) instead of O(n²). The descent
/// stops at max(sky levels, productDepth); the density is
///   pdf(ω) = Π_levels w_chosen / Σ w  ÷  leaf area,
/// exact for any ω (pdf() walks the same path), which is what MIS needs.
///
/// Lobes come in two forms that share the warp: SHLobe, any n² SH coefficients (for BRDF lobes
/// and as the slow reference), and ZonalLobe, the fast path for rotated zonal lobes. Writing
/// ω₀ = (z₀, φ₀) and q_l^m = √(4π/(2l+1)) p_l N_l^m(z₀), the rotated coefficients are
/// c_l^0 = q_l^0 and c_l^{±m} = √2 q_l^m {cos, sin}(mφ₀), so the mass over a cell factors as
///   M = S_0 G_0 + 2 Σ_{m≥1} S_m G_m,  S_m = Σ_{l≥m} q_l^m J_l^m,  G_m = ∫cos(m(φ − φ₀)) dφ
///     = cos(mφ₀) C[m] + sin(mφ₀) S[m],
/// which costs n(n+1)/2 per z-interval instead of n² (tested against SHLobe).
///
/// Holes. A child whose lobe integral is ≤ 0 (ringing of a low-order fit) or whose compressed sky
/// average is ≤ 0 gets no samples, although the true integrand may be positive there. The
/// mixture form sample(c, β, u) / pdf(c, β, ω) adds a share β of the sky-only sampler
/// (pdf = (1 − β) p_product + β p_sky) so that no direction with sky > 0 is left unsampled;
/// callers choose β > 0 exactly when holes are possible (see defensiveShare()).
#include <vector>

#include "shvol/lights/sky_hierarchy.h"
#include "shvol/sh/legendre.h"

namespace shvol {

class ProductSampler {
  public:
    /// Largest lobe order (the caller's coefficient buffers hold kMaxOrder² doubles).
    static constexpr int kMaxOrder = 32;
    /// Share of the sky-only sampler in the mixture when holes are possible.
    static constexpr double kDefensiveFraction = 0.1;

    /// sky must outlive the sampler. productDepth < 0 chooses defaultProductDepth(order).
    ProductSampler(const SkyHierarchy& sky, int order, int productDepth = -1);

    /// Levels warped by the product: ⌈log2 n⌉ + 2 (a level-D cell is 2π/2^D wide in φ, ≤ 1/4
    /// of the 2π/n period of the lobe's highest band), clamped to [3, 9]. In validation/product
    /// depths 3–9 changed the MSE by < 7% and the efficiency by less than the run-to-run noise,
    /// so the default keeps the O(n²) levels few.
    static int defaultProductDepth(int order);

    /// A lobe given by n² SH coefficients (flat index l(l+1)+m); c must outlive the lobe.
    struct SHLobe {
        const double* c;
    };
    /// A zonal lobe rotated to an axis, in the factored form above.
    struct ZonalLobe {
        int n = 0;                                ///< bands in use (≤ order())
        double q[sh::triSize(kMaxOrder)];         ///< √(4π/(2l+1)) p_l N_l^m(z₀)
        double cosm[kMaxOrder], sinm[kMaxOrder];  ///< cos mφ₀, sin mφ₀
    };

    /// c (n² doubles) = the zonal coefficients p (n doubles) rotated to the unit axis:
    /// c_l^m = √(4π/(2l+1)) p_l y_l^m(axis).
    void rotateZonal(const double* p, const Vec3& axis, double* c) const;
    /// The same lobe in the fast factored form, using the first `bands` coefficients (0: all
    /// order() of them; see significantBands).
    void rotateZonal(const double* p, const Vec3& axis, ZonalLobe& lobe, int bands = 0) const;
    /// The bands that matter: 1 + the largest l with |p_l| > 1e-9·|p_0| (1 for an isotropic
    /// lobe, whose higher coefficients are rounding noise). Dropping the rest changes the lobe by
    /// less than 1e-9 of its mean, and the cost of a level by the square of the ratio.
    static int significantBands(const std::vector<double>& p);

    /// Product warp of u ∈ [0, 1)², direction and pdf only (pdf 0 if the product has no mass).
    /// Lobe: SHLobe or ZonalLobe.
    template <class Lobe>
    WarpSample warp(const Lobe& lobe, Vec2 u) const;
    /// Density of warp(lobe, ·) at a unit direction.
    template <class Lobe>
    double pdf(const Lobe& lobe, const Vec3& w) const;
    /// Warps a point set through the product (stratification preserved). Its masses come from
    /// lobeMasses directly, so its pdfs agree with pdf() to rounding, not bit for bit.
    template <class Lobe>
    void warp(const Lobe& lobe, const std::vector<Vec2>& u, std::vector<WarpSample>& out) const;

    /// Mixture with the sky-only sampler: share beta of sky.warp().
    template <class Lobe>
    WarpSample warp(const Lobe& lobe, double beta, Vec2 u) const;
    template <class Lobe>
    double pdf(const Lobe& lobe, double beta, const Vec3& w) const;
    /// The lobe's reconstruction p̃ at a unit direction: Σ c_l^m y_l^m(w) (O(n²); for a ZonalLobe
    /// from its factored form, q_l^0 N̄_l^0(z) + 2 Σ_{m≥1} q_l^m N̄_l^m(z) cos(m(φ − φ₀))).
    double lobeValue(const SHLobe& lobe, const Vec3& w) const;
    double lobeValue(const ZonalLobe& lobe, const Vec3& w) const;
    /// warp(lobe, beta, u) with the product the sampler follows at its direction as the value:
    /// lobeValue × the sky's SkyHierarchy::value (the integrand of a lobe-weighted sky integral,
    /// as the sampler sees it; 0 with a failed draw's pdf).
    template <class Lobe>
    SphereSample sample(const Lobe& lobe, double beta, Vec2 u) const;
    /// β for a lobe: kDefensiveFraction when the lobe's reconstruction has a negative value
    /// (`lobeMinimum` < 0) or the sky is compressed, else 0.
    double defensiveShare(double lobeMinimum) const;

    int order() const { return n_; }
    int productDepth() const { return productDepth_; }
    /// Levels of the whole descent: max(sky levels, productDepth).
    int depth() const { return depth_; }
    const SkyHierarchy& sky() const { return sky_; }
    /// The four child weights of a node (for tests and the point-set warp).
    template <class Lobe>
    void childWeights(const Lobe& lobe, const WarpNode& node, double skyAvg, double w[4]) const;
    /// The lobe's masses over the four children of node (level, iz, iφ), level < productDepth.
    void lobeMasses(const SHLobe& lobe, int level, uint32_t iz, uint32_t iphi, double m[4]) const;
    void lobeMasses(const ZonalLobe& lobe, int level, uint32_t iz, uint32_t iphi,
                    double m[4]) const;

  private:
    /// Per-descent lobe state: computes the lobe masses of the current node's children and
    /// follows the chosen child (see product_sampler.cpp).
    template <class Lobe>
    class Descent;
    /// Sky averages of a node's children during a descent.
    void skyChildren(int level, uint64_t skyNode, double skyAvg, double s[4]) const;
    /// Product (d < productDepth) or sky-only child weights during a descent.
    template <class Masses>
    void weights(Masses&& masses, int d, const double s[4], double w[4]) const;
    /// The root-to-leaf walk shared by sample() and pdf(); see product_sampler.cpp.
    template <class Lobe, class Choose>
    double descend(const Lobe& lobe, Choose&& choose, uint32_t* iz, uint32_t* iphi) const;

    const SkyHierarchy& sky_;
    int n_, productDepth_, depth_;
    /// Per level d = 0 … productDepth: ∫N_l^m dz over the 2^d z-intervals (triSize(n) each) and
    /// ∫cos/sin(mφ) dφ over the 2^d φ-intervals (n each).
    std::vector<std::vector<double>> J_, C_, S_;
    std::vector<double> zonalScale_;  ///< √(4π/(2l+1))
};

}  // namespace shvol
