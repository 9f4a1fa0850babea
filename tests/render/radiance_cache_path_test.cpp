// The radiance cache in the path tracer (render.radiance_cache; VolumePathIntegrator's first pass
// and its lookups at camera paths' first vertices).
#include <gtest/gtest.h>

#include <functional>

#include "shvol/media/homogeneous_medium.h"
#include "shvol/phase/henyey_greenstein_phase.h"
#include "shvol/render/renderer.h"
#include "shvol/render/volume_path_integrator.h"
#include "shvol/sh/hsh.h"
#include "surfaces/surface_test_util.h"

namespace shvol {
namespace {

/// Inside a closed Lambertian box of reflectance ρ emitting L_e: the radiance is L_e/(1 − ρ)
/// everywhere, of which L_e arrives straight from the walls (next-event estimation's part) and
/// ρ L_e/(1 − ρ) after at least one bounce (the cache's part).
Scene furnaceBox(double rho, double Le) {
    Scene scene;
    scene.camera.position = Vec3(0.1, -0.5, 0.2);
    scene.camera.target = Vec3(0.1, 1, 0.1);
    scene.camera.width = scene.camera.height = 24;
    scene.camera.fovDegrees = 90;
    scene.settings.maxDepth = 1000;
    scene.settings.spp = 4;
    RadianceCacheSettings& rc = scene.settings.radianceCache;
    rc.enabled = true;
    rc.hshOrder = 3;
    rc.raysPerRecord = 400;
    rc.accuracy = 0.5;
    Surface box;
    box.kind = Surface::Kind::Mesh;
    box.mesh = testing::boxMesh(Vec3(-1, -1, -1), Vec3(1, 1, 1));
    box.bsdf = Bsdf::lambert(Spectrum::Constant(rho));
    box.emission = Spectrum::Constant(Le);
    box.twoSidedEmission = true;
    std::vector<Surface> v;
    v.push_back(std::move(box));
    scene.surfaces = std::make_unique<const SurfaceScene>(std::move(v));
    return scene;
}

/// The furnace box with a two-sided mirror panel inside it (R = 1, in the plane x = −0.5, seen
/// obliquely by the camera's walls): a lossless mirror in an isotropic field leaves it as it is,
/// so the radiance is still L_e/(1 − ρ) everywhere.
Scene mirroredFurnaceBox(double rho, double Le) {
    Scene scene = furnaceBox(rho, Le);
    std::vector<Surface> v = scene.surfaces->surfaces();
    Eigen::Affine3d panel = Eigen::Affine3d::Identity();
    panel.translate(Vec3(-0.5, 0, 0)).rotate(Eigen::AngleAxisd(Pi / 2, Vec3::UnitY())).scale(0.9);
    v.push_back(Surface::rectangle(panel));
    v.back().bsdf = Bsdf::mirror(Spectrum::Ones());
    scene.surfaces = std::make_unique<const SurfaceScene>(std::move(v));
    return scene;
}

/// A scene with the radiance cache on, seen from `eye` towards `at` on a film of width × height,
/// under a constant sky of radiance `sky`.
Scene cachedScene(const Vec3& eye, const Vec3& at, double fov, int width, int height, int spp,
                  double sky) {
    Scene scene;
    scene.camera.position = eye;
    scene.camera.target = at;
    scene.camera.fovDegrees = fov;
    scene.camera.width = width, scene.camera.height = height;
    scene.settings.spp = spp;
    scene.environment = Environment::constant(Spectrum::Constant(sky), false);
    scene.settings.radianceCache.enabled = true;
    return scene;
}

/// The irradiance of each record of the scene's cache (Monte Carlo estimates: 400 rays of a path
/// tracer in the furnace box), and their mean and its standard error.
struct RecordIrradiance {
    std::vector<double> E;
    double mean = 0, spread = 0, error = 0;
};
/// `less(p, n)` is taken off each record's irradiance first (0: none).
RecordIrradiance recordIrradiance(
    const Scene& scene, const std::function<double(const Vec3&, const Vec3&)>& less = {}) {
    const VolumePathIntegrator integrator(scene);
    const RadianceCache* cache = integrator.radianceCache();
    RecordIrradiance r;
    if (!cache) return r;
    const int n = cache->order();
    const Eigen::VectorXd cosine = sh::projectHSH(
        n, [](const Vec3& w) { return w.z(); }, sh::hemisphereQuadrature(8, 16));
    for (size_t i = 0; i < cache->size(); ++i)
        r.E.push_back(
            Eigen::Map<const Eigen::VectorXd>(cache->record(i).lambda.data(), n * n).dot(cosine) -
            (less ? less(cache->record(i).p, cache->record(i).frame.n) : 0.0));
    double var = 0;
    for (double e : r.E) r.mean += e / r.E.size();
    for (double e : r.E) var += sqr(e - r.mean) / (r.E.size() - 1);
    r.spread = std::sqrt(var);
    r.error = std::sqrt(var / r.E.size());
    return r;
}

/// Each record holds the indirect irradiance π ρ L_e/(1 − ρ) of the furnace box (with or without
/// the mirror), once `less` is taken off: their mean within 4 standard errors of it, and none
/// strays far.
void expectRecordsHoldTheIndirectIrradiance(
    const Scene& scene, double rho, double Le,
    const std::function<double(const Vec3&, const Vec3&)>& less = {}) {
    const RecordIrradiance r = recordIrradiance(scene, less);
    ASSERT_GT(r.E.size(), 4u);
    const double expected = Pi * rho * Le / (1 - rho);
    EXPECT_NEAR(r.mean, expected, 4 * r.error + 1e-9);
    EXPECT_LT(r.spread, 0.1 * expected);  // the spread of one record: a few per cent
    for (double e : r.E) EXPECT_NEAR(e, expected, 0.3 * expected);
}

TEST(RadianceCachePath, FurnaceRecordsHoldTheIndirectIrradiance) {
    expectRecordsHoldTheIndirectIrradiance(furnaceBox(0.6, 0.5), 0.6, 0.5);
}

// The light that reaches a record through delta surfaces alone (here a wall's L_e through the
// mirror) is the cached vertex's to take: its BSDF sample goes on through them to the light it
// meets, which no light sample reaches. Records held it for every point each serves, which no
// record spacing resolves where the light varies fast: a floor beside a mirror that shows it a
// lamp came out 1.2% dark (helper 134). Here they held 8.7% too much. So also without MIS and
// without next-event estimation, where records hold the direct light too: then they hold all
// but the mirror's share, L_e times the mirror's projected solid angle seen from the record
// (Lambert's formula for a polygon above the record's horizon: ½ Σ_edges γ_k n·u_k, γ_k the
// angle an edge subtends and u_k the unit normal of the plane through it and the record).
TEST(RadianceCachePath, RecordsLeaveTheLightThroughDeltaSurfacesToTheCachedVertex) {
    const double rho = 0.6, Le = 0.5;
    expectRecordsHoldTheIndirectIrradiance(mirroredFurnaceBox(rho, Le), rho, Le);
    const Vec3 corners[4] = {Vec3(-0.5, -0.9, -0.9), Vec3(-0.5, 0.9, -0.9), Vec3(-0.5, 0.9, 0.9),
                             Vec3(-0.5, -0.9, 0.9)};
    const auto mirrorShare = [&](const Vec3& p, const Vec3& n) {
        double sum = 0;
        for (int k = 0; k < 4; ++k) {
            const Vec3 a = (corners[k] - p).normalized(),
                       b = (corners[(k + 1) % 4] - p).normalized();
            sum += std::acos(std::clamp(a.dot(b), -1.0, 1.0)) * n.dot(a.cross(b).normalized());
        }
        return Le * std::abs(sum) / 2;
    };
    Scene noNee = mirroredFurnaceBox(rho, Le);
    noNee.settings.nee = false;  // (records: all the light, L_e/(1 − ρ) from every direction)
    const RecordIrradiance plusShare =
        recordIrradiance(noNee, [&](const Vec3& p, const Vec3& n) { return -mirrorShare(p, n); });
    ASSERT_GT(plusShare.E.size(), 4u);
    EXPECT_NEAR(plusShare.mean, Pi * Le / (1 - rho), 4 * plusShare.error);
    // (the share is more than the noise: records that kept it fail)
    const RecordIrradiance whole = recordIrradiance(noNee);
    EXPECT_GT(plusShare.mean - whole.mean, 6 * plusShare.error);
    Scene noMis = mirroredFurnaceBox(rho, Le);
    noMis.settings.mis = MisHeuristic::None;
    // (Light samples alone, whose weight is unbounded by the box's edges: many rays per record,
    // and only the records' mean is judged, not each.)
    noMis.settings.radianceCache.raysPerRecord = 16384;
    const RecordIrradiance r = recordIrradiance(noMis);
    ASSERT_GT(r.E.size(), 4u);
    EXPECT_NEAR(r.mean, Pi * rho * Le / (1 - rho), 4 * r.error);
}

// Over 8 seeds, in mean and in spread: every image within 2% of L_e/(1 − ρ) and their mean within
// 4 standard errors of it. The direct light at a cached vertex was light samples alone, whose
// weight grows without bound by the box's edges, where the emitting wall's solid-angle density
// falls as r²: the image mean spread by 4.0% from seed to seed (one light sample; +13.7% at worst
// of 16 seeds), so the 3% this test allowed its one seed let a bias of several per cent pass
// (helper 119). With a BSDF sample MIS-weighted against them, 0.38% (+1.1% at worst): the
// records' own noise.
void expectFurnaceRenderIsLeOverOneMinusRho(const std::function<Scene()>& box, double rho,
                                            double Le) {
    const double expected = Le / (1 - rho);
    for (const int lightSamples : {1, 4}) {  // several direct-light samples share the weight
        std::vector<double> means;
        for (uint64_t seed = 1; seed <= 8; ++seed) {
            Scene scene = box();
            scene.settings.radianceCache.lightSamples = lightSamples;
            scene.settings.seed = seed;
            const RenderResult r = render(scene, RenderOptions{});
            const Image img = r.film.image();
            double sum = 0;
            for (float v : img.rgb) {
                ASSERT_TRUE(std::isfinite(v));
                sum += v;
            }
            means.push_back(sum / img.rgb.size());
            EXPECT_NEAR(means.back(), expected, 0.02 * expected) << lightSamples << ", " << seed;
            EXPECT_GT(r.stats.counters.cacheHits, r.stats.counters.cacheLookups * 9 / 10);
            EXPECT_TRUE(r.stats.radianceCache.used);
        }
        double mean = 0, var = 0;
        for (double m : means) mean += m / means.size();
        for (double m : means) var += (m - mean) * (m - mean) / (means.size() - 1);
        EXPECT_NEAR(mean, expected, 4 * std::sqrt(var / means.size())) << lightSamples;
    }
}

TEST(RadianceCachePath, FurnaceRenderIsLeOverOneMinusRho) {
    expectFurnaceRenderIsLeOverOneMinusRho([] { return furnaceBox(0.6, 0.5); }, 0.6, 0.5);
}

// The same with the mirror, whose light the cached vertex now takes through its BSDF sample.
// (With `mis: "none"` the cached vertex's light samples alone take the walls' direct light, and
// the images spread 4% from seed to seed, above: the records are tested instead.)
TEST(RadianceCachePath, MirroredFurnaceRenderIsLeOverOneMinusRho) {
    expectFurnaceRenderIsLeOverOneMinusRho([] { return mirroredFurnaceBox(0.6, 0.5); }, 0.6, 0.5);
}

// A lobe the BRDF table cannot hold (Ward α = 10⁻⁴: the table reflected nothing, and said so
// only by a projection error of 0.008) leaves its surface path traced, so the furnace stays
// L_e/(1 − ρ); cached, its indirect light was black (the image L_e).
TEST(RadianceCachePath, SurfacesWhoseLobeTheTableMissesArePathTraced) {
    const double rho = 0.6, Le = 0.5;
    Scene scene = furnaceBox(rho, Le);
    std::vector<Surface> v;
    v.push_back(scene.surfaces->surfaces()[0]);
    v[0].bsdf = Bsdf::ward(Spectrum::Zero(), Spectrum::Constant(rho), 1e-4, 1e-4);
    scene.surfaces = std::make_unique<const SurfaceScene>(std::move(v));
    const RenderResult r = render(scene, RenderOptions{});
    const Image img = r.film.image();
    double sum = 0;
    for (float x : img.rgb) sum += x;
    EXPECT_NEAR(sum / img.rgb.size(), Le / (1 - rho), 0.03 * Le / (1 - rho));
    ASSERT_EQ(r.stats.radianceCache.uncached.size(), 1u);
    EXPECT_GT(r.stats.radianceCache.uncached[0].second, 0.5);
    EXPECT_EQ(r.stats.counters.cacheLookups, 0u);
}

// The BSDF sample of a cached vertex's direct light crosses media by their transmittance, as a
// light sample's shadow ray does: by a free flight, all or nothing, it made a floor under a lamp
// in absorbing fog (σ_t 4) noisier than light samples alone (pixels' relative error 0.0139
// against 0.0098 here; the image spread 3× as much between seeds in helper 121's scene). Now
// within 15% of light samples alone (0.00975 against 0.00980), by the pooled spread of the
// samples within pixels, which the cache's fixed records leave out.
TEST(RadianceCachePath, DirectLightThroughAbsorbingFogIsNoNoisierThanLightSamplesAlone) {
    double error[2] = {std::nan(""), std::nan("")};  // (a case that did not run fails)
    for (const MisHeuristic mis : {MisHeuristic::Balance, MisHeuristic::None}) {
        Scene scene = cachedScene(Vec3(0, -2.2, 1.6), Vec3(0, -0.4, 0), 45, 32, 32, 32, 0);
        scene.settings.maxDepth = 8;
        scene.settings.mis = mis;
        std::vector<Surface> v;
        v.push_back(Surface::rectangle(Eigen::Affine3d(Eigen::Scaling(2.0))));
        v.back().bsdf = Bsdf::lambert(Spectrum::Constant(0.7));
        Eigen::Affine3d lamp = Eigen::Affine3d::Identity();  // a disk facing down
        lamp.translate(Vec3(0.3, -0.3, 0.8)).rotate(Eigen::AngleAxisd(Pi, Vec3(1, 0, 0)));
        lamp.scale(0.3);
        v.push_back(Surface::disk(lamp));
        v.back().emission = Spectrum::Constant(8);
        scene.surfaces = std::make_unique<const SurfaceScene>(std::move(v));
        MediumShape box;  // about the lamp's foot, the floor's surface inside it
        box.lo = Vec3(-0.6, -0.9, 0.01), box.hi = Vec3(0.9, 0.3, 1);
        scene.media.push_back(std::make_unique<HomogeneousMedium>(
            box, 4.0, Spectrum::Zero(), PhaseFunction(HenyeyGreensteinPhase(0))));
        const RenderResult r = render(scene, RenderOptions{});
        ASSERT_GT(r.stats.counters.cacheHits, r.stats.counters.cacheLookups * 9 / 10);
        error[mis == MisHeuristic::None] = r.film.meanRelativeError();
    }
    EXPECT_LT(error[0], 1.15 * error[1]) << error[0] << " against " << error[1];
}

// A white furnace with an occluder: a white sphere on a white floor under a constant sky of 1,
// where every path returns exactly 1. The cache must too, up to its records' Monte Carlo error:
// its gradients, taken of the radiance itself, were those of the occlusion's parallax, and put
// pixels near the sphere 8.4% off here (a = 0.5; at 16 spp 1.1% at the default 0.25 and 9.8% at
// a = 1).
TEST(RadianceCachePath, FurnaceWithAnOccluderStaysOne) {
    Scene scene = cachedScene(Vec3(0, -4, 2), Vec3::Zero(), 40, 16, 16, 4, 1);
    scene.settings.maxDepth = 1000;
    scene.settings.radianceCache.accuracy = 0.5;
    std::vector<Surface> v;
    v.push_back(Surface::rectangle(Eigen::Affine3d(Eigen::Scaling(3.0))));
    v.push_back(Surface::sphere(Vec3(0, 0, 0.5), 0.5));
    for (Surface& sf : v) sf.bsdf = Bsdf::lambert(Spectrum::Ones());
    scene.surfaces = std::make_unique<const SurfaceScene>(std::move(v));
    const RenderResult r = render(scene, RenderOptions{});
    ASSERT_GT(r.stats.radianceCache.records, 8u);
    ASSERT_GT(r.stats.counters.cacheHits, r.stats.counters.cacheLookups / 2);
    double largest = 0;
    for (float v : r.film.image().rgb) largest = std::max(largest, std::abs(double(v) - 1));
    EXPECT_LT(largest, 0.005);
}

// A floor under a parallel shelf 0.02 above it (over x from 0 to 4), under a constant sky with
// next-event estimation off (the records carry the sky), seen from inside the gap towards its
// opening: the cached image is the path-traced one. Its records see the sky through the opening
// alone, a few per cent of their rays; taking c, what a displacement uncovers, as that sky made
// their gradients large where the radiance falls off like 1/x, and the floor deep inside came
// out 10–50 times too bright, +15.6% over the image (helper 105). c is now the sky only for a
// record that sees it in at least half its rays.
TEST(RadianceCachePath, NoLightLeaksUnderAShelf) {
    Scene scene = cachedScene(Vec3(1, 0, 0.01), Vec3(-5, 0, 0.01), 6, 32, 32, 16, 1);
    scene.settings.nee = false;
    std::vector<Surface> v;
    v.push_back(Surface::rectangle(Eigen::Affine3d(Eigen::Scaling(4.0))));  // the floor
    Eigen::Affine3d shelf = Eigen::Affine3d::Identity();
    shelf.translate(Vec3(2, 0, 0.02)).rotate(Eigen::AngleAxisd(Pi, Vec3::UnitX()));
    shelf.scale(Vec3(2, 3, 1));
    v.push_back(Surface::rectangle(shelf));
    for (Surface& sf : v) sf.bsdf = Bsdf::lambert(Spectrum::Constant(0.8));
    scene.surfaces = std::make_unique<const SurfaceScene>(std::move(v));
    const Image cached = render(scene, RenderOptions{}).film.image();
    scene.settings.radianceCache.enabled = false;
    const Image traced = render(scene, RenderOptions{}).film.image();
    double a = 0, b = 0;
    for (size_t k = 0; k < cached.rgb.size(); ++k) a += cached.rgb[k], b += traced.rgb[k];
    ASSERT_GT(b, 0);
    EXPECT_NEAR(a / b, 1, 0.04);
}

// A cube of dense black fog standing on a floor under a constant sky hides the floor under it and
// shades the floor beside it, as a wall would. Its absorptions are what the records' rays meet:
// taken for misses, records beside it reached under and across it: this cube (no null box about
// it) came out 3.4% dark, the same cube in a null box 3.50% (9.33% at a = 0.5), its pixels by
// the fog up to 0.43 too dark (helper 108; README, "Radiance cache").
TEST(RadianceCachePath, DenseFogOccludesAsAWall) {
    Scene scene = cachedScene(Vec3(0, -5, 4), Vec3(0, 0, 0.5), 50, 24, 24, 16, 1);
    std::vector<Surface> v;
    v.push_back(Surface::rectangle(Eigen::Affine3d(Eigen::Scaling(4.0))));
    v.back().bsdf = Bsdf::lambert(Spectrum::Constant(0.8));
    scene.surfaces = std::make_unique<const SurfaceScene>(std::move(v));
    MediumShape cube;
    cube.lo = Vec3(-1, -1, 0), cube.hi = Vec3(1, 1, 2);
    scene.media.push_back(std::make_unique<HomogeneousMedium>(
        cube, 50, Spectrum::Zero(), PhaseFunction(HenyeyGreensteinPhase(0))));
    for (const double a : {0.3, 0.5}) {
        scene.settings.radianceCache.enabled = true;
        scene.settings.radianceCache.accuracy = a;
        const RenderResult r = render(scene, RenderOptions{});
        ASSERT_GT(r.stats.counters.cacheHits, r.stats.counters.cacheLookups / 2);
        const Image cached = r.film.image();
        scene.settings.radianceCache.enabled = false;
        const Image traced = render(scene, RenderOptions{}).film.image();
        double sc = 0, st = 0, worst = 0;
        for (size_t k = 0; k < cached.rgb.size(); ++k) {
            sc += cached.rgb[k], st += traced.rgb[k];
            worst = std::max(worst, double(std::abs(cached.rgb[k] - traced.rgb[k])));
        }
        EXPECT_NEAR(sc / st, 1, 0.01) << a;
        EXPECT_LT(worst, 0.2) << a;
    }
    // A thin fog (optical depth below 0.1 across the cube) hides nothing: the records are those
    // of the floor alone. (Its collisions taken for walls, near ones ruled the records' harmonic
    // mean distance: a Cornell box of thin fog made 20,000 records in 23 s, against 2547 in 2.9.)
    scene.settings.radianceCache.enabled = true;
    scene.settings.radianceCache.accuracy = 0.3;
    scene.media.clear();
    const size_t bare = render(scene, RenderOptions{}).stats.radianceCache.records;
    scene.media.push_back(std::make_unique<HomogeneousMedium>(
        cube, 0.02, Spectrum::Constant(0.5), PhaseFunction(HenyeyGreensteinPhase(0))));
    EXPECT_EQ(render(scene, RenderOptions{}).stats.radianceCache.records, bare);
}

// A floor split by a wall of no thickness, a lamp on one side and a black sky: no light reaches
// the floor on the other side. Records at the wall's foot on the lit side reached past it (R is
// at least 1% of the scene's diagonal), and the dark floor beside the wall got 0.216 in its first
// column of pixels (helper 63's audit); a record now serves no query past the nearest surface its
// rays met beside it.
TEST(RadianceCachePath, NoLightThroughAThinWall) {
    Scene scene = cachedScene(Vec3(0, -0.3, 1.2), Vec3::Zero(), 4, 64, 32, 4, 0);
    scene.camera.up = Vec3(0, 1, 0);
    scene.settings.radianceCache.raysPerRecord = 256;
    const auto placed = [](const Vec3& at, const Vec3& scale) {
        Eigen::Affine3d m = Eigen::Affine3d::Identity();
        m.translate(at).rotate(Eigen::AngleAxisd(0.5 * Pi, Vec3::UnitY())).scale(scale);
        return m;
    };
    std::vector<Surface> v;
    v.push_back(Surface::rectangle(Eigen::Affine3d::Identity()));  // the floor, [−1, 1]²
    v.push_back(Surface::rectangle(placed(Vec3(0, 0, 0.5), Vec3(0.5, 1, 1))));        // x = 0
    v.push_back(Surface::rectangle(placed(Vec3(-0.6, 0, 0.15), Vec3(0.1, 0.3, 1))));  // the lamp
    for (Surface& sf : v) sf.bsdf = Bsdf::lambert(Spectrum::Constant(0.8));
    v.back().emission = Spectrum::Constant(20);
    v.back().twoSidedEmission = true;
    scene.surfaces = std::make_unique<const SurfaceScene>(std::move(v));
    const RenderResult r = render(scene, RenderOptions{});
    ASSERT_GT(r.stats.counters.cacheHits, r.stats.counters.cacheLookups / 2);
    const Image img = r.film.image();
    double lit = 0, dark = 0;  // the floor left and right of the wall (columns 0–31 and 32–63)
    for (int y = 0; y < img.height; ++y)
        for (int x = 0; x < img.width; ++x) (x < 32 ? lit : dark) += img.at(x, y)[0];
    EXPECT_GT(lit, 0.5 * 32 * img.height);  // (about 1 per pixel)
    EXPECT_EQ(dark, 0.0);
}

// Inside a bowl (a Lambertian sphere lit by a small one inside it) the surface's own rise ahead of
// a record is no wall: counted as one, it was met near the record by the lowest of its rays, and
// with 1024 rays per record 278 of 1024 lookups were answered, one record filled per pixel
// (review of the rule above).
TEST(RadianceCachePath, ConcaveSurfacesAreNoWalls) {
    Scene scene = cachedScene(Vec3(0, -0.5, 0), Vec3(0, 1, -0.3), 60, 32, 32, 1, 0);
    scene.settings.maxDepth = 3;
    scene.settings.radianceCache.hshOrder = 2;
    scene.settings.radianceCache.raysPerRecord = 1024;
    std::vector<Surface> v;
    v.push_back(Surface::sphere(Vec3::Zero(), 1));
    v.push_back(Surface::sphere(Vec3(0, 0, 0.6), 0.1));
    for (Surface& sf : v) sf.bsdf = Bsdf::lambert(Spectrum::Constant(0.5));
    v.back().emission = Spectrum::Constant(5);
    scene.surfaces = std::make_unique<const SurfaceScene>(std::move(v));
    const RenderResult r = render(scene, RenderOptions{});
    EXPECT_GT(r.stats.counters.cacheHits, r.stats.counters.cacheLookups * 9 / 10);
    EXPECT_LT(r.stats.radianceCache.records, 32u * 32u / 2);
}

// A cached pixel sees no more bounces than max_depth allows: the camera path's vertex is the
// first, the record paths continue from there. With depth d the furnace gives L_e Σ_{k≤d} ρ^k.
TEST(RadianceCachePath, CachedPixelsRespectMaxDepth) {
    const double rho = 0.6, Le = 0.5;
    for (const int d : {1, 2, 3}) {
        Scene scene = furnaceBox(rho, Le);
        scene.settings.maxDepth = d;
        const RenderResult r = render(scene, RenderOptions{});
        double sum = 0;
        for (float v : r.image.rgb) sum += v;
        double expected = 0;
        for (int k = 0; k <= d; ++k) expected += Le * std::pow(rho, k);
        EXPECT_NEAR(sum / r.image.rgb.size(), expected, 0.03 * expected) << "max depth " << d;
    }
}

TEST(RadianceCachePath, ImageDoesNotDependOnTheThreadCount) {
    const Scene scene = furnaceBox(0.5, 1);
    RenderOptions one, two;
    one.threads = 1;
    two.threads = 2;
    EXPECT_EQ(render(scene, one).film.image().rgb, render(scene, two).film.image().rgb);
}

}  // namespace
}  // namespace shvol

