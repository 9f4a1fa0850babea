#include "shvol/io/scene_loader.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "shvol/render/effects.h"
#include "shvol/render/renderer.h"
#include "test_util.h"

namespace shvol {
namespace {

const std::string kSunlitCloud = std::string(SHVOL_SOURCE_DIR) + "/media/sunlit_cloud.json";

double imageMean(const Image& img) {
    double s = 0;
    for (float v : img.rgb) s += v;
    return s / img.rgb.size();
}

}  // namespace

// The light-sampling keys are read, checked and reach the settings and the environment.
TEST(SceneLoader, LightSamplingKeys) {
    const Scene s = loadScene(
        kSunlitCloud, {"render.light_sampling=wavelet", "render.mis=power",
                       "render.product_order=12", "render.product_depth=5",
                       "environment.wavelet_coefficients=500", "environment.mapping=shvol"});
    EXPECT_EQ(s.settings.lightSampling, LightSampling::Wavelet);
    EXPECT_EQ(s.settings.mis, MisHeuristic::Power);
    EXPECT_EQ(s.settings.productOrder, 12);
    EXPECT_EQ(s.settings.productDepth, 5);
    EXPECT_EQ(s.settings.waveletCoefficients, 500u);
    EXPECT_EQ(s.environment.mapping(), LatLongMapping::Shvol);
    const Scene d = loadScene(kSunlitCloud, {"render.light_sampling=environment"});
    EXPECT_EQ(d.environment.mapping(), LatLongMapping::Blender);
    EXPECT_EQ(d.settings.productDepth, -1);

    using test::messageOf;
    EXPECT_NE(messageOf([] {
                  loadScene(kSunlitCloud, {"render.product_order=33"});
              }).find("render.product_order: value 33 out of range [1, 32]"),
              std::string::npos);
    EXPECT_NE(messageOf([] {
                  loadScene(kSunlitCloud, {"render.mis=max"});
              }).find("render.mis: unknown value \"max\""),
              std::string::npos);
    EXPECT_NE(messageOf([] {
                  loadScene(kSunlitCloud, {"environment.wavelet_coefficients=2.5"});
              }).find("environment.wavelet_coefficients: expected a non-negative integer"),
              std::string::npos);
    EXPECT_NE(messageOf([] {
                  loadScene(kSunlitCloud, {"environment.mapping=cycles"});
              }).find("environment.mapping: unknown value \"cycles\""),
              std::string::npos);
}

// render.nee is true, false or "auto" (unset: decided from the scene); render.sampler names the
// sample stream.
TEST(SceneLoader, NeeAndSamplerKeys) {
    EXPECT_FALSE(loadScene(kSunlitCloud, {"render.nee=\"auto\""}).settings.nee.has_value());
    EXPECT_EQ(loadScene(kSunlitCloud, {"render.nee=false"}).settings.nee, false);
    EXPECT_EQ(loadScene(kSunlitCloud, {"render.sampler=independent"}).settings.sampler,
              SampleStream::Independent);
    using test::messageOf;
    EXPECT_NE(messageOf([] {
                  loadScene(kSunlitCloud, {"render.nee=\"sometimes\""});
              }).find("render.nee: expected true, false or \"auto\""),
              std::string::npos);
    EXPECT_NE(messageOf([] {
                  loadScene(kSunlitCloud, {"render.sampler=halton"});
              }).find("render.sampler: unknown value \"halton\""),
              std::string::npos);
}

// media[i].majorant_cell is an integer or "auto" (the default, chosen at load); the choice is in
// the medium's description.
TEST(SceneLoader, MajorantCellKey) {
    EXPECT_NE(loadScene(kSunlitCloud, {}).media[0]->describe().find("(auto)"), std::string::npos);
    EXPECT_NE(loadScene(kSunlitCloud, {"media[0].majorant_cell=\"auto\""})
                  .media[0]
                  ->describe()
                  .find("(auto)"),
              std::string::npos);
    EXPECT_NE(loadScene(kSunlitCloud, {"media[0].majorant_cell=6"})
                  .media[0]
                  ->describe()
                  .find("majorant cells of 6 voxels,"),
              std::string::npos);
    EXPECT_NE(test::messageOf([] {
                  loadScene(kSunlitCloud, {"media[0].majorant_cell=\"fine\""});
              }).find("media[0].majorant_cell: expected an integer 1 … 4096 or \"auto\""),
              std::string::npos);
}

// media[i].regular_tracking (default true) is a bool; off, the medium's description says so.
TEST(SceneLoader, RegularTrackingKey) {
    EXPECT_EQ(loadScene(kSunlitCloud, {}).media[0]->describe().find("regular"), std::string::npos);
    EXPECT_NE(loadScene(kSunlitCloud, {"media[0].regular_tracking=false"})
                  .media[0]
                  ->describe()
                  .find(", no regular tracking"),
              std::string::npos);
    EXPECT_NE(test::messageOf([] {
                  loadScene(kSunlitCloud, {"media[0].regular_tracking=1"});
              }).find("media[0].regular_tracking: expected true or false"),
              std::string::npos);
}

// The sunlit cloud of media/ (VDB cloud, Preetham sky, 0.53° sun) renders the same expected
// image with every light-sampling strategy: image means over 6 seeds agree with the
// MIS(environment, phase) baseline within 5 combined standard errors.
TEST(SceneLoader, SunlitCloudStrategiesAgree) {
    struct Strategy {
        const char* lightSampling;
        const char* mis;
    };
    const Strategy strategies[] = {{"environment", "balance"},
                                   {"environment", "none"},
                                   {"wavelet", "power"},
                                   {"product", "balance"},
                                   {"product", "none"}};
    double baseMean = 0, baseVar = 0;
    for (const Strategy& st : strategies) {
        std::vector<double> means;
        for (int seed = 1; seed <= 6; ++seed) {
            const Scene s = loadScene(
                kSunlitCloud, {"camera.resolution=[16,12]", "render.spp=32",
                               "render.seed=" + std::to_string(seed), "media.0.density_scale=8",
                               std::string("render.light_sampling=") + st.lightSampling,
                               std::string("render.mis=") + st.mis});
            const RenderResult r = render(s, {});
            EXPECT_EQ(r.stats.counters.nonFiniteSamples, 0u);
            means.push_back(imageMean(r.image));
        }
        double m = 0, v = 0;
        for (double x : means) m += x;
        m /= means.size();
        for (double x : means) v += sqr(x - m);
        v /= (means.size() - 1) * means.size();  // variance of the mean
        if (&st == &strategies[0]) {
            baseMean = m, baseVar = v;
            continue;
        }
        EXPECT_NEAR(m, baseMean, 5 * std::sqrt(v + baseVar)) << st.lightSampling << "/" << st.mis;
    }
    EXPECT_GT(baseMean, 0.0);
}

// An object that names no type has the loader's default type, which is the one --set takes it
// to have (applyOverride: setting that type keeps the object's keys, another starts it afresh):
// the two lists of defaults agree.
TEST(SceneLoader, TypelessObjectsHaveTheTypeOverridesAssume) {
    const std::string media = std::string(SHVOL_SOURCE_DIR) + "/media/";
    const Json doc = Json::parse(R"({"camera": {"fov": 20}, "environment": {"radiance": 2},
        "media": [{"file": ")" + media +
                                 R"(cloud.vdb", "phase": {"sampling": "analytic"}},
                  {"type": "homogeneous", "sigma_t": 1, "shape": {"min": [-1, -1, -1]}}],
        "surfaces": [{"file": ")" +
                                 media + R"(cornell/white.obj",
                      "bsdf": {"reflectance": 0.3}}]})");
    Json resolved;
    sceneFromJson(doc, "scene.json", &resolved);
    for (const char* at : {"/camera", "/environment", "/media/0", "/media/0/phase",
                           "/media/1/shape", "/surfaces/0", "/surfaces/0/bsdf"}) {
        const Json::json_pointer ptr(at);
        ASSERT_TRUE(resolved[ptr].contains("type")) << at;
        const std::string type = resolved[ptr]["type"];
        std::string key = std::string(at).substr(1);
        std::replace(key.begin(), key.end(), '/', '.');
        Json set = doc;
        applyOverride(set, key + ".type=\"" + type + "\"", "scene.json");
        Json expected = doc[ptr];
        expected["type"] = type;
        EXPECT_EQ(set[ptr], expected) << at << " (the loader's default: " << type << ")";
    }
}

