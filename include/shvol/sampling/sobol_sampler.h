#pragma once
/// \file Quasi-random sample streams for the path tracer: a padded, Owen-scrambled (0,2)-sequence
/// keyed by (seed, pixel, sample), like Rng::forSample, so images stay independent of the thread
/// count and a render of N samples is the first N samples of a longer one.
///
/// The n-th point of the (0,2)-sequence is x_n = (R(n), C·n) ∈ [0,1)², the first two dimensions
/// of Sobol' (1967): R reverses the 32 bits of n (van der Corput), and C is the generator matrix
/// of the polynomial x + 1, whose direction numbers are v₁ = 2⁻¹, v_k = v_{k−1} ⊕ (v_{k−1} ≫ 1).
/// Each coordinate is scrambled by hash-based nested uniform (Owen) scrambling (Burley 2020,
/// "Practical Hash-based Owen Scrambling", JCGT 9(4), after Laine & Karras 2011): the bits are
/// reversed, permuted by a hash in which every bit depends only on the bits below it, and
/// reversed back, so every bit of the result depends only on the bits above it in the input: an
/// Owen scramble, which keeps the (0,2)-sequence's stratification. For every k ≤ 32, the first
/// 2^k samples of a pixel then put one point in each 2^a × 2^b elementary interval (a + b = k).
///
/// A path asks for its numbers in a fixed order (the camera jitter, then per bounce the free
/// flight's first two numbers, the light sample, the phase sample and, with next-event
/// estimation, the roulette's number). Request d
/// of a path is the (0,2)-sequence with its index shuffled and its coordinates scrambled by seeds
/// hashed from (seed, pixel, d): each request is stratified over the pixel's samples, and different
/// requests are decorrelated (padding, as pbrt-v4's PaddedSobolSampler). Beyond kDimensions
/// requests, and for the rest of the variable-length draws of tracking, the stream hands out its
/// independent PCG32 numbers (rng()). 16 bits below 2⁻³² are random too (what an Owen scramble of
/// infinite depth would give).
#include <cstdint>

#include "shvol/core/rng.h"

namespace shvol {

/// The 32 bits of x in reverse order.
inline uint32_t reverseBits32(uint32_t x) {
#if defined(__has_builtin) && __has_builtin(__builtin_bitreverse32)
    return __builtin_bitreverse32(x);
#else
    x = (x << 16) | (x >> 16);
    x = ((x & 0x00ff00ffu) << 8) | ((x & 0xff00ff00u) >> 8);
    x = ((x & 0x0f0f0f0fu) << 4) | ((x & 0xf0f0f0f0u) >> 4);
    x = ((x & 0x33333333u) << 2) | ((x & 0xccccccccu) >> 2);
    return ((x & 0x55555555u) << 1) | ((x & 0xaaaaaaaau) >> 1);
#endif
}

/// The second Sobol' dimension of point n as a 32-bit fraction: C·n over GF(2), bit by bit
/// (the slow reference of sobolSecondDimension).
inline uint32_t sobolSecondDimensionBitwise(uint32_t n) {
    uint32_t x = 0;
    for (uint32_t v = 0x80000000u; n; n >>= 1, v ^= v >> 1)
        if (n & 1) x ^= v;
    return x;
}

namespace detail {
/// C·n for each byte of n at each of its four places: table[k][b] = C·(b << 8k), and the same
/// with its bits reversed (reversal commutes with XOR, so the reversed C·n is the XOR of
/// reversed entries).
struct SobolSecondDimensionTable {
    uint32_t table[4][256];
    uint32_t reversed[4][256];
    constexpr SobolSecondDimensionTable() : table(), reversed() {
        uint32_t v[32] = {};
        v[0] = 0x80000000u;
        for (int i = 1; i < 32; ++i) v[i] = v[i - 1] ^ (v[i - 1] >> 1);
        for (int k = 0; k < 4; ++k)
            for (int b = 0; b < 256; ++b) {
                uint32_t x = 0, r = 0;
                for (int i = 0; i < 8; ++i)
                    if (b & (1 << i)) x ^= v[8 * k + i];
                for (int i = 0; i < 32; ++i) r |= ((x >> i) & 1u) << (31 - i);
                table[k][b] = x;
                reversed[k][b] = r;
            }
    }
};
inline constexpr SobolSecondDimensionTable kSobolSecondDimension{};
}  // namespace detail

/// The second Sobol' dimension of point n as a 32-bit fraction, a byte of n at a time.
inline uint32_t sobolSecondDimension(uint32_t n) {
    const auto& t = detail::kSobolSecondDimension.table;
    return t[0][n & 0xff] ^ t[1][(n >> 8) & 0xff] ^ t[2][(n >> 16) & 0xff] ^ t[3][n >> 24];
}

/// reverseBits32(sobolSecondDimension(n)), a byte of n at a time.
inline uint32_t sobolSecondDimensionReversed(uint32_t n) {
    const auto& t = detail::kSobolSecondDimension.reversed;
    return t[0][n & 0xff] ^ t[1][(n >> 8) & 0xff] ^ t[2][(n >> 16) & 0xff] ^ t[3][n >> 24];
}

/// A seeded bijection of 32-bit integers in which bit i of the result (from the least
/// significant) depends on bits 0 … i of x only (Burley 2020, the improved Laine–Karras
/// permutation).
inline uint32_t laineKarras(uint32_t x, uint32_t seed) {
    x ^= x * 0x3d20adeau;
    x += seed;
    x *= (seed >> 16) | 1u;
    x ^= x * 0x05526c56u;
    x ^= x * 0x53a22864u;
    return x;
}

/// Nested uniform scramble of a 32-bit fraction: bit i of the result (from the top) depends on
/// bits 0 … i of x and on the seed only.
inline uint32_t owenScramble(uint32_t x, uint32_t seed) {
    return reverseBits32(laineKarras(reverseBits32(x), seed));
}

class SobolPixel;

/// A 2D request of a path's sample stream whose value is computed when first read: the request
/// takes its place in the stream (its dimension, and the stream's random low bits) when it is
/// made, so the requests after it are unchanged whether or not it is ever read. A free flight
/// whose ray meets no medium's bounds (most camera rays of a sparse scene) then costs no
/// scramble. Either a given pair or a request of a SobolSampler.
class DeferredPair {
  public:
    explicit DeferredPair(const Vec2& u) : u_(u) {}
    /// The pair: the given one, or the Sobol' request's point (SobolSampler::next2D).
    Vec2 value() const;

