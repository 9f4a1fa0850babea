#include "shvol/lights/environment.h"

#include <gtest/gtest.h>

#include <cmath>
#include <thread>
#include <vector>

#include "shvol/core/error.h"
#include "shvol/core/rng.h"
#include "shvol/sampling/chi2.h"

namespace shvol {
namespace {

// The chi² tests in this file form one family: Šidák correction over all of them.
constexpr int kChi2Tests = 7;

// 32×16 map: a colour gradient over the whole sphere plus a bright "sun" pixel and a black band.
Image syntheticSky() {
    Image img(32, 16);
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x)
            img.set(x, y, Spectrum(0.1 + 0.05 * x, 0.2 + 0.1 * y, 0.3 + 0.02 * (x + y)));
    for (int x = 0; x < img.width; ++x) img.set(x, 12, Spectrum::Zero());  // black row
    img.set(5, 3, Spectrum(400, 300, 200));                                // sun
    return img;
}

Chi2Result runChi2(const Environment& env, uint64_t seed) {
    Chi2Options opt;
    opt.numTests = kChi2Tests;
    opt.seed = seed;
    return chi2TestSphere(
        [&](Rng& rng) -> std::optional<Vec3> {
            const LightSample s = env.sample(rng.uniform2());
            if (!(s.pdf > 0)) return std::nullopt;
            return s.wi;
        },
        [&](const Vec3& w) { return env.pdf(w); }, opt);
}

TEST(Environment, ImageChi2) {
    const auto r = runChi2(Environment::image(syntheticSky(), 1.0, 0.0, false), 1);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-6) << r.report;
}

TEST(Environment, ImageRotatedChi2) {
    const auto r = runChi2(Environment::image(syntheticSky(), 2.0, 37.0, false), 2);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-6) << r.report;
}

// The other latitude-longitude convention (environment.mapping "shvol"), rotated: untested before
// 6 Dec (helper 92), where a sign of its φ would draw light from the mirror image of the sky.
TEST(Environment, ImageShvolMappingRotatedChi2) {
    const auto r =
        runChi2(Environment::image(syntheticSky(), 1.0, 37.0, false, LatLongMapping::Shvol), 6);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-6) << r.report;
}

TEST(Environment, ImageLowerHemisphereBlackChi2) {
    const auto r = runChi2(Environment::image(syntheticSky(), 1.0, -120.0, true), 3);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-6) << r.report;
}

TEST(Environment, ImageOddHeightStraddlingRowChi2) {
    // 15 rows: row 7 straddles the horizon and keeps half its weight.
    Image img(20, 15);
    for (int y = 0; y < 15; ++y)
        for (int x = 0; x < 20; ++x) img.set(x, y, Spectrum::Constant(1.0 + x % 3 + y));
    const Environment env = Environment::image(img, 1.0, 10.0, true);
    const auto r = runChi2(env, 4);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-6) << r.report;
    // pdf > 0 wherever Le > 0 (just above the horizon, in the straddling row).
    const Vec3 w = sphericalDirection(0.01, 1.0);
    EXPECT_GT(env.Le(w).maxCoeff(), 0.0);
    EXPECT_GT(env.pdf(w), 0.0);
}

TEST(Environment, ConstantLowerHemisphereBlackChi2) {
    const Environment env = Environment::constant(Spectrum(1, 2, 3), true);
    const auto r = runChi2(env, 5);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-9) << r.report;
}

// The whole sphere of a constant sky: the case of every constant-sky scene (media/plume.json,
// the furnaces), which light sampling draws with NEE on.
TEST(Environment, ConstantChi2) {
    const Environment env = Environment::constant(Spectrum(1, 2, 3), false);
    const auto r = runChi2(env, 7);
    EXPECT_TRUE(r.passed) << r.report;
    EXPECT_NEAR(r.pdfIntegral, 1.0, 1e-9) << r.report;
}