// render.rr_threshold: a number in [1e-6, 1] or "auto" (the default: unset, decided from the
// scene), and in the resolved scene as given.
TEST(SceneLoader, RouletteThreshold) {
    EXPECT_FALSE(loadScene(kSunlitCloud).settings.rrThreshold.has_value());
    EXPECT_FALSE(
        loadScene(kSunlitCloud, {"render.rr_threshold=\"auto\""}).settings.rrThreshold.has_value());
    EXPECT_EQ(loadScene(kSunlitCloud, {"render.rr_threshold=1"}).settings.rrThreshold, 1.0);
    EXPECT_EQ(loadScene(kSunlitCloud, {"render.rr_threshold=0.25"}).settings.rrThreshold, 0.25);
    using test::messageOf;
    for (const char* bad : {"0", "1.5", "-0.25"})
        EXPECT_NE(messageOf([&] {
                      loadScene(kSunlitCloud, {std::string("render.rr_threshold=") + bad});
                  }).find("render.rr_threshold: value " + std::string(bad) + " out of range"),
                  std::string::npos)
            << bad;
    EXPECT_NE(messageOf([] {
                  loadScene(kSunlitCloud, {"render.rr_threshold=\"half\""});
              }).find("render.rr_threshold: expected a number in [1e-06, 1] or \"auto\""),
              std::string::npos);
    Json resolved;
    sceneFromJson(Json::parse(R"({"render": {"spp": 3}})"), "scene.json", &resolved);
    EXPECT_EQ(resolved["render"]["rr_threshold"], "auto");
}

/// Every number and boolean of the scene as given is the resolved scene's at the same place (a
/// number given for an [r, g, b] or [x, y, z] is each of them): the resolved scene is the one
/// rendered, not only one that reloads as itself (a value rounded on its way in, as float(x),
/// would reload rounded alike; helper 119). Strings (file names made absolute, names filled in)
/// are not compared.
void expectResolvedHolds(const Json& given, const Json& resolved, const std::string& at) {
    if (given.is_object()) {
        ASSERT_TRUE(resolved.is_object()) << at;
        for (const auto& [key, value] : given.items()) {
            ASSERT_TRUE(resolved.contains(key)) << at << "." << key;
            expectResolvedHolds(value, resolved.at(key), at + "." + key);
        }
    } else if (given.is_array()) {
        ASSERT_TRUE(resolved.is_array()) << at;
        ASSERT_EQ(given.size(), resolved.size()) << at;
        for (size_t i = 0; i < given.size(); ++i)
            expectResolvedHolds(given[i], resolved[i], at + "[" + std::to_string(i) + "]");
    } else if (given.is_number() && resolved.is_array()) {
        for (const Json& v : resolved) EXPECT_EQ(v.get<double>(), given.get<double>()) << at;
    } else if (given.is_number() || given.is_boolean()) {
        EXPECT_EQ(resolved, given) << at;
    }
}