  private:
    friend class SobolSampler;
    DeferredPair(const SobolPixel* pixel, uint32_t reversedIndex, int dimension, uint32_t low)
        : pixel_(pixel), reversedIndex_(reversedIndex), dimension_(dimension), low_(low) {}
    Vec2 u_{0, 0};
    const SobolPixel* pixel_ = nullptr;  ///< null: u_ is the pair
    uint32_t reversedIndex_ = 0;
    int dimension_ = 0;
    uint32_t low_ = 0;
};

/// The part of a pixel's sample streams that does not depend on the sample: the scrambling
/// seeds of each request d, hashed from (seed, pixel, d). They are computed when a sample of the
/// pixel first asks for request d and reused by the pixel's other samples (a pixel's samples
/// are rendered one after another), which takes two hashes off every request. It fills itself
/// lazily, so one thread uses it (the renderer makes one per pixel inside its tile loop).
class SobolPixel {
  public:
    /// Requests served from the (0,2)-sequence before the stream falls back to rng(): the camera
    /// jitter and the flight, light, phase and roulette numbers of the first 25 to 63 bounces (2
    /// requests a bounce, 4 with next-event estimation, 5 with area lights too).
    static constexpr int kDimensions = 128;
    /// A request's seeds: of the scramble of the sample index, and of its two coordinates.
    struct Seeds {
        uint32_t index, x, y;
    };

    SobolPixel(uint64_t seed, uint64_t pixel)
        : seed_(seed), pixel_(pixel), key_(mix64(mix64(seed) ^ (pixel * 0x9e3779b97f4a7c15ULL))) {}
    SobolPixel(const SobolPixel&) = delete;  // samplers and deferred pairs point to it
    SobolPixel& operator=(const SobolPixel&) = delete;

