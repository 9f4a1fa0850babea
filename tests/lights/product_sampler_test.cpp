#include "shvol/lights/product_sampler.h"

#include <gtest/gtest.h>

#include "shvol/core/rng.h"
#include "shvol/sampling/warp.h"
#include "shvol/sh/sh_basis.h"
#include "sky_test_util.h"

namespace shvol {
namespace {

// The chi² tests in this file form one family: Šidák correction over all of them.
constexpr int kChi2Tests = 10;  // 9 cases of ProductSamplerChi2 and MixtureChi2AndNoHoles

using SH = ProductSampler::SHLobe;

/// Henyey–Greenstein zonal coefficients p_l = g^l √((2l+1)/4π) (DESIGN.md), optionally
/// Hann-windowed.
std::vector<double> hgLobe(double g, int n, bool hann = true) {
    std::vector<double> p(n);
    for (int l = 0; l < n; ++l)
        p[l] = std::pow(g, l) * std::sqrt((2 * l + 1) / FourPi) *
               (hann ? 0.5 * (1 + std::cos(Pi * l / n)) : 1.0);
    return p;
}

double lobeMinimum(const std::vector<double>& p) {
    double m = 1e300, y[64];
    for (int i = 0; i <= 2000; ++i) {
        sh::shEvalZonal(int(p.size()), -1 + i / 1000.0, y);
        double v = 0;
        for (size_t l = 0; l < p.size(); ++l) v += p[l] * y[l];
        m = std::min(m, v);
    }
    return m;
}

SkyHierarchy sunSky(int levels, double sunRadius, double sunRadiance, size_t K = 0,
                    double sunZ = 0.5, double sunPhi = 1.0) {
    const Image img =
        test::testSky(1 << (levels + 1), sphericalDirection(sunZ, sunPhi), sunRadius, sunRadiance);
    SkyHierarchy::LatLongSource src;
    src.image = &img;
    return SkyHierarchy::fromLatLong(src, levels, K);
}

template <class Lobe>
Chi2Result productChi2(const ProductSampler& ps, const Lobe& c, double beta, uint64_t seed) {
    const test::GridProbability prob(ps.depth(), [&](const Vec3& w) { return ps.pdf(c, beta, w); });
    EXPECT_NEAR(prob.total(), 1.0, 1e-6);
    Chi2Options opt;
    opt.numTests = kChi2Tests;
    opt.seed = seed;
    opt.sampleCount = 400000;
    // Its lost mass, 1 − total ≤ 10⁻⁶, comes back empty: at most 0.4 of the draws in expectation
    // (five would be a Poisson tail of 10⁻⁶; helper 90).
    opt.allowFailedSamples = true;
    const Chi2Result r = chi2TestSphereCells(
        [&](Rng& rng) -> std::optional<Vec3> {
            const WarpSample s = ps.warp(c, beta, rng.uniform2());
            if (!(s.pdf > 0)) return std::nullopt;
            const double p = ps.pdf(c, beta, s.direction());
            EXPECT_NEAR(s.pdf, p, 1e-6 * p);
            return s.direction();
        },
        prob, opt);
    EXPECT_LE(r.failedSamples, 5) << r.report;
    return r;
}

}  // namespace

// The rotated zonal lobe is p̃(ω·ω₀): rotateZonal against the zonal reconstruction.
TEST(ProductSampler, RotateZonalMatchesZonalReconstruction) {
    const SkyHierarchy sky = SkyHierarchy::constant(1.0, false);
    for (int n : {1, 2, 5, 8, 32}) {
        const ProductSampler ps(sky, n);
        const std::vector<double> p = hgLobe(0.7, n);
        std::vector<double> c(n * n), y(n);
        Rng rng(n, 1);
        for (int i = 0; i < 20; ++i) {
            const Vec3 axis = sphericalDirection(2 * rng.uniform() - 1, TwoPi * rng.uniform());
            const Vec3 w = sphericalDirection(2 * rng.uniform() - 1, TwoPi * rng.uniform());
            ps.rotateZonal(p.data(), axis, c.data());
            sh::shEvalZonal(n, axis.dot(w), y.data());
            double ref = 0;
            for (int l = 0; l < n; ++l) ref += p[l] * y[l];
            EXPECT_NEAR(sh::shReconstruct(n, c.data(), w), ref, 1e-10 * (1 + std::abs(ref)));
        }
    }
}

// Fast path vs slow reference: the child weights under a constant sky are the lobe's integrals
// over the children, here checked against brute-force midpoint quadrature of p̃(ω·ω₀) in (z, φ).
TEST(ProductSampler, ChildWeightsAreLobeIntegrals) {
    const SkyHierarchy sky = SkyHierarchy::constant(1.0, false);
    const int n = 8;
    const ProductSampler ps(sky, n);
    const std::vector<double> p = hgLobe(0.8, n);
    std::vector<double> c(n * n), y(n);
    const Vec3 axis = sphericalDirection(0.3, 5.5);
    ps.rotateZonal(p.data(), axis, c.data());
    for (const WarpNode node :
         {WarpNode{}, WarpNode{}.child(1, 0), WarpNode{}.child(1, 1).child(0, 1)}) {
        double w[4];
        ps.childWeights(SH{c.data()}, node, 1.0, w);
        for (int r = 0; r < 2; ++r)
            for (int k = 0; k < 2; ++k) {
                const WarpNode ch = node.child(r, k);
                constexpr int M = 400;
                double ref = 0;
                for (int i = 0; i < M; ++i)
                    for (int j = 0; j < M; ++j) {
                        const double z = ch.z0 + (i + 0.5) / M * (ch.z1 - ch.z0);
                        const double phi = ch.phi0 + (j + 0.5) / M * (ch.phi1 - ch.phi0);
                        sh::shEvalZonal(n, axis.dot(sphericalDirection(z, phi)), y.data());
                        double v = 0;
                        for (int l = 0; l < n; ++l) v += p[l] * y[l];
                        ref += v;
                    }
                ref *= ch.area() / (M * M);
                EXPECT_NEAR(w[2 * r + k], std::max(0.0, ref), 2e-5) << node.level << r << k;
            }
    }
}

// The child weights under a sky that is not constant: the lobe's mass over each child times the
// sky's average over it, each clamped at 0, and the sky's alone below productDepth. The averages
// come from the leaves' own values (sky.value at each leaf's centre, in the sky's units), not
// from the Morton-ordered mip-map the sampler reads, so a child's sky taken from the wrong
// node, a swapped z or φ half, or a dropped sky factor fails; every other test of the weights
// has a constant sky and the χ² tests compare the warp only with its own pdf() (helper 176).
// Down the path to the sun and down a path across the φ seam, in both lobe forms.
TEST(ProductSampler, ChildWeightsAreTheLobesMassTimesTheSkysAverage) {
    const int levels = 7;
    const double sunZ = 0.5, sunPhi = 1.0;
    const SkyHierarchy sky = sunSky(levels, 0.2, 30, 0, sunZ, sunPhi);
    const int n = 8;
    const ProductSampler ps(sky, n);
    ASSERT_EQ(ps.depth(), levels);
    ASSERT_LT(ps.productDepth(), levels);
    const std::vector<double> p = hgLobe(0.8, n);
    const Vec3 axis = sphericalDirection(0.4, 1.3);
    std::vector<double> c(n * n);
    ps.rotateZonal(p.data(), axis, c.data());
    ProductSampler::ZonalLobe zonal;
    ps.rotateZonal(p.data(), axis, zonal);
    const int leaves = 1 << levels;
    const auto skyAverage = [&](const WarpNode& nd) {  // the mean of its leaves' values
        const int span = leaves >> nd.level;
        double sum = 0;
        for (int iz = nd.iz * span; iz < (nd.iz + 1) * span; ++iz)
            for (int ip = nd.iphi * span; ip < (nd.iphi + 1) * span; ++ip)
                sum += sky.value(sphericalDirection(-1 + (iz + 0.5) * 2.0 / leaves,
                                                    (ip + 0.5) * TwoPi / leaves));
        return sum / (double(span) * span);
    };
    for (const double targetPhi : {sunPhi, TwoPi - 1e-3}) {
        uint32_t izLeaf, ipLeaf;
        skyCell(sphericalDirection(sunZ, targetPhi), levels, &izLeaf, &ipLeaf);
        WarpNode node;
        for (int level = 0; level < levels; ++level) {
            const double avg = skyAverage(node) / sky.unit();
            double wSH[4], wZonal[4], m[4];
            ps.childWeights(SH{c.data()}, node, avg, wSH);
            ps.childWeights(zonal, node, avg, wZonal);
            if (level < ps.productDepth())
                ps.lobeMasses(zonal, level, uint32_t(node.iz), uint32_t(node.iphi), m);
            for (int r = 0; r < 2; ++r)
                for (int k = 0; k < 2; ++k) {
                    const int i = 2 * r + k;
                    const double s = std::max(0.0, skyAverage(node.child(r, k)) / sky.unit());
                    const double ref = level < ps.productDepth() ? std::max(0.0, m[i]) * s : s;
                    EXPECT_NEAR(wZonal[i], ref, 1e-6 * ref + 1e-15) << level << " " << i;
                    EXPECT_NEAR(wSH[i], ref, 1e-6 * ref + 1e-12 * std::abs(m[0]))
                        << level << " " << i;
                }
            const int shift = levels - 1 - level;
            node = node.child((izLeaf >> shift) & 1, (ipLeaf >> shift) & 1);
        }
    }
}

// The lobe masses of every level the product warps, in both lobe forms, against midpoint
// quadrature of the reconstruction p̃(ω·ω₀) over each child: at orders 2, 17 and 32, down the
// path of the heaviest child (the lobe's peak, where most samples go) and of the lightest (its
// ringing tail). The test above checks the top three levels at order 8 (helper 92).
TEST(ProductSampler, LobeMassesAtEveryLevelAndOrder) {
    const SkyHierarchy sky = SkyHierarchy::constant(1.0, false);
    for (const int n : {2, 17, 32}) {
        const ProductSampler ps(sky, n);
        const std::vector<double> p = hgLobe(0.9, n);
        const Vec3 axis = sphericalDirection(-0.45, 2.3);
        std::vector<double> c(n * n), y(n);
        ps.rotateZonal(p.data(), axis, c.data());
        ProductSampler::ZonalLobe zonal;
        ps.rotateZonal(p.data(), axis, zonal);
        for (const bool heaviest : {true, false}) {
            WarpNode node;
            for (int level = 0; level < ps.productDepth(); ++level) {
                double mSH[4], mZonal[4], ref[4];
                ps.lobeMasses(ProductSampler::SHLobe{c.data()}, level, uint32_t(node.iz),
                              uint32_t(node.iphi), mSH);
                ps.lobeMasses(zonal, level, uint32_t(node.iz), uint32_t(node.iphi), mZonal);
                int next = 0;
                for (int r = 0; r < 2; ++r)
                    for (int k = 0; k < 2; ++k) {
                        const WarpNode ch = node.child(r, k);
                        constexpr int M = 120;
                        double sum = 0;
                        // Midpoints in θ (dz = sin θ dθ): in z, √(1 − z²) has no derivative at
                        // the poles, and the rule's error was 5·10⁻⁴ of a polar child's mass.
                        const double t0 = std::acos(ch.z1), t1 = std::acos(ch.z0);
                        for (int i = 0; i < M; ++i) {
                            const double theta = t0 + (i + 0.5) / M * (t1 - t0);
                            for (int j = 0; j < M; ++j) {
                                const double phi = ch.phi0 + (j + 0.5) / M * (ch.phi1 - ch.phi0);
                                sh::shEvalZonal(n,
                                                axis.dot(sphericalDirection(std::cos(theta), phi)),
                                                y.data());
                                for (int l = 0; l < n; ++l) sum += p[l] * y[l] * std::sin(theta);
                            }
                        }
                        ref[2 * r + k] = sum * (t1 - t0) * (ch.phi1 - ch.phi0) / (M * M);
                    }
                for (int i = 0; i < 4; ++i) {
                    // (midpoint quadrature's error: about 10⁻⁵ of the parent's mass at the top)
                    const double tol = 1e-9 + 1e-4 * std::abs(ref[i]) +
                                       2e-5 * (std::abs(ref[0]) + std::abs(ref[1]) +
                                               std::abs(ref[2]) + std::abs(ref[3]));
                    EXPECT_NEAR(mSH[i], ref[i], tol) << "order " << n << " level " << level;
                    EXPECT_NEAR(mZonal[i], ref[i], tol) << "order " << n << " level " << level;
                    if (heaviest ? ref[i] > ref[next] : ref[i] < ref[next]) next = i;
                }
                node = node.child(next / 2, next % 2);
            }
        }
    }
}

// chi² over the sphere: the product sampler's samples follow pdf(), for several skies (a 0.53°
// sun, a compressed wavelet, a sun 1e6× the sky), lobe orders 2–32 and orientations including
// both poles and the φ seam. One test per case, so that ctest spreads them over the cores.
struct ProductChi2Case {
    int sky, order, axis;
    double g;
};
// The case in test names (gtest would print the struct's bytes, padding included, so the names
// would change from build to build).
void PrintTo(const ProductChi2Case& c, std::ostream* os) {
    *os << "sky" << c.sky << "_order" << c.order << "_axis" << c.axis << "_g" << c.g;
}
class ProductSamplerChi2 : public testing::TestWithParam<ProductChi2Case> {};

TEST_P(ProductSamplerChi2, SamplesFollowPdf) {
    static const double sun = 0.53 * Pi / 180 / 2;  // angular radius of the real sun
    static const SkyHierarchy skies[] = {sunSky(8, sun, 5e4), sunSky(8, 0.05, 100, 2000),
                                         sunSky(7, 0.02, 1e6)};
    const Vec3 axes[] = {Vec3(0, 0, 1), Vec3(0, 0, -1), sphericalDirection(0.2, 0.0),
                         sphericalDirection(0.5, TwoPi - 1e-9), sphericalDirection(0.5, 1.0)};
    const ProductChi2Case cs = GetParam();
    const ProductSampler ps(skies[cs.sky], cs.order);
    const std::vector<double> p = hgLobe(cs.g, cs.order);
    ProductSampler::ZonalLobe zl;  // the fast path the integrator uses
    ps.rotateZonal(p.data(), axes[cs.axis], zl);
    const double beta = ps.defensiveShare(lobeMinimum(p));
    const Chi2Result r = productChi2(ps, zl, beta, 1 + cs.sky * 100 + cs.order + cs.axis);
    EXPECT_TRUE(r.passed) << "sky " << cs.sky << " order " << cs.order << " axis " << cs.axis
                          << " g " << cs.g << "\n"
                          << r.report;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, ProductSamplerChi2,
    testing::Values(ProductChi2Case{0, 8, 4, 0.8}, ProductChi2Case{0, 2, 0, 0.5},
                    ProductChi2Case{0, 32, 4, 0.95}, ProductChi2Case{1, 8, 2, 0.8},
                    ProductChi2Case{1, 16, 3, 0.9}, ProductChi2Case{2, 8, 1, 0.8},
                    ProductChi2Case{2, 4, 3, -0.6}, ProductChi2Case{0, 8, 2, 0.999},
                    ProductChi2Case{2, 32, 0, -0.999}));

// The same with the mixture forced on (β = 0.1) and with an unwindowed, ringing lobe, whose
// negative regions the mixture must cover.
TEST(ProductSampler, MixtureChi2AndNoHoles) {
    const SkyHierarchy sky = sunSky(7, 0.04, 300);
    const int n = 6;
    const ProductSampler ps(sky, n);
    const std::vector<double> p = hgLobe(0.97, n, false);
    ASSERT_LT(lobeMinimum(p), 0);  // rings negative
    std::vector<double> c(n * n);
    const Vec3 axis = sphericalDirection(-0.3, 2.0);
    ps.rotateZonal(p.data(), axis, c.data());
    const double beta = ps.defensiveShare(lobeMinimum(p));
    EXPECT_EQ(beta, ProductSampler::kDefensiveFraction);
    EXPECT_TRUE(productChi2(ps, SH{c.data()}, beta, 77).passed);
    // Every direction where the sky is lit has a positive density, also behind the lobe.
    Rng rng(5, 5);
    int holesWithout = 0;
    for (int i = 0; i < 2000; ++i) {
        const Vec3 w = sphericalDirection(2 * rng.uniform() - 1, TwoPi * rng.uniform());
        uint32_t iz, ip;
        skyCell(w, sky.levels(), &iz, &ip);
        if (!(sky.average(sky.levels(), iz, ip) > 0)) continue;
        EXPECT_GT(ps.pdf(SH{c.data()}, beta, w), 0.0);
        holesWithout += !(ps.pdf(SH{c.data()}, w) > 0);
    }
    EXPECT_GT(holesWithout, 0);  // the product alone does have holes here
}

// Point sets warp like single samples.
TEST(ProductSampler, PointSetEqualsSingleSamples) {
    // The full and a wavelet-compressed sky (K = 40 coefficients), and both lobes: the SH one and
    // the zonal one the integrator uses (its point set was compared for neither; helper 78).
    for (const size_t K : {size_t(0), size_t(40)}) {
        const SkyHierarchy sky = sunSky(7, 0.05, 100, K);
        ASSERT_EQ(sky.compressed(), K > 0);
        const ProductSampler ps(sky, 8);
        const std::vector<double> p = hgLobe(0.8, 8);
        std::vector<double> c(64);
        ProductSampler::ZonalLobe z;
        ps.rotateZonal(p.data(), sphericalDirection(0.1, 3.0), c.data());
        ps.rotateZonal(p.data(), sphericalDirection(0.1, 3.0), z);
        std::vector<Vec2> u;
        Rng rng(9, 9);
        for (int i = 0; i < 100; ++i) u.push_back(rng.uniform2());
        const auto compare = [&](const auto& lobe, const char* name) {
            std::vector<WarpSample> out;
            ps.warp(lobe, u, out);
            ASSERT_EQ(out.size(), u.size()) << name;
            for (size_t i = 0; i < u.size(); ++i) {
                const WarpSample s = ps.warp(lobe, u[i]);
                EXPECT_GT(s.pdf, 0) << name << " K " << K;
                EXPECT_NEAR(out[i].z, s.z, 1e-12) << name << " K " << K;
                EXPECT_NEAR(out[i].phi, s.phi, 1e-12) << name << " K " << K;
                EXPECT_NEAR(out[i].pdf, s.pdf, 1e-9 * s.pdf) << name << " K " << K;
            }
        };
        compare(SH{c.data()}, "SH lobe");
        compare(z, "zonal lobe");
    }
}

// Hard cases: an all-black sky gives no samples; a sky lit in one leaf only gets every sample
// there with a finite pdf, wherever the lobe points.
TEST(ProductSampler, BlackAndSingleLeafSkies) {
    const SkyHierarchy black = SkyHierarchy::fromLeaves(5, std::vector<double>(1024, 0.0));
    const ProductSampler pb(black, 8);
    std::vector<double> c(64);
    const std::vector<double> p = hgLobe(0.9, 8);
    pb.rotateZonal(p.data(), Vec3(0, 0, 1), c.data());
    EXPECT_EQ(pb.warp(SH{c.data()}, 0.1, Vec2(0.5, 0.5)).pdf, 0.0);
    EXPECT_EQ(pb.pdf(SH{c.data()}, 0.1, Vec3(1, 0, 0)), 0.0);

    std::vector<double> leaves(1024, 0.0);
    leaves[size_t(3) * 32 + 0] = 1.0;  // near the south pole, at φ = 0
    const SkyHierarchy one = SkyHierarchy::fromLeaves(5, leaves);
    const ProductSampler ps(one, 8);
    for (const Vec3& axis : {Vec3(0, 0, 1), Vec3(0, 0, -1), Vec3(1, 0, 0)}) {
        ps.rotateZonal(p.data(), axis, c.data());
        Rng rng(1, 2);
        int drawn = 0;
        for (int i = 0; i < 200; ++i) {
            const WarpSample s = ps.warp(SH{c.data()}, 0.1, rng.uniform2());
            if (!(s.pdf > 0)) continue;  // the lobe may be ≤ 0 over the lit leaf
            ++drawn;
            EXPECT_TRUE(std::isfinite(s.pdf));
            uint32_t iz, ip;
            skyCell(s.direction(), 5, &iz, &ip);
            EXPECT_EQ(iz, 3u);
            EXPECT_EQ(ip, 0u);
        }
        // The 10% sky-only share always reaches the lit leaf, whatever the lobe does there.
        EXPECT_GE(drawn, 10) << axis.transpose();
    }
}

}  // namespace shvol

