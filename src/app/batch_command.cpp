// shvol batch SWEEP.json: runs every point of a sweep, with metrics against a reference, into a
// resumable ledger (io/sweep.h, io/ledger.h).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <regex>
#include <set>
#include <thread>
#include <unordered_map>

#include "commands.h"
#include "mpi_world.h"
#include "shvol/core/atomic_file.h"
#include "shvol/core/error.h"
#include "shvol/core/hash.h"
#include "shvol/core/image_metrics.h"
#include "shvol/core/interrupt.h"
#include "shvol/core/progress.h"
#include "shvol/io/checkpoint.h"
#include "shvol/io/exr.h"
#include "shvol/io/ledger.h"
#include "shvol/io/provenance.h"
#include "shvol/io/scene_loader.h"
#include "shvol/io/sweep.h"

namespace shvol::app {

namespace {

namespace fs = std::filesystem;

struct BatchArgs {
    std::string sweep, output;
    int threads = 0, jobs = 1;
    bool dryRun = false, quiet = false, report = false;
};

std::string describe(const SweepRun& run, const std::vector<std::string>& axes) {
    return run.id + " " + describeValues(run, axes);  // (values hold the repeat at least)
}

/// The standard errors beside a reference file ref.exr (ref.stderr.exr, as render --variance
/// names them), which the z-test reads when they exist.
std::string standardErrorsOf(const std::string& exr) {
    return fs::path(exr).replace_extension("").string() + ".stderr.exr";
}

/// What identifies a rendered reference: the scene document after its settings, the contents of
/// the files it names and whether it has a standard-error image; kept beside it in
/// REFERENCE.fingerprint. (Not the build: a converged reference of the same scene serves any.)
/// The files are read through `memo`, which the runs' fingerprints filled.
std::string referenceStamp(const Sweep& s, bool variance, std::map<std::string, Json>& memo) {
    const Json doc = sceneDocument(s.scene, s.reference->sets);
    // (Numbers as numbers: 38 and 38.0 are one scene; as written, a respelt number made the
    // finished rows' reference another one; helper 67.)
    return canonicalJson(doc) + "\n" + namedFileContents(inputFiles(doc, s.scene, &memo)) +
           (variance ? "variance" : "");
}

/// What REFERENCE.fingerprint holds of a rendered reference: its stamp, then the hashes of the
/// images rendered (and of its standard errors with `variance`), so that an image replaced since
/// is not taken for the rendered one (helper 67: one ledger mixed two references).
std::string referenceRecord(const std::string& stamp, const std::string& file, bool variance) {
    std::string r = stamp + "\nimage " + fileFingerprint(file)["fnv1a64"].get<std::string>();
    if (variance && fs::exists(standardErrorsOf(file)))
        r += " " + fileFingerprint(standardErrorsOf(file))["fnv1a64"].get<std::string>();
    return r;
}

/// Removes a file where there is one; one that cannot be removed is an error naming it.
void removeOrFail(const std::string& path, const std::string& what = "it") {
    if (std::error_code ec; (fs::remove(path, ec), ec))
        fail(path, "", "cannot remove " + what + " (" + ec.message() + ")");
}

/// The whole text of a file ("" if it cannot be read).
std::string fileText(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(f)), {});
}

/// Whether the rendered reference is on disk with `stamp`, the one the sweep gives now, and is
/// the image rendered for it.
bool referenceCached(const Sweep& s, const std::string& stamp, bool variance) {
    const std::string file = s.reference->file + ".fingerprint";
    return fs::exists(s.reference->file) && fs::exists(file) &&
           fileText(file) == referenceRecord(stamp, s.reference->file, variance);
}

/// "1 run", "2 runs".
std::string runsCounted(size_t n) {
    return std::to_string(n) + (n == 1 ? " run" : " runs");
}

/// What a ledger row keeps of the reference its metrics were measured against: the hash of a
/// rendered reference's stamp, or of a given reference file's contents (and its standard errors',
/// for the z-test, when there are any). A row whose reference is not the sweep's now cannot be
/// resumed into the same ledger.
std::string referenceFingerprint(const Sweep& s, const std::string& stamp, bool ztest) {
    if (s.reference->render) return hexHash(fnv1a(stamp.data(), stamp.size()));
    const std::string& file = s.reference->file;
    std::string id = fileFingerprint(file)["fnv1a64"].get<std::string>();
    const std::string se = standardErrorsOf(file);
    if (ztest && fs::exists(se)) id += "+" + fileFingerprint(se)["fnv1a64"].get<std::string>();
    return id;
}

/// The sweep's reference as it is now: a rendered reference's stamp (empty for a reference
/// file) and the fingerprint finished rows must carry (empty without a reference).
struct CurrentReference {
    std::string stamp, fingerprint;
};
CurrentReference currentReference(const Sweep& s, bool ztest, std::map<std::string, Json>& memo) {
    CurrentReference r;
    if (!s.reference) return r;
    if (s.reference->render) r.stamp = referenceStamp(s, ztest, memo);
    r.fingerprint = referenceFingerprint(s, r.stamp, ztest);
    return r;
}

/// The checkpoint one process keeps beside a rendered reference, often the sweep's longest
/// render (REFERENCE.checkpoint), which a batch started again resumes where its own stamp (the
/// reference's and the build's, which a checkpoint names) is this batch's; a Ctrl-C lost all of
/// it (helper 147). Ranks share no checkpoint (README, "MPI").
struct ReferenceCheckpoint {
    ReferenceCheckpoint(const SweepReference& ref, const std::string& referenceStamp)
        : file(ref.file + ".checkpoint"),
          stampFile(file + ".stamp"),
          stamp(referenceStamp + "\nbuild " + gitRevision() + "\n") {}
    bool resumable() const { return fs::exists(file) && fileText(stampFile) == stamp; }
    std::string file, stampFile, stamp;
};

