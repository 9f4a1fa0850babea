// Draws no path can use (InvalidDraws): a NaN or negative pdf, value, flight distance or
// transmittance is counted by its source and drops what met it. Before they were counted, each
// dropped its path or light sample without a word: a phase sampler's NaN pdf ended the path as a
// pdf of 0 would, a NaN flight distance let the path through the medium as if it met nothing, a
// NaN transmittance dropped the light sample. The loader refuses the parameters that could make
// one, so these scenes are built here directly (a NaN asymmetry, a negative sky, a medium that
// returns NaN).
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "shvol/media/homogeneous_medium.h"
#include "shvol/phase/henyey_greenstein_phase.h"
#include "shvol/render/volume_path_integrator.h"
#include "surfaces/surface_test_util.h"

namespace shvol {
namespace {

MediumShape unitSphere() {
    MediumShape s;
    s.type = MediumShape::Type::Sphere;
    return s;
}

/// An albedo-1 sphere of σ_t 2 under a constant sky: phase function, sky and medium given.
Scene furnace(PhaseFunction phase, Spectrum sky = Spectrum::Ones(),
              std::unique_ptr<Medium> medium = nullptr) {
    Scene s;
    s.environment = Environment::constant(sky, false);
    s.settings.maxDepth = 1000;
    s.media.push_back(
        medium ? std::move(medium)
               : std::make_unique<HomogeneousMedium>(unitSphere(), 2.0, Spectrum::Ones(), phase));
    return s;
}

/// A homogeneous medium whose free flights or transmittances are `bad` (NaN or negative), or,
/// where `bad` is not set for them, the homogeneous medium's.
class FaultyMedium final : public Medium {
  public:
    FaultyMedium(bool badFlights, bool badTransmittances, double bad)
        : Medium(Spectrum::Ones(), HenyeyGreensteinPhase(0.3)),
          inner_(unitSphere(), 2.0, Spectrum::Ones(), HenyeyGreensteinPhase(0.3)),
          badFlights_(badFlights),
          badTransmittances_(badTransmittances),
          bad_(bad) {}
    double sampleCollision(const Ray& ray, double tMax, Rng& rng, TrackingCounters& c,
                           const Vec2* first) const override {
        const double t = inner_.sampleCollision(ray, tMax, rng, c, first);
        return badFlights_ ? bad_ : t;
    }
    double transmittance(const Ray& ray, double tMax, TransmittanceEstimator est, Rng& rng,
                         TrackingCounters& c) const override {
        const double T = inner_.transmittance(ray, tMax, est, rng, c);
        return badTransmittances_ ? bad_ : T;
    }
    double sigmaT(const Vec3& p) const override { return inner_.sigmaT(p); }
    double sigmaMajorant(const Vec3& p) const override { return inner_.sigmaMajorant(p); }
    Bounds3 bounds() const override { return inner_.bounds(); }
    std::string describe() const override { return "faulty"; }