namespace shvol {

// sample() returns with each direction the product it follows, lobeValue × the sky's value: the
// factored zonal lobe's value agrees with the reconstruction of its rotated SH coefficients (fast
// path vs slow reference), and value/pdf estimates ∫ p̃ L̃ dω, by a midpoint rule over 512 × 1024
// cells, within 5 standard errors over 200,000 samples (the mixture reaches every direction).
TEST(ProductSampler, SampleValueIsTheProductItFollows) {
    const SkyHierarchy sky = sunSky(6, 0.1, 50);
    for (int n : {4, 12}) {
        const ProductSampler ps(sky, n);
        const std::vector<double> p = hgLobe(0.7, n);
        const Vec3 axis = sphericalDirection(0.4, 1.2);
        std::vector<double> c(n * n);
        ProductSampler::ZonalLobe z;
        ps.rotateZonal(p.data(), axis, c.data());
        ps.rotateZonal(p.data(), axis, z);
        Rng rng(n, 9);
        for (int i = 0; i < 200; ++i) {
            const Vec3 w = sampleUniformSphere(rng.uniform2());
            EXPECT_NEAR(ps.lobeValue(z, w), sh::shReconstruct(n, c.data(), w), 1e-12) << n;
            EXPECT_NEAR(ps.lobeValue(SH{c.data()}, w), sh::shReconstruct(n, c.data(), w), 1e-15);
        }
        double integral = 0;
        const int nz = 512, nphi = 1024;
        for (int i = 0; i < nz; ++i)
            for (int j = 0; j < nphi; ++j) {
                const Vec3 w =
                    sphericalDirection(-1 + (i + 0.5) * 2 / nz, (j + 0.5) * TwoPi / nphi);
                integral += ps.lobeValue(z, w) * sky.value(w) * (2.0 / nz) * (TwoPi / nphi);
            }
        double sum = 0, sum2 = 0;
        const int N = 200000;
        for (int i = 0; i < N; ++i) {
            const SphereSample x = ps.sample(z, 0.1, rng.uniform2());
            ASSERT_GT(x.pdf, 0);
            if (i < 2000) {  // each sample's value and pdf are those of its direction (helper 179)
                ASSERT_NEAR(x.value, ps.lobeValue(z, x.w) * sky.value(x.w),
                            1e-12 * std::abs(x.value) + 1e-300);
                ASSERT_NEAR(x.pdf, ps.pdf(z, 0.1, x.w), 1e-9 * x.pdf);
            }
            const double r = x.value / x.pdf;
            sum += r, sum2 += r * r;
        }
        const double mean = sum / N, se = std::sqrt((sum2 / N - mean * mean) / (N - 1));
        EXPECT_NEAR(mean, integral, 5 * se) << n << ": " << mean << " against " << integral;
    }
}

// Fast path vs slow reference: the factored zonal lobe gives the same child masses, samples and
// pdfs as its full set of rotated SH coefficients, at every product level, any order, at the
// poles and on the seam.
TEST(ProductSampler, ZonalFastPathEqualsSHLobe) {
    const SkyHierarchy sky = sunSky(6, 0.05, 300);
    for (int n : {1, 3, 8, 17, 32}) {
        const ProductSampler ps(sky, n);
        const std::vector<double> p = hgLobe(0.85, n);
        std::vector<double> c(n * n);
        ProductSampler::ZonalLobe z;
        for (const Vec3& axis : {Vec3(0, 0, 1), Vec3(0, 0, -1), sphericalDirection(0.3, 0.0),
                                 sphericalDirection(-0.7, 4.0)}) {
            ps.rotateZonal(p.data(), axis, c.data());
            ps.rotateZonal(p.data(), axis, z);
            Rng rng(n, 4);
            for (int i = 0; i < 50; ++i) {
                const int level = i % ps.productDepth();
                const uint32_t iz = uint32_t(rng.uniform() * (1 << level));
                const uint32_t ip = uint32_t(rng.uniform() * (1 << level));
                double a[4], b[4];
                ps.lobeMasses(SH{c.data()}, level, iz, ip, a);
                ps.lobeMasses(z, level, iz, ip, b);
                for (int k = 0; k < 4; ++k) EXPECT_NEAR(a[k], b[k], 1e-12) << n << " " << level;
                const Vec2 u = rng.uniform2();
                const WarpSample sa = ps.warp(SH{c.data()}, u), sb = ps.warp(z, u);
                EXPECT_NEAR(sa.z, sb.z, 1e-9);
                EXPECT_NEAR(sa.phi, sb.phi, 1e-9);
                EXPECT_NEAR(sa.pdf, sb.pdf, 1e-9 * sa.pdf);
            }
        }
    }
}

}  // namespace shvol