/// Renders the reference (quietly; under mpirun every rank takes part) and stamps it with
/// `stamp` (rank 0's). Returns the exit code of the render (InterruptGuard::stopExitCode():
/// interrupted).
int renderReference(const Sweep& s, const BatchArgs& a, bool variance, const std::string& stamp) {
    const SweepReference& ref = *s.reference;
    const MpiWorld& world = MpiWorld::get();
    if (!a.quiet && world.root())
        std::fprintf(stderr, "batch: rendering the reference %s\n", ref.file.c_str());
    RenderArgs r;
    r.scene = s.scene;
    r.output = ref.file;
    r.sets = ref.sets;
    r.threads = a.threads;
    r.quiet = a.quiet;
    r.variance = variance;
    r.lateSignalStops = false;
    r.checkpointOptional = true;
    r.run = "the reference";
    // The stamp of the reference being replaced goes first: a render interrupted after writing
    // its partial image must not leave that image passing for the old, finished one.
    collectively([&] {  // (rank 0 removes it; the others wait, and fail with it)
        if (world.root()) removeOrFail(ref.file + ".fingerprint", "the old stamp");
    });
    const ReferenceCheckpoint ck(ref, stamp);
    if (world.size() == 1) {
        r.checkpoint = ck.file;
        r.resume = ck.resumable();
        if (!r.resume) {  // (another render's checkpoint must not meet this stamp)
            removeOrFail(ck.file);
            writeTextAtomically(ck.stampFile, ck.stamp);
        }
    }
    const int code = runRender(r);
    // Rank 0 stamps it (a stamp that cannot be written is an error, on every rank: failing on
    // rank 0 alone left the others waiting for it for ever; review); the others read it after.
    collectively([&] {
        if (code == 0 && world.root())
            writeTextAtomically(ref.file + ".fingerprint",
                                referenceRecord(stamp, ref.file, variance));
    });
    // Finished: a checkpoint, also one an earlier start left, has served.
    if (code == 0 && world.root()) {
        removeOrFail(ck.file);
        removeOrFail(ck.stampFile);
    }
    return code;
}

/// errorMessage(e), followed by the run of sweep `s` it stopped (whose scene the error names).
std::string errorText(const std::exception& e, const Sweep& s, const SweepRun* run) {
    const std::string text = errorMessage(e);
    return run ? text + " (in run " + describe(*run, s.axes) + ")" : text;
}

/// An error of a value (or an unknown key) that one of a run's (or the reference's) `sets` gave
/// or changed (`doc`, the scene document after them, as checked; overrideOfError), refused at the
/// sweep's key that gave it (`places`): a `set` (in every run), or an axis or the reference's own
/// `set` (in `what`). It was blamed on the scene file, "in the reference" for a `set` that every
/// run has (helpers 127, 133). Where the scene itself is to blame, it returns and the caller names
/// the scene.
void blameSweepKey(const Error& e, const Sweep& s, const Json& doc,
                   const std::vector<std::string>& sets, const std::vector<std::string>& places,
                   const std::string& what) {
    std::string reason;
    const int i = overrideOfError(e.what(), s.scene, s.sceneDoc, doc, sets, &reason);
    if (i < 0 || size_t(i) >= places.size()) return;
    const std::string& place = places[size_t(i)];
    fail(s.path, place, reason + (place.rfind("set[", 0) == 0 ? "" : " (in " + what + ")"));
}

/// Checks the scenes of every run and of a rendered reference as loading them would (checkScene:
/// keys, types, ranges, files present) before anything renders: a bad value set by an axis stops
/// the batch, or its --dry-run, at once instead of when the batch reaches that run. The error
/// names the run, as one from its render does. Runs that differ only in the seed the sweep gave
/// them (repeats; readSweep has checked those seeds) are checked once: a phase function's SH fit
/// at order 256 takes about half a second. Each run's image must have the reference's size (a
/// reference file's, read here, or the rendered reference's camera), and so must the standard
/// errors beside a reference file that the z-test reads.
void checkRunScenes(const Sweep& s) {
    std::optional<std::pair<int, int>> refSize;
    std::string refName;
    if (s.reference && s.reference->render) {
        const Json doc = runDocument(s.sceneDoc, s.scene, s.reference->sets);
        try {
            const Camera c = checkScene(doc, s.scene);
            refSize = {c.width, c.height}, refName = "the rendered reference";
        } catch (const Error& e) {
            blameSweepKey(e, s, doc, s.reference->sets, s.reference->places, "the reference");
            throw Error(std::string(e.what()) + " (in the reference)");
        }
    } else if (s.reference) {
        // (Negative values too, as `shvol diff` compares them: another renderer's filter can
        // ring below 0; helper 67. Not infinite ones: every run's metrics would be infinite,
        // null in the ledger, and refused by the report; review.)
        const Image ref = readExr(s.reference->file, ExrValues::Reference);
        refSize = {ref.width, ref.height}, refName = s.reference->file;
        const std::string se = standardErrorsOf(s.reference->file);
        if (std::count(s.metrics.begin(), s.metrics.end(), "ztest") && fs::exists(se))
            if (const Image e = readExr(se); e.width != ref.width || e.height != ref.height)
                fail(se, "",
                     "the reference's standard errors are " + std::to_string(e.width) + "x" +
                         std::to_string(e.height) + ", the reference " + s.reference->file +
                         " is " + std::to_string(ref.width) + "x" + std::to_string(ref.height));
    }
    std::set<std::string> checked;
    for (const SweepRun& run : s.runs) {
        Json doc = runDocument(s.sceneDoc, s.scene, run.sets);
        if (!run.values.contains("seed")) doc["render"]["seed"] = 1;
        if (!checked.insert(dumpJson(doc)).second) continue;
        try {
            const Camera c = checkScene(doc, s.scene);
            if (refSize && std::pair(c.width, c.height) != *refSize)
                fail(s.path, "reference",
                     refName + " is " + std::to_string(refSize->first) + "x" +
                         std::to_string(refSize->second) + ", the run's image " +
                         std::to_string(c.width) + "x" + std::to_string(c.height));
        } catch (const Error& e) {
            // (By its values: its id is not known before the ledger's finished runs have kept
            // theirs, adoptFinishedIds; helper 159.)
            const std::string which = "the run " + describeValues(run, s.axes);
            blameSweepKey(e, s, doc, run.sets, run.places, which);
            throw Error(errorMessage(e) + " (in " + which + ")");
        }
    }
}

/// The stats a finished run's render wrote (an empty object when they cannot be read).
Json savedStats(const Sweep& s, const Json& row) {
    const std::string image = row.value("image", "");
    if (image.empty()) return Json::object();
    Json saved = parseOwnJsonFile(
        (fs::path(s.output) / fs::path(image).replace_extension(".stats.json")).string());
    return saved.is_object() ? saved : Json::object();
}

