// shvol bench: throughput on a scene, with and without the majorant grid, 1 and 2 threads.
#include <cstdio>
#include <filesystem>

#include "commands.h"
#include "shvol/core/error.h"
#include "shvol/io/scene_loader.h"
#include "shvol/render/renderer.h"

namespace shvol::app {

namespace {
struct BenchArgs {
    std::string scene = "media/default.json";
    int spp = 4, repeats = 1;
    std::vector<std::string> sets;
};

struct Row {
    std::string name;
    double pathsPerSecond, lookupsPerPath;
};

Row measure(const BenchArgs& a, const std::string& name, bool grid, int threads) {
    std::vector<std::string> sets = a.sets;
    sets.push_back("render.spp=" + std::to_string(a.spp));
    const Json doc = parseJsonFile(a.scene);
    if (doc.contains("media"))
        for (size_t i = 0; i < doc["media"].size(); ++i)
            if (doc["media"][i].value("type", "vdb") == "vdb")
                sets.push_back("media." + std::to_string(i) +
                               ".majorant_grid=" + (grid ? "true" : "false"));
    const Scene scene = loadScene(a.scene, sets);
    double best = 0, lookups = 0;
    for (int r = 0; r < a.repeats; ++r) {
        RenderOptions opt;
        opt.threads = threads;
        const RenderResult res = render(scene, opt);
        best = std::max(best, res.stats.pathsPerSecond());
        lookups = double(res.stats.counters.tracking.densityLookups) / res.stats.counters.paths;
    }
    std::fprintf(stderr, "  %-28s %12.0f paths/s\n", name.c_str(), best);
    return {name, best, lookups};
}
/// media/default.json in the current directory, else in the program's source tree.
std::string defaultBenchScene() {
    if (std::filesystem::exists("media/default.json")) return "media/default.json";
    const std::string p = sourceTreePath("media/default.json");
    if (p.empty())
        fail("media/default.json", "",
             "no scene given, and the default scene is neither in the current directory nor in "
             "the source tree of this program; give a scene file");
    return p;
}
}  // namespace

void addBenchCommand(CLI::App& app, std::function<int()>& run) {
    auto a = std::make_shared<BenchArgs>();
    CLI::App* c = app.add_subcommand(
        "bench", "Throughput on a scene: majorant grid vs one global majorant, 2 vs 1 threads");
    c->add_option("scene", a->scene,
                  "Scene file (default: media/default.json here, else in the source tree of this "
                  "shvol program)");
    c->add_option("--spp", a->spp, "Samples per pixel per measurement")
        ->check(integerIn(1, 1 << 24));
    c->add_option("--repeats", a->repeats, "Repeat each measurement, keep the best")
        ->check(integerIn(1, 1000));
    c->add_option("--set", a->sets, "Override a scene value: key.path=value (repeatable)")
        ->default_str("");
    c->callback([&run, a, c] {
        run = [a, c] {
            if (c->count("scene") == 0) a->scene = defaultBenchScene();
            std::fprintf(stderr, "shvol bench %s (%d spp)\n", a->scene.c_str(), a->spp);
            const Row g1 = measure(*a, "majorant grid, 1 thread", true, 1);
            const Row n1 = measure(*a, "global majorant, 1 thread", false, 1);
            const Row g2 = measure(*a, "majorant grid, 2 threads", true, 2);
            std::printf("| configuration | paths/s | density lookups/path |\n|---|---:|---:|\n");
            for (const Row& r : {g1, n1, g2})
                std::printf("| %s | %.0f | %.1f |\n", r.name.c_str(), r.pathsPerSecond,
                            r.lookupsPerPath);
            std::printf("\nmajorant grid / global majorant (1 thread): %.2fx\n",
                        g1.pathsPerSecond / n1.pathsPerSecond);
            std::printf("2 threads / 1 thread (majorant grid): %.2fx\n",
                        g2.pathsPerSecond / g1.pathsPerSecond);
            return 0;
        };
    });
}

}  // namespace shvol::app
