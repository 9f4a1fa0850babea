// shvol make-medium and shvol make-sky: procedural inputs written through OpenVDB and OpenEXR.
#include <cstdio>

#include "commands.h"
#include "shvol/core/error.h"
#include "shvol/io/exr.h"
#include "shvol/io/procedural.h"
#include "shvol/io/vdb.h"

namespace shvol::app {

namespace {
struct MediumArgs {
    std::string kind = "cloud", output, grid = "density";
    int resolution = 96;
    unsigned long long seed = 1;
    int octaves = 5;
    double frequency = 4, coverage = 0.1, radius = 0.45;
};
}  // namespace

void addMakeMediumCommand(CLI::App& app, std::function<int()>& run) {
    auto a = std::make_shared<MediumArgs>();
    CLI::App* c = app.add_subcommand("make-medium", "Write a procedural density grid (.vdb)");
    c->add_option("kind", a->kind, "cloud (fBm noise) or sphere")
        ->check(CLI::IsMember({"cloud", "sphere"}))
        ->required();
    c->add_option("-o,--output", a->output, "Output .vdb file")->required();
    c->add_option("--resolution", a->resolution, "Voxels per axis over the unit cube")
        ->check(CLI::Range(4, 1024));
    c->add_option("--grid", a->grid, "Grid name");
    c->add_option("--seed", a->seed, "Noise seed (cloud)");
    c->add_option("--octaves", a->octaves, "fBm octaves (cloud)")->check(CLI::Range(1, 12));
    c->add_option("--frequency", a->frequency, "Base noise frequency (cloud)");
    c->add_option("--coverage", a->coverage, "Cloud coverage offset (cloud)");
    c->add_option("--radius", a->radius, "Radius in the unit cube (sphere)")
        ->check(CLI::Range(0.0, 0.5));
    c->callback([&run, a] {
        run = [a] {
            VdbGridSpec s;
            s.name = a->grid;
            s.resolution = a->resolution;
            if (a->kind == "cloud") {
                CloudParams p;
                p.seed = a->seed, p.octaves = a->octaves, p.frequency = a->frequency;
                p.coverage = a->coverage;
                s.density = [p](const Vec3& x) { return float(cloudDensity(x, p)); };
            } else {
                const double edge = 1.0 / a->resolution, r = a->radius;
                s.density = [=](const Vec3& x) { return float(sphereDensity(x, r, edge)); };
            }
            const size_t n = writeVdb(a->output, {s});
            std::fprintf(stderr, "wrote %s: %s grid '%s', %d^3, %zu active voxels\n",
                         a->output.c_str(), a->kind.c_str(), a->grid.c_str(), a->resolution, n);
            return 0;
        };
    });
}

void addMakeSkyCommand(CLI::App& app, std::function<int()>& run) {
    auto p = std::make_shared<SkyParams>();
    auto out = std::make_shared<std::string>();
    CLI::App* c = app.add_subcommand("make-sky", "Write a procedural lat-long sky (.exr)");
    c->add_option("-o,--output", *out, "Output .exr file")->required();
    c->add_option("--width", p->width, "Width in pixels (height = width/2)")
        ->check(CLI::Range(8, 16384));
    c->add_option("--sun-elevation", p->sunElevationDegrees, "Sun elevation in degrees");
    c->add_option("--sun-azimuth", p->sunAzimuthDegrees, "Sun azimuth in degrees (from +x to +y)");
    c->add_option("--sun-radiance", p->sunRadiance, "Radiance inside the sun disc");
    c->add_option("--sun-radius", p->sunAngularRadius, "Sun angular radius in radians");
    c->callback([&run, p, out] {
        run = [p, out] {
            p->height = p->width / 2;
            writeExr(*out, makeSky(*p));
            std::fprintf(stderr, "wrote %s: %dx%d sky\n", out->c_str(), p->width, p->height);
            return 0;
        };
    });
}

}  // namespace shvol::app
