#pragma once
// Subcommands of the shvol program; each registers its options on the CLI11 app.
#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

namespace shvol {
class SHSampledPhase;
}

namespace shvol::app {

/// Registers a subcommand; `run` is set to its action when it is selected.
void addRenderCommand(CLI::App& app, std::function<int()>& run);
void addMakeMediumCommand(CLI::App& app, std::function<int()>& run);
void addMakeSkyCommand(CLI::App& app, std::function<int()>& run);
void addBenchCommand(CLI::App& app, std::function<int()>& run);
void addPhaseCommand(CLI::App& app, std::function<int()>& run);
void addDiffCommand(CLI::App& app, std::function<int()>& run);
void addTonemapCommand(CLI::App& app, std::function<int()>& run);
void addBatchCommand(CLI::App& app, std::function<int()>& run);
void addReportCommand(CLI::App& app, std::function<int()>& run);

/// The text of a failure for the error line: shvol::Error's message as it is, memory running out
/// as "out of memory; …", any other exception's as "internal error: …" (isInternalError).
std::string errorMessage(const std::exception& e);
/// The whole error line: "shvol: error: " and errorMessage(e), or "shvol: internal error: …".
std::string errorLine(const std::exception& e);

/// What `shvol render` is asked to do (its options).
struct RenderArgs {
    std::string scene, output, checkpoint;
    std::string spp;  ///< "" (the scene's), "N" or "N1,N2,…,N"
    int threads = 0;
    long long seed = -1;  ///< < 0: the scene's
    double timeLimit = 0, checkpointInterval = 60;
    std::vector<std::string> sets;
    bool quiet = false, resume = false, variance = false;
    /// Render in this process alone even under mpirun (one run of a batch); otherwise the ranks
    /// of an MPI job share the render (README.md, "MPI").
    bool oneRank = false;
    /// A first signal that comes once the render has finished, while its outputs are written,
    /// makes the exit code 128 + the signal (a command's own render). A batch's renders clear it:
    /// their outputs are whole and their rows go in; the batch then stops before its next run.
    bool lateSignalStops = true;
    /// The batch run this render is ("r0003 albedo=0.9 spp=16", "the reference"), which its
    /// warnings name; "" outside a batch.
    std::string run;
    /// The checkpoint only saves work (a batch's reference): one that cannot be resumed (damaged,
    /// of another render) is warned of and the render starts afresh, one that cannot be written
    /// is warned of once and no more are written, and none is written once the render completes.
    /// (A checkpoint is 36 bytes a pixel, 60 with --variance: the reference of a batch failed at
    /// every start where it did not fit, or where it was damaged; helper 151.)
    bool checkpointOptional = false;
};
/// Renders as `shvol render` does (images, stats, checkpoints); returns the exit code (128 + the
/// signal when interrupted). Errors are shvol::Error. Under mpirun (and without oneRank) every rank
/// must call it: they render a share of the pixels each and rank 0 writes the outputs.
int runRender(const RenderArgs& a);

/// Prints "shvol: warning: SCENE: TEXT" ("SCENE (run RUN): TEXT" in a batch) once per process for
/// each text, and once for texts that differ in their numbers only, naming the first run that
/// gave it; or passes it to the warning sink when one is set.
void warnOnce(const std::string& scene, const std::string& run, const std::string& text);
/// Where warnOnce sends warnings instead of stderr (an MPI batch's ranks other than 0 send them to
/// rank 0, which says each once for the whole batch); an empty sink restores stderr.
using WarningSink =
    std::function<void(const std::string& scene, const std::string& run, const std::string& text)>;
void setWarningSink(WarningSink sink);

/// What an SH-sampled phase function with structure finer than the quadrature of its fit sees
/// does (SHSampledPhase::quadratureMass more than kBlindQuadrature from 1): "the function has
/// structure finer than …", for a warning; "" when the quadrature sees it. A tabulated spike
/// 2·10⁻⁶° wide rendered a white furnace at 0.76 while the weight's m₂ read 0 (helper 94), and
/// `phase fit` printed those figures without a word (helper 110).
std::string blindSHFitText(const SHSampledPhase& sh);

/// The commit this program was built from, "<commit>-dirty-<12 hex digits of a hash of the
/// changed and untracked files>" if the tree had changes, or, built outside a checkout of its
/// own, "no-git-<12 hex digits of a hash of the sources>" (cmake/git_revision.cmake).
const char* gitRevision();

/// The files a render with -o `out` writes: its image, statistics and (--variance) standard
/// errors.
struct Outputs {
    std::string image, stats, stderrImage;
};
/// "x.exr" → x.exr, x.stats.json, x.stderr.exr; `tag` (e.g. "spp16") goes before the extension,
/// which keeps its case (x.EXR → x.spp16.EXR, x.stats.json).
Outputs outputsFor(const std::string& out, const std::string& tag = "");

/// `relative` in the tree this program is in (build/shvol in a checkout: ../relative from its
/// directory), else in the source tree it was built from (a copy of the program elsewhere), or ""
/// if it is in neither.
std::string sourceTreePath(const std::string& relative);

/// Writes DIR/report.md and DIR/report.html with plots from DIR/results.jsonl (tools/report.py
/// run by /usr/bin/python3), and names them on stderr unless `quiet`; returns its exit code.
int runReport(const std::string& dir, bool quiet = false);
/// The files tools/report.py writes into a batch's directory for a sweep of these axes and
/// metrics: report.md, report.html and its plots (error vs time and spp with an error metric,
/// time vs spp and each axis that is a ledger column of its own).
std::vector<std::string> reportOutputs(const std::vector<std::string>& axes,
                                       const std::vector<std::string>& metrics);

/// Peak resident memory of this process in MiB.
double peakMemoryMiB();

/// A CLI11 check that a number lies in [lo, hi] ((lo, hi] with loOpen); its message is one line
/// naming that range and the unit, e.g. "must be in [2, 10], got 11".
CLI::Validator numberIn(double lo, double hi, bool loOpen = false, const std::string& unit = "");
/// A CLI11 check that the text is a decimal integer in [lo, hi], e.g. "--spp: must be an integer
/// in [1, 16777216], got 0" (CLI11's own number checks print a 310-digit bound).
CLI::Validator integerIn(long long lo, long long hi);
/// Whether `path` ends in `ext` (".exr"), in any case.
bool hasExtension(const std::string& path, const std::string& ext);
/// What is wrong with `path` as the name of an output of type `ext`: "<what>; name the file
/// <ext>" without the extension, "the output needs a name before <ext>" for a bare extension
/// (".exr", "dir/.exr"); empty when it is fine. `what` says what the command writes.
std::string outputNameProblem(const std::string& path, const std::string& ext,
                              const std::string& what);
/// The --set option of render and bench: key.path=value, one value per --set, repeatable (taking
/// several values, it swallowed a scene written after it: `render --set a=1 s.json --threads 1`
/// said "scene is required"; helper 96).
CLI::Option* addSetOption(CLI::App* c, std::vector<std::string>& sets);
/// The hint of the errors a second value given to one --set makes.
inline constexpr const char* kOneValuePerSet =
    "each --set takes one key.path=value: give --set before each";
/// A CLI11 check of a scene argument: a name holding '=' that is no file is a second value given
/// to one --set, taken for the scene (`render --set a=1 b=2`): "b=2: no such file; …" with that
/// hint (it said "no such file" only; helper 99).
CLI::Validator notAStrayOverride();
/// A CLI11 check that a file or directory argument is not an empty string ("scene: an empty
/// name"; the empty name reached the file's reader, whose error could name no file).
CLI::Validator nonEmptyName();
/// outputFileProblem as a CLI11 check of an output option, checked as the options are parsed,
/// before any work: "--output: x.exr: cannot write: directory x does not exist".
CLI::Validator writableOutput();
/// outputNameProblem, then writableOutput, as a CLI11 check of an output option.
CLI::Validator outputNamed(const std::string& ext, const std::string& what);
/// Whether the two paths name one file: the same existing file (through links too), or the same
/// path once made absolute and normal. An output that would replace what the command reads, or
/// another of its outputs.
bool sameFile(const std::string& a, const std::string& b);
/// The largest --seed (2^53, as render.seed: every seed is exact in a JSON number).
inline constexpr long long kMaxSeed = 9007199254740992LL;

}  // namespace shvol::app
