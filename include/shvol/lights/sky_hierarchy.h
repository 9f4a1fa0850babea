#pragma once
/// \file The sky on the equal-area square of DESIGN.md, as a mip-map and a Haar wavelet, and the
/// hierarchical-warping sampler through it (Clarberg et al. 2005, "Wavelet importance sampling";
/// Jarosz, Carr & Jensen 2009 §5.2).
///
/// Domain. The cylindrical square (z = cos θ, φ) ∈ [−1, 1] × [0, 2π) is equal-area (dω = dz dφ).
/// It is cut into 2^k × 2^k leaves; a node at level d covers z ∈ [−1 + 2iz/2^d, −1 + 2(iz+1)/2^d]
/// and φ ∈ [2π iφ/2^d, 2π(iφ+1)/2^d] in *world* φ (the environment's rotation and lat-long
/// mapping are folded in when the sky is resampled). Its four children are numbered 2r + c with
/// r the z half and c the φ half, as in sampling/hierarchical_warp.h, and nodes are stored in
/// Morton order, so the children of node I at level d are 4I … 4I+3 at level d+1.
///
/// Resampling. Each leaf holds the exact average of the luminance Y = 0.2126R + 0.7152G + 0.0722B
/// (clamped at 0) over its solid angle: a lat-long pixel covers z ∈ [cos θ_{y+1}, cos θ_y] and a φ
/// interval of width 2π/W, so its overlap with a leaf is the product of a z overlap and a φ
/// overlap (with wrap-around), and
///   avg_leaf = Σ_pixels Y_pixel · |Δz ∩| · |Δφ ∩| / (leaf area).
/// Hence ∫ Y dω is preserved exactly (tests/lights/sky_hierarchy_test.cpp). k is chosen from the
/// source resolution: 2^k ≥ √(W·H), 1 ≤ k ≤ 11 (at most 2048²).
///
/// Mip-map: node averages at every level (float, 4/3·4^k values), stored in sampler units: divided
/// by the brightest leaf, so that no scale of the sky overflows a float or flushes to zero.
/// average() and rootAverage() convert back (× unit()). Haar wavelet (non-standard 2D
/// decomposition): for a node with child averages c_{rc} and average a = ¼Σc,
///   D_φ = ¼(c00 − c01 + c10 − c11),  D_z = ¼(c00 + c01 − c10 − c11),  D_d = ¼(c00 − c01 − c10 +
///   c11),
/// and the children are reconstructed as c_{rc} = a + s_c D_φ + s_r D_z + s_r s_c D_d, s_0 = 1,
/// s_1 = −1. On the unit square the orthonormal coefficient of a detail at level d is 2^{−d}·D, so
/// keeping the K largest |2^{−d} D| (top-K compression) minimises the L2 error, which by Parseval
/// is (Σ_dropped (2^{−d} D)²)^{1/2}.
///
/// Sampling. The warp splits at each node by the children's averages clamped at 0 (equal areas,
/// so averages are proportional to masses); the pdf is Π (chosen / Σ) ÷ leaf area, computed
/// exactly by pdf(). Without compression the mip-map and the wavelet give the same sampler. A
/// compressed wavelet can reconstruct a child as ≤ 0 where the sky is bright, which would leave
/// it unsampled; the compressed sampler is therefore mixed with a uniform share
/// (pdf = (1 − α) p_wavelet + α/4π, α = kDefensiveFraction; Hesterberg 1995), so compression
/// changes noise but never the expected image. Radiance is never taken from the hierarchy:
/// callers look it up in the environment exactly.
#include <array>
#include <cstdint>
#include <vector>

#include "shvol/core/image.h"
#include "shvol/lights/latlong.h"
#include "shvol/sampling/hierarchical_warp.h"

