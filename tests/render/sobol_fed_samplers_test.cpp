// The directional samplers fed by the path tracer's quasi-random stream (SobolSampler) instead of
// independent numbers: the chi² test over the sphere still finds their samples distributed as
// their pdfs say. Sample i is request `kRequest` of sample i of one pixel, so the points are one
// scrambled (0,2)-sequence, as a pixel's paths see them.
#include <gtest/gtest.h>

#include "lights/sky_test_util.h"
#include "shvol/lights/environment.h"
#include "shvol/lights/product_sampler.h"
#include "shvol/lights/sky_hierarchy.h"
#include "shvol/phase/cornette_shanks_phase.h"
#include "shvol/phase/phase_function.h"
#include "shvol/phase/phase_table_csv.h"
#include "shvol/phase/rayleigh_phase.h"
#include "shvol/phase/schlick_phase.h"
#include "shvol/phase/sh_sampled_phase.h"
#include "shvol/phase/two_term_hg_phase.h"
#include "shvol/sampling/chi2.h"
#include "shvol/sampling/sobol_sampler.h"
#include "shvol/sampling/zonal_sh_sampler.h"

namespace shvol {
namespace {

constexpr int kChi2Tests = 12;  // one family: Šidák correction over the tests in this file
constexpr int kRequest = 2;     // a phase sample of the first bounce (camera jitter, light, phase)

/// The kRequest-th 2D number of consecutive samples of pixel 4711.
class SobolPoints {
  public:
    Vec2 next() {
        SobolSampler s(pixel_, index_++);
        for (int d = 0; d < kRequest; ++d) s.next2D();
        return s.next2D();
    }