// The resolved scene of the stats file loads back as the scene it resolves: every shipped scene,
// some with keys the defaults leave out or at "auto" set, and one of every type. It did not:
// render.product_depth was written as "auto", which the loader refused; a Ward lobe was written
// with alpha, alpha_x and alpha_y together, which it refuses; an absent environment resolved to
// fewer keys than the constant environment it stands for.
TEST(SceneLoader, ResolvedSceneLoadsBackAsItself) {
    const std::string media = std::string(SHVOL_SOURCE_DIR) + "/media/";
    std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
        {"default.json", {}},
        {"plume.json", {"render.light_sampling=\"product\"", "media[0].majorant_cell=2"}},
        {"sunlit_cloud.json", {"render.light_sampling=\"product\"", "render.product_depth=4"}},
        {"cloud_ground.json", {}},
        {"cornell.json", {"render.radiance_cache.enabled=true"}},
        {"cornell_fog.json", {}},
        {"milk_glass.json", {}},
    };
    // And a scene of every surface, BSDF, medium and phase function type, its keys at their
    // defaults (the loader fills them in) or given.
    const std::string every = test::privateTempPath("resolved_every") + ".json";
    std::ofstream(every) << R"({"environment": {"type": "constant", "radiance": 0.5},
      "surfaces": [
        {"type": "rectangle", "bsdf": {"type": "ward", "alpha": 0.2}},
        {"type": "rectangle", "bsdf": {"type": "ward", "alpha_x": 0.1, "alpha_y": 0.3}},
        {"type": "disk", "bsdf": {"type": "phong"}},
        {"type": "sphere", "center": [0, 0, 3], "bsdf": {"type": "dielectric"}},
        {"type": "rectangle", "bsdf": {"type": "mirror"}, "emission": 1},
        {"type": "sphere", "center": [0, 0, 6], "bsdf": {"type": "null"}}],
      "media": [
        {"type": "homogeneous", "shape": {"type": "sphere"}, "phase": {"type": "isotropic"}},
        {"type": "homogeneous", "shape": {}, "phase": {"type": "two_term_hg", "g1": 0.5,
         "g2": -0.3, "w": 0.7}},
        {"type": "homogeneous", "shape": {}, "phase": {"type": "rayleigh", "sampling": "sh"}},
        {"type": "homogeneous", "shape": {}, "phase": {"type": "schlick", "k": 0.4}},
        {"type": "homogeneous", "shape": {}, "phase": {"type": "cornette_shanks", "g": 0.8,
         "sampling": "sh", "order": 12, "evaluate": "exact"}},
        {"type": "homogeneous", "boundary": 5, "phase": {"type": "tabulated",
         "file": ")" + media + R"(phase/mie_like.csv"}}]})";
    cases.push_back({every, {}});
    for (const auto& [file, sets] : cases) {
        SCOPED_TRACE(file);
        const std::string path = file.front() == '/' ? file : media + file;
        Json resolved, again;
        loadScene(path, sets, &resolved);
        EXPECT_EQ(test::messageOf([&] { sceneFromJson(resolved, path, &again); }), "(no error)");
        EXPECT_EQ(dumpJson(again), dumpJson(resolved));
        if (sets.empty()) expectResolvedHolds(Json::parse(std::ifstream(path)), resolved, "");
    }
}

// The resolved scene holds every value the loader read, defaults filled in.
TEST(SceneLoader, ResolvedSceneFillsInDefaults) {
    const Json doc = Json::parse(R"({"render": {"spp": 3},
        "media": [{"type": "homogeneous", "shape": {}, "phase": {"type": "hg", "sampling": "sh"}}]})");
    Json resolved;
    const Scene s = sceneFromJson(doc, "scene.json", &resolved);
    EXPECT_EQ(resolved["render"]["spp"], 3);
    EXPECT_EQ(resolved["render"]["max_depth"], s.settings.maxDepth);
    EXPECT_EQ(resolved["render"]["nee"], "auto");
    EXPECT_EQ(resolved["render"]["sampler"], "sobol");
    EXPECT_FALSE(s.settings.nee.has_value());
    EXPECT_EQ(resolved["camera"]["fov"], s.camera.fovDegrees);
    EXPECT_EQ(resolved["camera"]["resolution"], Json({s.camera.width, s.camera.height}));
    // A vector default's integral components are integers too, as a reader writes them.
    EXPECT_EQ(dumpJson(resolved["camera"]["position"]), "[0,-4,0]");
    EXPECT_EQ(dumpJson(resolved["media"][0]["albedo"]), "[1,1,1]");
    EXPECT_EQ(resolved["environment"], Json({{"type", "constant"},
                                             {"lower_hemisphere_black", false},
                                             {"wavelet_coefficients", 0},
                                             {"radiance", 0}}));
    const Json& m = resolved["media"][0];
    EXPECT_EQ(m["sigma_t"], 1.0);
    EXPECT_EQ(m["shape"]["type"], "box");
    EXPECT_EQ(m["phase"]["order"], "auto");
    EXPECT_EQ(m["phase"]["tolerance"], 0.01);
    EXPECT_EQ(m["phase"]["g"], 0.0);
    EXPECT_EQ(m["phase"]["evaluate"], "sh");
    // An analytic phase function records no SH keys.
    Json r2;
    sceneFromJson(
        Json::parse(
            R"({"media": [{"type": "homogeneous", "shape": {}, "phase": {"type": "hg"}}]})"),
        "s.json", &r2);
    EXPECT_FALSE(r2["media"][0]["phase"].contains("order"));
    // No phase: the isotropic one, recorded as such.
    Json r3;
    const Scene s3 = sceneFromJson(
        Json::parse(R"({"media": [{"type": "homogeneous", "shape": {}}]})"), "s.json", &r3);
    EXPECT_EQ(r3["media"][0]["phase"], Json({{"type", "isotropic"}, {"sampling", "analytic"}}));
    EXPECT_TRUE(std::holds_alternative<IsotropicPhase>(s3.media[0]->phase().variant()));
}

}  // namespace shvol

