#pragma once
/// \file Sweep files for `shvol batch`: a base scene, axes of values, repeats, a reference and
/// metrics, expanded into a list of runs. The format is in README.md, "Batch experiments":
///   {"scene": "scene.json", "set": ["camera.resolution=[150,100]"],
///    "axes": {"media[0].phase.order": [4, 8, 16], "spp": [16, 64]}, "combine": "grid",
///    "repeats": 2, "seed": 1,
///    "reference": {"file": "ref.exr"}  or  {"spp": 4096, "seed": 1000000, "set": [...]},
///    "metrics": ["rmse", "relmse", "mae", "bias", "ztest"], "output": "out/dir"}
/// Axes combine as a grid (every combination, the first axis slowest) or zipped (equal lengths,
/// taken together). An axis key is a scene key path as for --set, or "spp" or "seed". Each
/// repeat has its own seed (seed + repeat index) unless "seed" is an axis. Runs are in the order
/// repeat (slowest), then the points, and numbered so (r0000, r0001, …) until adoptFinishedIds
/// gives the runs a ledger has finished their ledger ids.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "shvol/io/json_reader.h"

namespace shvol {

/// The most runs a sweep may expand to (grid points or zipped points, times repeats): more is
/// refused before anything is expanded, as a few kB of axes can name 1000³ points. Each run's
/// scene document is built and checked when the sweep is read, about 94 µs and 2.2 kB a run
/// (a 10⁵-run dry run of the Cornell fog scene: 9.4 s, 217 MB): at 10⁶, the limit until 7 Dec,
/// a 14 kB sweep took over 2 minutes and 2.3 GB before its first word (helper 127).
inline constexpr double kMaxSweepRuns = 1e5;

struct SweepRun {
    int index = 0;   ///< the place in Sweep::runs
    std::string id;  ///< "r0007": sweepRunId(index), or a ledger's (adoptFinishedIds)
    Json values;     ///< {axis key: value, …, "repeat": k}
    std::vector<std::string> sets;    ///< --set assignments: base, axes, render.seed, render.spp
    std::vector<std::string> places;  ///< the sweep's key that gave each of sets (set[0], axes.spp)
    /// FNV-1a of the scene document after `sets` (spp included; canonicalJson): what the run
    /// renders, but for the contents of the files it names. A finished run whose settings
    /// changed would be a different render; --dry-run, which reads no grid, can tell.
    std::string settingsFingerprint;
    /// settingsFingerprint, and after fingerprintInputs also the contents of the files the scene
    /// names (grids, skies, tables).
    std::string fingerprint;
    double spp = 0;  ///< the samples per pixel the run renders (sppOf its document)
};

struct SweepReference {
    std::string file;                 ///< an EXR, or where the rendered reference is cached
    std::vector<std::string> sets;    ///< non-empty: render it (base sets + these + spp/seed)
    std::vector<std::string> places;  ///< the sweep's key that gave each of sets
    bool render = false;
    double spp = 0;  ///< a rendered reference's samples per pixel (sppOf its document)
};

struct Sweep {
    std::string path, scene, output;
    bool outputGiven = false;       ///< `output` is the sweep's key, not its default
    Json sceneDoc;                  ///< the scene's document, read once (sceneDocument)
    std::vector<std::string> axes;  ///< axis keys in order (the ledger's columns)
    std::vector<SweepRun> runs;
    std::optional<SweepReference> reference;
    std::vector<std::string> metrics;  ///< rmse, relmse, mae, bias, ztest
};

/// Reads and expands a sweep file; errors are one line naming the file and the key. Relative
/// "scene", "output" and reference "file" paths are relative to the sweep file. A sweep of more
/// than `maxRuns` runs is refused (the sweep fuzzer lowers it to bound the time per input).
Sweep readSweep(const std::string& path, double maxRuns = kMaxSweepRuns);

/// A run's values, its axes' in the sweep's order first, then the rest ("spp=16 repeat=0"): how
/// messages name a run before its id is known (adoptFinishedIds).
std::string describeValues(const SweepRun& run, const std::vector<std::string>& axes);

/// The id of the run at `index` of a freshly read sweep: "r0007" (four digits at least).
std::string sweepRunId(int index);

/// Gives the runs the ids under which `rows` (a batch ledger's finished rows, each with a unique
/// "run") hold them, so that a sweep changed by adding values anywhere in its axes, or more
/// repeats, resumes into the same output: a row holds a run when it records the run's `values`
/// (every axis key and "repeat" with the same values: canonicalJson). Each other run keeps its own
/// id when no row has it, else takes the lowest id that neither a row nor another run has. Rows
/// that hold no run are left for the caller to refuse (their ids stay out of use). Returns how many
/// runs were found finished.
size_t adoptFinishedIds(Sweep& s, const std::vector<Json>& rows);

/// Why `row`, a finished row to which adoptFinishedIds gave no run, holds none, as the refusal
/// says it after "run r0003: ": an axis the row lacks, a value its axis no longer has, a repeat
/// beyond the repeats, a combination zipped axes no longer give, or a point another row holds.
std::string unheldRowReason(const Sweep& s, const Json& row);

/// The samples per pixel a scene document asks for (render.spp, or its default).
double sppOf(const Json& doc);

/// The scene document `doc` (Sweep::sceneDoc) after a run's or the reference's assignments, as
/// --set applies them; `scene` names the scene file in errors.
Json runDocument(Json doc, const std::string& scene, const std::vector<std::string>& sets);

/// Adds to each run's fingerprint the contents of the files its scene names, read through
/// `memo` (inputFiles): each file once, also for whatever else of the batch hashes inputs with
/// the same memo. Separate from readSweep so that listing and checking the runs (batch --dry-run)
/// reads no grid. shvol::Error naming a file that cannot be read and the key that names it.
void fingerprintInputs(Sweep& s, std::map<std::string, Json>& memo);

}  // namespace shvol