/// The scene values in which a finished run (its stats' scene_resolved) and the render the sweep
/// now gives it differ, as a resumed render names them (`scene values camera.fov differ`); ""
/// when that cannot be told. (A checkpoint's identity leaves render.spp out: a render may be
/// continued to more samples; a run's sample count is compared here.)
std::string changedSettings(const Sweep& s, const SweepRun& run, const Json& row) {
    const Json saved = savedStats(s, row);
    if (!saved.contains("scene_resolved") || !saved["scene_resolved"].is_object()) return "";
    Json resolved;
    try {
        checkScene(runDocument(s.sceneDoc, s.scene, run.sets), s.scene, &resolved);
    } catch (const std::exception&) {
        return "";
    }
    // A run's stats leave out the keys its render did not use; read again, its scene has their
    // defaults, and a key given another value since is named (helper 140).
    Json was = saved["scene_resolved"];
    try {
        Json full;
        checkScene(was, s.scene, &full);
        was = std::move(full);
    } catch (const std::exception&) {  // (compared as the stats hold it)
    }
    std::string difference;
    if (const double a = sppOf(was), b = sppOf(resolved); a != b) {
        char text[96];
        std::snprintf(text, sizeof text, "render.spp was %.17g, is %.17g", a, b);
        difference = text;
    }
    const std::string rest = identityDifference(renderIdentity(was, Json::object(), ""),
                                                renderIdentity(resolved, Json::object(), ""),
                                                "seed, set or axes, or scene file");
    return difference + (difference.empty() || rest.empty() ? "" : "; ") + rest;
}

/// Which files of a finished run's scene changed since it rendered ("the file named by
/// media[0].file differs in contents"), as a resumed render says it (identityDifference), by the
/// hashes the run's stats kept; what they could be where its stats are gone (the batch named
/// none: helper 77).
std::string changedInputs(const Sweep& s, const SweepRun& run, const Json& row) {
    const std::string unknown = "which of them (grids, skies, tables, meshes) cannot be told";
    const Json saved = savedStats(s, row);
    if (!saved.contains("inputs") || !saved["inputs"].is_array()) return unknown;
    const std::string difference = identityDifference(
        renderIdentity(Json::object(), saved["inputs"], ""),
        renderIdentity(Json::object(),
                       inputFiles(runDocument(s.sceneDoc, s.scene, run.sets), s.scene), ""));
    return difference.empty() ? unknown : difference;
}

/// Warns of a reference file without standard errors beside it, which the z-test then takes as
/// exact: every difference is tested against the run's errors alone, and a reference of 64 spp
/// failed every run's z-test, said nowhere (helper 77).
void warnOfExactReference(const Sweep& s, bool ztest) {
    if (!ztest || !s.reference || s.reference->render) return;
    if (const std::string se = standardErrorsOf(s.reference->file); !fs::exists(se))
        std::fprintf(stderr,
                     "shvol: warning: %s: reference.file: %s has no standard errors beside it "
                     "(%s, as render --variance writes them): the z-test takes it as exact, so "
                     "its own noise counts as the runs' error\n",
                     s.path.c_str(), s.reference->file.c_str(), se.c_str());
}

/// Warns of a rendered reference with fewer than 10 times the samples of the sweep's largest
/// run: its noise adds about spp_run/spp_reference to that run's MSE (at equal noise per sample),
/// which every metric counts as the run's own error (helper 86: runs of 1024 spp against a
/// reference of 1024 had half their MSE from the reference, their efficiency halved).
void warnOfNoisyReference(const Sweep& s) {
    if (!s.reference || !s.reference->render || s.runs.empty()) return;
    const double reference = s.reference->spp;
    double most = 0;
    for (const SweepRun& run : s.runs) most = std::max(most, run.spp);
    if (10 * most <= reference) return;
    std::fprintf(stderr,
                 "shvol: warning: %s: reference.spp: %g samples per pixel, fewer than 10 times the "
                 "runs' largest (%g): the reference's own noise adds about %.0f%% to that run's "
                 "MSE, counted as the run's error; give the reference more samples\n",
                 s.path.c_str(), reference, most, 100 * most / reference);
}

/// Warns of z-tests of runs with fewer than kZTestReliableSpp samples per pixel: their standard
/// errors come from too few samples, and an unbiased run fails (the default scene at 2 and 4
/// spp: every repeat, p down to 10⁻²⁷⁷; helper 122). README's metrics row said so, the batch
/// did not, and the report's table read as a biased renderer (it now marks those cells).
void warnOfUnreliableZTest(const Sweep& s, bool ztest) {
    if (!ztest) return;
    size_t few = 0;
    double fewest = INFINITY;
    std::string which;
    for (const SweepRun& run : s.runs)
        if (run.spp < kZTestReliableSpp) {
            ++few;
            if (run.spp < fewest) fewest = run.spp, which = run.id;
        }
    if (few == 0) return;
    std::fprintf(stderr,
                 "shvol: warning: %s: metrics: ztest of %zu run%s with fewer than %d samples per "
                 "pixel (the fewest: %g, run %s): standard errors from so few samples are "
                 "unreliable, and unbiased runs fail the z-test there; it needs %d spp or more, "
                 "and a few hundred where samples have heavy tails (README, metrics)\n",
                 s.path.c_str(), few, few == 1 ? "" : "s", kZTestReliableSpp, fewest, which.c_str(),
                 kZTestReliableSpp);
}

/// Warns when runs are left to render on another thread count per render than the finished runs
/// had (their stats say): their times, and the report's efficiencies, would not compare (helper
/// 86: a batch resumed with --threads 1 after --threads 2 flipped two configurations' order).
void warnOfOtherThreadCounts(const Sweep& s, const Ledger& ledger, int threads) {
    std::set<int> other;
    size_t left = 0, finished = 0;
    for (const SweepRun& run : s.runs) {
        const Json* row = ledger.find(run.id);
        if (!row) {
            ++left;
            continue;
        }
        const Json saved = savedStats(s, *row);
        if (saved.value("threads", Json()).is_number_integer() && saved["threads"] != threads)
            other.insert(saved["threads"].get<int>()), ++finished;
    }
    if (left == 0 || other.empty()) return;
    std::string counts;
    for (const int t : other) counts += (counts.empty() ? "" : ", ") + std::to_string(t);
    std::fprintf(stderr,
                 "shvol: warning: %s: %zu finished run%s rendered on %s threads each, this batch "
                 "renders on %d: their times, and the report's efficiencies, do not compare with "
                 "the %zu run%s left (--threads and --jobs as before, or another output directory, "
                 "time them alike)\n",
                 ledger.jsonlPath().c_str(), finished, finished == 1 ? " was" : "s were",
                 counts.c_str(), threads, left, left == 1 ? "" : "s");
}

