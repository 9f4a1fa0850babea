#pragma once
/// \file Radiance caching at surfaces with hemispherical harmonics (Gautron et al. 2004 §6.2,
/// after Křivánek et al. 2005 "Radiance caching for efficient global illumination computation").
///
/// A record at a surface point P with normal N stores the incoming radiance over the hemisphere of
/// its local frame Frame(N) as RGB HSH coefficients of order n, computed from N_r uniformly
/// distributed (stratified) directions ω_k by Monte Carlo quadrature (Gautron eq. 22),
///   λ_i = (2π / N_r) Σ_k L_k H_i(ω_k),
/// with translational gradients ∂λ/∂x, ∂λ/∂y along the frame's tangents by the displaced-point
/// quadrature of Gautron §6.2: moving P to P′ = P + Δx s re-weights the sample that met the
/// surface point W_k (normal n_W) by the ratio of the solid angles it subtends,
///   λ′_i = (2π / N_r) Σ_k (|W_k − P|² cos ξ′_k) / (|W_k − P′|² cos ξ_k) L_k H_i(ω′_k),
/// ω′_k the direction from P′ to W_k, and ∂λ/∂x = (λ′ − λ)/Δx (samples that met no surface keep
/// their direction and weight). The quadrature gives nothing to directions a displacement
/// uncovers behind an occluder; the gradients are taken of L_k − c, so that those directions
/// count as showing radiance c: the mean radiance of the samples that met no surface (the
/// background), or for a record that sees only surfaces that of the farther half of its hits;
/// exact for constant radiance behind the occluders. Hits whose surface's plane passes within
/// 10 Δx of P are not displaced (the reprojection's Jacobian is unbounded there). R_i is the
/// harmonic mean distance to the surfaces the samples met, clamped to [0.01, 0.25] × the scene's
/// diagonal (as irradiance caches do, so that records in corners do not shrink to nothing nor open
/// spaces reach across the scene). A query at (P, N) averages the records with weight (Gautron
/// eq. 23)
///   w_i = 1 / (|P − P_i| / R_i + √(1 − N·N_i))  >  1/a,
/// that do not reach past a surface beside them: a record keeps, for each of 16 sectors of
/// azimuth about its normal, the distance in its tangent plane to the nearest hit within 45° of
/// the plane on a surface standing across it (normal more than 30° from its own; a bowl's
/// own rise is no wall), and serves no query at or beyond the least of those of the query's sector
/// and the two next to it (with R_i's lower clamp, a record at the foot of a wall of no thickness
/// reached past it, and the floor it keeps dark got a fifth of the lit side's light; helper 63's
/// audit). Each is extrapolated by its gradients and rotated from its frame to the query's (eq. 24;
/// sh::HshRotation, through SH with the record held at its horizon and the truncation's residual
/// kept, so that it is exact and continuous at the identity; skipped when the two frames are the
/// same).
/// Records are found through uniform grids of cell widths (diagonal/64)·2^l: each record is listed
/// in the cells of the first level at least as wide as its reach a R_i (at most 3 × 3 × 3 cells),
/// and a query visits the one cell containing it on every level. Adding is not thread-safe;
/// lookups are read-only.
#include <array>
#include <cstdint>
#include <memory>
#include <unordered_map>
#include <vector>

#include "shvol/core/math.h"
#include "shvol/sh/hsh.h"

namespace shvol {

/// One incoming-radiance sample of a record: the direction it arrives from (local, z > 0), its
/// radiance, and the first surface point along it (for the gradients). `below`: the direction
/// dips below the surface (a shading normal's hemisphere), so no light and nothing met: neither
/// background nor a hit.
struct IncomingSample {
    Vec3 w;
    Spectrum L;
    bool hit = false;
    Vec3 W{0, 0, 0}, nW{0, 0, 1};
    bool below = false;
};

/// The standard error of a record's irradiance estimate E = (2π/N) Σ_k L_k cos θ_k (the channels'
/// mean of L), as if its N samples were independent, relative to the irradiance at its point:
///   2π s_y / √N / (E + E_direct),  y_k = L_k cos θ_k,  s_y² = Σ (y_k − ȳ)² / (N − 1),
/// E_direct the irradiance that next-event estimation adds there and the record leaves out (0
/// without it); 0 where there is no light (or N < 2). The records' strata make the true error
/// smaller where the light varies smoothly over the hemisphere; where it comes from a small bright
/// patch that few rays meet, the error is about this, and the record's noise is in every pixel it
/// serves (a wall lit by a tiny bulb: regions 31–49% off at 1024 rays, within 2% at 16,384; helper
/// 105). Against E alone, records that hold a faint indirect share beside bright direct light
/// counted as noisy (a ground under a sunlit cloud: 0.67 at the median; helper 107).
double irradianceRelativeError(const std::vector<IncomingSample>& samples, double direct = 0);

class RadianceCache {
  public:
    /// \param order HSH order n; \param accuracy a; lo, hi the scene's bounding box.
    RadianceCache(int order, double accuracy, const Vec3& lo, const Vec3& hi);
    ~RadianceCache();
    int order() const { return n_; }
    int coefficientCount() const { return 3 * n_ * n_; }

