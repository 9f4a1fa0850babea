#pragma once
// Shared by the integrator tests: Monte Carlo estimates of Li over rays that enter a medium.
#include <gtest/gtest.h>

#include "shvol/render/volume_path_integrator.h"

namespace shvol::test {

struct Estimate {
    Spectrum mean, stdErr;
    PathCounters counters;
};

/// Mean and standard error of Li over n camera rays aimed along +y from y = −3 at random points of
/// the disc of radius 0.95 about the y axis (so every ray enters the unit sphere at the origin).
inline Estimate estimate(const Scene& scene, int n, uint64_t seed = 1,
                         SampleStream stream = SampleStream::Independent) {
    const VolumePathIntegrator integrator(scene);
    Estimate e;
    Spectrum s = Spectrum::Zero(), s2 = Spectrum::Zero();
    // One path: its first request places the ray on the disc of radius 0.95 facing +y.
    auto path = [&](auto&& sampler) {
        const Vec2 u = sampler.next2D();
        const double r = 0.95 * std::sqrt(u.x()), phi = TwoPi * u.y();
        const Ray ray{Vec3(r * std::cos(phi), -3, r * std::sin(phi)), Vec3(0, 1, 0)};
        return integrator.Li(ray, sampler, e.counters);
    };
    const SobolPixel pixel(seed, 0);
    for (int i = 0; i < n; ++i) {
        // Sobol: the samples of one pixel (a stratified sequence; stdErr below is then an
        // overestimate). Independent: one stream per path.
        const Spectrum L = stream == SampleStream::Sobol
                               ? path(SobolSampler(pixel, uint32_t(i)))
                               : path(Rng::forSample(seed, uint64_t(i), 0));
        EXPECT_TRUE(L.allFinite()) << L.transpose();
        s += L, s2 += L * L;
    }
    e.mean = s / n;
    e.stdErr = ((s2 / n - e.mean * e.mean).max(0) / n).sqrt();
    return e;
}

}  // namespace shvol::test