namespace shvol {
namespace {

/// A closed room with a glossy Phong-22 back wall and a light: the cached image stays near the
/// path-traced one (the experiment in validation/cache measures the bias), on the whole and on
/// the glossy wall, whose radiance depends on the view direction. The ratios of cached to
/// path-traced means, measured over seeds 1-8: 0.981-1.003 on the wall, 0.974-1.019 on its
/// outer column groups (the most oblique views). A cache that reads the BRDF table for the normal
/// direction instead of the view gave 1.049-1.068 and 1.073-1.158 (seeds 1-7).
void checkGlossyRoom(const std::function<std::unique_ptr<const SurfaceScene>()>& surfaces) {
    auto room = [&](bool cache) {
        Scene scene;
        scene.camera.position = Vec3(0, -0.95, 0);
        scene.camera.target = Vec3(0, 1, 0);
        scene.camera.width = scene.camera.height = 24;
        scene.camera.fovDegrees = 80;
        scene.settings.spp = cache ? 64 : 512;
        scene.settings.radianceCache.enabled = cache;
        scene.settings.radianceCache.hshOrder = 6;
        scene.settings.radianceCache.raysPerRecord = 256;
        scene.surfaces = surfaces();
        return render(scene, RenderOptions{});
    };
    const RenderResult pt = room(false), rc = room(true);
    double a = 0, b = 0;
    for (size_t i = 0; i < pt.image.rgb.size(); ++i) {
        ASSERT_TRUE(std::isfinite(rc.image.rgb[i]));
        ASSERT_GE(rc.image.rgb[i], 0);
        a += pt.image.rgb[i], b += rc.image.rgb[i];
    }
    EXPECT_NEAR(b / a, 1, 0.03);
    EXPECT_GT(rc.stats.radianceCache.records, 10u);
    // Pixels 6-17 of both axes see the glossy wall (it subtends ±27° of the ±40° field); the
    // outer column groups are pixels 6-8 and 15-17.
    double wall[2] = {0, 0}, outer[2] = {0, 0};
    for (int y = 6; y < 18; ++y)
        for (int x = 6; x < 18; ++x)
            for (int k = 0; k < 3; ++k) {
                const size_t i = 3 * (size_t(y) * 24 + x) + k;
                const bool isOuter = x < 9 || x >= 15;
                for (int j = 0; j < 2; ++j) {
                    const float v = (j == 0 ? pt : rc).image.rgb[i];
                    wall[j] += v;
                    if (isOuter) outer[j] += v;
                }
            }
    EXPECT_NEAR(wall[1] / wall[0], 1, 0.03);
    EXPECT_NEAR(outer[1] / outer[0], 1, 0.045);
    EXPECT_TRUE(rc.stats.radianceCache.uncached.empty());  // (every surface cached)
}

TEST(RadianceCachePath, GlossyRoomStaysNearThePathTracedImage) {
    checkGlossyRoom(testing::glossyRoom);
}

// The same with an anisotropic Ward back wall turned by 90° about its normal (its BRDF table in
// the wall's own frame, turned into the records' by HshBrdfTable::coefficients): the cache with
// an anisotropic lobe stays near the path tracer. Not a test of the turn itself: here the wall's
// mean moves by only 0.8% without it; HshBrdfTable.AnisotropicLobesAreTurnedIntoTheGivenFrame
// is that test.
TEST(RadianceCachePath, AnisotropicGlossyRoomStaysNearThePathTracedImage) {
    checkGlossyRoom([] {
        const std::unique_ptr<const SurfaceScene> room = testing::glossyRoom();
        std::vector<Surface> v = room->surfaces();
        Eigen::Affine3d back = Eigen::Affine3d::Identity();
        back.translate(Vec3(0, 0.99, 0))
            .rotate(Eigen::AngleAxisd(Pi / 2, Vec3::UnitX()))
            .rotate(Eigen::AngleAxisd(Pi / 2, Vec3::UnitZ()));
        v[1] = Surface::rectangle(back);
        v[1].bsdf = Bsdf::ward(Spectrum::Constant(0.2), Spectrum::Constant(0.6), 0.05, 0.5);
        return std::make_unique<const SurfaceScene>(std::move(v));
    });
}

}  // namespace
}  // namespace shvol