TEST(Environment, Chi2DetectsAMissingJacobianFactor) {
    // A classic bug: dividing by sin θ at the row centre instead of at the sampled direction.
    // The harness must reject that pdf (it is only wrong within rows, most near the poles).
    const Environment env = Environment::image(syntheticSky(), 1.0, 0.0, false);
    const int H = 16;
    Chi2Options opt;
    opt.seed = 6;
    const auto r =
        chi2TestSphere([&](Rng& rng) { return std::optional<Vec3>(env.sample(rng.uniform2()).wi); },
                       [&](const Vec3& w) {
                           const double theta = safeAcos(w.z());
                           const int y = std::clamp(int(theta / Pi * H), 0, H - 1);
                           return env.pdf(w) * std::sin(theta) / std::sin(Pi * (y + 0.5) / H);
                       },
                       opt);
    EXPECT_FALSE(r.passed) << r.report;
}

// The brightest value a sky shows, before its scale (what the loader holds against the float
// range): a constant's largest channel; an image's largest over the rows seen, the rows wholly
// below a black lower hemisphere left out, the straddling middle row of an odd height kept.
TEST(Environment, BrightestSeen) {
    EXPECT_EQ(Environment::constant(Spectrum(1, 2, 3), true).brightestSeen(), 3);
    Image img(2, 3);  // rows: above, straddling the horizon, below
    img.set(0, 0, Spectrum(1, 0, 0));
    img.set(1, 1, Spectrum(0, 5, 0));
    img.set(0, 2, Spectrum(0, 0, 9));
    EXPECT_EQ(Environment::image(img, 2, 0, false, LatLongMapping::Shvol).brightestSeen(), 9);
    EXPECT_EQ(Environment::image(img, 2, 0, true, LatLongMapping::Shvol).brightestSeen(), 5);
    img.set(1, 1, Spectrum::Zero());
    EXPECT_EQ(Environment::image(img, 2, 0, true, LatLongMapping::Shvol).brightestSeen(), 1);
}

// The peak: the brightest directions holding half of ∫ Y² dω, with their solid angle and share of
// ∫ Y dω, worked by hand. One row of two texels covers the sphere, 2π sr each: of luminances 3
// and 1, ∫ Y² = 20π, half of it 10π sr·Y² in 10π/9 sr of the first texel (9 a steradian), which
// hold 3 · 10π/9 of the 8π of light, 5/12. Two rows of one texel split it at the horizon, 2π sr
// each; with the lower hemisphere black only the upper row is seen; of an odd height the middle
// row counts half (π sr of its 2π).
TEST(Environment, PeakHoldsHalfTheSecondMoment) {
    // The peak of a sky of W × H grey texels of the given luminances, row by row.
    const auto peak = [](int W, int H, const std::vector<double>& y, bool lowerBlack) {
        Image img(W, H);
        for (int i = 0; i < W * H; ++i) img.set(i % W, i / W, Spectrum::Constant(y[size_t(i)]));
        return Environment::image(img, 1, 0, lowerBlack).peak();
    };
    const auto expectPeak = [](const Environment::Peak& p, double solidAngle, double share) {
        EXPECT_NEAR(p.solidAngle, solidAngle, 1e-12);
        EXPECT_NEAR(p.powerShare, share, 1e-12);
    };
    expectPeak(peak(2, 1, {3, 1}, false), 10 * Pi / 9, 5.0 / 12);
    expectPeak(peak(2, 1, {1, 1}, false), TwoPi, 0.5);  // equal luminances: half of them
    // 1 above, 2 below: ∫ Y² = 2π + 8π, half of it in 5π/4 sr of the lower texel, holding
    // 5π/2 of the 6π of light; seen alone, the upper one holds half in half its 2π sr.
    expectPeak(peak(1, 2, {1, 2}, false), 5 * Pi / 4, 5.0 / 12);
    expectPeak(peak(1, 2, {1, 2}, true), Pi, 0.5);
    // Three rows of one texel, the lower hemisphere black: the top row, θ in [0, π/3], has
    // 2π(1 − cos π/3) = π sr, the middle row half of its 2π sr, π. Luminances 1 and 1.5 (and
    // 100 below the horizon, not seen): ∫ Y² = π + 2.25π, half of it in 1.625π/2.25 sr of the
    // middle row, which hold 1.5 times that of the 2.5π of light.
    expectPeak(peak(1, 3, {1, 1.5, 100}, true), 1.625 * Pi / 2.25, 1.5 * 1.625 / 2.25 / 2.5);
    // A constant: half of what is seen, half the light; black: nothing.
    expectPeak(Environment::constant(Spectrum::Ones(), true).peak(), Pi, 0.5);
    EXPECT_EQ(Environment::image(Image(4, 2), 1, 0, false).peak().solidAngle, 0);
}