namespace shvol {
namespace {

/// A directory with a closed box mesh (box.obj), an open one (open.obj) and a scene file path.
struct SurfaceFiles {
    std::string dir = test::privateTempPath("surface_loader");
    SurfaceFiles() {
        std::filesystem::create_directories(dir);
        std::ofstream(dir + "/box.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                                           "v 0 0 1\nv 1 0 1\nv 0 1 1\nv 1 1 1\n"
                                           "f 1 3 4 2\nf 5 6 8 7\nf 1 2 6 5\n"
                                           "f 3 7 8 4\nf 1 5 7 3\nf 2 4 8 6\n";
        std::ofstream(dir + "/open.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                            "f 1 3 2\nf 1 2 4\nf 1 4 3\n";
        // Inward-facing: the loader turns a boundary mesh outwards.
        std::ofstream(dir + "/inward.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                              "f 1 2 3\nf 1 4 2\nf 1 3 4\nf 2 4 3\n";
        // The same, flat-shaded: a normal per face, so no two faces share a vertex of the mesh
        // (one per distinct v/vn corner), only positions.
        std::ofstream(dir + "/inward_flat.obj")
            << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
               "vn 0 0 1\nvn 0 1 0\nvn 1 0 0\nvn -1 -1 -1\n"
               "f 1//1 2//1 3//1\nf 1//2 4//2 2//2\nf 1//3 3//3 4//3\nf 2//4 4//4 3//4\n";
        // Two tetrahedra apart, the first outwards, the second (8 times its volume) inwards.
        std::ofstream(dir + "/mixed.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                             "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"
                                             "v 5 0 0\nv 7 0 0\nv 5 2 0\nv 5 0 2\n"
                                             "f 5 6 7\nf 5 8 6\nf 5 7 8\nf 6 8 7\n";
    }
    Scene load(const std::string& json) const {
        return sceneFromJson(Json::parse(json), dir + "/scene.json");
    }
};

}  // namespace

// A rotation axis is a direction at any scale (the norm of [0, 0, 1e200] overflowed and shrank
// the mesh to nothing; that of [0, 0, 1e-300] underflowed and was refused), and a file's normal
// of any length is a direction too (1e300 read as "normal is zero").
TEST(SceneLoader, AxesAndNormalsOfAnyScale) {
    const SurfaceFiles f;
    const auto points = [&](const std::string& axis) {
        return f
            .load(R"({"surfaces": [{"type": "mesh", "file": "box.obj", "transform": {"rotate":
                     {"axis": )" +
                  axis + R"(, "degrees": 90}}}]})")
            .surfaces->surfaces()[0]
            .mesh.p;
    };
    const std::vector<Vec3> unit = points("[0, 0, 1]");
    for (const char* axis : {"[0, 0, 1e200]", "[0, 0, 1e-300]", "[0, 0, 5e-324]"}) {
        const std::vector<Vec3> p = points(axis);
        ASSERT_EQ(p.size(), unit.size());
        for (size_t i = 0; i < p.size(); ++i)
            EXPECT_NEAR((p[i] - unit[i]).norm(), 0, 1e-12) << axis;
    }
    std::ofstream(f.dir + "/normals.ply")
        << "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\n"
           "property double z\nproperty double nx\nproperty double ny\nproperty double nz\n"
           "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
           "0 0 0 0 0 1e300\n1 0 0 0 0 1e-300\n0 1 0 0 0 1\n3 0 1 2\n";
    const Scene s = f.load(R"({"surfaces": [{"type": "mesh", "file": "normals.ply",
                                             "transform": {"scale": 1e12}}]})");
    // (three of them: with none loaded the loop below passed; helper 119)
    ASSERT_EQ(s.surfaces->surfaces()[0].mesh.n.size(), 3u);
    for (const Vec3& n : s.surfaces->surfaces()[0].mesh.n)
        EXPECT_NEAR((n - Vec3(0, 0, 1)).norm(), 0, 1e-12) << n.transpose();
}

TEST(SceneLoader, SurfacesAndTheirBsdfs) {
    const SurfaceFiles f;
    const Scene s = f.load(R"({
      "surfaces": [
        {"type": "mesh", "file": "box.obj", "name": "box",
         "transform": {"translate": [1, 2, 3], "scale": 2},
         "bsdf": {"type": "phong", "diffuse": 0.2, "specular": 0.7, "exponent": 22}},
        {"type": "rectangle", "bsdf": {"type": "ward", "specular": 0.5, "alpha_x": 0.1,
                                       "alpha_y": 0.3}, "emission": [1, 2, 3]},
        {"type": "disk", "bsdf": {"type": "mirror"}},
        {"type": "sphere", "center": [0, 0, 5], "radius": 0.5, "bsdf": {"type": "dielectric",
                                                                       "ior": 1.33}}
      ]})");
    ASSERT_TRUE(s.surfaces);
    const auto& v = s.surfaces->surfaces();
    ASSERT_EQ(v.size(), 4u);
    EXPECT_EQ(v[0].name, "box");
    EXPECT_EQ(v[0].mesh.triangleCount(), 12u);
    EXPECT_NEAR(v[0].area(), 6 * 4, 1e-12);
    Vec3 lo = v[0].mesh.p[0],
         hi = lo;  // translate · scale puts the unit cube at [1, 3]×[2, 4]×[3, 5]
    for (const Vec3& p : v[0].mesh.p) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
    EXPECT_NEAR((lo - Vec3(1, 2, 3)).norm(), 0, 1e-12);
    EXPECT_NEAR((hi - Vec3(3, 4, 5)).norm(), 0, 1e-12);
    EXPECT_EQ(v[0].bsdf.type, BsdfType::Phong);
    EXPECT_EQ(v[0].bsdf.exponent, 22);
    EXPECT_EQ(v[1].name, "surfaces[1]");
    EXPECT_EQ(v[1].bsdf.type, BsdfType::Ward);
    EXPECT_EQ(v[1].bsdf.alphaY, 0.3);
    EXPECT_EQ(v[1].emission[2], 3);
    EXPECT_TRUE(v[1].emits());
    EXPECT_EQ(v[2].bsdf.type, BsdfType::Mirror);
    EXPECT_EQ(v[3].bsdf.ior, 1.33);
    EXPECT_EQ(v[3].radius, 0.5);
    const Effects fx = Effects::of(s);
    EXPECT_TRUE(fx.surfaces);
    EXPECT_TRUE(fx.areaLights);
    EXPECT_FALSE(fx.boundedMedia);
}

TEST(SceneLoader, RadianceCacheKeys) {
    const SurfaceFiles f;
    const Scene off = f.load(R"({"surfaces": [{"type": "sphere"}]})");
    EXPECT_FALSE(off.settings.radianceCache.enabled);
    EXPECT_FALSE(Effects::of(off).radianceCache);
    const Scene on = f.load(R"({"surfaces": [{"type": "sphere"}],
        "render": {"radiance_cache": {"enabled": true, "accuracy": 0.1, "hsh_order": 5,
                                      "rays_per_record": 300, "max_records": 7,
                                      "light_samples": 3}}})");
    const RadianceCacheSettings& rc = on.settings.radianceCache;
    EXPECT_TRUE(rc.enabled);
    EXPECT_EQ(rc.accuracy, 0.1);
    EXPECT_EQ(rc.hshOrder, 5);
    EXPECT_EQ(rc.raysPerRecord, 300);
    EXPECT_EQ(rc.maxRecords, 7);
    EXPECT_EQ(rc.lightSamples, 3);
    EXPECT_TRUE(Effects::of(on).radianceCache);
    // Nothing to cache on: a mirror only.
    EXPECT_FALSE(
        Effects::of(f.load(R"({"surfaces": [{"type": "sphere", "bsdf": {"type": "mirror"}}],
        "render": {"radiance_cache": {"enabled": true}}})"))
            .radianceCache);
    const std::string msg =
        test::messageOf([&] { f.load(R"({"render": {"radiance_cache": {"hsh_order": 0}}})"); });
    EXPECT_NE(msg.find("render.radiance_cache.hsh_order"), std::string::npos) << msg;
}