/// Warns of finished runs whose image is gone from the output directory (deleted, moved), or is
/// there but no whole OpenEXR image (cut short, overwritten by another file): their rows stand and
/// they are not rendered again, which went unsaid (helper 67; a damaged image, helper 116).
void warnOfMissingImages(const Sweep& s, const Ledger& ledger) {
    std::vector<std::string> missing, unreadable;
    std::string why;     // why the first unreadable image is
    std::error_code ec;  // (a file that cannot be looked at counts as missing)
    for (const SweepRun& run : s.runs)
        if (const Json* row = ledger.find(run.id)) {
            const std::string image = (fs::path(s.output) / row->value("image", "")).string();
            if (row->value("image", "").empty() || !fs::exists(image, ec)) {
                missing.push_back(image);
                continue;
            }
            // Its size as its run wrote it (rows before 7 Dec have none), then its header and
            // chunk table: a whole image's pixels are not read (146 ms a 1024² image, minutes
            // for a large batch; helper 120).
            const Json written = row->value("image_bytes", Json());
            const uintmax_t bytes = fs::file_size(image, ec);
            std::string damage =
                written.is_number_unsigned() && written.get<uintmax_t>() != bytes
                    ? std::to_string(bytes) + " bytes, where its run wrote " + written.dump()
                    : exrDamage(image);
            if (!damage.empty()) {
                if (unreadable.empty()) why = std::move(damage);
                unreadable.push_back(image);
            }
        }
    const auto warn = [&](const std::vector<std::string>& files, const std::string& what,
                          const std::string& first) {
        if (files.empty()) return;
        std::fprintf(
            stderr,
            "shvol: warning: %s: finished runs' images %s: %s%s%s; their rows stand "
            "and the runs are not rendered again (to render one again, delete its line "
            "from %s)\n",
            s.output.c_str(), what.c_str(), files[0].c_str(), first.c_str(),
            files.size() > 1 ? (" and " + std::to_string(files.size() - 1) + " more").c_str() : "",
            ledger.jsonlPath().c_str());
    };
    warn(missing, "are missing", "");
    warn(unreadable, "are not as their runs wrote them", " (" + why + ")");
}

/// Refuses, before anything renders, a run's output that cannot be written (a directory or a
/// FIFO named rNNNN.exr, say): found after the reference's render and the runs before it, it
/// wasted them. Runs the ledger has finished are not written again.
void checkRunOutputs(const Sweep& s, const Ledger& ledger, bool ztest) {
    if (!fs::is_directory(s.output)) return;  // (made for the runs: nothing in it yet)
    for (const SweepRun& run : s.runs) {
        if (ledger.find(run.id)) continue;
        const Outputs o = outputsFor((fs::path(s.output) / (run.id + ".exr")).string());
        std::vector<std::string> files = {o.image, o.stats};
        if (ztest) files.push_back(o.stderrImage);
        for (const std::string& file : files)
            if (const std::string problem = outputFileProblem(file); !problem.empty())
                fail(file, "", "cannot write: " + problem + " (the output of run " + run.id + ")");
    }
}

/// Refuses a ledger whose finished rows the batch cannot resume, naming the run: a finished run
/// must be the run the sweep describes now, recorded under the same axes with the same values
/// and measured by the same metrics (an axis renamed, added or dropped, or another list of
/// metrics, would leave the report columns of nulls and configurations split in two), rendered
/// by this build (another may render the same scene differently: a changed default, a fix), and
/// measured against the reference the sweep gives now (`reference`, its fingerprint), or
/// resuming would mix experiments.
void checkFinishedRows(const Ledger& ledger, const Sweep& s, const std::string& reference) {
    // Runs by id: a row holds the run adoptFinishedIds gave its id, whose values are the row's.
    std::unordered_map<std::string, const SweepRun*> runs;  // (a search each: O(n²))
    for (const SweepRun& r : s.runs) runs.emplace(r.id, &r);
    for (const Json& row : ledger.rows()) {
        const std::string id = row["run"].get<std::string>();
        // The row as the batch wrote it: its id one of the batch's, its numbers numbers (a row
        // with "run": "zzz" gave its run that id, and one with "rmse": "abc" was taken as
        // finished, for the report to refuse or not; helper 127), as tools/report.py checks them.
        if (id.size() < 5 || id.size() > 10 || id[0] != 'r' ||
            id.find_first_not_of("0123456789", 1) != id.npos ||
            id != sweepRunId(int(std::stol(id.substr(1)))))  // (r00001 is not run 1's id)
            fail(ledger.jsonlPath(), "run " + id,
                 "not a run id of shvol batch (r0000, r0001, …); delete its line to render that "
                 "run again");
        for (const char* key :
             {"wall_time_s", "total_s", "rmse", "relmse", "mae", "bias", "ztest_min_p"})
            if (const bool signedValue = std::string(key) == "bias";
                row.contains(key) &&
                !(row[key].is_number() && std::abs(row[key].get<double>()) <= 1e100 &&
                  (signedValue || row[key].get<double>() >= 0)))
                fail(ledger.jsonlPath(), "run " + id,
                     std::string(key) + ": expected a finite number" +
                         (signedValue ? "" : " >= 0") + " of at most 1e100, got " +
                         dumpJson(row[key]) + "; delete its line to render that run again");
        if (!(row.contains("spp") && row["spp"].is_number_integer() &&
              row["spp"].get<long long>() >= 1))
            fail(ledger.jsonlPath(), "run " + id,
                 "spp: expected an integer >= 1, got " + dumpJson(row.value("spp", Json())) +
                     "; delete its line to render that run again");
        if (row.contains("ztest_passed") && !row["ztest_passed"].is_boolean())
            fail(ledger.jsonlPath(), "run " + id,
                 "ztest_passed: expected true or false, got " + dumpJson(row["ztest_passed"]) +
                     "; delete its line to render that run again");
        const auto it = runs.find(id);
        if (it == runs.end())
            fail(ledger.jsonlPath(), "run " + id,
                 unheldRowReason(s, row) + "; use another output directory");
        const Json& values = it->second->values;
        std::set<std::string> known = kLedgerRunColumns;
        for (const auto& [metric, columns] : kLedgerMetricColumns) {
            const bool asked = std::count(s.metrics.begin(), s.metrics.end(), metric) > 0;
            if (asked != row.contains(columns[0]))
                fail(ledger.jsonlPath(), "run " + id,
                     std::string(asked ? "finished without " : "finished with ") + metric +
                         ", which the sweep now " + (asked ? "asks for" : "does not ask for") +
                         "; use another output directory");
            known.insert(columns.begin(), columns.end());
        }
        for (const auto& [key, value] : row.items())
            if (!values.contains(key) && !known.count(key))
                fail(ledger.jsonlPath(), "run " + id,
                     "finished with " + key + "=" + dumpJson(value) +
                         ", an axis the sweep no longer has; use another output directory");
        if (row.value("settings_fingerprint", "") != it->second->settingsFingerprint) {
            // (named as a resumed render names them; helper 84: it said only "other settings")
            const std::string what = changedSettings(s, *it->second, row);
            fail(ledger.jsonlPath(), "run " + id,
                 "finished with other settings or another scene than the sweep now gives" +
                     (what.empty() ? "" : ": " + what) + "; use another output directory");
        }
        if (row.value("fingerprint", "") != it->second->fingerprint)
            fail(ledger.jsonlPath(), "run " + id,
                 "finished when the files its scene names had other contents: " +
                     changedInputs(s, *it->second, row) + "; use another output directory");
        const std::string build = row.value("git_revision", "(none)");
        if (build != gitRevision())
            fail(ledger.jsonlPath(), "run " + id,
                 "finished by shvol " + build + ", this is " + gitRevision() +
                     "; use another output directory");
        if (row.value("reference_fingerprint", "") != reference)
            fail(ledger.jsonlPath(), "run " + id,
                 "measured against another reference than the sweep now gives (its settings, "
                 "scene or file changed); use another output directory");
    }
}