    /// N_r uniform directions of the upper hemisphere (z = u₁, φ = 2π u₂): the first ⌊√N_r⌋²
    /// jittered in a ⌊√N_r⌋ × ⌊√N_r⌋ grid of strata, the rest uniform; `jitter` gives each its
    /// 2 numbers.
    static std::vector<Vec3> directions(int count, const std::vector<Vec2>& jitter);

    /// A record serves a query only where the two geometric normals are within 30°: a record's
    /// directions below its own surface are dark (the path tracer refuses reflection through a
    /// surface), so one reused across a crease whose vertex normals are shared would be dark
    /// where the query's surface is not, and lit where it is dark. Below 30° the difference is
    /// a thin wedge near the horizon (the facets of a smooth-shaded low-poly sphere).
    static constexpr double kMinGeometricCos = 0.8660254037844386;  // cos 30°

    /// Builds the record at p, with shading normal n (its frame) and geometric normal ng on the
    /// same side, from its samples and stores it.
    void add(const Vec3& p, const Vec3& n, const Vec3& ng,
             const std::vector<IncomingSample>& samples);
    /// λ (3n², channel-major) of the interpolated incoming radiance at (p, n, ng) in the frame
    /// Frame(n); false if no record serves it (weight > 1/a, kMinGeometricCos).
    bool lookup(const Vec3& p, const Vec3& n, const Vec3& ng, double* lambda) const;
    /// Whether some record serves (p, n, ng).
    bool covers(const Vec3& p, const Vec3& n, const Vec3& ng) const;

    size_t size() const { return records_.size(); }
    size_t memoryBytes() const;

    /// Sectors of azimuth about a record's normal, for what lies beside it.
    static constexpr int kSectors = 16;
    /// A record as stored (for tests).
    struct Record {
        Vec3 p;
        Frame frame;  ///< Frame(n) (frame.n is the normal): the frame of λ and of the gradients
        Vec3 ng;      ///< the geometric normal, on frame.n's side
        double R;
        std::vector<double> lambda, dx, dy;  ///< 3n² each
        /// Per sector of azimuth (sector()), the distance in the tangent plane to the nearest hit
        /// within 45° of it on a surface standing across it (+∞: none).
        std::array<float, kSectors> clear;
    };
    const Record& record(size_t i) const { return records_[i]; }
    /// The record that add() would build from these samples, without storing it.
    Record build(const Vec3& p, const Vec3& n, const std::vector<IncomingSample>& samples) const;

  private:
    /// The sector of azimuth of the tangent-plane offset (x, y): 0 … kSectors − 1.
    static int sector(double x, double y);
    double weight(const Record& r, const Vec3& p, const Vec3& n) const;
    /// weight(r, p, n) where r serves (p, n, ng), else 0.
    double servingWeight(const Record& r, const Vec3& p, const Vec3& n, const Vec3& ng) const;
    uint64_t cellKey(const Eigen::Vector3i& c, int level) const;
    Eigen::Vector3i cellOf(const Vec3& p, int level) const;
    /// visit(record) for every record listed in the cells containing p, level by level.
    template <typename Visit>
    void candidates(const Vec3& p, Visit visit) const;

    static constexpr int kLevels = 16;  ///< grid levels, cell widths diagonal/64 · 2^l
    uint32_t usedLevels_ = 0;           ///< bit l: some record is listed on level l
    int n_;
    double a_, diag_, cell_;
    Vec3 lo_;
    std::vector<Record> records_;
    std::unordered_map<uint64_t, std::vector<uint32_t>> grid_;
    std::unique_ptr<const sh::HshRotation> rotation_;  ///< of records into a query's frame
};

}  // namespace shvol