// Every shape's tangent (an anisotropic lobe's x axis) is its transform's x axis, scaled ones
// too; without a transform, world x.
TEST(SceneLoader, SurfacesAreOrientedByTheirTransforms) {
    const SurfaceFiles f;
    const std::string turn = R"("transform": {"rotate": {"axis": [0, 0, 1], "degrees": 90},
                                              "scale": [2, 3, 1]})";
    const Scene s = f.load(R"({"surfaces": [
        {"type": "mesh", "file": "box.obj", )" +
                           turn + R"(},
        {"type": "sphere", "transform": {"rotate": {"axis": [0, 0, 1], "degrees": 90}}},
        {"type": "rectangle", )" +
                           turn + R"(},
        {"type": "disk", "transform": {"rotate": {"axis": [0, 0, 1], "degrees": 90}}},
        {"type": "sphere"}]})");
    const std::vector<Surface>& v = s.surfaces->surfaces();
    for (int i : {0, 1, 2, 3}) {
        EXPECT_NEAR((v[i].tangent - Vec3(0, 1, 0)).norm(), 0, 1e-12) << i;
        EXPECT_NEAR((v[i].tangentY - Vec3(-1, 0, 0)).norm(), 0, 1e-12) << i;
    }
    EXPECT_EQ(v[4].tangent, Vec3(1, 0, 0));
}

TEST(SceneLoader, MediumBoundedByAClosedSurface) {
    const SurfaceFiles f;
    const Scene s = f.load(R"({
      "surfaces": [{"type": "mesh", "file": "inward.obj", "name": "glass",
                    "bsdf": {"type": "dielectric"}}],
      "media": [{"type": "homogeneous", "sigma_t": 2, "boundary": "glass"}]})");
    const Surface& glass = s.surfaces->surfaces()[0];
    EXPECT_EQ(glass.interiorMedium, 0);
    EXPECT_GT(signedVolume(glass.mesh), 0);  // turned outwards
    // By index, an integral number however written (0.0 was "expected a string"; helper 74).
    EXPECT_EQ(f.load(R"({"surfaces": [{"type": "mesh", "file": "inward.obj", "name": "glass",
                                       "bsdf": {"type": "dielectric"}}],
                         "media": [{"type": "homogeneous", "boundary": 0.0}]})")
                  .surfaces->surfaces()[0]
                  .interiorMedium,
              0);
    EXPECT_TRUE(Effects::of(s).boundedMedia);
    EXPECT_EQ(s.media[0]->describe(), "homogeneous (inside its boundary)");
    // A closed glass mesh without a medium faces outwards too, flat-shaded or not (its faces
    // meet at positions, not at shared vertices: it was refused as a boundary, "not closed", and
    // left facing inwards as glass).
    for (const char* file : {"inward.obj", "inward_flat.obj"}) {
        EXPECT_GT(signedVolume(f.load(R"({"surfaces": [{"type": "mesh", "file": ")" +
                                      std::string(file) + R"(", "bsdf": {"type": "dielectric"}}]})")
                                   .surfaces->surfaces()[0]
                                   .mesh),
                  0)
            << file;
        EXPECT_GT(signedVolume(f.load(R"({"surfaces": [{"type": "mesh", "file": ")" +
                                      std::string(file) + R"(", "name": "glass",
                    "bsdf": {"type": "dielectric"}}],
                    "media": [{"type": "homogeneous", "boundary": "glass"}]})")
                                   .surfaces->surfaces()[0]
                                   .mesh),
                  0)
            << file;
    }
    // A one-sided emitter turned outwards still emits from the side its file's winding gave
    // (inwards here): turned with its winding, a camera inside saw it dark.
    for (const char* media : {"", R"(, "media": [{"type": "homogeneous", "boundary": 0}])"}) {
        const Scene lit = f.load(R"({"surfaces": [{"type": "mesh", "file": "inward.obj",
            "bsdf": {"type": ")" +
                                 std::string(*media ? "null" : "dielectric") +
                                 R"("}, "emission": 1}])" + media + "}");
        const Surface& sf = lit.surfaces->surfaces()[0];
        ASSERT_GT(signedVolume(sf.mesh), 0) << media;
        const uint32_t* t = &sf.mesh.indices[0];
        const Vec3 ng = (sf.mesh.p[t[1]] - sf.mesh.p[t[0]])
                            .cross(sf.mesh.p[t[2]] - sf.mesh.p[t[0]])
                            .normalized();         // outwards now
        EXPECT_EQ(sf.Le(ng, -ng)[0], 1) << media;  // towards the inside
        EXPECT_EQ(sf.Le(ng, ng)[0], 0) << media;
    }
    // Shell by shell: a second part facing inwards beside one facing outwards is turned alone
    // (the mesh was turned as a whole by its total volume, negative here, which left the first
    // part inside out: as a boundary, its medium filled all space behind it).
    for (const char* media : {"", R"(, "media": [{"type": "homogeneous", "boundary": 0}])"}) {
        const Scene two =
            f.load(R"({"surfaces": [{"type": "mesh", "file": "mixed.obj",
            "bsdf": {"type": ")" +
                   std::string(*media ? "null" : "dielectric") + R"("}}])" + media + "}");
        const TriangleMesh& m = two.surfaces->surfaces()[0].mesh;
        EXPECT_EQ(meshSolidity(m).inwardFaces.size(), 0u) << media;
        EXPECT_NEAR(signedVolume(m), 1.0 / 6 + 8.0 / 6, 1e-12) << media;
    }
    // A one-sided emitter cannot be turned shell by shell.
    const std::string mixedLamp = test::messageOf([&] {
        f.load(R"({"surfaces": [{"type": "mesh", "file": "mixed.obj", "name": "lamp",
                "bsdf": {"type": "null"}, "emission": 1}],
                "media": [{"type": "homogeneous", "boundary": 0}]})");
    });
    EXPECT_NE(mixedLamp.find("media[0].boundary: lamp: some of its shells face inwards and "
                             "others outwards"),
              std::string::npos)
        << mixedLamp;
    // By index too.
    EXPECT_EQ(f.load(R"({"surfaces": [{"type": "sphere", "bsdf": {"type": "null"}}],
                         "media": [{"type": "homogeneous", "boundary": 0}]})")
                  .surfaces->surfaces()[0]
                  .interiorMedium,
              0);
}