/// What every worker needs to turn a run into its ledger row.
struct RunContext {
    explicit RunContext(const Sweep& s) : sweep(s) {}
    const Sweep& sweep;
    Image reference, referenceSe;
    bool ztest = false;
    int threads = 0;
};

/// Renders one run and measures it against the reference. Returns the ledger row, or null with
/// `code` set to the render's exit code when it did not finish (InterruptGuard::stopExitCode():
/// interrupted).
Json runOne(const RunContext& c, const SweepRun& run, int& code) {
    const Sweep& s = c.sweep;
    RenderArgs r;
    r.scene = s.scene;
    r.output = (fs::path(s.output) / (run.id + ".exr")).string();
    r.sets = run.sets;
    r.threads = c.threads;
    r.quiet = true;
    r.variance = c.ztest;
    r.oneRank = true;
    r.lateSignalStops = false;
    r.run = describe(run, s.axes);
    code = runRender(r);
    if (code) return nullptr;
    const std::string stem = fs::path(r.output).replace_extension("").string();
    const Json stats = parseJsonFile(stem + ".stats.json");
    Json row = run.values;
    row["run"] = run.id;
    row["seed"] = stats["seed"];
    row["spp"] = stats["spp"];
    row["wall_time_s"] = stats["wall_time_s"];
    row["total_s"] = stats["total_s"];  // (loading and set-up too: the report's time)
    row["paths_per_second"] = stats["paths_per_second"];
    row["image"] = run.id + ".exr";
    // (its size, which a resume compares: OpenEXR's chunk table does not tell an image cut
    // short after it; helper 120)
    if (std::error_code ec; fs::is_regular_file(r.output, ec))
        row["image_bytes"] = uint64_t(fs::file_size(r.output, ec));
    row["fingerprint"] = run.fingerprint;
    row["settings_fingerprint"] = run.settingsFingerprint;
    row["git_revision"] = stats["git_revision"];
    if (!s.reference) return row;
    const Image img = readExr(r.output);
    const ImageMetrics m = imageMetrics(img, c.reference);
    for (const std::string& k : s.metrics) {
        if (k == "rmse") row["rmse"] = m.rmse;
        if (k == "relmse") row["relmse"] = m.relMse;
        if (k == "mae") row["mae"] = m.mae;
        if (k == "bias") row["bias"] = m.bias, row["bias_ci95"] = m.biasHalfWidth95;
        if (k == "ztest") {
            const ZTest z =
                zTest(img, readExr(standardErrorsOf(r.output)), c.reference, c.referenceSe);
            row["ztest_min_p"] = z.minP;
            row["ztest_threshold"] = z.threshold;
            row["ztest_passed"] = z.passed;
        }
    }
    return row;
}

/// The runs still to do, handed out in sweep order to the local jobs and, on rank 0 of an MPI
/// batch, to the other ranks; finished rows go to the ledger one at a time. The first failure
/// (an error, or a render's non-zero exit code) stops the handing out.
class WorkQueue {
  public:
    /// `reference`: the reference's fingerprint, written into every row (empty: none).
    WorkQueue(const Sweep& s, Ledger& ledger, std::vector<const SweepRun*> todo,
              std::string reference, bool quiet)
        : sweep_(s),
          ledger_(ledger),
          todo_(std::move(todo)),
          reference_(std::move(reference)),
          quiet_(quiet),
          progress_("batch", (long long)todo_.size(), !quiet && Progress::stderrIsTerminal()) {}