namespace shvol {
namespace {

/// A Lambertian square in the plane z = 0 whose vertex normals all lean by α = 60° from its
/// geometric normal, under a constant sky, without next-event estimation. Reflection stays on
/// the viewer's side of the plane and the BSDF's cosine is the shading normal's (flipped to the
/// viewer's side), so the irradiance is that of a plane tilted by the angle β between the
/// flipped shading normal and the geometric normal on the viewer's side, under the sky's half on
/// that side: π L_e (1 + cos β)/2, and the radiance leaving it ρ L_e (1 + cos β)/2. Seen from
/// above or below, β = α; seen grazing from the side the normals lean away from, the shading
/// normal faces away and is flipped: β = 180° − α. A cache framed by the geometric normal would
/// give ρ L_e.
TEST(RadianceCachePath, UsesTheShadingNormalsOfSmoothMeshes) {
    const double rho = 0.8, Le = 1, alpha = Pi / 3;
    struct View {
        Vec3 position;
        double fov, cosBeta;
    };
    // Each camera's every pixel sees the square (the grazing one at 7.5°–11.5° of elevation).
    const View views[] = {{Vec3(0, 0, 3), 30, std::cos(alpha)},
                          {Vec3(0, 0, -3), 30, std::cos(alpha)},
                          {Vec3(0, 3, 0.5), 4, -std::cos(alpha)}};
    for (const View& view : views) {
        const double expected = rho * Le * (1 + view.cosBeta) / 2;
        for (const bool cache : {false, true}) {
            Scene scene;
            scene.camera.position = view.position;
            scene.camera.target = Vec3(0, 0, 0);
            scene.camera.up = Vec3(0, 1, 1).normalized();
            scene.camera.width = scene.camera.height = 16;
            scene.camera.fovDegrees = view.fov;
            scene.settings.spp = cache ? 4 : 256;
            scene.settings.nee = false;  // the sky's light then reaches the pixels by the cache
            scene.settings.radianceCache.enabled = cache;
            scene.settings.radianceCache.hshOrder = 4;
            scene.settings.radianceCache.raysPerRecord = 256;
            scene.environment = Environment::constant(Spectrum::Constant(Le), false);
            Surface square;
            square.kind = Surface::Kind::Mesh;
            square.mesh.p = {Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(-1, 1, 0)};
            square.mesh.n.assign(4, Vec3(0, -std::sin(alpha), std::cos(alpha)));
            square.mesh.indices = {0, 1, 2, 0, 2, 3};
            square.bsdf = Bsdf::lambert(Spectrum::Constant(rho));
            std::vector<Surface> v;
            v.push_back(std::move(square));
            scene.surfaces = std::make_unique<const SurfaceScene>(std::move(v));
            const RenderResult r = render(scene, RenderOptions{});
            double sum = 0;
            for (float x : r.image.rgb) sum += x;
            EXPECT_NEAR(sum / r.image.rgb.size(), expected, 0.03 * expected)
                << "camera at " << view.position.transpose() << ", cache " << cache;
            if (cache)
                EXPECT_GT(r.stats.counters.cacheHits, r.stats.counters.cacheLookups * 9 / 10);
        }
    }
}

}  // namespace
}  // namespace shvol