TEST(SceneLoader, BadSurfacesGiveOneLineNamingThePlace) {
    const SurfaceFiles f;
    auto message = [&](const std::string& json) { return test::messageOf([&] { f.load(json); }); };
    auto expectIn = [](const std::string& msg, const std::string& part) {
        EXPECT_NE(msg.find(part), std::string::npos) << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    };
    expectIn(message(R"({"surfaces": [{"type": "mesh", "file": "missing.obj"}]})"), "missing.obj");
    // (The mesh's file and line too: the place was the loader's triangle.)
    const std::string open = message(R"({"surfaces": [{"type": "mesh", "file": "open.obj",
                          "bsdf": {"type": "null"}}],
                         "media": [{"type": "homogeneous", "boundary": 0}]})");
    expectIn(open, "scene.json: media[0].boundary: surfaces[0]: /");
    expectIn(open, "/open.obj: line 5: edge");
    expectIn(message(R"({"surfaces": [{"type": "rectangle", "bsdf": {"type": "null"}}],
                         "media": [{"type": "homogeneous", "boundary": 0}]})"),
             "media[0].boundary: surfaces[0] is not a closed shape");
    expectIn(message(R"({"surfaces": [{"type": "sphere"}],
                         "media": [{"type": "homogeneous", "boundary": 0}]})"),
             "a medium boundary must be \"null\" or \"dielectric\"");
    expectIn(message(R"({"surfaces": [{"type": "sphere", "bsdf": {"type": "null"}}],
                         "media": [{"type": "homogeneous", "boundary": "glass"}]})"),
             "media[0].boundary: no surface is named \"glass\"");
    expectIn(message(R"({"surfaces": [{"type": "sphere", "bsdf": {"type": "null"}}],
                         "media": [{"type": "homogeneous", "boundary": 0},
                                   {"type": "homogeneous", "boundary": 0}]})"),
             "media[1].boundary: surfaces[0] already bounds another medium");
    expectIn(message(R"({"surfaces": [{"type": "sphere", "name": "a"},
                                      {"type": "sphere", "name": "a"}]})"),
             "surfaces[1].name: \"a\" is also the name of surfaces[0]");
    expectIn(message(R"({"surfaces": [{"type": "sphere",
                          "bsdf": {"type": "ward", "alpha": 0.2, "alpha_y": 0.3}}]})"),
             "surfaces[0].bsdf.alpha: give alpha (isotropic) or alpha_x and alpha_y, not both");
    {  // 64 bounded media at most (the integrator's inside set has 64 bits)
        Json doc = Json::parse(R"({"surfaces": [], "media": []})");
        for (int i = 0; i < 65; ++i) {
            doc["surfaces"].push_back(
                {{"type", "sphere"}, {"center", {3 * i, 0, 0}}, {"bsdf", {{"type", "null"}}}});
            doc["media"].push_back({{"type", "homogeneous"}, {"boundary", i}});
        }
        expectIn(message(doc.dump()), "media[64].boundary: more than 64 media have a boundary");
        doc["media"].erase(64);
        EXPECT_EQ(message(doc.dump()), "(no error)");
    }
    expectIn(message(R"({"surfaces": [{"bsdf": {"type": "phong", "diffuse": 0.6,
                                                 "specular": 0.6}, "file": "box.obj"}]})"),
             "surfaces[0].bsdf.specular: diffuse + specular exceeds 1 (0.6 + 0.6)");
    expectIn(message(R"({"surfaces": [{"bsdf": {"type": "ward", "diffuse": [0.2, 0.7, 0.1],
                                                 "specular": 0.5}, "file": "box.obj"}]})"),
             "surfaces[0].bsdf.specular: diffuse + specular exceeds 1 (0.7 + 0.5 in channel g)");
    expectIn(message(R"({"surfaces": [{"type": "disk", "transform": {"scale": [1, 2, 1]}}]})"),
             "surfaces[0].transform: a disk needs the same scale along x and y");
    expectIn(message(R"({"surfaces": [{"type": "sphere", "transform": {"scale": [1, 2, 1]}}]})"),
             "surfaces[0].transform: a sphere needs a uniform scale");
    expectIn(message(R"({"surfaces": [{"type": "cone"}]})"), "surfaces[0].type: unknown value");
    expectIn(message(R"({"surfaces": [{"type": "sphere", "bsdf": {"type": "lambert",
                                                                   "reflectance": 1.5}}]})"),
             "surfaces[0].bsdf.reflectance");
    expectIn(message(R"({"surfaces": [{"type": "sphere", "emission": -1}]})"),
             "surfaces[0].emission: value -1 out of range (expected ≥ 0)");
    expectIn(message(R"({"media": [{"type": "homogeneous", "boundary": 0}]})"),
             "media[0].boundary: the scene has no surfaces");
    // Beyond the ray tracer's range (±1e15, after the transform).
    expectIn(message(R"({"surfaces": [{"file": "box.obj", "transform": {"scale": 1e12,
                                                                   "translate": [1e15, 0, 0]}}]})"),
             "scene.json: surfaces[0].file: ");
    // ... at the mesh's first vertex beyond it (an OBJ vertex is named by the first f line that
    // uses it; the key alone named neither file nor vertex: helper 161).
    expectIn(message(R"({"surfaces": [{"file": "box.obj", "transform": {"scale": 1e12,
                                                                   "translate": [1e15, 0, 0]}}]})"),
             "box.obj: line 9, after the surface's transform: coordinates reach 1.001e+15, "
             "beyond ±1e15");
    // A triangle the transform flattens is named at the file's place (it was "face 0").
    std::ofstream(f.dir + "/thin.obj") << "v 0 0 0\nv 2 0 0\nv 1 0 0.1\nf 1 2 3\n";
    const std::string thin = R"({"surfaces": [{"file": "thin.obj", "transform": {"scale": )";
    EXPECT_EQ(message(thin + "[1, 1, 1e-3]}}]}"), "(no error)");
    expectIn(message(thin + "[1, 1, 1e-12]}}]}"),
             "/thin.obj: line 4, after the surface's transform: zero area (collinear vertices): "
             "degenerate triangle");
    // With the scene and the surface (the mesh file's place alone said neither; helper 143).
    expectIn(message(thin + "[1, 1, 1e-12]}}]}"), "scene.json: surfaces[0].file: ");
    expectIn(message(R"({"surfaces": [{"type": "rectangle", "transform": {"scale": 1e12,
                                       "translate": [0, -1e15, 0]}}]})"),
             "scene.json: surfaces[0]: coordinates reach 1.001e+15, beyond ±1e15");
    expectIn(message(R"({"surfaces": [{"type": "sphere", "center": [0, 0, 2e15]}]})"),
             "scene.json: surfaces[0]: coordinates reach 2e+15, beyond ±1e15");
    EXPECT_EQ(message(R"({"surfaces": [{"type": "sphere", "center": [0, 0, 9e14]}]})"),
              "(no error)");
}