    uint64_t seed() const { return seed_; }
    uint64_t pixel() const { return pixel_; }
    /// The seeds of request d < kDimensions.
    const Seeds& seeds(int d) const {
        while (filled_ <= d) seeds_[filled_] = hashSeeds(key_, filled_), ++filled_;
        return seeds_[d];
    }
    /// What seeds(d) holds, from the definition.
    static Seeds hashSeeds(uint64_t key, int d) {
        const uint64_t h = mix64(key + uint64_t(d));
        // A third seed from h by a 32-bit finaliser (Wellons' lowbias32): enough for a scramble.
        uint32_t g = uint32_t(h) ^ uint32_t(h >> 32);
        g = (g ^ (g >> 16)) * 0x7feb352du;
        g = (g ^ (g >> 15)) * 0x846ca68bu;
        g ^= g >> 16;
        return {g, uint32_t(h), uint32_t(h >> 32)};
    }

  private:
    uint64_t seed_, pixel_, key_;
    mutable int filled_ = 0;
    mutable Seeds seeds_[kDimensions];
};

class SobolSampler {
  public:
    static constexpr int kDimensions = SobolPixel::kDimensions;

    /// The stream of sample `sample` of `pixel` (which must outlive the sampler and the pairs
    /// it defers).
    SobolSampler(const SobolPixel& pixel, uint32_t sample)
        : rng_(Rng::forSample(pixel.seed(), pixel.pixel(), sample)),
          pixel_(&pixel),
          reversedIndex_(reverseBits32(sample)) {}

    /// The next pair of the path's numbers.
    Vec2 next2D() { return deferred2D().value(); }
    /// The next pair of the path's numbers, computed when first read (DeferredPair).
    DeferredPair deferred2D() {
        if (dimension_ >= kDimensions) return DeferredPair(rng_.uniform2());
        // 16 random bits below 2⁻³² for each coordinate, drawn now to keep the stream's order.
        const uint32_t low = rng_.nextU32();
        return DeferredPair(pixel_, reversedIndex_, dimension_++, low);
    }
    /// The next single number of the path (its own request, from the first coordinate).
    double next1D() {
        if (dimension_ >= kDimensions) return rng_.uniform();
        const Request r = request(*pixel_, reversedIndex_, dimension_++);
        return toUnit(reverseBits32(laineKarras(r.index, r.seedX)), rng_.nextU32() >> 16);
    }
    /// Independent numbers for draws whose count varies (free-flight and transmittance tracking).
    Rng& rng() { return rng_; }

  private:
    friend class DeferredPair;
    /// The point of the sequence a request uses and its coordinates' scrambling seeds.
    struct Request {
        uint32_t index, seedX, seedY;
    };
    /// Request `dimension` of the pixel's stream for the sample whose reversed index is
    /// `reversedIndex`.
    static Request request(const SobolPixel& pixel, uint32_t reversedIndex, int dimension) {
        const SobolPixel::Seeds& s = pixel.seeds(dimension);
        // Each request visits the sequence in its own order (a nested scramble of the index
        // maps the first 2^k samples onto an aligned block of 2^k points, which is a (0,k,2)-net
        // too), or all requests of a sample would share the top bits of their points and be
        // correlated (Burley 2020, §4: shuffling).
        // owenScramble(index, g), with the index's reversal done once per sampler.
        return {reverseBits32(laineKarras(reversedIndex, s.index)), s.x, s.y};
    }

    /// x·2⁻³² with 16 random bits below (48 bits in all, exactly a double in [0, 1)).
    static double toUnit(uint32_t x, uint32_t low16) {
        return double((uint64_t(x) << 16) | low16) * 0x1p-48;
    }

    Rng rng_;
    const SobolPixel* pixel_;
    uint32_t reversedIndex_;  ///< the sample index, bits reversed
    int dimension_ = 0;
};

inline Vec2 DeferredPair::value() const {
    if (!pixel_) return u_;
    const SobolSampler::Request r = SobolSampler::request(*pixel_, reversedIndex_, dimension_);
    // owenScramble(reverseBits32(i), seed) = reverseBits32(laineKarras(i, seed)), and
    // owenScramble(C·i, seed) = reverseBits32(laineKarras(reversed C·i, seed)).
    return {SobolSampler::toUnit(reverseBits32(laineKarras(r.index, r.seedX)), low_ >> 16),
            SobolSampler::toUnit(
                reverseBits32(laineKarras(sobolSecondDimensionReversed(r.index), r.seedY)),
                low_ & 0xffffu)};
}

/// deferred2D for the independent stream: the pair is drawn at once.
inline DeferredPair deferred2D(Rng& rng) {
    return DeferredPair(rng.uniform2());
}
inline DeferredPair deferred2D(SobolSampler& sampler) {
    return sampler.deferred2D();
}

}  // namespace shvol
