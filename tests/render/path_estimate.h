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
inline Estimate estimate(const Scene& scene, int n, uint64_t seed = 1) {
    const VolumePathIntegrator integrator(scene);
    Estimate e;
    Spectrum s = Spectrum::Zero(), s2 = Spectrum::Zero();
    for (int i = 0; i < n; ++i) {
        Rng rng = Rng::forSample(seed, i, 0);
        const Vec2 u = rng.uniform2();
        const double r = 0.95 * std::sqrt(u.x()), phi = TwoPi * u.y();
        const Ray ray{Vec3(r * std::cos(phi), -3, r * std::sin(phi)), Vec3(0, 1, 0)};
        const Spectrum L = integrator.Li(ray, rng, e.counters);
        EXPECT_TRUE(L.allFinite()) << L.transpose();
        s += L, s2 += L * L;
    }
    e.mean = s / n;
    e.stdErr = ((s2 / n - e.mean * e.mean).max(0) / n).sqrt();
    return e;
}

}  // namespace shvol::test