// Range errors print their bounds as a reader would write them (2^53 in full, no 1e30 sentinel),
// and a key of another type of the same object says which type takes it.
TEST(SceneLoader, ErrorsNameBoundsAndTheTypeAKeyBelongsTo) {
    const SurfaceFiles f;
    auto expectMessage = [&](const std::string& json, const std::string& part) {
        const std::string msg = test::messageOf([&] { f.load(json); });
        EXPECT_NE(msg.find(part), std::string::npos) << msg;
    };
    expectMessage(R"({"render": {"seed": -1}})",
                  "render.seed: value -1 out of range [0, 9007199254740992]");
    // The camera within the ray tracer's range, a rotation's angle bounded (media vanished
    // beyond 1e16; 1e308° was a rotation of NaN; helper 73).
    expectMessage(R"({"camera": {"position": [0, -1e17, 0]}})",
                  "camera.position[1]: value -1e17 out of range [-1e15, 1e15]");
    expectMessage(R"({"camera": {"target": [0, 0, 2e15]}})",
                  "camera.target[2]: value 2e15 out of range [-1e15, 1e15]");
    expectMessage(R"({"media": [{"type": "homogeneous", "shape": {"max": [1, 1, 1e300]}}]})",
                  "media[0].shape.max[2]: value 1e300 out of range [-1e15, 1e15]");
    expectMessage(
        R"({"media": [{"type": "homogeneous", "shape": {"type": "sphere", "center": [-3e16, 0, 0]}}]})",
        "media[0].shape.center[0]: value -3e16 out of range [-1e15, 1e15]");
    expectMessage(
        R"({"surfaces": [{"type": "sphere", "transform": {"rotate": {"degrees": 1e308}}}]})",
        "surfaces[0].transform.rotate.degrees: value 1e308 out of range [-1e6, 1e6]");
    // The resolution takes integral numbers however written, as integer keys do (4.0 was refused;
    // helper 74), and only those.
    const Scene res = f.load(R"({"camera": {"resolution": [4.0, 3e0]}})");
    EXPECT_EQ(res.camera.width, 4);
    EXPECT_EQ(res.camera.height, 3);
    for (const char* bad : {"[4.5, 3]", "[0, 3]", "[16385, 3]", "[4]", "[\"4\", 3]", "[1e300, 3]"})
        expectMessage(std::string(R"({"camera": {"resolution": )") + bad + "}}",
                      "camera.resolution: expected [width, height], integers in [1, 16384]");
    expectMessage(R"({"render": {"max_depth": 2000000}})",
                  "render.max_depth: value 2000000 out of range [0, 1048576]");
    // Integers beyond 2^53 are compared and written exactly (as doubles they would round: 2^53 + 1
    // to 2^53, which is in range).
    expectMessage(R"({"render": {"seed": 9007199254740993}})",
                  "render.seed: value 9007199254740993 out of range [0, 9007199254740992]");
    // Written with a fraction or an exponent, the same digits read as the double 2^53, in range:
    // refused too (they rendered as seed 2^53; helper 127), as is 2^53 itself written so, and
    // from 2^52 on, where a fraction is lost (helper 129). Below 2^52 a seed written so is read as
    // the double nearest to it (exact for the whole numbers there).
    for (const auto& [seed, read] : {std::pair{"9007199254740993.0", "9.007199254740992e+15"},
                                     std::pair{"9007199254740993e0", "9.007199254740992e+15"},
                                     std::pair{"9007199254740992.0", "9.007199254740992e+15"},
                                     std::pair{"4503599627370496.5", "4.503599627370496e+15"}})
        expectMessage(
            std::string(R"({"render": {"seed": )") + seed + "}}",
            std::string("render.seed: ") + kWrittenAsADouble + " (it reads as " + read + ")");
    Scene below =
        sceneFromJson(Json::parse(R"({"render": {"seed": 4503599627370495.0}})"), "s.json");
    EXPECT_EQ(below.settings.seed, 4503599627370495ull);
    expectMessage(R"({"render": {"max_depth": 100000000000000001}})",
                  "render.max_depth: value 100000000000000001 out of range [0, 1048576]");
    expectMessage(R"({"environment": {"type": "constant", "radiance": [1, -0.5, 1]}})",
                  "environment.radiance[1]: value -0.5 out of range (expected ≥ 0)");
    expectMessage(R"({"media": [{"type": "homogeneous", "albedo": 1.5}]})",
                  "media[0].albedo: value 1.5 out of range [0, 1]");
    expectMessage(R"({"surfaces": [{"type": "rectangle", "transform": {"scale": 1e300}}]})",
                  "surfaces[0].transform.scale: value 1e300 out of range [1e-12, 1e12]");
    expectMessage(R"({"surfaces": [{"type": "rectangle", "transform": {"scale": [1, 0, 1]}}]})",
                  "surfaces[0].transform.scale[1]: value 0 out of range [1e-12, 1e12]");
    // (A translation of 1e308 overflowed the grid's inverse transform, and the error named the
    // .vdb file.)
    expectMessage(R"({"surfaces": [{"type": "rectangle",
                                    "transform": {"translate": [0, 1e308, 0]}}]})",
                  "surfaces[0].transform.translate[1]: value 1e308 out of range [-1e15, 1e15]");
    // The cap of an unbounded range (1e30) is said only to a value beyond it.
    expectMessage(R"({"environment": {"type": "constant", "radiance": [1, 2e30, 1]}})",
                  "environment.radiance[1]: value 2e30 out of range (expected at most 1e30)");
    expectMessage(R"({"camera": {"up": [0, 0, 0]}})", "camera.up: is the zero vector");
    // Either key may be the wrong one: the message names both (helper 122).
    expectMessage(R"({"camera": {"position": [0, 0, 0], "target": [0, 0, 0]}})",
                  "camera.target: equals camera.position: the camera looks nowhere");
    // Far cameras are refused by their range (they were refused when the view direction
    // overflowed, and accepted below that, where a medium vanished); a long up vector is taken
    // without overflowing its norm.
    expectMessage(R"({"camera": {"position": [0, -1.7e308, 0], "target": [0, 1.7e308, 0]}})",
                  "camera.position[1]: value -1.7e308 out of range [-1e15, 1e15]");
    expectMessage(R"({"camera": {"position": [0, -1e15, 0], "up": [0, 1e300, 0]}})",
                  "camera.up: is parallel to the viewing direction");
    expectMessage(R"({"environment": {"type": "constant", "scale": 2}})",
                  "environment.scale: only with \"type\": \"image\"");
    expectMessage(
        R"({"media": [{"type": "homogeneous", "shape": {"type": "sphere"}, "majorant_cell": 4}]})",
        "media[0].majorant_cell: only with \"type\": \"vdb\"");
    expectMessage(
        R"({"media": [{"type": "homogeneous", "shape": {"type": "sphere"}, "regular_tracking": false}]})",
        "media[0].regular_tracking: only with \"type\": \"vdb\"");
    expectMessage(
        R"({"media": [{"type": "homogeneous", "shape": {"type": "sphere"}, "transform": {"scale": 2}}]})",
        "media[0].transform: only with \"type\": \"vdb\"");
    expectMessage(R"({"media": [{"type": "vdb", "file": ")" + std::string(SHVOL_SOURCE_DIR) +
                      R"(/media/cloud.vdb", "sigma_t": 2}]})",
                  "media[0].sigma_t: only with \"type\": \"homogeneous\"");
    expectMessage(
        R"({"media": [{"type": "homogeneous", "shape": {"type": "sphere"}, "nonsense": 2}]})",
        "media[0].nonsense: unknown key");
}

