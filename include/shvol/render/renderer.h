#pragma once
/// \file Renders a scene in parallel over 16×16 tiles (TBB). Each (pixel, sample) owns an RNG
/// keyed by (seed, pixel, sample), and each pixel is written by one tile only, so the image depends
/// on the seed and never on the thread count.
///
/// Samples are taken in passes whose ends double (1, 2, 4, … spp samples per pixel), so a render
/// stopped early (cancel flag, time limit) has about the same number of samples everywhere; each
/// pixel is normalised by its own count (film.h). A render can continue a film from an earlier,
/// stopped one and then gives the image of an uninterrupted run, bit for bit.
#include <atomic>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "shvol/core/image.h"
#include "shvol/render/film.h"
#include "shvol/render/volume_path_integrator.h"

namespace shvol {

struct RenderStats;

struct RenderOptions {
    int threads = 0;        ///< 0 = all cores
    bool progress = false;  ///< progress bar on stderr
    /// When it becomes true (e.g. set by a signal handler) the render stops within one sample
    /// per thread and returns what it has.
    const std::atomic<bool>* cancel = nullptr;
    double timeLimitSeconds = 0;  ///< > 0: stop once the render has run this long
    /// Extra pass ends (samples per pixel below spp): after each the film is exactly the film of
    /// a render with that many samples (progressive checkpoints, --spp 16,64,256).
    std::vector<uint32_t> stops;
    /// ≥ 0: passes stop doubling where the next would take longer than this many seconds at the
    /// pace of the last one, and then take the samples that fit (at least 1; 0: every pass after
    /// the first is one sample). < 0: passes double. The image does not depend on the passes;
    /// only how often afterPass comes does (--checkpoint-interval).
    double maxPassSeconds = -1;
    /// Seconds on a monotonic clock, read at each pass's start and end to pace the passes; empty:
    /// std::chrono::steady_clock. (A test gives a scripted one, so that the pace is exact.)
    std::function<double()> passClock;
    /// Accumulate per-pixel sums of squares too (Film::standardError).
    bool variance = false;
    /// Render only the pixel rows y with y mod parts = part (every sample of them, in the order
    /// one process takes them); the other pixels keep their film values. Ranks of an MPI render
    /// take one part each, and their films add up to the single-process film exactly.
    int part = 0, parts = 1;
    /// Called after every completed pass, the last one included (not after a stop), with the
    /// film and the statistics so far.
    std::function<void(const Film&, const RenderStats&)> afterPass;
};

enum class RenderStop { Completed, Cancelled, TimeLimit };
const char* renderStopName(RenderStop s);  ///< "completed", "cancelled", "time-limit"

/// What the light sampler of a render was and cost (empty strategy: no light sampling).
struct LightSamplingStats {
    std::string strategy, mis;
    int productOrder = 0, productDepth = 0;  ///< product strategy only
    int skyResolution = 0;                   ///< 2^k of the sky hierarchy (wavelet, product)
    size_t skyBytes = 0, waveletKept = 0, waveletDetails = 0;
    double waveletL2Error = 0;       ///< relative L2 error of the compressed sky
    double waveletSecondMoment = 1;  ///< SkyHierarchy::lightSecondMoment
    double setupSeconds = 0;         ///< building the sky hierarchy, tables and lobes
};

/// What the radiance cache held and cost (render.radiance_cache; records 0 when not used).
struct RadianceCacheStats {
    bool used = false;
    size_t records = 0, memoryBytes = 0, tableBytes = 0;
    double tableSeconds = 0, fillSeconds = 0;
    /// Each BRDF table's projection and peak errors (HshBrdfTable), in the scene's order.
    std::vector<BrdfTableErrors> tableErrors;
    /// Surfaces left uncached (their lobe's albedo error, HshBrdfTable::albedoError), by name.
    std::vector<std::pair<std::string, double>> uncached;
    uint64_t recordPaths = 0;           ///< paths traced to fill the records
    uint64_t recordPathsTruncated = 0;  ///< of those, ended by max_depth
    uint64_t recordNonFinite = 0;       ///< of those, NaN or infinite (taken as 0)
    InvalidDraws recordInvalid;         ///< unusable draws the record paths met
    /// The records' irradiance relative errors (radiance_cache.h, irradianceRelativeError): the
    /// median, the 90th percentile (the value 90% of records are at or below) and the largest.
    double recordErrorMedian = 0, recordErrorP90 = 0, recordErrorMax = 0;
};

struct RenderStats {
    double wallSeconds = 0;
    int threads = 0;
    int spp = 0;
    uint64_t seed = 0;
    PathCounters counters;
    /// The relative standard error of the image's mean luminance (Film::meanRelativeError): of
    /// the whole film, a resumed render's earlier samples too.
    double imageMeanRelativeError = INFINITY;
    /// The degrees of freedom it rests on (Film::meanRelativeErrorDof).
    double imageMeanRelativeErrorDof = INFINITY;
    std::vector<std::string> effects;
    double rouletteThreshold = 1;  ///< Russian roulette's threshold θ as decided (Effects)
    LightSamplingStats lightSampling;
    RadianceCacheStats radianceCache;
    RenderStop stop = RenderStop::Completed;
    uint32_t resumedFromSamples = 0;          ///< samples per pixel (minimum) in the film continued
    uint32_t minSamples = 0, maxSamples = 0;  ///< samples per pixel taken, over the image
    uint32_t passEnd = 0;  ///< samples per pixel at the end of the last completed pass
    double pathsPerSecond() const { return counters.paths / std::max(1e-9, wallSeconds); }
    /// Mean number of scattering events per path.
    double meanPathLength() const {
        return counters.paths ? double(counters.scatteringEvents) / counters.paths : 0.0;
    }
};

struct RenderResult {
    Image image;
    Film film;
    RenderStats stats;
};

/// Renders scene.settings.spp samples per pixel, continuing `film` when it is not empty (it must
/// have the camera's resolution and no pixel beyond spp samples; shvol::Error otherwise).
RenderResult render(const Scene& scene, const RenderOptions& options, Film film = {});

/// Samples per pixel the next pass may take to last about maxPassSeconds (RenderOptions), at the
/// pace of a pass that took `samples` samples in `seconds` over a part of `pixels` pixels:
///   maxPassSeconds · samples / (seconds · pixels), clamped to [1, 10¹⁸].
/// The pace is per sample taken, not per pass: the first pass of a film stopped mid-pass runs
/// only on the pixels behind, and counted per pixel of the part it looked that many times faster
/// (helper 75: its next pass lasted up to two intervals).
uint64_t passSampleCap(double maxPassSeconds, double seconds, uint64_t samples, uint64_t pixels);

}  // namespace shvol