  private:
    const SobolPixel pixel_{1, 4711};
    uint32_t index_ = 0;
};

const Vec3 kWo = Vec3(0.48, -0.6, 0.64).normalized();

Chi2Options options() {
    Chi2Options opt;
    opt.numTests = kChi2Tests;
    opt.sampleCount = 1 << 20;
    return opt;
}

Chi2Result phaseChi2(const PhaseFunction& p) {
    SobolPoints u;
    return chi2TestSphere([&](Rng&) { return std::optional<Vec3>(p.sample(kWo, u.next()).wi); },
                          [&](const Vec3& wi) { return p.pdf(kWo, wi); }, options());
}

}  // namespace

TEST(SobolFedSamplers, HenyeyGreensteinChi2) {
    for (double g : {0.7, -0.99}) {
        const Chi2Result r = phaseChi2(HenyeyGreensteinPhase(g));
        EXPECT_TRUE(r.passed) << "g = " << g << "\n" << r.report;
    }
}

TEST(SobolFedSamplers, IsotropicChi2) {
    const Chi2Result r = phaseChi2(IsotropicPhase{});
    EXPECT_TRUE(r.passed) << r.report;
}

// The other phase functions, each with its own sampling routine: the analytic ones and a
// tabulated one (media/phase/mie_like.csv, sampled by inverting its piecewise-quadratic CDF).
TEST(SobolFedSamplers, OtherPhaseFunctionsChi2) {
    const std::vector<std::pair<const char*, PhaseFunction>> phases = {
        {"rayleigh", RayleighPhase{}},
        {"schlick 0.8", SchlickPhase(0.8)},
        {"cornette-shanks 0.9", CornetteShanksPhase(0.9)},
        {"two-term hg", TwoTermHenyeyGreensteinPhase(0.8, -0.4, 0.7)},
        {"tabulated mie_like",
         readPhaseTableCsv(std::string(SHVOL_SOURCE_DIR) + "/media/phase/mie_like.csv")}};
    for (const auto& [name, p] : phases) {
        const Chi2Result r = phaseChi2(p);
        EXPECT_TRUE(r.passed) << name << "\n" << r.report;
    }
}

// The SH-sampled phase function: cell probabilities from the sampler's CDF in μ, in kWo's frame
// (as tests/phase/sh_sampled_phase_test.cpp).
TEST(SobolFedSamplers, SHSampledPhaseChi2) {
    const SHSampledPhase sh(HenyeyGreensteinPhase(0.9), 32);
    const PhaseFunction phase(sh);
    const ZonalSHSampler& s = sh.sampler();
    const double a = sh.defensiveFraction();
    const Frame frame(kWo);
    SobolPoints u;
    const Chi2Result r = chi2TestSphereCells(
        [&](Rng&) -> std::optional<Vec3> {
            const PhaseSample x = phase.sample(kWo, u.next());
            if (!(x.pdf > 0)) return std::nullopt;
            return frame.toLocal(x.wi);
        },
        [&](double z0, double z1, double p0, double p1) {
            return (1 - a) * (p1 - p0) / TwoPi * (s.cdf(z1) - s.cdf(z0)) +
                   a * (z1 - z0) * (p1 - p0) / FourPi;
        },
        options());
    EXPECT_TRUE(r.passed) << r.report;
}

namespace {
/// A 32×16 lat-long sky with a gradient, a black row and a bright pixel.
Environment testEnvironment() {
    Image img(32, 16);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            img.set(x, y, Spectrum(0.1 + 0.05 * x, 0.2 + 0.1 * y, 0.3 + 0.02 * (x + y)));
    for (int x = 0; x < img.width; ++x) img.set(x, 12, Spectrum::Zero());
    img.set(5, 3, Spectrum(400, 300, 200));
    return Environment::image(img, 1.0, 0.0, false);
}
}  // namespace

// The wavelet strategy's sky sampler (hierarchical warping down the sky's quadtree), with the
// exact cell probabilities of its piecewise-constant pdf.
TEST(SobolFedSamplers, SkyHierarchyChi2) {
    const SkyHierarchy sky = testEnvironment().skyHierarchy();
    const test::GridProbability prob(sky.levels(), [&](const Vec3& w) { return sky.pdf(w); });
    SobolPoints u;
    const Chi2Result r = chi2TestSphereCells(
        [&](Rng&) -> std::optional<Vec3> {
            const WarpSample s = sky.warp(u.next());
            if (!(s.pdf > 0)) return std::nullopt;
            return s.direction();
        },
        prob, options());
    EXPECT_TRUE(r.passed) << r.report;
}

// The product strategy's sampler: an HG 0.7 lobe (order 8, Hann) rotated off-axis times the sky,
// with the 10% sky-only share, as the integrator builds it at a scattering event.
TEST(SobolFedSamplers, ProductSamplerChi2) {
    const SkyHierarchy sky = testEnvironment().skyHierarchy();
    const ProductSampler ps(sky, 8);
    std::vector<double> p(8);
    for (int l = 0; l < 8; ++l)
        p[size_t(l)] =
            std::pow(0.7, l) * std::sqrt((2 * l + 1) / FourPi) * 0.5 * (1 + std::cos(Pi * l / 8));
    ProductSampler::ZonalLobe lobe;
    ps.rotateZonal(p.data(), kWo, lobe);
    const double beta = ProductSampler::kDefensiveFraction;
    const test::GridProbability prob(ps.depth(),
                                     [&](const Vec3& w) { return ps.pdf(lobe, beta, w); });
    SobolPoints u;
    const Chi2Result r = chi2TestSphereCells(
        [&](Rng&) -> std::optional<Vec3> {
            const WarpSample s = ps.warp(lobe, beta, u.next());
            if (!(s.pdf > 0)) return std::nullopt;
            return s.direction();
        },
        prob, options());
    EXPECT_TRUE(r.passed) << r.report;
}

// Importance sampling of a lat-long environment with a bright pixel and a black row.
TEST(SobolFedSamplers, EnvironmentImageChi2) {
    const Environment env = testEnvironment();
    SobolPoints u;
    const Chi2Result r = chi2TestSphere(
        [&](Rng&) -> std::optional<Vec3> {
            const LightSample s = env.sample(u.next());
            if (!(s.pdf > 0)) return std::nullopt;
            return s.wi;
        },
        [&](const Vec3& w) { return env.pdf(w); }, options());
    EXPECT_TRUE(r.passed) << r.report;
}

}  // namespace shvol
