// Effects::of and emissionSurrounds: which light samples a scene draws under render.nee "auto".
#include "shvol/render/effects.h"

#include <gtest/gtest.h>

#include <algorithm>
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
    // An image sky is judged as without the emitters: a gap the probes missed must not hide a
    // sun from next-event estimation (helper 185).
    Scene sky = sceneIn(Vec3(0, 0, 0));
    Image varying(8, 4);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 8; ++x) varying.set(x, y, Spectrum::Constant(1 + x * y));
    varying.set(2, 1, Spectrum::Constant(100));  // (uneven light, which "auto" samples)
    sky.environment = Environment::image(varying, 1, 0, false);
    const Effects underSky = Effects::of(sky);
    EXPECT_TRUE(underSky.emissionSurrounds);
    EXPECT_FALSE(underSky.areaLights);
    EXPECT_TRUE(underSky.nextEvent);
    EXPECT_EQ(underSky.rouletteThreshold, 1);
    const std::vector<std::string> names = automatic.names();
    EXPECT_NE(std::find(names.begin(), names.end(), "emission-surrounds"), names.end());
    EXPECT_EQ(std::find(names.begin(), names.end(), "nee-area-lights"), names.end());
}

TEST(EmissionSurrounds, NotThroughEmittersThatLetLightIn) {
    // A null or glass emitter lets the sky (or what lies beyond) through: helper 185's null shell.
    for (const Bsdf& clear : {Bsdf::null(), Bsdf::dielectric(1.5)}) {
        Scene scene = sceneIn(Vec3(0, 0, 0));
        std::vector<Surface> v = scene.surfaces->surfaces();
        v[0].bsdf = clear;
        scene.surfaces = std::make_unique<const SurfaceScene>(std::move(v));
        EXPECT_FALSE(emissionSurrounds(scene));
    }
    // An orthographic camera's rays start all over its film, which may reach out of the sphere.
    Scene ortho = sceneIn(Vec3(0, 0, 0));
    ortho.camera.type = Camera::Type::Orthographic;
    EXPECT_FALSE(emissionSurrounds(ortho));
}

TEST(EmissionSurrounds, SeesAHoleOfAboutOnePercentOfTheSphere) {
    // The emitting box [−1, 1]³ with a hole of 0.4 × 0.4 in its top, seen from near its centre:
    // about 0.17 sr, 1.3% of the sphere (helper 185: one of 0.22 × 0.22, 0.05 sr, went unseen).
    Scene scene;
    scene.camera.position = Vec3(0.05, -0.1, 0.02);
    std::vector<Surface> v;
    for (int face = 0; face < 6; ++face) {
        const int axis = face / 2;
        const double side = face % 2 ? 1 : -1;
        const auto wall = [&](const Vec3& centre, double du, double dv) {
            Eigen::Affine3d t = Eigen::Affine3d::Identity();
            t.translate(centre);
            if (axis == 0) t.rotate(Eigen::AngleAxisd(Pi / 2, Vec3::UnitY()));
            if (axis == 1) t.rotate(Eigen::AngleAxisd(Pi / 2, Vec3::UnitX()));
            t.scale(Vec3(du, dv, 1));
            v.push_back(Surface::rectangle(t));
            v.back().bsdf = Bsdf::lambert(Spectrum::Constant(0.5));
            v.back().emission = Spectrum::Constant(1);
            v.back().twoSidedEmission = true;
        };
        Vec3 c = Vec3::Zero();
        c[axis] = side;
        if (axis != 2 || side < 0) {
            wall(c, 1, 1);
            continue;
        }
        // The top in four strips around the hole |x|, |y| < 0.2 (a rectangle spans ±1 scaled).
        wall(Vec3(-0.6, 0, 1), 0.4, 1), wall(Vec3(0.6, 0, 1), 0.4, 1);
        wall(Vec3(0, -0.6, 1), 0.2, 0.4), wall(Vec3(0, 0.6, 1), 0.2, 0.4);
    }
    const auto surrounds = [&](std::vector<Surface> walls) {
        scene.surfaces = std::make_unique<const SurfaceScene>(std::move(walls));
        return emissionSurrounds(scene);
    };
    std::vector<Surface> closed = v;
    Eigen::Affine3d lid = Eigen::Affine3d::Identity();
    lid.translate(Vec3(0, 0, 1)).scale(Vec3(0.2, 0.2, 1));
    closed.push_back(Surface::rectangle(lid));
    closed.back().bsdf = v.back().bsdf;
    closed.back().emission = v.back().emission;
    closed.back().twoSidedEmission = true;
    EXPECT_TRUE(surrounds(closed));
    EXPECT_FALSE(surrounds(v));
}

