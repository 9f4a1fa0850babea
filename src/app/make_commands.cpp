// shvol make-medium and shvol make-sky: procedural inputs written through OpenVDB and OpenEXR.
#include <cmath>
#include <cstdio>

#include "commands.h"
#include "shvol/core/error.h"
#include "shvol/core/thread_arena.h"
#include "shvol/io/exr.h"
#include "shvol/io/procedural.h"
#include "shvol/io/vdb.h"

namespace shvol::app {

namespace {
struct MediumArgs {
    std::string kind, output, grid = "density";  // (kind: required, so no default)
    int resolution = 96, threads = 0;
    unsigned long long seed = 1;
    int octaves = 5;
    double frequency = 4, coverage = 0.1, radius = 0.45;
};
}  // namespace

void addMakeMediumCommand(CLI::App& app, std::function<int()>& run) {
    auto a = std::make_shared<MediumArgs>();
    CLI::App* c = app.add_subcommand("make-medium", "Write a procedural density grid (.vdb)");
    c->add_option("kind", a->kind,
                  "cloud (fBm noise), plume (a sparse rising smoke column) or sphere")
        ->check(CLI::IsMember({"cloud", "plume", "sphere"}))
        ->required();
    c->add_option("-o,--output", a->output, "Output .vdb file")
        ->required()
        ->check(outputNamed(".vdb", "make-medium writes OpenVDB"));
    c->add_option("--resolution", a->resolution, "Voxels per axis over the unit cube")
        ->transform(integerIn(4, 1024));
    c->add_option("--threads", a->threads, "Worker threads (0: all cores)")
        ->transform(integerIn(0, 4096));
    c->add_option("--grid", a->grid, "Grid name")
        ->check(CLI::Validator(
            [](std::string& name) -> std::string {
                if (name.empty()) return "a grid needs a name";
                // (a newline in it made every later message naming the grid two lines; helper 77)
                for (const char c : name)
                    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
                        return "a control character in the grid name";
                return "";
            },
            "NAME"));
    // Each kind's own options, and which kinds take them (a note says when one has no effect).
    const std::vector<std::pair<CLI::Option*, std::string>> kindOptions = {
        {c->add_option("--seed", a->seed, "Noise seed (cloud, plume)")
             ->transform(integerIn(0, kMaxSeed)),
         "cloud plume"},
        {c->add_option("--octaves", a->octaves, "fBm octaves (cloud)")->transform(integerIn(1, 12)),
         "cloud"},
        {c->add_option("--frequency", a->frequency, "Base noise frequency (cloud)")
             ->check(numberIn(0, 1000, true)),
         "cloud"},
        {c->add_option("--coverage", a->coverage, "Cloud coverage offset (cloud)")
             ->check(numberIn(-1, 1)),
         "cloud"},
        {c->add_option("--radius", a->radius, "Radius in the unit cube (sphere)")
             ->check(numberIn(0.0, 0.5)),
         "sphere"}};
    c->callback([&run, a, kindOptions] {
        for (const auto& [option, kinds] : kindOptions)
            if (option->count() > 0 && kinds.find(a->kind) == std::string::npos)
                std::fprintf(stderr, "shvol: note: %s has no effect with %s\n",
                             option->get_name().c_str(), a->kind.c_str());
        run = [a] {
            VdbGridSpec s;
            s.name = a->grid;
            s.resolution = a->resolution;
            if (a->kind == "cloud") {
                CloudParams p;
                p.seed = a->seed, p.octaves = a->octaves, p.frequency = a->frequency;
                p.coverage = a->coverage;
                s.density = [p](const Vec3& x) { return float(cloudDensity(x, p)); };
            } else if (a->kind == "plume") {
                const uint64_t seed = a->seed;
                s.density = [seed](const Vec3& x) { return float(plumeDensity(x, seed)); };
            } else {
                const double edge = 1.0 / a->resolution, r = a->radius;
                s.density = [=](const Vec3& x) { return float(sphereDensity(x, r, edge)); };
            }
            // A grid with no density renders as nothing: refuse it before writing a file.
            VdbGridSummary made;
            const auto refuseEmpty = [&](const std::vector<VdbGridSummary>& grids) {
                made = grids.front();
                if (made.activeVoxels == 0)
                    fail(a->output, "",
                         std::string("the grid would be empty (no voxel has density > 0); raise ") +
                             (a->kind == "cloud"    ? "--coverage"
                              : a->kind == "sphere" ? "--radius"
                                                    : "--resolution"));
            };
            ThreadArena arena(a->threads);
            size_t n = 0;
            arena.execute([&] { n = writeVdb(a->output, {s}, refuseEmpty, true); });
            const double box = (made.hi - made.lo + Eigen::Vector3i::Ones()).cast<double>().prod();
            std::fprintf(stderr,
                         "wrote %s: %s grid '%s', %d^3, %zu active voxels, %.1f%% of their "
                         "bounding box\n",
                         a->output.c_str(), a->kind.c_str(), a->grid.c_str(), a->resolution, n,
                         100.0 * double(n) / box);
            return 0;
        };
    });
}

namespace {
struct SkyArgs {
    SkyParams params;
    std::string output, model = "simple", mapping = "blender";
    double sunRadiance = 0, sunRadius = 0;
};
}  // namespace

void addMakeSkyCommand(CLI::App& app, std::function<int()>& run) {
    auto a = std::make_shared<SkyArgs>();
    SkyParams& p = a->params;
    CLI::App* c = app.add_subcommand("make-sky", "Write a procedural lat-long sky (.exr)");
    c->add_option("-o,--output", a->output, "Output .exr file")
        ->required()
        ->check(outputNamed(".exr", "make-sky writes OpenEXR"));
    c->add_option("--model", a->model,
                  "simple (gradient sky, arbitrary units) or preetham (Preetham et al. 1999 "
                  "clear sky and a physical sun, kcd/m^2)")
        ->check(CLI::IsMember({"simple", "preetham"}));
    c->add_option("--mapping", a->mapping,
                  "Lat-long convention: blender (default) or shvol (mirrored)")
        ->check(CLI::IsMember({"blender", "shvol"}));
    c->add_option("--width", p.width, "Width in pixels (height = width/2)")
        ->transform(integerIn(8, 16384));
    c->add_option("--sun-elevation", p.sunElevationDegrees, "Sun elevation in degrees")
        ->check(numberIn(-90, 90, false, " degrees"));
    c->add_option("--sun-azimuth", p.sunAzimuthDegrees,
                  "Sun azimuth in degrees, from +x towards +y (world space)")
        ->check(numberIn(-360, 360, false, " degrees"));
    c->add_option("--turbidity", p.turbidity, "Atmospheric turbidity T (preetham), 2 to 10")
        ->check(numberIn(2, 10, false, ""));
    c->add_option("--sun-radiance", a->sunRadiance,
                  "Radiance inside the sun disc (preetham: its luminance in kcd/m^2; default: "
                  "physical)")
        ->check(numberIn(0, 1e30, true, ""))  // (the cap of every radiance: describeSky)
        ->default_str("the model's");
    c->add_option("--sun-radius", a->sunRadius,
                  "Sun angular radius in radians (default: 0.02 simple, 0.004625 preetham)")
        ->check(numberIn(0, 0.5, true, " rad"))
        ->default_str("the model's");
    c->callback([&run, a, c] {
        const bool radianceGiven = c->count("--sun-radiance") > 0;
        const bool radiusGiven = c->count("--sun-radius") > 0;
        const bool turbidityGiven = c->count("--turbidity") > 0;
        run = [a, radianceGiven, radiusGiven, turbidityGiven] {
            SkyParams& p = a->params;
            p.model = skyModelFromName(a->model);
            p.mapping = latLongMappingFromName(a->mapping);
            if (p.width % 2)
                failOption("--width",
                           "must be even (the height is width/2), got " + std::to_string(p.width));
            p.height = p.width / 2;
            if (radianceGiven) p.sunRadiance = a->sunRadiance;
            if (radiusGiven) p.sunAngularRadius = a->sunRadius;
            const SkySummary s = describeSky(p);
            writeExr(a->output, makeSky(p));
            const bool preetham = p.model == SkyModel::Preetham;
            const char* unit = preetham ? " kcd/m^2" : "";
            std::fprintf(stderr, "wrote %s: %dx%d %s sky, %s mapping", a->output.c_str(), p.width,
                         p.height, skyModelName(p.model), latLongMappingName(p.mapping));
            if (preetham) std::fprintf(stderr, ", turbidity %g", p.turbidity);
            std::fprintf(stderr, "\n  sun: elevation %g deg, azimuth %g deg, radius %g rad%s\n",
                         p.sunElevationDegrees, p.sunAzimuthDegrees, s.sunAngularRadius,
                         preetham && !radiusGiven ? " (true size)" : "");
            std::fprintf(stderr, "  sun radiance (luminance) %.4g%s%s; zenith %.4g%s; ",
                         s.sunLuminance, unit,
                         !preetham       ? ""
                         : radianceGiven ? " (given)"
                         : radiusGiven   ? " (physical illuminance over this disc)"
                                         : " (physical)",
                         s.zenithLuminance, unit);
            std::fprintf(stderr, "sun/zenith ratio %.4g; ground %.4g%s\n",
                         s.sunLuminance / s.zenithLuminance,
                         0.2126 * s.groundRadiance[0] + 0.7152 * s.groundRadiance[1] +
                             0.0722 * s.groundRadiance[2],
                         unit);
            if (p.sunElevationDegrees < 0)
                std::fprintf(stderr, "  note: %s\n",
                             preetham ? "the Preetham model does not cover twilight; the sky is "
                                        "that of a sun on the horizon and the disc is below the "
                                        "ground"
                                      : "the simple model's ground does not hide the sun: its "
                                        "disc is drawn below the horizon");
            if (!preetham && turbidityGiven)
                std::fprintf(stderr, "  note: --turbidity has no effect with --model simple\n");
            return 0;
        };
    });
}

}  // namespace shvol::app
