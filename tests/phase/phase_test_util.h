#pragma once
// Shared checks for the phase-function tests: chi² against the claimed pdf (the harness of
// shvol/sampling/chi2.h), normalisation by quadrature, and per-sample consistency.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <string>

#include "shvol/core/rng.h"
#include "shvol/phase/phase_function.h"
#include "shvol/sampling/chi2.h"
#include "shvol/sh/sh_projection.h"

namespace shvol::testing {

inline const Vec3 kWo = Vec3(0.48, -0.6, 0.64).normalized();  // off-axis: the frame is exercised

/// χ² of phase.sample against phase.pdf for wo = kWo; numTests = size of the Šidák family.
inline Chi2Result phaseChi2(const PhaseFunction& phase, int numTests, uint64_t seed,
                            long long sampleCount = 1000000) {
    Chi2Options opt;
    opt.numTests = numTests;
    opt.seed = seed;
    opt.sampleCount = sampleCount;
    const Chi2Result r = chi2TestSphere(
        [&](Rng& rng) { return std::optional<Vec3>(phase.sample(kWo, rng.uniform2()).wi); },
        [&](const Vec3& wi) { return phase.pdf(kWo, wi); }, opt);
    if (std::getenv("SHVOL_CHI2_VERBOSE")) std::cout << phase.name() << "\n" << r.report;
    return r;
}

/// χ² of a lobe too narrow for equal-area cells (HG g = 0.999999 is about 10⁻¹² wide in 1 − μ):
/// samples around kWo are binned by their distance d from the lobe's pole (d = 1 − μ for a
/// forward lobe, 1 + μ for a backward one, each from |wo ∓ wi|²/2 without the rounding of
/// wo·wi) in 64 cells equal in ln d from dMin = 10⁻¹⁵ to 2 (d < dMin in the first), and by φ
/// about wo in 8. Expected counts come from `density(d)`, the test's own density over d (φ
/// integrated out), by Gauss–Legendre quadrature in ln d on each cell (in d below dMin).
inline Chi2Result narrowLobeChi2(const PhaseFunction& phase, bool backward,
                                 const std::function<double(double)>& density, int numTests,
                                 uint64_t seed) {
    const LogDistanceCells cells;
    const double dMin = cells.dMin;
    const auto integral = [&](double a, double b, bool logScale) {  // ∫_a^b density(d) dd
        std::vector<double> x, w;
        sh::gaussLegendre(16, 0.0, 1.0, x, w);
        const double u0 = logScale ? std::log(a) : a, u1 = logScale ? std::log(b) : b;
        double sum = 0;
        for (size_t i = 0; i < x.size(); ++i) {
            const double u = u0 + (u1 - u0) * x[i], d = logScale ? std::exp(u) : u;
            sum += w[i] * (u1 - u0) * density(d) * (logScale ? d : 1.0);
        }
        return sum;
    };
    const Frame frame(kWo);
    Chi2Options opt;
    opt.zBins = 64;
    opt.phiBins = 8;
    opt.numTests = numTests;
    opt.seed = seed;
    return chi2TestSphereCells(
        [&](Rng& rng) -> std::optional<Vec3> {
            const Vec3 wi = phase.sample(kWo, rng.uniform2()).wi;
            const double d = 0.5 * (backward ? Vec3(kWo + wi) : Vec3(kWo - wi)).squaredNorm();
            const Vec3 l = frame.toLocal(wi);
            return sphericalDirection(cells.z(d), std::atan2(l.y(), l.x()));
        },
        [&](double z0, double z1, double phi0, double phi1) {
            const double d0 = cells.d(z0), d1 = cells.d(z1);
            const double mass = d0 == 0 ? integral(0, dMin, false) + integral(dMin, d1, true)
                                        : integral(d0, d1, true);
            return mass * (phi1 - phi0) / TwoPi;
        },
        opt);
}

/// ∫ f(+z, ω) dω over the sphere (f is zonal about +z, so a few φ cells suffice; each cell is
/// still integrated adaptively to ≈ 1e-7).
inline double zonalIntegral(const std::function<double(const Vec3&)>& f) {
    return integrateOverSphere(f, 40, 4);
}
/// ∫ eval(+z, ω) dω over the sphere.
inline double evalIntegral(const PhaseFunction& phase) {
    const Vec3 z(0, 0, 1);
    return zonalIntegral([&](const Vec3& w) { return phase.eval(z, w); });
}

/// For random wo and u: wi is a unit vector, value and pdf are finite and positive, value equals
/// eval(wo, wi) and sample.pdf equals pdf(wo, wi) (to relTol, the rounding of recomputing
/// wo·wi), and pdf == eval exactly at unrelated directions when exactPdf.
inline void checkSamples(const PhaseFunction& phase, bool exactPdf, double relTol = 1e-9,
                         int n = 4000, uint64_t seed = 7) {
    Rng rng(seed, 3);
    for (int i = 0; i < n; ++i) {
        const Vec3 wo = sphericalDirection(2 * rng.uniform() - 1, TwoPi * rng.uniform());
        // Include the ends of the unit square, where inversions are most fragile.
        Vec2 u = rng.uniform2();
        if (i % 50 == 0) u.x() = 0.0;
        if (i % 50 == 1) u.x() = std::nextafter(1.0, 0.0);
        const PhaseSample s = phase.sample(wo, u);
        ASSERT_NEAR(s.wi.norm(), 1.0, 1e-12) << phase.name();
        ASSERT_TRUE(std::isfinite(s.value) && std::isfinite(s.pdf)) << phase.name();
        ASSERT_GT(s.pdf, 0.0) << phase.name();
        ASSERT_GT(s.value, 0.0) << phase.name();
        if (exactPdf) ASSERT_EQ(s.value, s.pdf) << phase.name();
        EXPECT_NEAR(phase.eval(wo, s.wi), s.value, relTol * s.value)
            << phase.name() << " u=" << u.x();
        EXPECT_NEAR(phase.pdf(wo, s.wi), s.pdf, relTol * s.pdf) << phase.name() << " u=" << u.x();
        const Vec3 other = sphericalDirection(2 * rng.uniform() - 1, TwoPi * rng.uniform());
        const double e = phase.eval(wo, other), p = phase.pdf(wo, other);
        ASSERT_TRUE(std::isfinite(e) && std::isfinite(p) && e > 0 && p > 0) << phase.name();
        if (exactPdf) EXPECT_EQ(e, p) << phase.name();
    }
}

/// eval/pdf at exactly forward, backward and grazing directions, and samples at the extreme u:
/// finite and non-negative.
inline void checkFiniteAtExtremes(const PhaseFunction& phase) {
    const Vec3 wo = kWo;
    const Frame f(wo);
    for (const Vec3& wi : {wo, Vec3(-wo), f.s, f.t, Vec3((wo + 1e-9 * f.s).normalized())}) {
        const double e = phase.eval(wo, wi), p = phase.pdf(wo, wi);
        EXPECT_TRUE(std::isfinite(e) && e >= 0) << phase.name() << " " << e;
        EXPECT_TRUE(std::isfinite(p) && p >= 0) << phase.name() << " " << p;
    }
    for (double u1 : {0.0, 1e-300, 1e-12, 0.5, 1 - 1e-12, std::nextafter(1.0, 0.0), 1.0}) {
        const PhaseSample s = phase.sample(wo, Vec2(u1, 0.3));
        EXPECT_TRUE(s.wi.allFinite()) << phase.name() << " u=" << u1;
        EXPECT_NEAR(s.wi.norm(), 1.0, 1e-12) << phase.name();
        EXPECT_TRUE(std::isfinite(s.value) && s.value >= 0) << phase.name() << " u=" << u1;
        EXPECT_TRUE(std::isfinite(s.pdf) && s.pdf > 0) << phase.name() << " u=" << u1;
    }
}

}  // namespace shvol::testing