TEST(Environment, ConstantLookupAndSampling) {
    const Environment all = Environment::constant(Spectrum(1, 2, 3), false);
    EXPECT_TRUE(all.isConstant());
    EXPECT_TRUE((all.constantRadiance() == Spectrum(1, 2, 3)).all());
    EXPECT_TRUE((all.Le(Vec3(0, 0, -1)) == Spectrum(1, 2, 3)).all());
    EXPECT_DOUBLE_EQ(all.pdf(Vec3(0, 0, -1)), Inv4Pi);
    const Environment upper = Environment::constant(Spectrum(1, 2, 3), true);
    EXPECT_TRUE((upper.Le(Vec3(0.3, 0, -0.1)) == 0).all());
    EXPECT_TRUE((upper.Le(Vec3(0.3, 0, 0.1)) == Spectrum(1, 2, 3)).all());
    EXPECT_EQ(upper.pdf(Vec3(0, 0, -1)), 0.0);
    Rng rng(1, 1);
    for (int i = 0; i < 1000; ++i) {
        const LightSample s = upper.sample(rng.uniform2());
        ASSERT_GE(s.wi.z(), 0.0);
        EXPECT_DOUBLE_EQ(s.pdf, upper.pdf(s.wi));
    }
}

// The shvol convention (φ = 2π(x+½)/W), which scenes can still choose.
TEST(Environment, LookupOrientation) {
    Image img(8, 4);
    img.set(2, 0, Spectrum(5, 0, 0));  // top row: around +z
    img.set(2, 3, Spectrum(0, 0, 7));  // bottom row: around −z
    img.set(0, 1, Spectrum(0, 3, 0));  // column 0: φ_img just above 0
    const Environment env = Environment::image(img, 2.0, 0.0, false, LatLongMapping::Shvol);
    EXPECT_FALSE(env.isConstant());
    // Column 2 covers φ ∈ [π/2, 3π/4); look at its centre, near each pole.
    const double phi2 = TwoPi * 2.5 / 8;
    EXPECT_DOUBLE_EQ(env.Le(sphericalDirection(0.99, phi2))[0], 10.0);
    EXPECT_DOUBLE_EQ(env.Le(sphericalDirection(-0.99, phi2))[2], 14.0);
    EXPECT_EQ(env.Le(sphericalDirection(0.99, phi2 + Pi)).maxCoeff(), 0.0);
    // Row 1 covers θ ∈ [π/4, π/2); column 0 is φ ∈ [0, π/4) → +x side.
    EXPECT_DOUBLE_EQ(env.Le(sphericalDirection(std::cos(3 * Pi / 8), Pi / 8))[1], 6.0);
    // Rotation by 90°: the pixel at φ_img = 0 moves to world +y.
    const Environment rot = Environment::image(img, 1.0, 90.0, false, LatLongMapping::Shvol);
    EXPECT_DOUBLE_EQ(rot.Le(sphericalDirection(std::cos(3 * Pi / 8), Pi / 2 + Pi / 8))[1], 3.0);
    EXPECT_DOUBLE_EQ(rot.Le(Vec3(-0.001, 1, 0.3))[1], 3.0);  // just past +y: φ_img ≈ 0⁺
    EXPECT_EQ(rot.Le(sphericalDirection(std::cos(3 * Pi / 8), Pi / 8))[1], 0.0);
    // The sampler goes only where the image is bright, and carries the radiance Le gives there
    // (one sample's pdf > 0 was all this checked: helper 118).
    Rng rng(2, 2);
    for (int i = 0; i < 1000; ++i) {
        const LightSample s = env.sample(rng.uniform2());
        ASSERT_GT(s.pdf, 0.0);
        EXPECT_TRUE((s.Le > 0).any()) << s.wi.transpose();
        EXPECT_TRUE((env.Le(s.wi) == s.Le).all()) << s.wi.transpose();
    }
}