    /// The next run, or null when all are handed out or the batch stopped. A signal that came
    /// while a run wrote its outputs (its render clears lateSignalStops: they are whole, and its
    /// row goes in) stops the batch here (InterruptGuard::stopExitCode()), rather than start a run
    /// that the signal would cancel at once into an image of no samples.
    const SweepRun* next() {
        const std::lock_guard<std::mutex> lock(mutex_);
        if (InterruptGuard::interrupted() && !stopped_)
            stopped_ = true, code_ = InterruptGuard::stopExitCode();
        return stopped_ || next_ == todo_.size() ? nullptr : todo_[next_++];
    }
    void finished(Json row) {
        const std::lock_guard<std::mutex> lock(mutex_);
        if (!reference_.empty()) row["reference_fingerprint"] = reference_;
        ledger_.append(row);
        progress_.advance();
        if (quiet_ || Progress::stderrIsTerminal()) return;
        const SweepRun* run = runOf(row);
        // Time per run so far × runs left (this start's runs only).
        const double elapsed =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        const size_t done = ++finished_;
        // (A non-finite RMSE, of an image with an infinite pixel, is null in JSON.)
        char rmse[32] = "";
        if (const auto it = row.find("rmse"); it != row.end() && it->is_number())
            std::snprintf(rmse, sizeof rmse, " rmse %.4g", it->get<double>());
        else if (it != row.end())
            std::snprintf(rmse, sizeof rmse, " rmse %s", dumpJson(*it).c_str());
        std::fprintf(stderr, "batch: %zu/%zu %s%s, ETA %.0fs\n", ledger_.rows().size(),
                     sweep_.runs.size(),
                     (run ? describe(*run, sweep_.axes) : dumpJson(row["run"])).c_str(), rmse,
                     elapsed / double(done) * double(todo_.size() - done));
    }
    void fail(int code, const std::string& error) {
        const std::lock_guard<std::mutex> lock(mutex_);
        if (stopped_) return;
        stopped_ = true;
        code_ = code;
        error_ = error;
    }
    /// Runs jobs until none is left, on `jobs` threads.
    void work(const RunContext& c, int jobs) {
        auto job = [&] {
            while (const SweepRun* run = next()) {
                try {
                    int code = 0;
                    const Json row = runOne(c, *run, code);
                    if (code) return fail(code, "");
                    finished(row);
                } catch (const std::exception& e) {  // not past the thread: the batch ends
                    return fail(1, errorText(e, c.sweep, run));
                }
            }
        };
        std::vector<std::thread> threads;
        for (int j = 1; j < jobs; ++j) threads.emplace_back(job);
        job();
        for (std::thread& t : threads) t.join();
    }
    /// Rank 0 of an MPI batch: answers the other ranks' requests for runs (from a thread of its
    /// own while this rank renders) until each has been told to stop.
    void serve(const MpiWorld& world) {
        for (int active = world.size() - 1; active > 0;) {
            int from = 0;
            // The warnings of the run reported, said here once for the whole batch (each rank
            // said them once of its own; helper 165), then the report.
            const std::string received = world.recv(kRequest, from);
            const size_t lineEnd = received.find('\n');
            for (const Json& w : Json::parse(received.substr(0, lineEnd)))
                warnOnce(w[0], w[1], w[2]);
            const std::string report = received.substr(lineEnd + 1);
            if (report.rfind("row ", 0) == 0) {
                const Json row = Json::parse(report.substr(4));
                try {
                    finished(row);
                } catch (const std::exception& e) {  // e.g. the ledger cannot be written
                    // (named by its run, as a local job's failure is; it named none)
                    fail(1, errorText(e, sweep_, runOf(row)));
                }
            }
            if (report.rfind("code ", 0) == 0) fail(std::stoi(report.substr(5)), "");
            if (report.rfind("error ", 0) == 0) fail(1, report.substr(6));
            const SweepRun* run = next();
            // (The id too: rank 0 alone has the ledger whose ids the runs take.)
            world.send(from, kReply, run ? std::to_string(run->index) + " " + run->id : "stop");
            active -= run == nullptr;
        }
    }
    /// Another rank of an MPI batch: asks rank 0 for runs, reporting each one's row, until told
    /// to stop.
    static void ask(const MpiWorld& world, const RunContext& c) {
        // Each report carries the warnings of the run it reports, on a first line, for rank 0 to
        // say once for the whole batch: a row's, and an interrupted or failed run's too (this
        // rank said those itself, a second time; review).
        Json said = Json::array();
        setWarningSink(
            [&](const std::string& scene, const std::string& run, const std::string& text) {
                said.push_back({scene, run, text});
            });
        struct Restore {  // (stderr again however ask() ends: the sink refers to `said`)
            ~Restore() { setWarningSink({}); }
        } restore;
        for (std::string report = "ready";;) {
            world.send(0, kRequest, dumpJson(said) + "\n" + report);
            said = Json::array();
            int from = 0;
            const std::string reply = world.recv(kReply, from);
            if (reply == "stop") return;
            const size_t space = reply.find(' ');
            SweepRun run = c.sweep.runs.at(size_t(std::stoi(reply.substr(0, space))));
            run.id = reply.substr(space + 1);
            try {
                int code = 0;
                const Json row = runOne(c, run, code);
                report = code ? "code " + std::to_string(code) : "row " + dumpJson(row);
            } catch (const std::exception& e) {
                report = "error " + errorText(e, c.sweep, &run);
            }
        }
    }
    void done() { progress_.done(); }
    int code() const { return code_; }
    const std::string& error() const { return error_; }

  private:
    static constexpr int kRequest = 1, kReply = 2;  // MPI message tags
    /// The run of a finished row (by its id), or null.
    const SweepRun* runOf(const Json& row) const {
        const auto run = std::find_if(sweep_.runs.begin(), sweep_.runs.end(),
                                      [&](const SweepRun& r) { return r.id == row["run"]; });
        return run == sweep_.runs.end() ? nullptr : &*run;
    }
    const Sweep& sweep_;
    Ledger& ledger_;
    std::vector<const SweepRun*> todo_;
    std::string reference_;
    bool quiet_;
    Progress progress_;
    std::mutex mutex_;
    size_t next_ = 0, finished_ = 0;
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
    bool stopped_ = false;
    int code_ = 0;
    std::string error_;
};

