#include "shvol/io/scene_loader.h"

#include <gtest/gtest.h>

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
    EXPECT_EQ(resolved["environment"], Json({{"type", "constant"}, {"radiance", 0}}));
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
}

}  // namespace shvol