// Each sample's pdf and radiance are the environment's own at its direction, in both
// latitude-longitude conventions (the sampler returns the drawn texel's radiance: a direction
// mapped otherwise than Le maps it would carry another texel's light).
TEST(Environment, PdfMatchesSample) {
    for (const LatLongMapping mapping : {LatLongMapping::Blender, LatLongMapping::Shvol})
        for (bool lower : {false, true}) {
            const Environment env = Environment::image(syntheticSky(), 1.5, 33.0, lower, mapping);
            Rng rng(3, 7);
            for (int i = 0; i < 20000; ++i) {
                const LightSample s = env.sample(rng.uniform2());
                ASSERT_GT(s.pdf, 0.0);
                ASSERT_NEAR(s.wi.norm(), 1.0, 1e-12);
                EXPECT_NEAR(env.pdf(s.wi), s.pdf, 1e-9 * s.pdf);
                EXPECT_TRUE(s.Le.isApprox(env.Le(s.wi)));
                if (lower) ASSERT_GE(s.wi.z(), 0.0);  // H = 16: no row straddles the horizon
            }
        }
}

// The sampler is built by prepareSampling() or the first sample() or pdf() (a render that draws
// no light sample from the sky builds none; helper 168): threads that ask at once, through
// copies, all get the one sampler a single thread would. (Whether it is built at all is not
// observable here; the render's setup decides that, VolumePathIntegrator::buildLightSamplers.)
TEST(Environment, LazySamplerIsTheSameForEveryThread) {
    const Environment alone = Environment::image(syntheticSky(), 1.0, 10.0, false);
    std::vector<Vec2> us;
    Rng rng(5, 1);
    for (int i = 0; i < 2000; ++i) us.push_back(rng.uniform2());
    for (int round = 0; round < 20; ++round) {
        const Environment fresh = Environment::image(syntheticSky(), 1.0, 10.0, false);
        std::vector<std::vector<double>> pdfs(4);
        std::vector<std::thread> threads;
        for (size_t t = 0; t < pdfs.size(); ++t)
            threads.emplace_back([&, t, copy = fresh] {
                for (const Vec2& u : us) pdfs[t].push_back(copy.sample(u).pdf);
            });
        for (std::thread& t : threads) t.join();
        for (size_t i = 0; i < us.size(); ++i)
            for (const std::vector<double>& p : pdfs) ASSERT_EQ(p[i], alone.sample(us[i]).pdf);
    }
}

TEST(Environment, LowerHemisphereBlack) {
    const Environment env = Environment::image(syntheticSky(), 1.0, 0.0, true);
    Rng rng(4, 4);
    for (int i = 0; i < 2000; ++i) {
        const Vec3 w = sphericalDirection(-rng.uniform() - 1e-9, TwoPi * rng.uniform());
        EXPECT_EQ(env.Le(w).maxCoeff(), 0.0);
        EXPECT_EQ(env.pdf(w), 0.0);
    }
    EXPECT_GT(env.Le(Vec3(0, 0, 1)).maxCoeff(), 0.0);
}

TEST(Environment, PdfProportionalToLuminanceAwayFromSun) {
    // pdf_ω ∝ Y sin θ_row / sin θ: within a row, proportional to luminance.
    const Environment env = Environment::image(syntheticSky(), 1.0, 0.0, false);
    auto lum = [](const Spectrum& s) { return 0.2126 * s[0] + 0.7152 * s[1] + 0.0722 * s[2]; };
    const double cosT = std::cos(Pi * 6.5 / 16);
    const Vec3 a = sphericalDirection(cosT, TwoPi * 3.5 / 32);
    const Vec3 b = sphericalDirection(cosT, TwoPi * 20.5 / 32);
    EXPECT_NEAR(env.pdf(a) / env.pdf(b), lum(env.Le(a)) / lum(env.Le(b)), 1e-12);
    // Black row 12 is never sampled and has pdf 0.
    EXPECT_EQ(env.pdf(sphericalDirection(std::cos(Pi * 12.5 / 16), 1.0)), 0.0);
}

