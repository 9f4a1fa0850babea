#pragma once
/// \file Random numbers keyed by (seed, pixel, sample) so that an image depends on the seed and
/// never on the thread count or the order in which tiles run.
#include <cstdint>

#include "shvol/core/math.h"

namespace shvol {

/// SplitMix64 finaliser (Steele, Lea, Flood 2014): a bijective 64-bit mixer.
inline uint64_t mix64(uint64_t z) {
    z += 0x9e3779b97f4a7c15ULL;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

/// PCG32 (O'Neill 2014, pcg-random.org, XSH-RR 64/32) with a selectable stream.
class Rng {
  public:
    Rng() { seed(0, 0); }
    Rng(uint64_t state, uint64_t stream) { seed(state, stream); }
    /// The generator for one path: stream and state derived from (seed, pixel, sample).
    static Rng forSample(uint64_t seed, uint64_t pixel, uint64_t sample) {
        const uint64_t k = mix64(mix64(seed) ^ mix64(pixel * 0x632be59bd9b4e019ULL + sample));
        return Rng(k, mix64(k ^ 0xda942042e4dd58b5ULL));
    }
    void seed(uint64_t initState, uint64_t stream) {
        state_ = 0;
        inc_ = (stream << 1u) | 1u;
        nextU32();
        state_ += initState;
        nextU32();
    }
    uint32_t nextU32() {
        const uint64_t old = state_;
        state_ = old * 0x5851f42d4c957f2dULL + inc_;
        const uint32_t xorShifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
        const uint32_t rot = static_cast<uint32_t>(old >> 59u);
        return (xorShifted >> rot) | (xorShifted << ((~rot + 1u) & 31));
    }
    /// Uniform double in [0, 1) with 53 random bits.
    double uniform() {
        const uint64_t hi = nextU32(), lo = nextU32();
        return static_cast<double>(((hi << 32) | lo) >> 11) * 0x1.0p-53;
    }
    /// The sample-stream interface the path tracer is written against (SobolSampler has the
    /// same): an independent stream serves every request with fresh numbers.
    double next1D() { return uniform(); }
    Vec2 next2D() { return uniform2(); }
    Rng& rng() { return *this; }
    Vec2 uniform2() {
        const double a = uniform();
        return {a, uniform()};
    }

  private:
    uint64_t state_ = 0, inc_ = 1;
};

/// A uniformly distributed rotation: a unit quaternion from four Box–Muller normals
/// (Shoemake 1992, "Uniform random rotations").
inline Eigen::Matrix3d uniformRandomRotation(Rng& rng) {
    double q[4];
    for (int i = 0; i < 4; i += 2) {
        const double u1 = std::max(rng.uniform(), 1e-300), u2 = rng.uniform();
        const double r = std::sqrt(-2 * std::log(u1));
        q[i] = r * std::cos(TwoPi * u2);
        q[i + 1] = r * std::sin(TwoPi * u2);
    }
    return Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
}

}  // namespace shvol
