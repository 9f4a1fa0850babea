// shvol batch SWEEP.json: runs every point of a sweep, with metrics against a reference, into a
// resumable ledger (io/sweep.h, io/ledger.h).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "commands.h"
#include "shvol/core/error.h"
#include "shvol/core/image_metrics.h"
#include "shvol/core/progress.h"
#include "shvol/io/exr.h"
#include "shvol/io/ledger.h"
#include "shvol/io/sweep.h"

namespace shvol::app {

namespace {

namespace fs = std::filesystem;

struct BatchArgs {
    std::string sweep, output;
    int threads = 0;
    bool dryRun = false, quiet = false, report = false;
};

std::string describe(const SweepRun& run) {
    std::string s = run.id;
    for (auto it = run.values.begin(); it != run.values.end(); ++it)
        s += " " + it.key() + "=" + dumpJson(it.value());
    return s;
}

Json readJson(const std::string& path) {
    std::ifstream f(path);
    return Json::parse(f);
}

/// Renders `sets` to `image` (quietly) unless a cached render with the same fingerprint exists.
/// Returns the exit code of the render (130: interrupted), 0 when cached.
int renderReference(const Sweep& s, const BatchArgs& a, bool variance) {
    const SweepReference& ref = *s.reference;
    const std::string stamp = ref.file + ".fingerprint";
    std::string want = s.scene;
    for (const std::string& x : ref.sets) want += "\n" + x;
    want += variance ? "\nvariance" : "";
    if (fs::exists(ref.file) && fs::exists(stamp)) {
        std::ifstream f(stamp);
        const std::string have((std::istreambuf_iterator<char>(f)), {});
        if (have == want) return 0;
    }
    if (!a.quiet) std::fprintf(stderr, "batch: rendering the reference %s\n", ref.file.c_str());
    RenderArgs r;
    r.scene = s.scene;
    r.output = ref.file;
    r.sets = ref.sets;
    r.threads = a.threads;
    r.quiet = a.quiet;
    r.variance = variance;
    const int code = runRender(r);
    if (code == 0) std::ofstream(stamp) << want;
    return code;
}

int runBatch(BatchArgs a) {
    Sweep s = readSweep(a.sweep);
    if (!a.output.empty()) {
        s.output = a.output;
        if (s.reference && s.reference->render)
            s.reference->file = (fs::path(s.output) / "reference.exr").string();
    }
    if (a.dryRun) {
        if (s.reference)
            std::printf("reference %s%s\n", s.reference->file.c_str(),
                        s.reference->render ? " (rendered once, cached)" : "");
        for (const SweepRun& run : s.runs) std::printf("%s\n", describe(run).c_str());
        std::printf("%zu runs into %s\n", s.runs.size(), s.output.c_str());
        return 0;
    }
    fs::create_directories(s.output);
    Ledger ledger(s.output);
    // A finished run must be the run the sweep describes now, or resuming would mix experiments.
    for (const Json& row : ledger.rows()) {
        const std::string id = row["run"].get<std::string>();
        const auto it = std::find_if(s.runs.begin(), s.runs.end(),
                                     [&](const SweepRun& r) { return r.id == id; });
        if (it == s.runs.end() || row.value("fingerprint", "") != it->fingerprint)
            fail(ledger.jsonlPath(), "run " + id,
                 it == s.runs.end()
                     ? "finished, but the sweep no longer has it; use another output directory"
                     : "finished with other settings or another scene than the sweep now gives; "
                       "use another output directory");
    }
    const bool ztest = std::find(s.metrics.begin(), s.metrics.end(), "ztest") != s.metrics.end();
    Image reference, referenceSe;
    if (s.reference) {
        if (s.reference->render) {
            if (const int code = renderReference(s, a, ztest)) return code;
        }
        reference = readExr(s.reference->file);
        if (ztest) {
            const std::string se =
                fs::path(s.reference->file).replace_extension("").string() + ".stderr.exr";
            referenceSe = fs::exists(se) ? readExr(se) : Image(reference.width, reference.height);
        }
    }

    std::vector<const SweepRun*> todo;
    for (const SweepRun& run : s.runs)
        if (!ledger.find(run.id)) todo.push_back(&run);
    if (!a.quiet && todo.size() < s.runs.size())
        std::fprintf(stderr, "batch: %zu of %zu runs already finished in %s\n",
                     s.runs.size() - todo.size(), s.runs.size(), ledger.jsonlPath().c_str());
    Progress progress("batch", (long long)todo.size(), !a.quiet && Progress::stderrIsTerminal());
    for (const SweepRun* run : todo) {
        RenderArgs r;
        r.scene = s.scene;
        r.output = (fs::path(s.output) / (run->id + ".exr")).string();
        r.sets = run->sets;
        r.threads = a.threads;
        r.quiet = true;
        r.variance = ztest;
        if (const int code = runRender(r)) {
            progress.done();
            std::fprintf(stderr, "batch: stopped; %zu runs are in %s, run again to finish\n",
                         ledger.rows().size(), ledger.jsonlPath().c_str());
            return code;
        }
        const std::string stem = fs::path(r.output).replace_extension("").string();
        const Json stats = readJson(stem + ".stats.json");
        Json row = run->values;
        row["run"] = run->id;
        row["seed"] = stats["seed"];
        row["spp"] = stats["spp"];
        row["wall_time_s"] = stats["wall_time_s"];
        row["paths_per_second"] = stats["paths_per_second"];
        row["image"] = run->id + ".exr";
        row["fingerprint"] = run->fingerprint;
        if (s.reference) {
            const Image img = readExr(r.output);
            const ImageMetrics m = imageMetrics(img, reference);
            for (const std::string& k : s.metrics) {
                if (k == "rmse") row["rmse"] = m.rmse;
                if (k == "relmse") row["relmse"] = m.relMse;
                if (k == "mae") row["mae"] = m.mae;
                if (k == "bias") row["bias"] = m.bias, row["bias_ci95"] = m.biasHalfWidth95;
                if (k == "ztest") {
                    const ZTest z =
                        zTest(img, readExr(stem + ".stderr.exr"), reference, referenceSe);
                    row["ztest_min_p"] = z.minP;
                    row["ztest_threshold"] = z.threshold;
                    row["ztest_passed"] = z.passed;
                }
            }
        }
        ledger.append(row);
        progress.advance();
        if (!a.quiet && !Progress::stderrIsTerminal())
            std::fprintf(stderr, "batch: %zu/%zu %s%s\n", ledger.rows().size(), s.runs.size(),
                         describe(*run).c_str(),
                         row.contains("rmse") ? (" rmse " + dumpJson(row["rmse"])).c_str() : "");
    }
    progress.done();
    if (!a.quiet)
        std::fprintf(stderr, "batch: %zu runs in %s and %s\n", ledger.rows().size(),
                     ledger.jsonlPath().c_str(), ledger.csvPath().c_str());
    return a.report ? runReport(s.output) : 0;
}

}  // namespace

void addBatchCommand(CLI::App& app, std::function<int()>& run) {
    auto a = std::make_shared<BatchArgs>();
    CLI::App* c = app.add_subcommand(
        "batch",
        "Run a sweep of renders into a resumable ledger, with metrics against a reference");
    c->add_option("sweep", a->sweep, "Sweep file (JSON; README.md, \"Batch experiments\")")
        ->required();
    c->add_option("--output", a->output, "Output directory")->default_str("the sweep's output");
    c->add_option("--threads", a->threads, "Worker threads per render (0: all cores)")
        ->check(integerIn(0, 4096));
    c->add_flag("--dry-run", a->dryRun, "Print one line per run and do nothing");
    c->add_flag("--quiet", a->quiet, "No progress");
    c->add_flag("--report", a->report, "Then write the report (as shvol report DIR)");
    c->callback([&run, a] { run = [a] { return runBatch(*a); }; });
}

}  // namespace shvol::app