TEST(Environment, AllBlackImageDoesNotCrash) {
    const Environment env = Environment::image(Image(8, 4), 1.0, 0.0, false);
    const LightSample s = env.sample({0.3, 0.6});
    EXPECT_EQ(s.pdf, 0.0);
    EXPECT_EQ(s.Le.maxCoeff(), 0.0);
    EXPECT_EQ(env.pdf(Vec3(0, 0, 1)), 0.0);
    EXPECT_THROW(Environment::image(Image(), 1.0, 0.0, false), Error);
}

}  // namespace
}  // namespace shvol

namespace shvol {

// A marked test map: pixel (x, y) holds (x, y, 0). Each convention must put the documented column
// in the documented direction (lights/latlong.h): with W = 8, Blender column x faces
// φ = π − 2π(x+½)/8 and shvol column x faces φ = 2π(x+½)/8, both plus the rotation.
TEST(Environment, LatLongMappingsAgainstAMarkedMap) {
    Image img(8, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) img.set(x, y, Spectrum(x, y, 0));
    struct Probe {
        double phi;      // world direction, just above the horizon (row 1)
        int blenderCol;  // hand-computed from the formulas above
        int shvolCol;
    };
    // Blender u = (π − φ)/2π mod 1, shvol u = φ/2π: φ = 0⁺ gives u = ½⁻ (column 3) and 0⁺
    // (column 0); φ = π/2⁺ gives ¼⁻ (column 1) and ¼⁺ (column 2); φ = π⁺ gives 1⁻ (column 7) and
    // ½⁺ (column 4); φ = 3π/2⁺ gives ¾⁻ (column 5) and ¾⁺ (column 6).
    const Probe probes[] = {
        {0.01, 3, 0}, {Pi / 2 + 0.01, 1, 2}, {Pi + 0.01, 7, 4}, {1.5 * Pi + 0.01, 5, 6}};
    for (const Probe& p : probes) {
        const Vec3 w = sphericalDirection(0.2, p.phi);  // θ ≈ 78°: row 1 of 4
        const Environment b = Environment::image(img, 1, 0, false, LatLongMapping::Blender);
        const Environment s = Environment::image(img, 1, 0, false, LatLongMapping::Shvol);
        EXPECT_EQ(b.Le(w)[0], p.blenderCol) << p.phi;
        EXPECT_EQ(s.Le(w)[0], p.shvolCol) << p.phi;
        EXPECT_EQ(b.Le(w)[1], 1);
        // A rotation of 90° turns the map: what faced φ now faces φ + 90°.
        const Environment r = Environment::image(img, 1, 90, false, LatLongMapping::Blender);
        EXPECT_EQ(r.Le(sphericalDirection(0.2, p.phi + Pi / 2))[0], p.blenderCol) << p.phi;
    }
    // The sampler agrees with the lookup: samples of a map lit in column 1 only (Blender) go
    // towards +y (φ ∈ [π/2, 3π/4]).
    Image col(8, 4);
    for (int y = 0; y < 4; ++y) col.set(1, y, Spectrum::Ones());
    const Environment e = Environment::image(col, 1, 0, false, LatLongMapping::Blender);
    Rng rng(1, 1);
    for (int i = 0; i < 100; ++i) {
        const LightSample s = e.sample(rng.uniform2());
        const double phi = sphericalPhi(s.wi);
        EXPECT_GE(phi, Pi / 2 - 1e-9);
        EXPECT_LE(phi, 0.75 * Pi + 1e-9);
    }
}

}  // namespace shvol
