// The hard-case suite (issue 10 §2): scenes at the edges of what the renderer must survive —
// optical depths from 1e−6 to 1e6, albedo 1 with ~1e5 bounces per path, g = ±0.999999, a 1e6×
// hot environment pixel, a black environment, empty and zero-density grids, transforms scaled by
// 1e−6 and 1e6, a camera inside a medium, rays grazing a box face. Every case is rendered through
// the scene loader and the renderer as a user would, and must have no NaN/Inf pixel and no
// unusable draw (InvalidDraws: a NaN or negative pdf, value, distance or transmittance); where an
// analytic answer exists the image mean must match it within 5 standard errors of the pixel
// mean (plus 1e−6 relative for float output), and where only bounds exist every pixel must lie
// within them.
//
// Usage: validate_hardcases [--check] [--quick] [--out TABLE.md]
//   --check  exit 1 if a case fails (ctest runs `validate_hardcases --check --quick`)
//   --quick  fewer samples (the cases are the same)
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "shvol/io/exr.h"
#include "shvol/io/json_reader.h"
#include "shvol/io/scene_loader.h"
#include "shvol/io/vdb.h"
#include "shvol/render/renderer.h"

using namespace shvol;
namespace fs = std::filesystem;

namespace {

struct Case {
    std::string group, name;
    Json scene;
    std::optional<double> expected;        ///< analytic image mean (every pixel has it)
    double lo = -INFINITY, hi = INFINITY;  ///< bounds every pixel must respect
};

struct Outcome {
    double mean = 0, se = 0, min = 0, max = 0, seconds = 0, pathLength = 0;
    long long samples = 0;
    long long nonFinite = 0;
    uint64_t invalidDraws = 0;  ///< InvalidDraws::total()
    bool pass = false;
};

Json orthoDown(double extent, int res, int spp) {  // looks along −z from z = 5 at the origin
    return {{"camera",
             {{"type", "orthographic"},
              {"position", {0, 0, 5}},
              {"target", {0, 0, 0}},
              {"up", {0, 1, 0}},
              {"extent", extent},
              {"resolution", {res, res}}}},
            {"render", {{"spp", spp}, {"max_depth", 1 << 20}}},
            {"environment", {{"type", "constant"}, {"radiance", 1}}}};
}

/// Perspective camera at `distance` on −y looking at the origin, with a field of view that keeps
/// every pixel on a ball of `radius` about the origin.
Json lookingAtBall(double distance, double radius, int res, int spp) {
    const double fov = 2 * std::asin(0.6 * radius / distance) * 180 / M_PI;
    return {{"camera",
             {{"position", {0, -distance, 0}},
              {"target", {0, 0, 0}},
              {"up", {0, 0, 1}},
              {"fov", fov},
              {"resolution", {res, res}}}},
            {"render", {{"spp", spp}, {"max_depth", 1 << 20}}},
            {"environment", {{"type", "constant"}, {"radiance", 1}}}};
}

Json homogeneousSphere(double sigmaT, double albedo, const Json& phase,
                       const std::string& estimator = "analytic") {
    return {{"type", "homogeneous"},  {"sigma_t", sigmaT},
            {"albedo", albedo},       {"phase", phase},
            {"estimator", estimator}, {"shape", {{"type", "sphere"}, {"radius", 1}}}};
}

Json iso() {
    return {{"type", "isotropic"}};
}

Outcome run(const Case& c) {
    Outcome o;
    const Scene scene = sceneFromJson(c.scene, c.group + "/" + c.name);
    const auto t0 = std::chrono::steady_clock::now();
    const RenderResult r = render(scene, RenderOptions{});
    o.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    o.pathLength = r.stats.meanPathLength();
    const ImageStatistics st = imageStatistics(r.image);
    o.nonFinite = st.nonFinite + (long long)r.stats.counters.nonFiniteSamples;
    o.mean = st.mean[0], o.min = st.min[0], o.max = st.max[0];
    double s2 = 0;
    const size_t n = r.image.rgb.size() / 3;
    for (size_t i = 0; i < n; ++i) s2 += std::pow(r.image.rgb[3 * i] - o.mean, 2);
    o.se = n > 1 ? std::sqrt(s2 / (n - 1) / n) : 0;
    o.samples = (long long)n * scene.settings.spp;
    o.invalidDraws = r.stats.counters.invalid.total();
    o.pass = o.nonFinite == 0 && o.invalidDraws == 0 && o.min >= c.lo && o.max <= c.hi;
    if (c.expected) {
        // A [0, 1]-valued estimator of mean e has variance at most e(1 − e): a floor for the
        // measured standard error, which is 0 when every sample happened to agree (delta tracking
        // through τ = 1e−6 returns 1 on all 576 samples of the quick run).
        const double e = *c.expected;
        const double floor = e > 0 && e < 1 ? std::sqrt(e * (1 - e) / o.samples) : 0.0;
        o.pass = o.pass && std::abs(o.mean - e) <= 5 * std::max(o.se, floor) + 1e-6 * e + 1e-30;
    }
    return o;
}

std::string number(double x) {
    char b[32];
    std::snprintf(b, sizeof b, "%.6g", x);
    return b;
}

}  // namespace

