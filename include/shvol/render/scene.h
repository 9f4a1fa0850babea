#pragma once
/// \file Everything a render needs, as loaded from a scene file.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "shvol/lights/environment.h"
#include "shvol/media/medium.h"
#include "shvol/render/camera.h"
#include "shvol/surfaces/surface_scene.h"

namespace shvol {

/// How a light direction is drawn at a scattering event (render.light_sampling).
enum class LightSampling {
    Environment,  ///< the environment's own sampler (uniform, or luminance·sin θ of the image)
    Wavelet,      ///< hierarchical warp through the sky hierarchy alone (Clarberg et al. 2005)
    Product,      ///< rotated zonal phase lobe × sky hierarchy (Jarosz et al. 2009 §5.2)
};
/// How light and phase samples are combined (render.mis; Veach 1997 §9.2).
enum class MisHeuristic {
    Balance,  ///< w_a = p_a / (p_a + p_b)
    Power,    ///< w_a = p_a² / (p_a² + p_b²)
    None,     ///< environment light only through light samples (phase-sampled escapes get 0)
};
/// Where a path's numbers come from (sampling/sobol_sampler.h, core/rng.h).
enum class SampleStream { Sobol, Independent };
const char* sampleStreamName(SampleStream s);  ///< "sobol", "independent"
const char* lightSamplingName(LightSampling s);
const char* misHeuristicName(MisHeuristic h);

/// HSH radiance caching at diffuse and glossy surfaces (render.radiance_cache; cache/).
struct RadianceCacheSettings {
    bool enabled = false;
    double accuracy = 0.25;    ///< a: records count where their weight exceeds 1/a
    int hshOrder = 8;          ///< n: HSH bands (n² coefficients per channel)
    int raysPerRecord = 1024;  ///< N: hemisphere rays per record
    int maxRecords = 20000;
    int lightSamples = 1;  ///< next-event samples of the direct light at a cached vertex
};

/// The most samples per pixel a render takes (render.spp, --spp, a sweep's spp axis).
inline constexpr int kMaxSpp = 1 << 24;

struct RenderSettings {
    int spp = 16;
    uint64_t seed = 1;
    int maxDepth = 64;  ///< maximum number of scattering events per path (1 = single scattering)
    int rrDepth = 3;    ///< Russian roulette starts after this many scattering events
    /// Russian roulette's threshold θ: a path whose throughput's largest component is m < θ
    /// survives with probability m/θ (rouletteSurvival); 1 is roulette on the throughput.
    /// Unset: decided from the scene (Effects::of).
    std::optional<double> rrThreshold;
    /// Next-event estimation towards the environment, MIS with phase sampling; unset: decided
    /// from the scene (Effects::of).
    std::optional<bool> nee;
    /// The numbers a path uses: Owen-scrambled Sobol' (0,2)-sequences or independent PCG32.
    SampleStream sampler = SampleStream::Sobol;
    TransmittanceEstimator transmittance = TransmittanceEstimator::Ratio;
    LightSampling lightSampling = LightSampling::Environment;
    MisHeuristic mis = MisHeuristic::Balance;
    int productOrder = 4;   ///< bands of the zonal phase lobe in product sampling (1 … 32)
    int productDepth = -1;  ///< levels warped by the product; −1: ProductSampler's default
    size_t waveletCoefficients = 0;  ///< sky wavelet details kept (0 = all)
    RadianceCacheSettings radianceCache;
};

struct Scene {
    Camera camera;
    RenderSettings settings;
    Environment environment = Environment::constant(Spectrum::Zero(), false);
    std::vector<std::unique_ptr<Medium>> media;
    /// The surfaces in their Embree BVH; null when the scene has none (no surface code runs).
    /// A surface whose interiorMedium is k bounds media[k]: that medium exists only inside it.
    std::unique_ptr<const SurfaceScene> surfaces;
    std::string path;  ///< the scene file, for messages
};

}  // namespace shvol
