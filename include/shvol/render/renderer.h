#pragma once
/// \file Renders a scene in parallel over 16×16 tiles (TBB). Each (pixel, sample) owns an RNG
/// keyed by (seed, pixel, sample), and each pixel is written by one tile only, so the image depends
/// on the seed and never on the thread count.
#include <string>
#include <vector>

#include "shvol/core/image.h"
#include "shvol/render/volume_path_integrator.h"

namespace shvol {

struct RenderOptions {
    int threads = 0;        ///< 0 = all cores
    bool progress = false;  ///< progress bar on stderr
};

/// What the light sampler of a render was and cost (empty strategy: no light sampling).
struct LightSamplingStats {
    std::string strategy, mis;
    int productOrder = 0, productDepth = 0;  ///< product strategy only
    int skyResolution = 0;                   ///< 2^k of the sky hierarchy (wavelet, product)
    size_t skyBytes = 0, waveletKept = 0, waveletDetails = 0;
    double waveletL2Error = 0;  ///< relative L2 error of the compressed sky
    double setupSeconds = 0;    ///< building the sky hierarchy, tables and lobes
};

struct RenderStats {
    double wallSeconds = 0;
    int threads = 0;
    int spp = 0;
    uint64_t seed = 0;
    PathCounters counters;
    std::vector<std::string> effects;
    LightSamplingStats lightSampling;
    double pathsPerSecond() const { return counters.paths / std::max(1e-9, wallSeconds); }
    /// Mean number of scattering events per path.
    double meanPathLength() const {
        return counters.paths ? double(counters.scatteringEvents) / counters.paths : 0.0;
    }
};

struct RenderResult {
    Image image;
    RenderStats stats;
};

RenderResult render(const Scene& scene, const RenderOptions& options);

}  // namespace shvol
