// shvol bench: what a path costs on a scene and what accuracy costs in time (README, "shvol
// bench"): throughput with each of the hot loop's choices switched back (majorant grid, brick
// lookups, threads), the cost of one density lookup, and, with --accuracy, RMSE·√spp and the time
// to reach an RMSE ε against a cached converged reference, for the renderer before issue 11's
// changes and now.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <Eigen/QR>

#include "commands.h"
#include "shvol/core/error.h"
#include "shvol/core/hash.h"
#include "shvol/core/image_metrics.h"
#include "shvol/io/exr.h"
#include "shvol/io/provenance.h"
#include "shvol/io/scene_loader.h"
#include "shvol/render/renderer.h"
#include "shvol/render/scene.h"

namespace shvol::app {

namespace {
struct BenchArgs {
    std::string scene = "media/default.json", cache = ".";
    int spp = 4, repeats = 1, referenceSpp = 4096;
    double epsilon = 0.003;
    bool accuracy = false, cellSweep = false;
    std::vector<std::string> sets;
};

/// `sets` plus `key=value` for every VDB medium of the scene.
std::vector<std::string> withVdbKey(const Json& doc, std::vector<std::string> sets,
                                    const std::string& key, const std::string& value) {
    if (doc.contains("media"))
        for (size_t i = 0; i < doc["media"].size(); ++i)
            if (doc["media"][i].value("type", "vdb") == "vdb")
                sets.push_back("media[" + std::to_string(i) + "]." + key + "=" + value);
    return sets;
}

struct Row {
    std::string name;
    std::string medium;  ///< the first VDB medium's describe(): what was measured
    double pathsPerSecond = 0, lookupsPerPath = 0, segmentsPerPath = 0, cellsPerPath = 0,
           secondsPerSpp = 0;
    std::vector<double> rounds;  ///< paths/s of each round (pathsPerSecond is the best)
    Image image;
};

/// "a / b" in paths/s as "1.97x", the ratio of the two rows' best rounds, followed with more than
/// one round by the range of the ratios round by round ("1.97x (rounds 1.85-2.05x)"): the rounds
/// interleave the configurations, so a round's ratio is a same-run ratio too, and their spread
/// shows part of the machine's noise (README: not all of it). The best-of ratio always lies within
/// that range: the round of a's best gives a ratio at least as large, the round of b's best one at
/// least as small.
std::string ratioText(const Row& a, const Row& b) {
    char text[96];
    std::snprintf(text, sizeof text, "%.2fx", a.pathsPerSecond / b.pathsPerSecond);
    if (a.rounds.size() < 2 || a.rounds.size() != b.rounds.size()) return text;
    double lo = INFINITY, hi = -INFINITY;
    for (size_t r = 0; r < a.rounds.size(); ++r)
        lo = std::min(lo, a.rounds[r] / b.rounds[r]), hi = std::max(hi, a.rounds[r] / b.rounds[r]);
    char range[64];
    std::snprintf(range, sizeof range, " (rounds %.2f-%.2fx)", lo, hi);
    return text + std::string(range);
}

/// A timed render shorter than this (its best round) is warned of.
constexpr double kShortestMeasuredMs = 10;

/// One configuration to measure: the scene with `sets` on `threads` threads.
struct Config {
    std::string name;
    std::vector<std::string> sets;
    int threads = 1;
};

/// Renders every configuration at `spp`, `repeats` rounds of one render each in turn, and keeps
/// each one's best. The rounds interleave the configurations, so a drift of the machine's speed
/// (a shared host) reaches every configuration alike and the same-run ratios keep their meaning.
/// A configuration's scene is loaded for each of its renders (loading is not timed), so one
/// scene is in memory at a time. An untimed render of the first configuration comes first: the
/// first timed render would otherwise pay for the cold caches and the first touch of the files
/// and the code, which the others do not.
std::vector<Row> measure(const BenchArgs& a, const std::vector<Config>& configs, int spp) {
    std::vector<Row> rows(configs.size());
    for (size_t i = 0; i < configs.size(); ++i) rows[i].name = configs[i].name;
    for (int r = -1; r < a.repeats; ++r)
        for (size_t i = 0; i < configs.size() && (r >= 0 || i == 0); ++i) {
            std::vector<std::string> sets = configs[i].sets;
            sets.push_back("render.spp=" + std::to_string(spp));
            const Scene scene = loadScene(a.scene, sets);
            RenderOptions opt;
            opt.threads = configs[i].threads;
            RenderResult res = render(scene, opt);
            if (r < 0) continue;  // the warm-up
            const PathCounters& c = res.stats.counters;
            Row& row = rows[i];
            row.rounds.push_back(res.stats.pathsPerSecond());
            for (const auto& m : scene.media)  // the first VDB medium: what --cell-sweep sets
                if (row.medium.empty() && m->describe().rfind("vdb ", 0) == 0)
                    row.medium = m->describe();
            if (res.stats.pathsPerSecond() > row.pathsPerSecond) {
                row.pathsPerSecond = res.stats.pathsPerSecond();
                row.secondsPerSpp = res.stats.wallSeconds / spp;
                row.image = std::move(res.image);
            }
            row.lookupsPerPath = double(c.tracking.densityLookups) / double(c.paths);
            row.segmentsPerPath = double(c.tracking.segments) / double(c.paths);
            row.cellsPerPath = double(c.tracking.exactCells) / double(c.paths);
        }
    for (const Row& row : rows)
        std::fprintf(stderr, "  %-34s %12.0f paths/s\n", row.name.c_str(), row.pathsPerSecond);
    // Renders of a few milliseconds time the scheduler and the first touch of memory more than
    // the paths: helper 84's 8×6 pixels at 1 spp read 118 k, 148 k and 11 k paths/s in three
    // runs, and a 9.3× ratio that was 1.06× at 64×48.
    const auto ms = [&](const Row& row) { return 1e3 * row.secondsPerSpp * spp; };
    const auto shortest = std::min_element(
        rows.begin(), rows.end(), [&](const Row& p, const Row& q) { return ms(p) < ms(q); });
    if (shortest != rows.end() && ms(*shortest) < kShortestMeasuredMs)
        std::fprintf(
            stderr,
            "shvol: warning: bench: %zu of %zu configurations rendered in under %g ms "
            "(\"%s\" in %.2g ms): timings that short are noise; raise --spp or the "
            "resolution\n",
            size_t(std::count_if(rows.begin(), rows.end(),
                                 [&](const Row& r) { return ms(r) < kShortestMeasuredMs; })),
            rows.size(), kShortestMeasuredMs, shortest->name.c_str(), ms(*shortest));
    return rows;
}

/// Nanoseconds per σ_t lookup of the first medium (Medium::sigmaT, with its transform and
/// majorant check) at 2^20 points of its majorant-positive region, best of three.
double nsPerLookup(const BenchArgs& a, const std::vector<std::string>& sets) {
    const Scene scene = loadScene(a.scene, sets);
    if (scene.media.empty()) return 0;
    const Medium& m = *scene.media[0];
    std::vector<Vec3> pts;
    Rng rng(7, 7);
    for (int tries = 0; pts.size() < 4096 && tries < 1 << 22; ++tries) {
        const Vec3 p = 4 * Vec3(rng.uniform(), rng.uniform(), rng.uniform()) - Vec3::Constant(2);
        if (m.sigmaMajorant(p) > 0) pts.push_back(p);
    }
    if (pts.empty()) return 0;
    double best = INFINITY, sink = 0;
    for (int r = 0; r < 3; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        for (int i = 0; i < 1 << 20; ++i) sink += m.sigmaT(pts[size_t(i) % pts.size()]);
        best = std::min(
            best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    volatile double keep = sink;  // the lookups must happen
    (void)keep;
    return best * 1e9 / double(1 << 20);
}

/// The table rows of `rows`: paths/s, ns per path, density lookups, majorant segments and cells
/// crossed by regular tracking per path.
void printRows(const std::vector<Row>& rows) {
    std::printf(
        "| configuration | paths/s | ns/path | density lookups/path | majorant segments/path | "
        "regular-tracking cells/path |\n"
        "|---|---:|---:|---:|---:|---:|\n");
    for (const Row& r : rows)
        std::printf("| %s | %.0f | %.1f | %.2f | %.2f | %.2f |\n", r.name.c_str(), r.pathsPerSecond,
                    1e9 / r.pathsPerSecond, r.lookupsPerPath, r.segmentsPerPath, r.cellsPerPath);
}

/// --cell-sweep: the defaults with majorant cells of 1, 2, 4, 8 and 16 voxels (1 thread), and a
/// least-squares fit over them of ns per path = shared + a·(lookups per path) + b·(segments per
/// path). The shared part is what no majorant structure changes at this lookup cost, so (global
/// majorant's ns per path, measured in the same rounds) / shared bounds what any of them can buy
/// over one global majorant on whole paths. The fit's RMS residual shows how far to trust it.
void cellSweep(const BenchArgs& a, const Json& doc) {
    const std::vector<int> cells = {1, 2, 4, 8, 16};
    auto label = [](int cell) {
        return "majorant cells of " + std::to_string(cell) + (cell == 1 ? " voxel" : " voxels");
    };
    std::vector<Config> configs;
    for (int cell : cells)
        configs.push_back({label(cell) + ", 1 thread",
                           withVdbKey(doc, a.sets, "majorant_cell", std::to_string(cell)), 1});
    if (configs[0].sets.size() == a.sets.size()) {
        std::printf("\nno VDB medium: no majorant cell sweep\n");
        return;
    }
    configs.push_back(
        {"global majorant, 1 thread", withVdbKey(doc, a.sets, "majorant_grid", "false"), 1});
    std::vector<Row> rows = measure(a, configs, a.spp);
    const Row global = rows.back();
    rows.pop_back();
    // A cell the loader doubled (at most 2^22 cells per grid) is named by the size it has.
    for (size_t i = 0; i < rows.size(); ++i) {
        const size_t at = rows[i].medium.find("majorant cells of ");
        if (at == std::string::npos) continue;  // (a global majorant set by --set)
        const int got = std::atoi(rows[i].medium.c_str() + at + 18);
        if (got != cells[i])
            rows[i].name = label(got) + " (" + std::to_string(cells[i]) +
                           " asked; at most 2^22 cells), 1 thread";
    }
    std::printf("\n");
    printRows(rows);
    Eigen::MatrixXd A(rows.size(), 3);
    Eigen::VectorXd ns(rows.size());
    for (size_t i = 0; i < rows.size(); ++i) {
        A.row(Eigen::Index(i)) << 1, rows[i].lookupsPerPath, rows[i].segmentsPerPath;
        ns(Eigen::Index(i)) = 1e9 / rows[i].pathsPerSecond;
    }
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(A);
    if (qr.rank() < 3) {
        std::printf("the cell sizes do not separate lookups from segments: no fit\n");
        return;
    }
    const Eigen::VectorXd x = qr.solve(ns);
    std::printf(
        "ns per path fitted over the cell sizes (1 thread): %.1f shared + %.1f per density "
        "lookup + %.1f per majorant segment (RMS residual %.1f ns)\n",
        x(0), x(1), x(2), std::sqrt((A * x - ns).squaredNorm() / double(rows.size())));
    const double globalNs = 1e9 / global.pathsPerSecond;
    std::printf(
        "most any majorant structure can buy over the global majorant on whole paths at "
        "this lookup cost: ");
    if (x(0) > 0)
        std::printf("%.2fx (%.1f / %.1f ns per path)\n", globalNs / x(0), globalNs, x(0));
    else
        std::printf("n/a (the fitted shared part is not positive)\n");
}

/// The converged reference for the scene after `sets`: rendered once at referenceSpp with its
/// own seed and cached in the cache directory under a hash of the scene document and of the
/// contents of the files it names (a changed .vdb renders a new reference).
Image reference(const BenchArgs& a, std::vector<std::string> sets) {
    sets.push_back("render.spp=" + std::to_string(a.referenceSpp));
    sets.push_back("render.seed=1000000000");
    const Json doc = sceneDocument(a.scene, sets);
    const std::string text = dumpJson(doc) + "\n" + namedFileContents(inputFiles(doc, a.scene));
    const std::string file =
        (std::filesystem::path(a.cache) /
         ("shvol_bench_reference_" + hexHash(fnv1a(text.data(), text.size())) + ".exr"))
            .string();
    if (std::filesystem::exists(file)) {
        // A cached reference that cannot be read (damaged, of another size) is rendered again.
        try {
            Image ref = readExr(file);
            const Camera camera = checkScene(doc, a.scene);
            if (ref.width == camera.width && ref.height == camera.height) {
                std::fprintf(stderr, "  reference: %s (cached)\n", file.c_str());
                return ref;
            }
            std::fprintf(stderr, "shvol: warning: %s: %d x %d pixels, not the scene's\n",
                         file.c_str(), ref.width, ref.height);
        } catch (const Error& e) {
            std::fprintf(stderr, "shvol: warning: %s\n", e.what());
        }
        std::fprintf(stderr, "shvol: the cached reference is rendered again\n");
    }
    std::fprintf(stderr, "  reference: rendering %d spp into %s\n", a.referenceSpp, file.c_str());
    const RenderResult r = render(loadScene(a.scene, sets), RenderOptions{});
    writeExr(file, r.image);
    return r.image;
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

/// A --set of what the bench sets itself: the sample count (its --spp, applied after the sets),
/// or a VDB medium's key that its rows vary. Taken, it was replaced without a word, or it made
/// both sides of a named ratio one configuration ("majorant grid / global majorant: 0.95x" with
/// majorant_grid false on both).
void refuseSetsTheBenchMakes(const BenchArgs& a) {
    std::vector<std::string> varied = {"lookup", "decomposition", "regular_tracking",
                                       "majorant_grid"};
    if (a.cellSweep) varied.push_back("majorant_cell");
    if (const std::string* set = overrideSetting(a.sets, {"render", "spp"}))
        failOption("--set", *set + ": the bench renders at --spp; give the sample count there");
    for (const std::string& name : varied)
        if (const std::string* set = overrideSetting(a.sets, {"media", "*", name}))
            failOption("--set", *set + ": the bench varies " + name +
                                    " itself (README.md, \"bench\"); leave it to the scene");
}

int runBench(BenchArgs& a) {
    refuseSetsTheBenchMakes(a);
    const Json doc = sceneDocument(a.scene, a.sets);
    checkScene(doc, a.scene);  // a bad value fails now, not after the table is printed
    if (a.accuracy) {          // (before the first line is printed: an error is one line)
        std::error_code ec;
        std::filesystem::create_directories(a.cache, ec);
        if (ec || !std::filesystem::is_directory(a.cache))
            failOption("--cache", a.cache + ": cannot make the directory" +
                                      (ec ? " (" + ec.message() + ")" : std::string()));
    }
    // As a batch warns of its rendered reference: the figures measured mostly the reference's
    // noise, without a word (helper 130).
    if (a.accuracy && a.referenceSpp < 10 * double(a.spp))
        std::fprintf(stderr,
                     "shvol: warning: --reference-spp %d: fewer than 10 times --spp (%d): the "
                     "reference's own noise adds about %.0f%% to each renderer's MSE, counted as "
                     "its error; give the reference more samples\n",
                     a.referenceSpp, a.spp, 100.0 * a.spp / a.referenceSpp);
    std::fprintf(stderr, "shvol bench %s (%d spp)\n", a.scene.c_str(), a.spp);
    // With --accuracy: read or rendered now, not after minutes of timings.
    const Image ref = a.accuracy ? reference(a, a.sets) : Image();
    const std::vector<std::string> vdbLookups = withVdbKey(doc, a.sets, "lookup", "\"openvdb\"");
    // Without a VDB medium the lookup, tracking and majorant configurations are the defaults'
    // render: they are not measured, and no ratio of noise is printed (helper 72).
    const bool vdb = vdbLookups.size() > a.sets.size();
    std::vector<Config> configs = {{"defaults, 1 thread", a.sets, 1}};
    if (vdb)
        configs.insert(
            configs.end(),
            {{"OpenVDB lookups, 1 thread", vdbLookups, 1},
             {"no decomposition, 1 thread", withVdbKey(doc, a.sets, "decomposition", "false"), 1},
             {"no regular tracking, 1 thread", withVdbKey(doc, a.sets, "regular_tracking", "false"),
              1},
             {"global majorant, 1 thread", withVdbKey(doc, a.sets, "majorant_grid", "false"), 1},
             {"global majorant, OpenVDB lookups, 1 thread",
              withVdbKey(doc, vdbLookups, "majorant_grid", "false"), 1}});
    const size_t twoThreads = configs.size();
    configs.push_back({"defaults, 2 threads", a.sets, 2});
    // The floor: what a path costs when no medium is there (camera, surfaces, lights, sky).
    const bool media = doc.contains("media") && !doc["media"].empty();
    if (media) {
        configs.push_back({"without media, 1 thread", a.sets, 1});
        configs.back().sets.push_back("media=[]");
    }
    const std::vector<Row> rows = measure(a, configs, a.spp);
    const Row &now = rows[0], &two = rows[twoThreads];
    printRows(rows);
    auto ratio = [](const char* what, const Row& a, const Row& b) {
        std::printf("%s: %s\n", what, ratioText(a, b).c_str());
    };
    // A method switched off that the scene never used: the two rendered the same image with the
    // same counts, the same work, and their ratio is timing noise, which was printed as a
    // speed-up (helper 77: regular tracking on the default cloud, "1.22x", then "0.80x").
    auto methodRatio = [&](const char* what, const Row& a, const Row& b) {
        if (a.image.rgb == b.image.rgb && a.lookupsPerPath == b.lookupsPerPath &&
            a.segmentsPerPath == b.segmentsPerPath && a.cellsPerPath == b.cellsPerPath)
            std::printf("%s: n/a (unused here: equal images and counts per path)\n", what);
        else
            ratio(what, a, b);
    };
    if (const double ns = nsPerLookup(a, a.sets); ns > 0) {  // (0: no medium to look up)
        std::printf("\nns per density lookup (Medium::sigmaT): %s%.1f", vdb ? "bricks " : "", ns);
        if (vdb) std::printf(", OpenVDB accessor %.1f", nsPerLookup(a, vdbLookups));
        std::printf("\n");
    }
    if (!vdb)
        std::printf("no VDB medium: no lookup, tracking or majorant configurations to compare\n");
    else {
        const Row &openvdb = rows[1], &plain = rows[2], &tentative = rows[3], &global = rows[4],
                  &globalVdb = rows[5];
        ratio("bricks / OpenVDB lookups (1 thread)", now, openvdb);
        methodRatio("decomposition / plain delta and ratio tracking (1 thread)", now, plain);
        methodRatio("regular tracking where preferred / tentative collisions only (1 thread)", now,
                    tentative);
        ratio("majorant grid / global majorant (1 thread)", now, global);
        // What the grid saves grows with the cost of a lookup: OpenVDB is what a grid too large for
        // bricks uses, and what every grid used before issue 11.
        ratio("majorant grid / global majorant, both with OpenVDB lookups (1 thread)", openvdb,
              globalVdb);
        if (media) {
            // Time per path above the floor: what the media add to a path (none, within noise, when
            // the media cost no more than the floor).
            const double floor = 1 / rows.back().pathsPerSecond,
                         grid = 1 / now.pathsPerSecond - floor,
                         one = 1 / global.pathsPerSecond - floor;
            std::printf("majorant grid / global majorant, time above the floor (1 thread): ");
            if (grid > 0 && one > 0)
                std::printf("%.2fx (%.1f vs %.1f ns per path)\n", one / grid, 1e9 * grid,
                            1e9 * one);
            else
                std::printf("n/a (the media add no measurable time to a path)\n");
        }
    }
    ratio("2 threads / 1 thread", two, now);
    if (a.cellSweep) cellSweep(a, doc);
    if (!a.accuracy) return 0;

    // Before issue 11: NEE toward every sky, independent numbers, OpenVDB lookups, plain delta
    // and ratio tracking, Russian roulette on the throughput.
    std::vector<std::string> before = withVdbKey(
        doc, withVdbKey(doc, vdbLookups, "decomposition", "false"), "regular_tracking", "false");
    before.push_back("render.nee=true");
    before.push_back("render.sampler=\"independent\"");
    before.push_back("render.rr_threshold=1");
    const std::vector<Row> timed =
        measure(a,
                {{"before (NEE, independent, OpenVDB, delta, RR θ = 1), 2 threads", before, 2},
                 {"now (defaults), 2 threads", a.sets, 2}},
                a.spp);
    const Row &b = timed[0], &n = timed[1];
    std::printf(
        "\n| renderer | ms per spp | RMSE | RMSE·√spp | time to RMSE %g |\n"
        "|---|---:|---:|---:|---:|\n",
        a.epsilon);
    double timeTo[2];
    for (int i = 0; i < 2; ++i) {
        const Row& r = i ? n : b;
        const double rmse = imageMetrics(r.image, ref).rmse, k = rmse * std::sqrt(a.spp);
        timeTo[i] = (k / a.epsilon) * (k / a.epsilon) * r.secondsPerSpp;
        // (%.3g: one decimal printed 0.0 s beside a ratio of 3.64x at small settings; helper 122)
        std::printf("| %s | %.2f | %.4g | %.4g | %.3g s |\n", r.name.c_str(), 1e3 * r.secondsPerSpp,
                    rmse, k, timeTo[i]);
    }
    // (An RMSE of 0, a scene the reference matches exactly, gives no time to compare.)
    if (timeTo[1] > 0)
        std::printf(
            "time to equal RMSE, before / now: %.2fx (the reference's own noise, %d spp, is "
            "in every RMSE)\n",
            timeTo[0] / timeTo[1], a.referenceSpp);
    else
        std::printf("time to equal RMSE, before / now: n/a (an RMSE of 0 against the reference)\n");
    return 0;
}
}  // namespace

void addBenchCommand(CLI::App& app, std::function<int()>& run) {
    auto a = std::make_shared<BenchArgs>();
    CLI::App* c = app.add_subcommand(
        "bench",
        "Cost per path on a scene (majorant grid, brick lookups, threads) and, with --accuracy, "
        "time to an RMSE of the defaults against the renderer before its performance work (NEE "
        "toward every sky, independent numbers, OpenVDB lookups, plain tracking, roulette on the "
        "throughput)");
    c->add_option("scene", a->scene,
                  "Scene file (default: media/default.json here, else in the source tree of this "
                  "shvol program)")
        ->check(nonEmptyName())
        ->check(notAStrayOverride());
    c->add_option("--spp", a->spp, "Samples per pixel per measurement")
        ->transform(integerIn(1, kMaxSpp));
    c->add_option("--repeats", a->repeats,
                  "Rounds of the measurements, each configuration once per round in turn; the "
                  "best of each is kept")
        ->transform(integerIn(1, 1000));
    addSetOption(c, a->sets);
    CLI::Option* accuracy =
        c->add_flag("--accuracy", a->accuracy,
                    "Also measure RMSE against a converged reference (rendered once, cached)");
    c->add_flag(
        "--cell-sweep", a->cellSweep,
        "Also measure majorant cells of 1, 2, 4, 8 and 16 voxels and split ns per path into a "
        "shared part and costs per density lookup and per majorant segment");
    // (Options of --accuracy only: without it they would be silently ignored.)
    c->add_option("--reference-spp", a->referenceSpp, "Samples per pixel of the reference")
        ->transform(integerIn(1, kMaxSpp))
        ->needs(accuracy);
    c->add_option("--epsilon", a->epsilon, "The RMSE whose time is reported")
        ->check(numberIn(0, 1e30, true))
        ->needs(accuracy);
    c->add_option("--cache", a->cache, "Directory of cached references (made if missing)")
        ->check(nonEmptyName())
        ->needs(accuracy);
    c->callback([&run, a, c] {
        run = [a, c] {
            if (c->count("scene") == 0) a->scene = defaultBenchScene();
            return runBench(*a);
        };
    });
}

}  // namespace shvol::app
