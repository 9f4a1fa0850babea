#include "shvol/sampling/sobol_sampler.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace shvol {

TEST(SobolSampler, ReverseBits) {
    EXPECT_EQ(reverseBits32(1u), 0x80000000u);
    EXPECT_EQ(reverseBits32(0x80000000u), 1u);
    EXPECT_EQ(reverseBits32(0x0000f00du), 0xb00f0000u);
    for (uint32_t x : {0u, 7u, 0x12345678u, 0xffffffffu})
        EXPECT_EQ(reverseBits32(reverseBits32(x)), x);
}

// The second dimension's direction numbers are m_k / 2^k with m_k = 2 m_{k−1} ⊕ m_{k−1}, m₁ = 1
// (primitive polynomial x + 1): 1, 3, 5, 15, 17, 51, 85, 255 (Bratley & Fox 1988, Table 1; Joe &
// Kuo's new-joe-kuo-6.21201, dimension 2). Point 2^(k−1) is v_k alone.
TEST(SobolSampler, SecondDimensionDirectionNumbers) {
    const uint32_t m[] = {1, 3, 5, 15, 17, 51, 85, 255};
    for (int k = 1; k <= 8; ++k)
        EXPECT_EQ(sobolSecondDimensionBitwise(1u << (k - 1)), m[k - 1] << (32 - k)) << "k = " << k;
    EXPECT_EQ(sobolSecondDimension(3), sobolSecondDimension(1) ^ sobolSecondDimension(2));
    // The table-driven fast path against the bit-by-bit product.
    Rng rng(1, 1);
    for (int i = 0; i < 100000; ++i) {
        const uint32_t n = i < 4096 ? uint32_t(i) : rng.nextU32();
        ASSERT_EQ(sobolSecondDimension(n), sobolSecondDimensionBitwise(n)) << n;
        ASSERT_EQ(sobolSecondDimensionReversed(n), reverseBits32(sobolSecondDimensionBitwise(n)))
            << n;
    }
}

// Each request is its definition, computed the slow way: request d of sample i is the point
// n = owenScramble(i, seeds(d).index) of the (0,2)-sequence, (R(n), C·n), each coordinate
// Owen-scrambled with its own seed, with 16 low bits from the sample's PCG stream (one number per
// request, drawn when it is made; a 1D request keeps the first coordinate and the number's top
// half). Past kDimensions the numbers are the PCG stream's. Requests of all three kinds, mixed.
TEST(SobolSampler, RequestsFollowTheirDefinition) {
    const uint64_t seed = 11, pixelIndex = 4242;
    const SobolPixel pixel(seed, pixelIndex);
    // SobolPixel's key, as its constructor defines it.
    const uint64_t key = mix64(mix64(seed) ^ (pixelIndex * 0x9e3779b97f4a7c15ULL));
    auto unit = [](uint32_t top, uint32_t low16) {
        return std::ldexp(double(top), -32) + std::ldexp(double(low16), -48);
    };
    for (uint32_t i : {0u, 1u, 2u, 1000u, 0xfffffffeu}) {
        SobolSampler sampler(pixel, i);
        Rng rng = Rng::forSample(seed, pixelIndex, i);
        for (int d = 0; d < SobolSampler::kDimensions + 6; ++d) {
            SCOPED_TRACE("sample " + std::to_string(i) + ", request " + std::to_string(d));
            if (d >= SobolSampler::kDimensions) {
                if (d % 3 == 2)
                    ASSERT_EQ(sampler.next1D(), rng.uniform());
                else
                    ASSERT_EQ(d % 3 ? sampler.deferred2D().value() : sampler.next2D(),
                              rng.uniform2());
                continue;
            }
            const SobolPixel::Seeds s = SobolPixel::hashSeeds(key, d);
            const uint32_t n = owenScramble(i, s.index);
            const uint32_t x = owenScramble(reverseBits32(n), s.x),
                           y = owenScramble(sobolSecondDimensionBitwise(n), s.y);
            const uint32_t low = rng.nextU32();
            const Vec2 expected(unit(x, low >> 16), unit(y, low & 0xffffu));
            if (d % 3 == 0)
                ASSERT_EQ(sampler.next2D(), expected);
            else if (d % 3 == 1)
                ASSERT_EQ(sampler.deferred2D().value(), expected);
            else
                ASSERT_EQ(sampler.next1D(), expected.x());
        }
    }
}

// A deferred request takes its place in the stream when it is made: read late, or never, it
// leaves the numbers of every other request and of the independent stream unchanged, and read it
// gives what next2D would have. Past kDimensions the pairs come from the independent stream.
TEST(SobolSampler, DeferredRequestsKeepTheStream) {
    const SobolPixel pixel(9, 4);
    for (uint32_t sample : {0u, 1u, 77u}) {
        SobolSampler eager(pixel, sample), deferred(pixel, sample);
        for (int bounce = 0; bounce < SobolSampler::kDimensions / 3 + 2; ++bounce) {
            const Vec2 flight = eager.next2D(), phase = eager.next2D();
            const double select = eager.next1D(), tracking = eager.rng().uniform();
            const DeferredPair f = deferred.deferred2D();
            const Vec2 p = deferred.next2D();
            const double r = deferred.next1D();
            ASSERT_EQ(p, phase) << bounce;
            ASSERT_EQ(r, select) << bounce;
            if (bounce % 2) ASSERT_EQ(f.value(), flight) << bounce;  // read after the others
            ASSERT_EQ(deferred.rng().uniform(), tracking) << bounce;
        }
    }
}