int main(int argc, char** argv) {
    bool check = false, quick = false;
    std::string out;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--check")
            check = true;
        else if (a == "--quick")
            quick = true;
        else if (a == "--out" && i + 1 < argc)
            out = argv[++i];
        else {
            std::fprintf(stderr,
                         "usage: validate_hardcases [--check] [--quick] [--out TABLE.md]\n");
            return 2;
        }
    }
    const int spp = quick ? 16 : 128;
    const fs::path dir =
        fs::temp_directory_path() / ("shvol_hardcases_" + std::to_string(getpid()));
    fs::create_directories(dir);
    // Grids: a block of density 1 filling the cube [−½, ½]³, a ball, and an empty grid.
    const std::string block = (dir / "block.vdb").string(), ball = (dir / "ball.vdb").string(),
                      empty = (dir / "empty.vdb").string();
    writeVdb(block, {{"density", VdbGridSpec::Type::Float, 16, [](const Vec3&) { return 1.f; }}});
    writeVdb(ball, {{"density", VdbGridSpec::Type::Float, 32,
                     [](const Vec3& p) { return p.norm() < 0.45 ? 1.f : 0.f; }}});
    writeVdb(empty, {{"density", VdbGridSpec::Type::Float, 8, [](const Vec3&) { return 0.f; }}});
    // An environment of 1 with one pixel 1e6 times brighter.
    const std::string hot = (dir / "hot.exr").string();
    {
        Image img(64, 32);
        for (int y = 0; y < 32; ++y)
            for (int x = 0; x < 64; ++x)
                img.set(x, y, Spectrum::Constant(x == 20 && y == 9 ? 1e6 : 1.0));
        writeExr(hot, img);
    }

    std::vector<Case> cases;
    // Absorbing slab z ∈ [−½, ½] seen from above: every pixel is e^{−τ}.
    for (double tau : {1e-6, 1e-3, 1.0, 10.0, 100.0, 1e3, 1e6})
        for (const char* est : {"analytic", "tracking"}) {
            Json s = orthoDown(1, 6, spp);
            s["media"] = Json::array(
                {{{"type", "homogeneous"},
                  {"sigma_t", tau},
                  {"albedo", 0},
                  {"estimator", est},
                  {"shape", {{"type", "box"}, {"min", {-2, -2, -0.5}}, {"max", {2, 2, 0.5}}}}}});
            cases.push_back({"optical depth", std::string(est) + " slab, tau " + number(tau), s,
                             std::exp(-tau)});
        }
    // The same through a VDB block (delta/ratio tracking over the majorant grid, regular tracking
    // where dense); the slab is the grid's unit cube, seen through its middle half. Rays enter
    // through the ramp of the trilinear interpolation from the background 0 to 1 over the outer
    // half voxel: at τ = 10¹², the top of density_scale's range, tentative collisions there would
    // number ~10¹¹ per ray (regular tracking crosses it in one voxel cell).
    for (double tau : {1e-6, 1.0, 100.0, 1e4, 1e6, 1e12}) {
        Json s = orthoDown(0.5, 6, spp);
        s["media"] = Json::array(
            {{{"type", "vdb"}, {"file", block}, {"density_scale", tau}, {"albedo", 0}}});
        cases.push_back({"optical depth", "vdb block, tau " + number(tau), s, std::exp(-tau)});
    }
    // White furnaces: albedo 1 under radiance 1 renders 1 for any density and phase function.
    {
        Json s = lookingAtBall(3, 1, 3, quick ? 2 : 8);
        s["render"]["nee"] = false;  // every path is exactly 1: any error is a bug, not noise
        s["media"] = Json::array({homogeneousSphere(300, 1, iso())});
        cases.push_back({"furnace", "albedo 1, tau 300, no NEE", s, 1.0});
        // From the centre of a ball of optical radius τ a diffusing path needs about τ²/2
        // scattering events to leave it (mean squared step 2/σ²): ~1e5 at τ = 450.
        s["camera"]["position"] = {0, 0, 0};
        s["camera"]["target"] = {0, 1, 0};
        s["media"] = Json::array({homogeneousSphere(450, 1, iso())});
        cases.push_back({"furnace", "albedo 1, camera at the centre of tau 450, no NEE", s, 1.0});
        s["media"] = Json::array({homogeneousSphere(60, 1, iso(), "tracking")});
        cases.push_back(
            {"furnace", "albedo 1, camera at the centre of tau 60, tracking, no NEE", s, 1.0});
    }
    for (double g : {0.999999, -0.999999}) {
        Json s = lookingAtBall(3, 1, 6, spp);
        s["media"] = Json::array({homogeneousSphere(10, 1, {{"type", "hg"}, {"g", g}})});
        cases.push_back({"furnace", "HG g " + number(g) + ", tau 10, NEE+MIS", s, 1.0});
        s["media"][0]["phase"]["sampling"] = "sh";
        cases.push_back({"furnace", "HG g " + number(g) + " SH-sampled (default keys)", s, 1.0});
    }
    for (double scale : {1e-6, 1e6}) {
        Json s = lookingAtBall(3 * scale, 0.45 * scale, 6, spp);
        s["media"] = Json::array({{{"type", "vdb"},
                                   {"file", ball},
                                   {"density_scale", 20 / scale},
                                   {"albedo", 1},
                                   {"phase", {{"type", "hg"}, {"g", 0.7}}},
                                   {"transform", {{"scale", scale}}}}});
        cases.push_back(
            {"scale", "vdb ball scaled " + number(scale) + " (tau 18), furnace", s, 1.0});
    }
    {  // the camera inside: a furnace, and an absorbing ball seen from its centre (e^{−σ·1})
        Json s = lookingAtBall(3, 1, 6, spp);
        s["camera"]["position"] = {0, 0, 0};
        s["camera"]["target"] = {0, 1, 0};
        s["camera"]["fov"] = 90;
        s["media"] = Json::array({homogeneousSphere(5, 1, {{"type", "hg"}, {"g", 0.3}})});
        cases.push_back({"camera inside", "furnace, tau 5", s, 1.0});
        s["media"] = Json::array({homogeneousSphere(2, 0, iso(), "tracking")});
        cases.push_back(
            {"camera inside", "absorbing ball sigma 2, from its centre", s, std::exp(-2.0)});
    }
    {  // environments: black gives 0 exactly; a 1e6x hot pixel stays finite
        Json s = lookingAtBall(3, 1, 6, spp);
        s["media"] = Json::array({homogeneousSphere(3, 0.9, {{"type", "hg"}, {"g", 0.5}})});
        s["environment"] = {{"type", "constant"}, {"radiance", 0}};
        cases.push_back({"environment", "black", s, 0.0});
        s["environment"] = {{"type", "image"}, {"file", hot}};
        for (const char* ls : {"environment", "product"}) {
            s["render"]["light_sampling"] = ls;
            cases.push_back({"environment", std::string("1e6x hot pixel, ") + ls + " sampling", s,
                             std::nullopt, 0.0, INFINITY});
        }
    }
    {  // grids with nothing in them: the environment shows through unchanged
        Json s = lookingAtBall(3, 0.5, 6, spp);
        s["media"] = Json::array({{{"type", "vdb"}, {"file", empty}}});
        cases.push_back({"empty media", "empty grid", s, 1.0});
        s["media"] = Json::array({{{"type", "vdb"}, {"file", ball}, {"density_scale", 0}}});
        cases.push_back({"empty media", "zero density (density_scale 0)", s, 1.0});
    }
    {  // rays along the top face z = ½ of an absorbing box, within 1e−7 of it: each pixel lies
       // between e^{−σ·2} (fully inside, 2 units of box) and 1 (fully outside)
        // One row of pixels, each straddling the face: rays within ±3e−9 of it, half of each
        // pixel's area inside (e^{−2σ}) and half outside (1).
        const double sigma = 1.5;
        for (const char* est : {"analytic", "tracking"}) {
            Json s = orthoDown(2e-7, 32, spp);
            s["camera"]["resolution"] = {32, 1};
            s["camera"]["position"] = {-5, 0, 0.5};
            s["camera"]["target"] = {0, 0, 0.5};
            s["camera"]["up"] = {0, 0, 1};
            s["media"] = Json::array(
                {{{"type", "homogeneous"},
                  {"sigma_t", sigma},
                  {"albedo", 0},
                  {"estimator", est},
                  {"shape", {{"type", "box"}, {"min", {-1, -1, -0.5}}, {"max", {1, 1, 0.5}}}}}});
            const bool exact = std::string(est) == "analytic";
            cases.push_back({"grazing", std::string(est) + " box, rays within 3e-9 of a face", s,
                             0.5 * (1 + std::exp(-2 * sigma)),
                             exact ? std::exp(-2 * sigma) * (1 - 1e-6) : 0.0, 1 + 1e-6});
        }
    }

    std::ostringstream table;
    table << "| group | case | expected | image mean ± se | min | max | non-finite | "
             "invalid draws | bounces per path | time (s) | result |\n"
             "|---|---|---|---|---|---|---|---|---|---|---|\n";
    int failed = 0;
    for (const Case& c : cases) {
        Outcome o;
        std::string error;
        try {
            o = run(c);
        } catch (const std::exception& e) {
            error = e.what();
        }
        if (!error.empty()) {
            ++failed;
            table << "| " << c.group << " | " << c.name << " | | error: " << error
                  << " | | | | | | | **FAIL** |\n";
            continue;
        }
        failed += !o.pass;
        std::string expected = c.expected ? number(*c.expected) : "";
        if (!c.expected && std::isfinite(c.lo))
            expected = "in [" + number(c.lo) + ", " + number(c.hi) + "]";
        if (!c.expected && !std::isfinite(c.lo)) expected = "finite";
        if (!c.expected && c.lo == 0 && !std::isfinite(c.hi)) expected = "finite, ≥ 0";
        table << "| " << c.group << " | " << c.name << " | " << expected << " | " << number(o.mean)
              << " ± " << number(o.se) << " | " << number(o.min) << " | " << number(o.max) << " | "
              << o.nonFinite << " | " << o.invalidDraws << " | " << number(o.pathLength) << " | "
              << number(o.seconds) << " | " << (o.pass ? "pass" : "**FAIL**") << " |\n";
        std::fprintf(stderr, "%-14s %-50s %s\n", c.group.c_str(), c.name.c_str(),
                     o.pass ? "pass" : "FAIL");
    }
    fs::remove_all(dir);
    std::printf("%s\n%zu cases, %d failed (%d spp)\n", table.str().c_str(), cases.size(), failed,
                spp);
    if (!out.empty()) std::ofstream(out) << table.str();
    return check && failed ? 1 : 0;
}