namespace shvol {

/// Interleaves the bits of (iz, iφ) with the z bit above the φ bit of each pair, so that
/// child index = 4·parent + 2r + c.
inline uint64_t mortonIndex(uint32_t iz, uint32_t iphi) {
    auto spread = [](uint64_t x) {
        x &= 0xffffffffULL;
        x = (x | (x << 16)) & 0x0000ffff0000ffffULL;
        x = (x | (x << 8)) & 0x00ff00ff00ff00ffULL;
        x = (x | (x << 4)) & 0x0f0f0f0f0f0f0f0fULL;
        x = (x | (x << 2)) & 0x3333333333333333ULL;
        x = (x | (x << 1)) & 0x5555555555555555ULL;
        return x;
    };
    return (spread(iz) << 1) | spread(iphi);
}

/// Where a unit direction falls at level d: (iz, iφ), clamped to the grid.
inline void skyCell(const Vec3& w, int level, uint32_t* iz, uint32_t* iphi) {
    const int n = 1 << level;
    const double z = std::clamp(w.z(), -1.0, 1.0);
    *iz = uint32_t(std::clamp(int((z + 1) * 0.5 * n), 0, n - 1));
    *iphi = uint32_t(std::clamp(int(sphericalPhi(w) * Inv2Pi * n), 0, n - 1));
}

class SkyHierarchy {
  public:
    /// Uniform share of the compressed-wavelet sampler.
    static constexpr double kDefensiveFraction = 0.05;
    /// Largest leaf level (2048² leaves).
    static constexpr int kMaxLevels = 11;

    struct LatLongSource {
        const Image* image = nullptr;
        LatLongMapping mapping = LatLongMapping::Blender;
        double scale = 1, rotation = 0;  ///< rotation in radians about +z
        bool lowerHemisphereBlack = false;
    };
    /// Resamples a lat-long image (see the file comment). levels < 0 chooses k from the image's
    /// resolution. waveletCoefficients: K details kept (0 = all; no compression).
    static SkyHierarchy fromLatLong(const LatLongSource& src, int levels = -1,
                                    size_t waveletCoefficients = 0);
    /// A constant luminance (zero below the horizon with lowerHemisphereBlack: k = 1).
    static SkyHierarchy constant(double luminance, bool lowerHemisphereBlack);
    /// From leaf averages given in row-major order (iz·2^k + iφ), for tests and tools.
    static SkyHierarchy fromLeaves(int levels, const std::vector<double>& leaves,
                                   size_t waveletCoefficients = 0);

    int levels() const { return levels_; }
    int resolution() const { return 1 << levels_; }
    /// Average luminance at level d, cell (iz, iφ): exact (the mip-map), or for a compressed sky
    /// the wavelet's reconstruction.
    double average(int level, uint32_t iz, uint32_t iphi) const {
        return unit_ * (compressed_ ? samplingAverage(level, iz, iphi)
                                    : double(mip_[level][mortonIndex(iz, iphi)]));
    }
    /// Luminance of one sampler unit (the brightest leaf; 1 for a black sky).
    double unit() const { return unit_; }
    /// The average the sampler uses at a node, in sampler units: the mip-map's, or the compressed
    /// wavelet's reconstruction (descending from the root, O(level · log K)).
    double samplingAverage(int level, uint32_t iz, uint32_t iphi) const;
    /// The root's sampling average, in sampler units (where descents start).
    double samplingRoot() const { return mip_[0][0]; }
    /// Children's sampling averages (sampler units) of node `morton` at `level` whose own
    /// sampling average is `avg` (used during a top-down descent, O(1) or O(log K)).
    /// level < levels().
    void childAverages(int level, uint64_t morton, double avg, double c[4]) const {
        if (!compressed_) {
            const float* p = &mip_[level + 1][4 * morton];
            c[0] = p[0], c[1] = p[1], c[2] = p[2], c[3] = p[3];
            return;
        }
        compressedChildren(level, morton, avg, c);
    }
    /// Mean luminance over the sphere.
    double rootAverage() const { return unit_ * mip_[0][0]; }
    /// Hints the cache that a descent at node `morton` of `level` will next read one of its
    /// children's children: in Morton order the 16 grandchildren are 64 contiguous bytes.
    /// Its 64 great-grandchildren (four lines) are fetched too: a level's work is shorter than a
    /// miss to memory, and one level ahead left the deep levels of a 2048² sky waiting on each
    /// (`bench_lights` WaveletSample/11/0: about 10% faster with them; a fourth level was slower).
    void prefetchGrandchildren(int level, uint64_t morton) const {
        if (compressed_) return;
        if (level + 2 <= levels_) __builtin_prefetch(&mip_[level + 2][16 * morton]);
        if (level + 3 <= levels_)
            for (int line = 0; line < 4; ++line)
                __builtin_prefetch(&mip_[level + 3][64 * morton + 16 * line]);
    }
    /// Hints the cache that a descent will read the child averages along the root-to-leaf path of
    /// leaf (iz, iφ): a pdf's path is known before it starts, so its misses can overlap.
    void prefetchPath(uint32_t iz, uint32_t iphi) const {
        if (compressed_) return;
        for (int d = 1; d <= levels_; ++d)
            __builtin_prefetch(
                &mip_[d][4 * mortonIndex(iz >> (levels_ - d + 1), iphi >> (levels_ - d + 1))]);
    }