int runBatch(BatchArgs a) {
    const MpiWorld& world = MpiWorld::get();
    // Signals are caught for the whole batch, not only during its renders: one that came while
    // the sweep's scenes were checked or the next run loaded ended the batch by the signal's
    // default action (SIGTERM: exit code 143, nothing said; helper 67). Caught, it stops the
    // batch before its next run (exit code 128 + the signal), as one during a run does. (Under
    // mpirun the renders catch them, as before.) A dry run writes nothing and keeps the signals'
    // default action: caught, its first Ctrl-C was ignored (review).
    std::optional<InterruptGuard> guard;
    if (!world.parallel() && !a.dryRun) guard.emplace();
    Sweep s;
    collectively([&] {
        if (world.parallel() && a.jobs > 1)
            failOption("--jobs",
                       "under mpirun each rank renders one run at a time; start more ranks");
        s = readSweep(a.sweep);
        if (world.root()) checkRunScenes(s);
    });
    if (!a.output.empty()) {
        s.output = a.output;
        if (s.reference && s.reference->render)
            s.reference->file = (fs::path(s.output) / "reference.exr").string();
    }
    // The runs go into a directory, made with its parents if missing: fail now (--dry-run too),
    // not after the reference's render, if that cannot be. (Checked by every rank, reported once.)
    collectively([&] {
        // Named where it was given: --output in the option's form, the sweep's key, or the
        // sweep's default.
        if (std::string problem = outputDirectoryProblem(s.output); !problem.empty()) {
            problem = s.output + ": " + problem + " (batch writes a directory of runs there)";
            if (!a.output.empty()) failOption("--output", problem);
            if (s.outputGiven) fail(a.sweep, "output", problem);
            fail(a.sweep, "", "the default output directory " + problem);
        }
        // The files it writes there whatever its runs' ids: the ledger, the reference it
        // renders, and with --report the report (runs' own outputs: checkRunOutputs).
        if (fs::is_directory(s.output)) {
            std::vector<std::string> names = {"results.jsonl", "results.csv"};
            if (s.reference && s.reference->render) {
                const Outputs ref = outputsFor(fs::path(s.reference->file).filename().string());
                names.insert(names.end(), {ref.image, ref.stats, ref.image + ".fingerprint"});
                if (std::count(s.metrics.begin(), s.metrics.end(), "ztest"))
                    names.push_back(ref.stderrImage);
            }
            if (a.report)
                for (std::string& name : reportOutputs(s.axes, s.metrics))
                    names.push_back(std::move(name));
            for (const std::string& name : names)
                if (const std::string file = (fs::path(s.output) / name).string(),
                    problem = outputFileProblem(file);
                    !problem.empty())
                    fail(file, "", "cannot write: " + problem);
        }
        // A reference file among the batch's own outputs would be written over by a run.
        if (!s.reference || s.reference->render) return;
        std::error_code ec;
        const fs::path ref = fs::weakly_canonical(fs::absolute(s.reference->file, ec), ec),
                       out = fs::weakly_canonical(fs::absolute(s.output, ec), ec);
        if (ec || ref.parent_path() != out) return;
        const std::vector<std::string> written = {"results.jsonl", "results.csv", "report.md",
                                                  "report.html"};
        // Any run's image, stats or standard errors: the ids of a resumed batch's runs depend on
        // its ledger (adoptFinishedIds). (report's plots are PNG files, which no reference can
        // be: readExr refuses them.) The z-test also reads the reference's standard errors.
        static const std::regex runOutput(R"(r[0-9]{4,}\.(exr|stats\.json|stderr\.exr))");
        std::vector<std::string> read = {ref.string()};
        if (std::count(s.metrics.begin(), s.metrics.end(), "ztest"))
            read.push_back(standardErrorsOf(ref.string()));
        for (const std::string& file : read)
            if (const std::string name = fs::path(file).filename().string();
                std::find(written.begin(), written.end(), name) != written.end() ||
                std::regex_match(name, runOutput))
                fail(s.reference->file, "",
                     std::string(file == read[0] ? "the reference" : "its standard errors") +
                         " would be written over by the batch's own " + name +
                         "; keep it outside the output directory " + s.output);
    });
    const bool ztest = std::find(s.metrics.begin(), s.metrics.end(), "ztest") != s.metrics.end();
    if (world.root()) warnOfExactReference(s, ztest), warnOfNoisyReference(s);
    // (Runs are named once adoptFinishedIds has given them their ledger's ids: before, a sweep
    // extended at the front named a finished run's id; helper 159.)
    const int threads = a.threads > 0 ? a.threads : threadsPerRender(a.jobs);
    if (a.dryRun) {
        if (!world.root()) return 0;
        // Runs an earlier start finished, as its ledger has them (read, not repaired: a dry run
        // writes nothing), checked as the start checks them: the files their scenes name and
        // the reference are hashed when there are finished runs to compare them with.
        const Ledger done(s.output, Ledger::Open::ReadOnly, s.axes);
        adoptFinishedIds(s, done.rows());
        std::map<std::string, Json> inputs;  // each named file hashed once
        if (!done.rows().empty()) {
            fingerprintInputs(s, inputs);
            const std::string reference = currentReference(s, ztest, inputs).fingerprint;
            checkFinishedRows(done, s, reference);
        }
        checkRunOutputs(s, done, ztest);
        warnOfMissingImages(s, done);
        // (As the start warns, once its checks pass: of a thread count that differs too; helper
        // 159.)
        warnOfUnreliableZTest(s, ztest), warnOfOtherThreadCounts(s, done, threads);
        const size_t finished = size_t(std::count_if(
            s.runs.begin(), s.runs.end(), [&](const SweepRun& run) { return done.find(run.id); }));
        // A rendered reference is said to be cached or to render first, or not to be needed
        // when every run is finished, as the start decides (helper 86: the same words whether
        // it was finished, half-rendered or missing; helper 90: or not needed).
        if (s.reference && !s.reference->render)
            std::printf("reference %s\n", s.reference->file.c_str());
        else if (s.reference && finished == s.runs.size())
            std::printf("reference %s (not needed: every run is finished)\n",
                        s.reference->file.c_str());
        else if (s.reference) {
            const std::string stamp = currentReference(s, ztest, inputs).stamp;
            std::printf("reference %s (%s)\n", s.reference->file.c_str(),
                        referenceCached(s, stamp, ztest) ? "rendered, cached"
                        : world.size() == 1 && ReferenceCheckpoint(*s.reference, stamp).resumable()
                            ? "rendered first, from its checkpoint where that reads, then cached"
                            : "rendered first, then cached");
        }
        for (const SweepRun& run : s.runs)
            std::printf("%s%s\n", describe(run, s.axes).c_str(),
                        done.find(run.id) ? " (finished)" : "");
        std::printf("%s into %s", runsCounted(s.runs.size()).c_str(), s.output.c_str());
        if (finished > 0)
            std::printf(", %zu of them finished (the start checks that they match this sweep)",
                        finished);
        std::printf("\n");
        return 0;
    }
    // Every rank stamps the runs it may render (it reads their files to render them anyway).
    std::map<std::string, Json> inputs;  // each named file hashed once per batch
    collectively([&] { fingerprintInputs(s, inputs); });
    // Rank 0 stamps the reference (reading the files its scene names) and keeps the ledger,
    // whose finished rows must belong to this sweep, build and reference.
    std::string stamp, reference;
    std::optional<Ledger> ledger;
    collectively([&] {
        if (!world.root()) return;
        const CurrentReference now = currentReference(s, ztest, inputs);
        stamp = now.stamp, reference = now.fingerprint;
        if (std::error_code ec; !fs::create_directories(s.output, ec) && ec)
            fail(s.output, "", "cannot make the directory (" + ec.message() + ")");
        ledger.emplace(s.output, Ledger::Open::Repair, s.axes);
        // The temporaries of its outputs that a killed batch left (mpirun kills the ranks a
        // second after it passed a Ctrl-C on; helper 147): the directory is this batch's while it
        // holds the ledger's lock.
        // (report.py's are named without a PID, and are not: a `shvol report` may be writing.)
        static const std::regex own(R"((r[0-9]{4,}|reference)\..+|results\.(jsonl|csv))");
        if (ledger->locked())
            removeStaleTemporaries(
                s.output, [&](const std::string& name) { return std::regex_match(name, own); });
        adoptFinishedIds(s, ledger->rows());
        checkFinishedRows(*ledger, s, reference);
        checkRunOutputs(s, *ledger, ztest);
        warnOfMissingImages(s, *ledger);
    });
    RunContext c(s);
    c.ztest = ztest;
    c.threads = threads;
    // (Not by --dry-run, which renders nothing; review.)
    if (const std::string w = bindingWarning(threads); world.root() && a.threads == 0 && !w.empty())
        std::fprintf(stderr, "shvol: warning: %s\n", w.c_str());
    if (world.root()) warnOfUnreliableZTest(s, ztest), warnOfOtherThreadCounts(s, *ledger, threads);
    // With every run finished the reference is not needed: one deleted since is not rendered
    // again for nothing (its fingerprint was checked with the rows above).
    const bool allFinished = world.broadcast(
        world.root() && std::all_of(s.runs.begin(), s.runs.end(),
                                    [&](const SweepRun& run) { return ledger->find(run.id); }));
    if (InterruptGuard::interrupted()) {  // (while the sweep was read and its scenes checked)
        std::fprintf(stderr, "batch: stopped before a run finished; run again to finish\n");
        return InterruptGuard::stopExitCode();
    }
    if (s.reference && !allFinished) {
        // The ranks render the reference together (an MPI render), once.
        if (s.reference->render &&
            world.broadcast(world.root() && !referenceCached(s, stamp, c.ztest)))
            if (const int code = renderReference(s, a, c.ztest, stamp)) return code;
        collectively([&] {
            c.reference = readExr(s.reference->file, ExrValues::Reference);
            if (c.ztest) {
                const std::string se = standardErrorsOf(s.reference->file);
                c.referenceSe =
                    fs::exists(se) ? readExr(se) : Image(c.reference.width, c.reference.height);
            }
        });
    }
    if (!world.root()) {
        WorkQueue::ask(world, c);
        return 0;
    }

    std::vector<const SweepRun*> todo;
    for (const SweepRun& run : s.runs)
        if (!ledger->find(run.id)) todo.push_back(&run);
    if (!a.quiet && todo.size() < s.runs.size())
        std::fprintf(stderr, "batch: %zu of %zu runs already finished in %s\n",
                     s.runs.size() - todo.size(), s.runs.size(), ledger->jsonlPath().c_str());
    WorkQueue queue(s, *ledger, std::move(todo), reference, a.quiet);
    std::thread server;
    if (world.parallel()) server = std::thread([&] { queue.serve(world); });
    queue.work(c, a.jobs);
    if (server.joinable()) server.join();
    queue.done();
    // (every other rank has been told to stop: none waits for this one)
    if (!queue.error().empty()) throw KnownToEveryRank(queue.error());
    if (queue.code()) {
        const size_t n = ledger->rows().size();
        if (n == s.runs.size())  // (a signal while the last run wrote its outputs)
            std::fprintf(stderr, "batch: interrupted as its last run finished; all %s %s in %s\n",
                         runsCounted(n).c_str(), n == 1 ? "is" : "are",
                         ledger->jsonlPath().c_str());
        else if (ledger->rows().empty())
            std::fprintf(stderr, "batch: stopped before a run finished; run again to finish\n");
        else
            std::fprintf(stderr, "batch: stopped; %s %s in %s, run again to finish\n",
                         runsCounted(ledger->rows().size()).c_str(),
                         ledger->rows().size() == 1 ? "is" : "are", ledger->jsonlPath().c_str());
        return queue.code();
    }
    if (!a.quiet)
        std::fprintf(stderr, "batch: %s in %s and %s\n", runsCounted(ledger->rows().size()).c_str(),
                     ledger->jsonlPath().c_str(), ledger->csvPath().c_str());
    if (!a.report) return 0;
    // The report, a child process, takes the signals as `shvol report` does (Ctrl-C ends both;
    // caught here, a SIGTERM to the batch waited for the report and was lost; review).
    guard.reset();
    return runReport(s.output, a.quiet);
}

}  // namespace