// checkScene reads every key as sceneFromJson does, with its errors, but not the grid, the sky
// image or a mesh: files that exist but are not a .vdb, an .exr or a .ply pass the check and fail
// the load.
TEST(SceneLoader, CheckSceneReadsKeysNotGridsSkiesOrMeshes) {
    using test::messageOf;
    const std::string dir = test::privateTempPath("");
    std::filesystem::create_directories(dir);
    for (const char* f : {"cloud.vdb", "sunsky.exr", "bad.ply"})
        std::ofstream(dir + "/" + f) << "not a file";
    const std::string path = dir + "/s.json";
    Json doc = sceneDocument(kSunlitCloud);
    EXPECT_EQ(messageOf([&] { checkScene(doc, path); }), "(no error)");
    EXPECT_NE(messageOf([&] { sceneFromJson(doc, path); }).find("sunsky.exr: not a readable"),
              std::string::npos);
    doc["environment"] = Json{{"type", "constant"}};
    EXPECT_EQ(messageOf([&] { checkScene(doc, path); }), "(no error)");
    EXPECT_NE(messageOf([&] { sceneFromJson(doc, path); }).find("cloud.vdb: not a readable"),
              std::string::npos);
    // Nor a mesh: not even to see whether one bounding a medium is closed.
    const Json meshes = Json::parse(R"({"surfaces": [{"type": "mesh", "file": "bad.ply",
                                                      "bsdf": {"type": "null"}}],
                                        "media": [{"type": "homogeneous", "boundary": 0}]})");
    EXPECT_EQ(messageOf([&] { checkScene(meshes, path); }), "(no error)");
    EXPECT_NE(messageOf([&] { sceneFromJson(meshes, path); }).find("bad.ply"), std::string::npos);

    // The same message as the load's, for a key, a range and a missing file.
    // (A scale of 1e-300 once passed the check and made the grid's transform singular at load.)
    for (const std::string set :
         {"media[0].nosuch=1", "media[0].albedo=2", "environment.file=\"none.exr\"", "render.spp=0",
          "media[0].transform.scale=1e-300", "media[0].transform.translate=[1e308,0,0]"}) {
        const Json bad = sceneDocument(kSunlitCloud, {set});
        const std::string message = messageOf([&] { checkScene(bad, kSunlitCloud); });
        EXPECT_NE(message, "(no error)") << set;
        EXPECT_EQ(message, messageOf([&] { sceneFromJson(bad, kSunlitCloud); })) << set;
    }
}

}  // namespace shvol