  private:
    HomogeneousMedium inner_;
    bool badFlights_, badTransmittances_;
    double bad_;
};

struct Paths {
    PathCounters c;
    int zeros = 0, ones = 0;           ///< paths that returned exactly 0 and exactly 1
    Spectrum mean = Spectrum::Zero();  ///< the paths' mean
    double lowest = INFINITY;          ///< the least channel value of any path
};

/// n paths into the sphere along +y, each required to be finite.
Paths trace(const Scene& scene, int n = 2000) {
    const VolumePathIntegrator integrator(scene);
    Paths r;
    for (int i = 0; i < n; ++i) {
        Rng rng = Rng::forSample(7, uint64_t(i), 0);
        const Vec2 u = rng.uniform2();
        const Ray ray{Vec3(0.9 * u.x() - 0.45, -3, 0.9 * u.y() - 0.45), Vec3(0, 1, 0)};
        const Spectrum L = integrator.Li(ray, rng, r.c);
        EXPECT_TRUE(L.allFinite()) << L.transpose();
        r.zeros += L[0] == 0, r.ones += L[0] == 1;
        r.mean += L / n, r.lowest = std::min(r.lowest, L.minCoeff());
    }
    return r;
}

}  // namespace

TEST(InvalidDraws, PhaseSamplesOfNaNAreCountedAndEndTheirPaths) {
    const double nan = std::nan("");
    for (const bool nee : {false, true}) {
        SCOPED_TRACE(nee ? "nee" : "no nee");
        Scene scene = furnace(HenyeyGreensteinPhase(nan));
        scene.settings.nee = nee;
        const Paths r = trace(scene);
        // Every scattering event's phase sample is NaN, and ends its path.
        EXPECT_GT(r.c.scatteringEvents, 1000u);
        EXPECT_EQ(r.c.scatteringEvents, r.c.phaseSamples);
        if (!nee) {
            EXPECT_EQ(r.c.invalid.phase, r.c.scatteringEvents);
            EXPECT_EQ(uint64_t(r.zeros), r.c.scatteringEvents);  // the rest passed through: 1
            EXPECT_EQ(r.zeros + r.ones, 2000);
        } else {
            // Next-event estimation evaluates the phase function too (NaN), before the sample.
            EXPECT_EQ(r.c.invalid.phase, 2 * r.c.scatteringEvents);
        }
        EXPECT_EQ(r.c.invalid.total(), r.c.invalid.phase);
    }
    // The same scene with a valid asymmetry counts nothing.
    Scene scene = furnace(HenyeyGreensteinPhase(0.3));
    const Paths r = trace(scene);
    EXPECT_GT(r.c.scatteringEvents, 1000u);
    EXPECT_EQ(r.c.invalid.total(), 0u);
}

TEST(InvalidDraws, LightDrawsOfNegativeRadianceAreCountedAndDropped) {
    // (A sky of no positive radiance would have next-event estimation left off.)
    Scene scene = furnace(HenyeyGreensteinPhase(0.3), Spectrum(1, -1, 1));
    scene.settings.nee = true;
    const Paths r = trace(scene);
    EXPECT_GT(r.c.lightSamples, 1000u);
    EXPECT_EQ(r.c.invalid.light, r.c.lightSamples);
    EXPECT_EQ(r.c.invalid.total(), r.c.invalid.light);
    // Dropped, they add nothing: the furnace keeps only its phase-sampled share, 0.55 here
    // (2000 paths). Counted, they made it the furnace's 1 (0.9985 with `ls.pdf = 0` removed;
    // helper 118 found the test blind to that).
    EXPECT_LT(r.mean[0], 0.75);
    EXPECT_EQ(r.mean[1], -r.mean[0]);
}

TEST(InvalidDraws, FlightsOfNaNOrNegativeLengthAreCountedAndEndTheirPaths) {
    for (const double bad : {std::nan(""), -0.5}) {
        SCOPED_TRACE(bad);
        // Uncounted, a NaN flight let every path through the sphere as if it met nothing (1).
        const Paths r = trace(furnace(HenyeyGreensteinPhase(0.3), Spectrum::Ones(),
                                      std::make_unique<FaultyMedium>(true, false, bad)));
        EXPECT_EQ(r.c.invalid.flight, 2000u);
        EXPECT_EQ(r.zeros, 2000);
        EXPECT_EQ(r.c.scatteringEvents, 0u);
        EXPECT_EQ(r.c.invalid.total(), r.c.invalid.flight);
    }
}

TEST(InvalidDraws, TransmittancesOfNaNOrNegativeValueAreCountedAndDropped) {
    for (const double bad : {std::nan(""), -0.5}) {
        SCOPED_TRACE(bad);
        Scene scene = furnace(HenyeyGreensteinPhase(0.3), Spectrum::Ones(),
                              std::make_unique<FaultyMedium>(false, true, bad));
        scene.settings.nee = true;
        const Paths r = trace(scene);
        EXPECT_GT(r.c.transmittanceRays, 1000u);
        EXPECT_EQ(r.c.invalid.transmittance, r.c.transmittanceRays);
        EXPECT_EQ(r.c.invalid.total(), r.c.invalid.transmittance);
        // Dropped: no light sample's contribution turns negative (or NaN, which trace refuses).
        EXPECT_GE(r.lowest, 0);
    }
}

TEST(InvalidDraws, BsdfSamplesOfNaNAreCountedAndEndTheirPaths) {
    // Inside a closed sphere of a Phong BSDF whose specular reflectance is NaN (its samples'
    // values and pdfs), lit by its own emission. (A NaN exponent is not counted: the lobe's
    // density, 0 where cos α > 0 fails, turns its NaN directions into "no sample" before the path
    // sees them; README, invalid_draws.)
    Surface shell = Surface::sphere(Vec3(0, 0, 0), 1);
    shell.bsdf = Bsdf::phong(Spectrum::Constant(0.5), Spectrum::Constant(std::nan("")), 10);
    shell.emission = Spectrum::Constant(0.3);
    shell.twoSidedEmission = true;
    for (const bool nee : {false, true}) {
        SCOPED_TRACE(nee ? "nee" : "no nee");
        Scene scene;
        scene.settings.nee = nee;
        std::vector<Surface> v{shell};
        scene.surfaces = std::make_unique<const SurfaceScene>(std::move(v));
        const VolumePathIntegrator integrator(scene);
        PathCounters c;
        for (int i = 0; i < 500; ++i) {
            Rng rng = Rng::forSample(3, uint64_t(i), 0);
            const Spectrum L = integrator.Li(Ray{Vec3(0.1, 0.2, 0), Vec3(0, 0, 1)}, rng, c);
            EXPECT_TRUE(L.allFinite()) << L.transpose();
        }
        EXPECT_EQ(c.surfaceEvents, 500u);  // each path ends at its first surface event
        EXPECT_GE(c.invalid.bsdf, 500u);
        EXPECT_EQ(c.invalid.total(), c.invalid.bsdf);
    }
}

// Each source's key and words go with its own count (the stats' keys come from this list).
TEST(InvalidDraws, EachSourceIsNamedWithItsCount) {
    InvalidDraws d;
    d.phase = 1, d.bsdf = 2, d.light = 3, d.flight = 4, d.transmittance = 5;
    std::string seen;
    d.forEachSource([&](const char* key, const char* words, uint64_t n) {
        seen += std::string(key) + " " + words + " " + std::to_string(n) + "; ";
    });
    EXPECT_EQ(seen,
              "phase from phase functions 1; bsdf from BSDFs 2; light from light sampling 3; "
              "flight free-flight distances 4; transmittance transmittances 5; ");
}

TEST(InvalidDraws, WarningNamesTheSourcesCounted) {
    InvalidDraws d;
    EXPECT_EQ(invalidDrawsWarning(d), "");
    d.phase = 12, d.transmittance = 3;
    const std::string tail =
        "): the paths or light samples that met them were dropped, so the image lacks their "
        "light; this is a defect of shvol: please report it with the scene";
    EXPECT_EQ(invalidDrawsWarning(d),
              "15 draws of samplers or media were NaN or negative (12 from phase functions, 3 "
              "transmittances" +
                  tail);
    InvalidDraws e;
    e.bsdf = 1, e.light = 2, e.flight = 4;
    d.add(e);
    EXPECT_EQ(d.total(), 22u);
    EXPECT_EQ(invalidDrawsWarning(d),
              "22 draws of samplers or media were NaN or negative (12 from phase functions, 1 "
              "from BSDFs, 2 from light sampling, 4 free-flight distances, 3 transmittances" +
                  tail);
}

}  // namespace shvol