void addBatchCommand(CLI::App& app, std::function<int()>& run) {
    auto a = std::make_shared<BatchArgs>();
    CLI::App* c = app.add_subcommand(
        "batch",
        "Run a sweep of renders into a resumable ledger, with metrics against a reference");
    c->add_option("sweep", a->sweep, "Sweep file (JSON; README.md, \"Batch experiments\")")
        ->required()
        ->check(nonEmptyName());
    c->add_option("-o,--output", a->output, "Output directory")
        ->default_str("the sweep's output")
        ->check(nonEmptyName());
    c->add_option("--threads", a->threads,
                  "Worker threads per render (0: the cores shared between the jobs and ranks)")
        ->transform(integerIn(0, 4096));
    c->add_option("--jobs", a->jobs,
                  "Renders at once in this process, each on its share of the cores (under "
                  "mpirun each rank renders one: more than 1 is refused; start more ranks)")
        ->transform(integerIn(1, 256));
    c->add_flag("--dry-run", a->dryRun,
                "Check every run's scene, print one line per run and render nothing");
    c->add_flag("--quiet", a->quiet, "No progress");
    c->add_flag("--report", a->report, "Then write the report (as shvol report DIR)");
    c->callback([&run, a] { run = [a] { return runBatch(*a); }; });
}

}  // namespace shvol::app
