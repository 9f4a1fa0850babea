// Effects::of and emissionSurrounds: which light samples a scene draws under render.nee "auto".
#include "shvol/render/effects.h"

#include <gtest/gtest.h>

#include <memory>
#include <optional>

#include "shvol/media/homogeneous_medium.h"
#include "shvol/phase/henyey_greenstein_phase.h"
#include "surfaces/surface_test_util.h"

namespace shvol {
namespace {

/// A camera at `eye` inside (or outside) an emitting sphere of radius 2 about the origin, the
/// extra surfaces `more` beside it, and render.nee `nee`.
Scene sceneIn(const Vec3& eye, std::vector<Surface> more = {}, std::optional<bool> nee = {},
              bool twoSided = true) {
    Scene scene;
    scene.camera.position = eye;
    scene.settings.nee = nee;
    std::vector<Surface> v;
    v.push_back(Surface::sphere(Vec3(0, 0, 0), 2));
    v.back().bsdf = Bsdf::lambert(Spectrum::Constant(0.9));
    v.back().emission = Spectrum::Constant(1);
    v.back().twoSidedEmission = twoSided;  // the inside is the back of a sphere
    for (Surface& s : more) v.push_back(std::move(s));
    scene.surfaces = std::make_unique<const SurfaceScene>(std::move(v));
    return scene;
}

Surface ball(const Vec3& c, double r, double emission = 0) {
    Surface s = Surface::sphere(c, r);
    s.bsdf = Bsdf::lambert(Spectrum::Constant(0.5));
    s.emission = Spectrum::Constant(emission);
    s.twoSidedEmission = true;
    return s;
}

TEST(EmissionSurrounds, AnEmittingSphereAroundTheCamera) {
    EXPECT_TRUE(emissionSurrounds(sceneIn(Vec3(0.3, -0.2, 0.1))));
    // Seen from outside, half the probe rays escape.
    EXPECT_FALSE(emissionSurrounds(sceneIn(Vec3(0, -4, 0))));
    // Emitting outwards only, the sphere is dark inside; emitting from its back, it is lit.
    EXPECT_FALSE(emissionSurrounds(sceneIn(Vec3(0, 0, 0), {}, {}, false)));
    Scene back = sceneIn(Vec3(0, 0, 0), {}, {}, false);
    std::vector<Surface> v = back.surfaces->surfaces();
    v[0].emitsFromBack = true;
    back.surfaces = std::make_unique<const SurfaceScene>(std::move(v));
    EXPECT_TRUE(emissionSurrounds(back));
}

TEST(EmissionSurrounds, SeesThroughSurfacesThatDoNotEmitAndNotPastOtherLight) {
    std::vector<Surface> inside;
    inside.push_back(ball(Vec3(1, 0, 0), 0.5));
    inside.push_back(ball(Vec3(0, 0, 0), 0.2));  // around the camera itself
    EXPECT_TRUE(emissionSurrounds(sceneIn(Vec3(0, 0, 0), std::move(inside))));
    // A second emitter, of the same radiance or not.
    std::vector<Surface> same, brighter;
    same.push_back(ball(Vec3(1, 0, 0), 0.5, 1));
    brighter.push_back(ball(Vec3(1, 0, 0), 0.5, 3));
    EXPECT_TRUE(emissionSurrounds(sceneIn(Vec3(0, 0, 0), std::move(same))));
    EXPECT_FALSE(emissionSurrounds(sceneIn(Vec3(0, 0, 0), std::move(brighter))));
    // An emitter out of the probes' way counts too: a lamp brighter than the rest.
    std::vector<Surface> farLamp;
    farLamp.push_back(ball(Vec3(10, 0, 0), 0.5, 3));
    EXPECT_FALSE(emissionSurrounds(sceneIn(Vec3(0, 0, 0), std::move(farLamp))));
    Scene lampFirst = sceneIn(Vec3(0, 0, 0));
    std::vector<Surface> v{ball(Vec3(10, 0, 0), 0.5, 3)};
    v.push_back(lampFirst.surfaces->surfaces()[0]);
    lampFirst.surfaces = std::make_unique<const SurfaceScene>(std::move(v));
    EXPECT_FALSE(emissionSurrounds(lampFirst));
}

TEST(EmissionSurrounds, AnOpenBoxDoesNotSurround) {
    Surface box;
    box.kind = Surface::Kind::Mesh;
    box.mesh = testing::boxMesh(Vec3(-1, -1, -1), Vec3(1, 1, 1));
    box.emission = Spectrum::Constant(1);
    box.twoSidedEmission = true;
    Scene scene;
    scene.camera.position = Vec3(0.1, 0.2, -0.3);
    std::vector<Surface> v{box};
    scene.surfaces = std::make_unique<const SurfaceScene>(std::move(v));
    EXPECT_TRUE(emissionSurrounds(scene));
    box.mesh.indices.resize(box.mesh.indices.size() - 6);  // without its face at x = 1
    v = {box};
    scene.surfaces = std::make_unique<const SurfaceScene>(std::move(v));
    EXPECT_FALSE(emissionSurrounds(scene));
    // No emitter, no surfaces.
    box.emission = Spectrum::Zero();
    v = {box};
    scene.surfaces = std::make_unique<const SurfaceScene>(std::move(v));
    EXPECT_FALSE(emissionSurrounds(scene));
    scene.surfaces.reset();
    EXPECT_FALSE(emissionSurrounds(scene));
}

TEST(EmissionSurrounds, ProbesFromEveryMedium) {
    Scene scene = sceneIn(Vec3(0, 0, 0));
    const PhaseFunction iso(HenyeyGreensteinPhase(0.0));
    MediumShape fog;
    fog.type = MediumShape::Type::Sphere, fog.radius = 1;
    scene.media.push_back(std::make_unique<HomogeneousMedium>(fog, 1.0, Spectrum::Ones(), iso));
    EXPECT_TRUE(emissionSurrounds(scene));
    fog.center = Vec3(5, 0, 0);  // a medium outside the sphere
    scene.media.push_back(std::make_unique<HomogeneousMedium>(fog, 1.0, Spectrum::Ones(), iso));
    EXPECT_FALSE(emissionSurrounds(scene));
}

TEST(Effects, NoLightSampleWhereEmissionSurroundsTheScene) {
    const Effects automatic = Effects::of(sceneIn(Vec3(0, 0, 0)));
    EXPECT_TRUE(automatic.emissionSurrounds);
    EXPECT_TRUE(automatic.emitters);
    EXPECT_FALSE(automatic.areaLights);
    EXPECT_FALSE(automatic.anyNextEvent());
    EXPECT_EQ(automatic.rouletteThreshold, 0.25);
    // render.nee true asks for light samples anyway; outside the sphere "auto" draws them.
    const Effects asked = Effects::of(sceneIn(Vec3(0, 0, 0), {}, true));
    EXPECT_FALSE(asked.emissionSurrounds);
    EXPECT_TRUE(asked.areaLights);
    EXPECT_EQ(asked.rouletteThreshold, 1);
    const Effects outside = Effects::of(sceneIn(Vec3(0, -4, 0)));
    EXPECT_FALSE(outside.emissionSurrounds);
    EXPECT_TRUE(outside.areaLights);
    // With the radiance cache on, next-event estimation keeps the direct light out of its records.
    Scene cached = sceneIn(Vec3(0, 0, 0));
    cached.settings.radianceCache.enabled = true;
    const Effects withCache = Effects::of(cached);
    EXPECT_TRUE(withCache.radianceCache);
    EXPECT_FALSE(withCache.emissionSurrounds);
    EXPECT_TRUE(withCache.areaLights);
    // Nor is an image sky sampled that the emitter hides.
    Scene sky = sceneIn(Vec3(0, 0, 0));
    Image varying(8, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) varying.set(x, y, Spectrum::Constant(1 + x * y));
    sky.environment = Environment::image(varying, 1, 0, false);
    const Effects hidden = Effects::of(sky);
    EXPECT_TRUE(hidden.emissionSurrounds);
    EXPECT_FALSE(hidden.nextEvent);
}

}  // namespace
}  // namespace shvol
