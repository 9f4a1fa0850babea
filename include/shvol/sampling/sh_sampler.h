#pragma once
/// \file Importance sampling of a spherical function given by SH coefficients, by hierarchical
/// warping (Jarosz, Carr & Jensen 2009, §4–5.1).
///
/// The target is the reconstruction f̃(ω) = Σ_{l<n} Σ_m f_l^m y_l^m(ω) (DESIGN.md conventions,
/// flat index l(l+1)+m). The mass of f̃ over a (z, φ) cell is Σ f_l^m ŷ_l^m (Jarosz eq. 3), with
/// the basis integrals ŷ from sh/sh_integrals.h (eq. 17: a Legendre integral times a φ integral).
///
/// Two modes, one result up to rounding where f̃ ≥ 0:
///  - OnTheFly: no precomputation; at each visited node the basis integrals over its four children
///    are computed by the recurrences (O(n²) per level), to any depth. Masses are clamped at 0
///    level by level.
///  - Tables: the function-independent 1D integral tables of Jarosz §5.1 — ∫ N_l^m dz over the
///    2^D z-intervals and ∫ cos/sin(mφ) dφ over the 2^D φ-intervals of the finest level — are built
///    once per (n, D) and shared. A sampler weights them with its coefficients once, exploiting
///    separability (O(n²·2^D + n·4^D)), into the masses of the 4^D leaves, clamps the leaves at 0
///    and sums them up into a quadtree. Each node's split probabilities and their reciprocals
///    and each leaf's pdf are stored as well, so a sample costs two compares and two multiplies
///    per level: O(D), independent of n (the same map as the generic warp, to rounding).
/// In both, negative regions of f̃ receive no samples and the returned pdf is the exact density
/// of the samples (see hierarchical_warp.h), not f̃/∫f̃.
#include <memory>
#include <vector>

#include "shvol/sampling/hierarchical_warp.h"

namespace shvol {

class SHSampler {
  public:
    enum class Mode { OnTheFly, Tables };

    /// coeffs: n² SH coefficients. depth: quadtree levels (default 7 for Tables = 128×128 leaves
    /// of 0.016 in z by 0.049 rad in φ, fine for orders ≤ 20 and small enough to stay in a 1 MB
    /// L2 cache — depth 8 measured 1.45× slower per sample; 16 for OnTheFly).
    SHSampler(int n, const double* coeffs, Mode mode = Mode::Tables, int depth = -1);

    /// Warps u ∈ [0,1)² into a direction; value is f̃(w).
    SphereSample sample(const Vec2& u) const;
    /// Direction and pdf only (no evaluation of f̃).
    WarpSample warp(const Vec2& u) const;
    /// Warps a point set, preserving its stratification.
    void warp(const std::vector<Vec2>& u, std::vector<WarpSample>& out) const;
    /// The sampler's density at w.
    double pdf(const Vec3& w) const;
    /// f̃(w).
    double eval(const Vec3& w) const;
    /// Probability that a sample lands in [z0, z1] × [φ0, φ1] (exact; for chi² tests).
    double probability(double z0, double z1, double phi0, double phi1) const;
    /// ∫ max(0, f̃) as the sampler sees it (clamped masses; the Tables mode sums clamped leaves).
    double positiveMass() const;

    int order() const { return n_; }
    int depth() const { return depth_; }
    Mode mode() const { return mode_; }

    /// Masses of the four children of a node, computed on the fly (the slow reference).
    void childMassesOnTheFly(const WarpNode& node, double c[4]) const;

  private:
    void buildTables();
    void childMassesFromTables(const WarpNode& node, double c[4]) const;

    int n_, depth_;
    Mode mode_;
    std::vector<double> coeffs_;
    WarpSample warpTables(Vec2 u) const;
    /// The same map for a block of up to 16 points, level by level, so that the independent
    /// per-point dependency chains (compare → indexed load → multiply) overlap.
    void warpTablesBlock(const Vec2* u, int count, WarpSample* out) const;

    /// Tables mode: masses per level, level d has 4^d cells indexed iz·2^d + iφ.
    std::vector<std::vector<double>> pyramid_;
    /// One binary split: side 0 with probability p = lo[1]; a point on side s is rescaled as
    /// (x − lo[s])·inv[s], lo = {0, p}, inv = {1/p, 1/(1−p)}. Indexed, not branched (the side is
    /// random; compilers turn s·p into a mispredicted branch).
    struct Split {
        double lo[2], inv[2];
        double p() const { return lo[1]; }
    };
    /// Per internal node (levels 0 … D−1, concatenated): the row split and the two column splits.
    struct NodeSplits {
        Split row, col[2];
    };
    std::vector<NodeSplits> splits_;
    std::vector<size_t> levelOffset_;
    std::vector<double> leafPdf_;  ///< leaf mass / (root mass · leaf area)
};

}  // namespace shvol