namespace shvol {

// Bands beyond significantBands() are dropped: an isotropic lobe padded with zeros to order 16
// uses one band and samples as the full lobe does; a lobe with a tiny last band keeps it.
TEST(ProductSampler, SignificantBands) {
    EXPECT_EQ(ProductSampler::significantBands({0.28, 1e-17, -2e-18, 0.0}), 1);
    EXPECT_EQ(ProductSampler::significantBands({0.28, 0.1, 0.0, 1e-6, 0.0}), 4);
    const SkyHierarchy sky = sunSky(6, 0.05, 300);
    const ProductSampler ps(sky, 16);
    std::vector<double> p(16, 0.0);
    p[0] = 1 / std::sqrt(FourPi);
    ProductSampler::ZonalLobe full, one;
    const Vec3 axis = sphericalDirection(0.4, 2.0);
    ps.rotateZonal(p.data(), axis, full);
    ps.rotateZonal(p.data(), axis, one, ProductSampler::significantBands(p));
    EXPECT_EQ(one.n, 1);
    Rng rng(8, 8);
    for (int i = 0; i < 100; ++i) {
        const Vec2 u = rng.uniform2();
        const WarpSample a = ps.warp(full, u), b = ps.warp(one, u);
        EXPECT_NEAR(a.z, b.z, 1e-12);
        EXPECT_NEAR(a.pdf, b.pdf, 1e-9 * a.pdf);
    }
}

}  // namespace shvol