TEST(EmissionSurrounds, GivesUpAfterSixtyFourCrossings) {
    // Null sheets between the camera and the sphere's top: a probe upwards crosses each.
    for (const int sheets : {60, 70}) {
        std::vector<Surface> more;
        for (int k = 0; k < sheets; ++k) {
            Eigen::Affine3d t = Eigen::Affine3d::Identity();
            t.translate(Vec3(0, 0, 0.1 + 0.02 * k)).scale(Vec3(0.3, 0.3, 1));
            more.push_back(Surface::rectangle(t));
            more.back().bsdf = Bsdf::null();
        }
        EXPECT_EQ(emissionSurrounds(sceneIn(Vec3(0, 0, 0), std::move(more))), sheets < 64)
            << sheets;
    }
}

// Under render.nee "auto" an image sky is sampled where its light is uneven (m ≥ 2.5) or
// concentrated (its brightest 1% hold 5% of it or more): a lit cap of a quarter of the sphere
// (m = 4) is, half the sphere lit (m = 2) is not, and an even sky with a sun of one texel (m about
// 2) is.
TEST(Effects, NextEventEstimationUnderImageSkiesWhereTheirLightIsUneven) {
    // Six rows of θ: rows 0–1 are the cap θ < 60° (a quarter of the sphere), rows 0–2 the upper
    // hemisphere.
    const auto capSky = [](int rows) {
        Image img(64, 6);
        for (int y = 0; y < rows; ++y)
            for (int x = 0; x < 64; ++x) img.set(x, y, Spectrum::Ones());
        return img;
    };
    const auto nee = [](const Image& img) {
        Scene scene;
        scene.settings.maxDepth = 8;
        MediumShape fog;
        scene.media.push_back(std::make_unique<HomogeneousMedium>(
            fog, 1.0, Spectrum::Ones(), PhaseFunction(HenyeyGreensteinPhase(0.0))));
        scene.environment = Environment::image(img, 1, 0, false);
        return Effects::of(scene).nextEvent;
    };
    EXPECT_NEAR(Environment::image(capSky(2), 1, 0, false).secondMomentRatio(), 4, 1e-12);
    EXPECT_NEAR(Environment::image(capSky(3), 1, 0, false).secondMomentRatio(), 2, 1e-12);
    EXPECT_TRUE(nee(capSky(2)));
    EXPECT_FALSE(nee(capSky(3)));
    // Half the sphere at 3 and half at 1: m = 2 (a² + b²)/(a + b)² = 1.25.
    Image halves = capSky(3);
    for (int y = 0; y < 6; ++y)
        for (int x = 0; x < 64; ++x) halves.set(x, y, Spectrum::Constant(y < 3 ? 3 : 1));
    EXPECT_NEAR(Environment::image(halves, 1, 0, false).secondMomentRatio(), 1.25, 1e-12);
    EXPECT_FALSE(nee(halves));
    // A sun: one texel of row 2 (θ from 60° to 90°: 0.39% of the sphere) at 18 over an even sky
    // of 1 holds 6.6% of the light and more than half of ∫ Y² dω, and m is only about 2.
    Image sun(64, 6);
    for (int y = 0; y < 6; ++y)
        for (int x = 0; x < 64; ++x) sun.set(x, y, Spectrum::Ones());
    sun.set(10, 2, Spectrum::Constant(18));
    const Environment withSun = Environment::image(sun, 1, 0, false);
    EXPECT_TRUE(withSun.hasSun());
    EXPECT_LT(withSun.secondMomentRatio(), Effects::kNeeSkySecondMomentRatio);
    EXPECT_GE(withSun.peak().brightestShare, Effects::kNeeSkyBrightestShare);
    EXPECT_TRUE(nee(sun));
    // Ten texels of row 2 at 2.5 over the even sky (3.9% of the sphere, 9.2% of the light): m
    // about 1.08, and the brightest 1% (2.56 texels' worth) hold 2.4%; at 8 (25% of the light) m
    // is about 2.1, under 2.5, but they hold 6.3%: sampled (helper 186: a cluster of bright
    // texels that is no sun left most pixels low without light samples).
    Image cluster = sun, denser = sun;
    cluster.set(10, 2, Spectrum::Ones()), denser.set(10, 2, Spectrum::Ones());
    for (int x = 20; x < 30; ++x)
        cluster.set(x, 2, Spectrum::Constant(2.5)), denser.set(x, 2, Spectrum::Constant(8));
    const Environment spread = Environment::image(cluster, 1, 0, false),
                      bright = Environment::image(denser, 1, 0, false);
    EXPECT_LT(spread.peak().brightestShare, Effects::kNeeSkyBrightestShare);
    EXPECT_FALSE(nee(cluster));
    EXPECT_LT(bright.secondMomentRatio(), Effects::kNeeSkySecondMomentRatio);
    EXPECT_GE(bright.peak().brightestShare, Effects::kNeeSkyBrightestShare);
    EXPECT_TRUE(nee(denser));
    // With the lower hemisphere black, over the whole sphere still, as phase sampling draws over
    // it (helper 186): the cap is a quarter of it (m = 4), as without.
    EXPECT_NEAR(Environment::image(capSky(2), 1, 0, true).secondMomentRatio(), 4, 1e-12);
}

}  // namespace
}  // namespace shvol