// A nested uniform scramble: inputs that share their top j bits give outputs that share their
// top j bits, and on the top 12 bits it is a permutation.
TEST(SobolSampler, OwenScrambleIsNested) {
    Rng rng(5, 0);
    for (int t = 0; t < 2000; ++t) {
        const uint32_t seed = rng.nextU32(), x = rng.nextU32();
        const int j = int(rng.nextU32() % 32);
        const uint32_t keep = j ? ~0u << (32 - j) : 0u;
        const uint32_t y = (x & keep) | (rng.nextU32() & ~keep);
        ASSERT_EQ(owenScramble(x, seed) & keep, owenScramble(y, seed) & keep) << "j = " << j;
    }
    for (uint32_t seed : {1u, 0xdeadbeefu}) {
        std::vector<int> hit(4096, 0);
        for (uint32_t i = 0; i < 4096; ++i) ++hit[owenScramble(i << 20, seed) >> 20];
        for (int h : hit) ASSERT_EQ(h, 1);
    }
}

// The first 2^k samples of a pixel put exactly one point in every elementary interval
// [i/2^a, (i+1)/2^a) × [j/2^b, (j+1)/2^b) with a + b = k, for each request of the path.
TEST(SobolSampler, EveryRequestIsAZeroTwoSequence) {
    for (uint64_t pixel : {0ULL, 12345ULL}) {
        for (int request : {0, 1, 7, SobolSampler::kDimensions - 1}) {
            std::vector<Vec2> pts;
            const SobolPixel px(9, pixel);
            for (uint32_t n = 0; n < 1024; ++n) {
                SobolSampler s(px, n);
                for (int d = 0; d < request; ++d) s.next2D();
                pts.push_back(s.next2D());
            }
            for (int k = 0; k <= 10; ++k)
                for (int a = 0; a <= k; ++a) {
                    const int b = k - a;
                    std::vector<int> cell(size_t(1) << k, 0);
                    for (size_t i = 0; i < (size_t(1) << k); ++i) {
                        const int cx = int(pts[i].x() * (1 << a)), cy = int(pts[i].y() * (1 << b));
                        ++cell[size_t(cy) * (size_t(1) << a) + size_t(cx)];
                    }
                    for (int c : cell)
                        ASSERT_EQ(c, 1) << "pixel " << pixel << " request " << request << " 2^" << a
                                        << " x 2^" << b;
                }
        }
    }
}

// Requests are decorrelated from each other and pixels from each other; the numbers are in
// [0, 1), depend only on (seed, pixel, sample), and past kDimensions come from the PCG stream.
TEST(SobolSampler, RequestsAndPixelsAreIndependent) {
    const int n = 4096;
    double sxy = 0, sx = 0, sy = 0, sxx = 0, syy = 0;
    double pxy = 0;
    const SobolPixel p77(3, 77), p78(3, 78);
    for (int i = 0; i < n; ++i) {
        SobolSampler s(p77, uint32_t(i)), t(p78, uint32_t(i));
        const double x = s.next1D(), y = s.next1D(), z = t.next1D();
        sx += x, sy += y, sxx += x * x, syy += y * y, sxy += x * y, pxy += x * z;
    }
    const double cov = sxy / n - sx / n * sy / n;
    const double corr = cov / std::sqrt((sxx / n - sx * sx / n / n) * (syy / n - sy * sy / n / n));
    EXPECT_LT(std::abs(corr), 0.05);             // 1/√4096 ≈ 0.016
    EXPECT_LT(std::abs(pxy / n - 0.25), 0.015);  // E[xz] = 1/4 for independent pixels (σ ≈ 0.0034)
    const SobolPixel fresh(3, 77);               // a pixel whose seeds no sample has asked for yet
    SobolSampler a(p77, 5), b(fresh, 5);
    for (int d = 0; d < SobolSampler::kDimensions + 10; ++d) {
        const Vec2 u = a.next2D();
        ASSERT_EQ(u, b.next2D());
        ASSERT_TRUE(u.x() >= 0 && u.x() < 1 && u.y() >= 0 && u.y() < 1);
    }
}

// A pixel's seeds are computed by whichever sample first asks for a request and reused by the
// others: samples sharing one SobolPixel give the numbers of samples with a fresh one each.
TEST(SobolSampler, PixelSeedsAreSharedExactly) {
    const SobolPixel shared(5, 321);
    for (uint32_t n = 0; n < 64; ++n) {
        const SobolPixel own(5, 321);
        SobolSampler a(shared, n), b(own, n);
        const int requests = int(n * 37 % 140);  // some samples go deeper than the others
        for (int d = 0; d < requests; ++d) ASSERT_EQ(a.next2D(), b.next2D()) << n << " " << d;
    }
    const SobolPixel other(5, 322);
    for (int d = 0; d < SobolPixel::kDimensions; ++d) {
        const SobolPixel::Seeds s = shared.seeds(d), t = other.seeds(d);
        ASSERT_TRUE(s.index != t.index || s.x != t.x || s.y != t.y) << d;  // pixels differ
    }
}

}  // namespace shvol
