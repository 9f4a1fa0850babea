#include "shvol/io/sweep.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "shvol/core/error.h"
#include "shvol/core/hash.h"
#include "shvol/io/provenance.h"
#include "shvol/io/scene_loader.h"
#include "shvol/render/scene.h"

namespace shvol {

namespace fs = std::filesystem;

namespace {

std::string relativeTo(const std::string& sweepFile, const std::string& p) {
    if (p.empty() || fs::path(p).is_absolute()) return p;
    return (fs::path(sweepFile).parent_path() / p).lexically_normal().string();
}

/// Whether an override's key path ends in a key named "file" (media[0].file, ….phase.file).
bool namesFile(const std::string& key) {
    const size_t at = key.find_last_of(".]");
    return (at == std::string::npos ? key : key.substr(at + 1)) == "file";
}

/// "key=value" with the value as JSON text (strings quoted, so they stay strings). A relative
/// path assigned to a key named "file" is made relative to the sweep file, as the sweep's other
/// paths are (--set on the command line takes it relative to the current directory).
std::string assignment(const std::string& sweepFile, const std::string& key, Json v) {
    if (namesFile(key) && v.is_string()) v = relativeTo(sweepFile, v.get<std::string>());
    return key + "=" + dumpJson(v);
}

constexpr const char* kSeedIsTheSweeps =
    "the sweep sets render.seed: use its \"seed\" key (or a \"seed\" axis)";
constexpr const char* kSppIsTheReferences =
    "the reference's samples per pixel are its \"spp\" key (default 4096)";

/// The "key=value" strings of `key`, file values made relative to the sweep file (assignment).
/// render.seed is refused (the sweep's seeds come last and would silently replace it), and so is
/// render.spp in the reference's (`reference`) list, which its "spp" would replace.
std::vector<std::string> stringList(JsonReader& r, const std::string& key,
                                    const std::string& sweepFile, bool reference = false) {
    std::vector<std::string> out;
    if (!r.has(key)) return out;
    const Json& j = r.raw(key);
    if (!j.is_array()) r.error(key, "expected an array of \"key.path=value\" strings");
    for (size_t i = 0; i < j.size(); ++i) {
        const std::string a = j[i].is_string() ? j[i].get<std::string>() : "";
        const size_t eq = a.find('=');
        const std::string place = key + "[" + std::to_string(i) + "]";
        if (eq == std::string::npos) r.error(place, "expected a \"key.path=value\" string");
        const std::string path = a.substr(0, eq);
        if (const std::string problem = keyPathProblem(path); !problem.empty())
            r.error(place, problem);
        const bool render = canonicalKeyPath(path).rfind("render", 0) == 0;
        // (read here for every key: a value no scene takes, 1e999 or a repeated key, is named
        // in the sweep, not in each run)
        const Json value = overrideValue(a.substr(eq + 1), path, r.file(), r.keyPath(place));
        if (render && overrideSets(path, value, {"render", "seed"}))
            r.error(place, kSeedIsTheSweeps);
        if (render && reference && overrideSets(path, value, {"render", "spp"}))
            r.error(place, kSppIsTheReferences);
        out.push_back(namesFile(path) ? assignment(sweepFile, path, value) : a);
    }
    return out;
}

std::string hashText(const std::string& text) {
    return hexHash(fnv1a(text.data(), text.size()));
}

/// runDocument(s.sceneDoc, s.scene, sets), with an assignment the scene cannot take (an index
/// beyond an array, a key inside a number) refused at the sweep's key that gave it, places[i]
/// (axes.media[3].albedo), naming `what` ("run r0002").
Json sweepDocument(const Sweep& s, const std::vector<std::string>& sets,
                   const std::vector<std::string>& places, const std::string& what) {
    Json doc = s.sceneDoc;
    for (size_t i = 0; i < sets.size(); ++i) try {
            applyOverride(doc, sets[i], s.scene, "");
        } catch (const Error& e) {
            fail(s.path, places[i], std::string(e.what()) + " (in " + what + ")");
        }
    return doc;
}

}  // namespace

double sppOf(const Json& doc) {
    const Json* spp =
        doc.contains("render") && doc["render"].is_object() && doc["render"].contains("spp")
            ? &doc["render"]["spp"]
            : nullptr;
    return spp && spp->is_number() ? spp->get<double>() : RenderSettings().spp;
}

Json runDocument(Json doc, const std::string& scene, const std::vector<std::string>& sets) {
    for (const std::string& s : sets) applyOverride(doc, s, scene);
    return doc;
}

Sweep readSweep(const std::string& path, double maxRuns) {
    const Json doc = parseJsonFile(path);
    // A scene given for a sweep was told "scene: missing required string" (helper 122).
    if (doc.is_object() && !doc.contains("scene"))
        for (const char* key : {"camera", "media", "surfaces", "environment", "render"})
            if (doc.contains(key))
                fail(path, "",
                     std::string("a scene (it has \"") + key +
                         "\"), not a sweep: render it with shvol render, or name it in a "
                         "sweep's \"scene\"");
    JsonReader r(doc, path, "");
    Sweep s;
    s.path = path;
    s.scene = r.inputFile("scene", fs::path(path).parent_path().string());
    const std::vector<std::string> base = stringList(r, "set", path);
    std::vector<std::string> basePlaces;
    for (size_t i = 0; i < base.size(); ++i) basePlaces.push_back("set[" + std::to_string(i) + "]");
    s.outputGiven = r.has("output");
    s.output = relativeTo(
        path, r.pathName("output", "directory", fs::path(path).stem().string() + "_results"));
    const bool zip = r.choice("combine", "grid", {"grid", "zip"}) == "zip";
    const int repeats = r.integer("repeats", 1, 1, 1000000);
    const double seed0 = r.wholeNumber("seed", 1, 0, 9007199254740992.0);
    if (seed0 > 9007199254740992.0 - (repeats - 1))  // (seed + repeats − 1 would round)
        r.error("seed", "the last repeat's seed, seed + repeats - 1, exceeds 2^53");

    // Axes, in the order the file gives them (Json sorts keys; ordered_json keeps them).
    std::vector<Json> values;
    if (r.has("axes")) {
        const Json& axes = r.raw("axes");
        if (!axes.is_object()) r.error("axes", "expected an object {\"key.path\": [values], …}");
        std::ifstream f(path);
        const auto ordered = nlohmann::ordered_json::parse(f)["axes"];
        for (auto it = ordered.begin(); it != ordered.end(); ++it) {
            const Json& v = axes[it.key()];
            if (!v.is_array() || v.empty())
                fail(path, "axes." + it.key(), "expected a non-empty array of values");
            if (const std::string problem = keyPathProblem(it.key()); !problem.empty())
                fail(path, "axes." + it.key(), problem);
            s.axes.push_back(it.key());
            values.push_back(v);
        }
    }
    // Two axes for one key (media.0.albedo and media[0].albedo, spp and render.spp), or one for a
    // key inside another's (media[0].phase.g and media[0].phase): the later would overwrite the
    // earlier, or a part of it, whose values the ledger would still record.
    std::vector<std::string> canonical;
    for (size_t a = 0; a < s.axes.size(); ++a) {
        const std::string& k = s.axes[a];
        canonical.push_back(canonicalKeyPath(k == "spp" || k == "seed" ? "render." + k : k) + ".");
        for (size_t b = 0; b < a; ++b) {
            const std::string &x = canonical[a], &y = canonical[b];
            if (x == y) fail(path, "axes." + k, "sets the same key as axes." + s.axes[b]);
            if (x.rfind(y, 0) == 0 || y.rfind(x, 0) == 0)
                fail(
                    path, "axes." + k,
                    std::string(x.size() > y.size() ? "sets a key inside" : "contains the key of") +
                        " axes." + s.axes[b] + "; vary one of them");
        }
    }
    for (size_t a = 0; a < s.axes.size(); ++a) {
        const std::string& k = s.axes[a];
        if (k == "seed" && repeats > 1)
            fail(path, "axes.seed", "give either a seed axis or repeats, not both");
        if (k == "seed" && r.has("seed"))
            fail(path, "axes.seed", "give either a seed axis or a \"seed\", not both");
        for (size_t i = 0; i < values[a].size(); ++i) {
            Json& v = values[a][i];
            if (overrideSets(k, v, {"render", "seed"})) fail(path, "axes." + k, kSeedIsTheSweeps);
            if (k != "spp" && k != "seed") continue;
            // (Each value named, by its place and as written: "expected integers ≥ 1" named
            // neither, and took 1e30 for a fraction; helper 159.)
            const bool spp = k == "spp";
            const std::string place = "axes." + k + "[" + std::to_string(i) + "]";
            const std::string wrong = std::string(spp ? "expected an integer in [1, 2^24]"
                                                      : "expected an integer in [0, 2^53]") +
                                      ", got " + typeAndValue(v);
            // An integral number however written (2.0, 2e0), as every integer key takes it:
            // kept as the integer, so that runs and rows hold one spelling of it.
            if (const double d = v.is_number_float() ? v.get<double>() : 0.5;
                d == std::floor(d) && std::abs(d) < kDoubleHoldsFractionsBelow)
                v = (long long)d;
            else if (!spp && v.is_number_float() && std::abs(d) >= kDoubleHoldsFractionsBelow)
                fail(path, place, kWrittenAsADouble);
            const long long most = spp ? kMaxSpp : 9007199254740992LL;
            if (!(v.is_number_integer() && v.get<long long>() >= (spp ? 1 : 0) &&
                  v.get<long long>() <= most))
                fail(path, place, wrong);
        }
        if (zip && values[a].size() != values[0].size())
            fail(path, "axes." + k,
                 "zipped axes need equal lengths (" + std::to_string(values[a].size()) + " vs " +
                     std::to_string(values[0].size()) + ")");
    }

    // Counted before anything is expanded: a file of a few kB can name 1000³ grid points.
    double pointCount = 1;
    std::string shape;
    for (size_t a = 0; a < values.size() && !(zip && a > 0); ++a) {
        pointCount *= double(values[a].size());
        shape += (shape.empty() ? "" : " × ") + std::to_string(values[a].size());
    }
    const double runs = pointCount * repeats;
    if (!(runs <= maxRuns))
        fail(path, values.empty() ? "repeats" : "axes",
             (runs < 1e18 ? std::to_string((long long)runs) : std::string("more than 10^18")) +
                 " runs (" + (shape.empty() ? "1" : shape) + (zip ? " zipped" : "") +
                 (pointCount == 1 ? " point, " : " points, ") + std::to_string(repeats) +
                 (repeats == 1 ? " repeat" : " repeats") + " each); a sweep has at most " +
                 std::to_string((long long)maxRuns));

    s.sceneDoc = sceneDocument(s.scene);  // read once, not once per run
    // Points: grid (first axis slowest) or zip.
    std::vector<std::vector<size_t>> points;
    if (s.axes.empty()) {
        points.push_back({});
    } else if (zip) {
        for (size_t i = 0; i < values[0].size(); ++i)
            points.push_back(std::vector<size_t>(s.axes.size(), i));
    } else {
        std::vector<size_t> idx(s.axes.size(), 0);
        while (true) {
            points.push_back(idx);
            int a = int(idx.size()) - 1;
            while (a >= 0 && ++idx[a] == values[a].size()) idx[a--] = 0;
            if (a < 0) break;
        }
    }
    std::map<double, std::string> runOfSeed;        // a run of each seed, for the reference's check
    std::map<std::string, std::string> runOfScene;  // a run of each fingerprint
    // Repeats are the slowest loop: the runs of one repeat come together (a resumed batch finds
    // its finished runs by their values, whatever their place: adoptFinishedIds).
    for (int k = 0; k < repeats; ++k)
        for (const auto& p : points) {
            SweepRun run;
            run.index = int(s.runs.size());
            run.id = sweepRunId(run.index);
            run.sets = base;
            std::vector<std::string> places = basePlaces;  // the sweep's key of each of run.sets
            bool seedAxis = false;
            for (size_t a = 0; a < s.axes.size(); ++a) {
                const std::string& key = s.axes[a];
                const Json& v = values[a][p[a]];
                run.values[key] = v;
                run.sets.push_back(
                    assignment(path, key == "spp" || key == "seed" ? "render." + key : key, v));
                places.push_back("axes." + key);
                seedAxis = seedAxis || key == "seed";
            }
            run.values["repeat"] = k;
            if (!seedAxis) {
                run.sets.push_back("render.seed=" + std::to_string((long long)seed0 + k));
                places.push_back("render.seed (set by the sweep)");
            }
            // (By its values: its id is not known before a ledger's finished runs have kept
            // theirs, adoptFinishedIds; helper 159.)
            const Json doc =
                sweepDocument(s, run.sets, places, "the run " + describeValues(run, s.axes));
            run.places = places;
            run.fingerprint = run.settingsFingerprint = hashText(canonicalJson(doc));
            // The same point twice (an axis value given twice, or a seed): the same render,
            // which the report would count as a repeat of no spread.
            if (const auto [same, added] = runOfScene.emplace(run.fingerprint, run.id); !added)
                fail(path, "axes",
                     "runs " + same->second + " and " + run.id + " would be the same render (" +
                         dumpJson(run.values) + "); give each value once");
            run.spp = sppOf(doc);
            if (const Json* seed = doc.contains("render") ? &doc["render"] : nullptr;
                seed && seed->contains("seed") && (*seed)["seed"].is_number())
                runOfSeed.emplace((*seed)["seed"].get<double>(), run.id);
            s.runs.push_back(run);
        }

    if (r.has("reference")) {
        JsonReader ref = r.object("reference");
        SweepReference sr;
        const bool renderSpec = ref.has("spp") || ref.has("set") || ref.has("seed");
        if (ref.has("file") && renderSpec)
            ref.error("file",
                      "a reference is either a file or a render spec (spp, set, seed), "
                      "not both");
        if (ref.has("file")) {
            // Checked here, so that --dry-run finds a missing reference too.
            sr.file = ref.inputFile("file", fs::path(path).parent_path().string());
        } else {
            sr.render = true;
            sr.sets = base;
            std::vector<std::string> places = basePlaces;  // as a run's (sweepDocument)
            for (const std::string& a : stringList(ref, "set", path, true)) {
                places.push_back("reference.set[" + std::to_string(places.size() - base.size()) +
                                 "]");
                sr.sets.push_back(a);
            }
            sr.sets.push_back("render.spp=" + std::to_string(ref.integer("spp", 4096, 1, kMaxSpp)));
            places.push_back("reference.spp");
            // A seed no run uses by default, so the reference's noise is independent: a run of
            // the same seed would repeat the reference's first samples, and its error would look
            // smaller than it is.
            constexpr long long kDefaultSeed = 1000000000;
            const double seed = ref.wholeNumber("seed", kDefaultSeed, 0, 9007199254740992.0);
            if (const auto same = runOfSeed.find(seed); same != runOfSeed.end()) {
                const std::string why = "is also the seed of run " + same->second +
                                        ", which would repeat the reference's first samples; ";
                if (ref.has("seed")) ref.error("seed", why + "give the reference another seed");
                r.error("reference", "its default seed " + std::to_string(kDefaultSeed) + " " +
                                         why + "give the reference a \"seed\" of its own");
            }
            sr.sets.push_back("render.seed=" + std::to_string((long long)seed));
            places.push_back("reference.seed");
            sr.spp = sppOf(sweepDocument(s, sr.sets, places, "the reference"));
            sr.places = places;
            sr.file = (fs::path(s.output) / "reference.exr").string();
        }
        ref.finish();
        s.reference = sr;
    }
    const std::vector<std::string> known = {"rmse", "relmse", "mae", "bias", "ztest"};
    if (r.has("metrics")) {
        const Json& m = r.raw("metrics");
        if (!m.is_array()) r.error("metrics", "expected an array such as [\"rmse\", \"bias\"]");
        for (const Json& v : m) {
            if (!v.is_string() ||
                std::find(known.begin(), known.end(), v.get<std::string>()) == known.end())
                r.error("metrics", "unknown metric " + dumpJson(v) +
                                       "; expected rmse, relmse, mae, bias or ztest");
            // (as every other value given twice in a sweep: accepted silently until helper 127)
            if (std::find(s.metrics.begin(), s.metrics.end(), v.get<std::string>()) !=
                s.metrics.end())
                r.error("metrics", dumpJson(v) + " is given twice; give each metric once");
            s.metrics.push_back(v.get<std::string>());
        }
    } else if (s.reference) {
        s.metrics = {"rmse", "relmse", "mae", "bias"};
    }
    if (!s.metrics.empty() && !s.reference) r.error("metrics", "metrics need a \"reference\"");
    // (A reference no metric reads would be rendered, or hashed, for nothing; helper 67.)
    if (s.metrics.empty() && s.reference)
        r.error("metrics",
                "none, but the sweep has a \"reference\", which only metrics use; "
                "name a metric or drop the reference");
    // The z-test needs standard errors, and so 2 samples per pixel in every run and in a rendered
    // reference: found here, not when the batch reaches that run.
    if (std::find(s.metrics.begin(), s.metrics.end(), "ztest") != s.metrics.end()) {
        std::vector<std::pair<std::string, double>> renders;
        for (size_t i = 0; i < s.runs.size(); ++i)
            renders.push_back({"run " + s.runs[i].id, s.runs[i].spp});
        if (s.reference->render) renders.push_back({"the reference", s.reference->spp});
        for (const auto& [what, spp] : renders)
            if (spp < 2)
                r.error("metrics",
                        "ztest needs standard errors, which need at least 2 samples "
                        "per pixel; " +
                            what + " has 1");
    }
    r.finish();
    return s;
}

void fingerprintInputs(Sweep& s, std::map<std::string, Json>& memo) {
    for (SweepRun& run : s.runs) {
        const Json doc = runDocument(s.sceneDoc, s.scene, run.sets);
        run.fingerprint = hashText(run.settingsFingerprint + "\n" +
                                   namedFileContents(inputFiles(doc, s.scene, &memo)));
    }
}

std::string describeValues(const SweepRun& run, const std::vector<std::string>& axes) {
    std::string s;
    for (const std::string& axis : axes)  // the sweep's order (it was alphabetical; helper 77)
        if (run.values.contains(axis)) s += " " + axis + "=" + dumpJson(run.values[axis]);
    for (auto it = run.values.begin(); it != run.values.end(); ++it)
        if (std::find(axes.begin(), axes.end(), it.key()) == axes.end())
            s += " " + it.key() + "=" + dumpJson(it.value());
    return s.empty() ? s : s.substr(1);
}

std::string sweepRunId(int index) {
    char id[16];
    std::snprintf(id, sizeof id, "r%04d", index);
    return id;
}

size_t adoptFinishedIds(Sweep& s, const std::vector<Json>& rows) {
    // A run's values as canonical text (one text per value set), and a row's the same way,
    // restricted to the run's keys.
    std::map<std::string, std::string> rowOfValues;  // values → the id of the row holding them
    std::set<std::string> taken;                     // ids of rows, then of runs given one
    for (const Json& row : rows) {
        const std::string id = row["run"].get<std::string>();
        taken.insert(id);
        if (s.runs.empty()) continue;
        Json values = Json::object();
        bool complete = true;
        for (const auto& [k, v] : s.runs.front().values.items())
            if (row.contains(k))
                values[k] = row[k];
            else
                complete = false;
        if (complete) rowOfValues.emplace(canonicalJson(values), id);
    }
    size_t finished = 0;
    std::vector<SweepRun*> unplaced;  // new runs whose own id a row has
    for (SweepRun& run : s.runs) {
        const std::string own = sweepRunId(run.index);
        if (const auto it = rowOfValues.find(canonicalJson(run.values)); it != rowOfValues.end())
            run.id = it->second, ++finished;
        else if (!taken.count(own))
            run.id = own;
        else
            unplaced.push_back(&run);
    }
    for (const SweepRun& run : s.runs) taken.insert(run.id);
    int next = 0;
    for (SweepRun* run : unplaced) {
        while (taken.count(sweepRunId(next))) ++next;
        taken.insert(run->id = sweepRunId(next));
    }
    return finished;
}

std::string unheldRowReason(const Sweep& s, const Json& row) {
    constexpr const char* kStay =
        " (a finished run must stay in the sweep: values may be added to its axes, and repeats, "
        "but not changed or removed)";
    std::vector<std::string> keys = s.axes;  // what each run's values hold, in the sweep's order
    keys.push_back("repeat");
    for (const std::string& key : keys)
        if (!row.contains(key)) return "finished with no " + key + ", an axis the sweep now has";
    std::string point;  // "key=value …" of the row
    Json values = Json::object();
    for (const std::string& key : keys) {
        std::set<std::string> given;  // the values the sweep gives `key` now
        for (const SweepRun& run : s.runs) given.insert(canonicalJson(run.values[key]));
        const std::string text = dumpJson(row[key]);
        if (!given.count(canonicalJson(row[key])))
            return key == "repeat" ? "finished as repeat " + text + ", and the sweep now has " +
                                         std::to_string(given.size()) +
                                         (given.size() == 1 ? " repeat" : " repeats") + kStay
                                   : "finished with " + key + "=" + text + ", a value axes." + key +
                                         " no longer has" + kStay;
        values[key] = row[key];
        point += (point.empty() ? "" : " ") + key + "=" + text;
    }
    // Every value is given, but not together (zipped axes), or together but held by another row.
    for (const SweepRun& run : s.runs)
        if (canonicalJson(run.values) == canonicalJson(values))
            return "finished at " + point + ", the point of run " + run.id +
                   ", which another row holds";
    return "finished at " + point + ", a combination the zipped axes no longer give" + kStay;
}

}  // namespace shvol