    /// Hierarchical warp of u ∈ [0, 1)² (with the defensive share when compressed): direction
    /// and pdf only.
    WarpSample warp(Vec2 u) const;
    /// Density of warp() and sample() at a unit direction.
    double pdf(const Vec3& w) const;
    /// Warps a point set (stratification preserved except for the defensive share).
    void warp(const std::vector<Vec2>& u, std::vector<WarpSample>& out) const;
    /// The luminance the sampler follows at w: its leaf's average (the compressed wavelet's
    /// reconstruction, which can be ≤ 0). Uncompressed, pdf(w) = value(w) / (4π rootAverage()).
    double value(const Vec3& w) const;
    /// warp(u) with value() at its direction (0 with a failed draw's pdf).
    SphereSample sample(Vec2 u) const;

    bool compressed() const { return compressed_; }
    double defensiveFraction() const { return compressed_ ? kDefensiveFraction : 0.0; }
    /// Detail coefficients: all of them (3 per internal node) and those kept (the non-zero ones
    /// among the K largest).
    size_t detailCount() const;
    size_t keptDetails() const { return compressed_ ? kept_ : detailCount(); }
    /// Relative L2 error of the compressed wavelet against the full one (0 uncompressed):
    /// (Σ_dropped (2^{−d}D)²)^{1/2} / (∫ Y² over the unit square)^{1/2}.
    double relativeL2Error() const { return l2Error_; }
    /// What compression costs light samples: Σ_i m_i² / P_i over the cells i of level
    /// min(levels, kMomentLevel), m_i the sky's exact share of its light in cell i and P_i the
    /// compressed sampler's probability of it (defensive share included). The second moment of a
    /// light-sampled estimate of the sky's light, in units of its square: 1 for the exact
    /// sampler (uncompressed), and the relative variance per sample is this − 1 at that level.
    /// The L2 error does not tell it: sunlit_cloud.json's sky at 64 coefficients, error 0.049,
    /// rendered 2.4–6 times the RMSE of the full sky (helper 109).
    double lightSecondMoment() const { return compressed_ ? secondMoment_ : 1.0; }
    static constexpr int kMomentLevel = 8;
    /// Bytes the sampler reads: the mip-map, or the root plus the kept details.
    size_t memoryBytes() const;
    size_t mipMapBytes() const;

  private:
    void buildMipMap(std::vector<double> leavesMorton);
    void compress(size_t K);
    void compressedChildren(int level, uint64_t morton, double avg, double c[4]) const;
    /// Sampler without the defensive share.
    WarpSample warpWithoutShare(Vec2 u) const;
    double pdfWithoutShare(const Vec3& w) const;

    int levels_ = 0;
    double unit_ = 1;                      ///< luminance of one sampler unit
    std::vector<std::vector<float>> mip_;  ///< per level, Morton order, in sampler units
    bool compressed_ = false;
    size_t kept_ = 0;
    double l2Error_ = 0;
    double secondMoment_ = 1;
    /// Compressed wavelet: per internal level, the nodes with a kept detail (sorted Morton
    /// indices) and their (D_φ, D_z, D_d), dropped components set to 0.
    std::vector<std::vector<uint32_t>> detailNodes_;
    std::vector<std::vector<std::array<float, 3>>> details_;
};

}  // namespace shvol
