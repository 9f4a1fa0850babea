#include "shvol/render/renderer.h"

#include <gtest/gtest.h>

#include <thread>

#include "shvol/core/error.h"
#include "shvol/media/homogeneous_medium.h"

namespace shvol {

namespace {

/// A small scattering sphere under a constant sky: cheap, but every pixel has variance.
Scene smallScene(int spp) {
    Scene s;
    s.camera.position = Vec3(0, -3, 0);
    s.camera.target = Vec3(0, 0, 0);
    s.camera.width = 12, s.camera.height = 9;
    s.environment = Environment::constant(Spectrum::Ones(), false);
    s.settings.spp = spp;
    MediumShape sphere;
    sphere.type = MediumShape::Type::Sphere;
    sphere.radius = 1;
    s.media.push_back(std::make_unique<HomogeneousMedium>(
        sphere, 3.0, Spectrum(0.9, 0.7, 0.5), PhaseFunction(HenyeyGreensteinPhase(0.5)), true));
    return s;
}

void expectSameImage(const Image& a, const Image& b) {
    ASSERT_EQ(a.rgb.size(), b.rgb.size());
    for (size_t i = 0; i < a.rgb.size(); ++i) ASSERT_EQ(a.rgb[i], b.rgb[i]) << "value " << i;
}

}  // namespace

// A render continued from the film of a shorter one is the longer render, bit for bit, whatever
// the thread counts.
TEST(Renderer, ContinuingAFilmReproducesTheUninterruptedImage) {
    const Scene s5 = smallScene(5), s13 = smallScene(13);
    RenderOptions one, two;
    one.threads = 1, two.threads = 2;
    const RenderResult full = render(s13, two);
    const RenderResult part = render(s5, one);
    EXPECT_EQ(part.stats.maxSamples, 5u);
    const RenderResult cont = render(s13, two, part.film);
    EXPECT_EQ(cont.stats.resumedFromSamples, 5u);
    EXPECT_EQ(cont.stats.minSamples, 13u);
    expectSameImage(cont.image, full.image);
}

// Stopped at an arbitrary moment (a cancel flag set from another thread while the render runs),
// each pixel holds the mean of its own samples, and continuing gives the uninterrupted image.
TEST(Renderer, CancelledRenderKeepsEachPixelsSamples) {
    const Scene s = smallScene(4000);
    RenderOptions opt;
    opt.threads = 2;
    const RenderResult full = render(s, opt);
    std::atomic<bool> cancel{false};
    opt.cancel = &cancel;
    std::thread stopper([&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(30));
        cancel = true;
    });
    const RenderResult part = render(s, opt);
    stopper.join();
    ASSERT_EQ(part.stats.stop, RenderStop::Cancelled);
    ASSERT_LT(part.stats.minSamples, 4000u);
    for (size_t i = 0; i < part.film.pixels(); ++i)
        for (int c = 0; c < 3; ++c)
            ASSERT_EQ(
                part.image.rgb[3 * i + c],
                part.film.count[i] ? float(part.film.sum[3 * i + c] / part.film.count[i]) : 0.f);
    // Passes double: no pixel is more than one pass ahead of another.
    EXPECT_LE(part.stats.maxSamples, std::max(1u, 2 * part.stats.minSamples));
    opt.cancel = nullptr;
    const RenderResult cont = render(s, opt, part.film);
    expectSameImage(cont.image, full.image);
}

TEST(Renderer, TimeLimitStopsTheRender) {
    RenderOptions opt;
    opt.timeLimitSeconds = 1e-9;
    const RenderResult r = render(smallScene(1000), opt);
    EXPECT_EQ(r.stats.stop, RenderStop::TimeLimit);
    EXPECT_LT(r.stats.minSamples, 1000u);
    EXPECT_STREQ(renderStopName(r.stats.stop), "time-limit");
}

// Checkpoint callbacks come between passes (1, 2, 4, … samples) and once at the end.
TEST(Renderer, AfterPassSeesEveryPass) {
    std::vector<uint32_t> seen;
    RenderOptions opt;
    opt.afterPass = [&](const Film& f) {
        EXPECT_EQ(f.minCount(), f.maxCount());
        seen.push_back(f.minCount());
    };
    render(smallScene(11), opt);
    EXPECT_EQ(seen, (std::vector<uint32_t>{1, 2, 4, 8, 11}));
}

TEST(Renderer, RefusesAFilmThatDoesNotFit) {
    const RenderResult r = render(smallScene(4), RenderOptions{});
    EXPECT_THROW(render(smallScene(3), RenderOptions{}, r.film), Error);  // more samples than spp
    Film wrong(5, 5);
    EXPECT_THROW(render(smallScene(4), RenderOptions{}, wrong), Error);
}

}  // namespace shvol
