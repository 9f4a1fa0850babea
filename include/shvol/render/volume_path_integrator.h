#pragma once
/// \file Unbiased volumetric path tracing with delta tracking, light sampling and MIS.
///
/// Along a path with throughput β, free flights are sampled by delta tracking (the nearest real
/// collision over all media: superposed Poisson processes). At a real collision in medium k,
/// β ← β·α_k and the in-scattered radiance ∫ p(ω·ω′) T L_env(ω′) dω′ is estimated twice,
/// combined by multiple importance sampling (Veach 1997, §9.2; render.mis):
///  - light sampling: ω′ ~ p_light, contribution β·p(ω·ω′)·T̂(x, ω′)·L_env(ω′)·w_light/p_light,
///    T̂ from ratio tracking (or the closed form). p_light is (render.light_sampling) the
///    environment's own sampler, the sky hierarchy alone (lights/sky_hierarchy.h), or the product
///    of the medium's zonal phase lobe rotated to ω and the sky (lights/product_sampler.h);
///  - phase sampling: ω′ ~ p_phase; if the next free flight escapes, the path adds
///    β·(f/p_phase)·L_env(ω′)·w_phase. Escape happens with probability T, so no transmittance
///    estimate is needed on that branch.
/// Weights: balance w_a = p_a/(p_a + p_b), power w_a = p_a²/(p_a² + p_b²), or none (w_light = 1,
/// w_phase = 0). The phase function is always evaluated exactly; the product sampler's SH lobe
/// only shapes its pdf, so every strategy has the same expected image.
/// Russian roulette after rrDepth scattering events, once max(β) is below the threshold θ
/// (sampling/russian_roulette.h; Effects::rouletteThreshold). Without scattering (albedo 0 or
/// max depth 0) a camera ray returns T̂·L_env directly: no collision or phase sample is drawn.
///
/// Surfaces (scene.surfaces, when the scene has any). Each flight runs to the nearest surface hit
/// t_s, and free flights are sampled in [0, t_s) over the media the path is in: unbounded media,
/// and each medium bounded by a closed surface while the path is inside that surface (entered
/// when a ray crosses it against its outward normal, left when it crosses along it; the state of a
/// camera ray is found by Embree). Without a collision the path meets the surface: it adds the
/// emission L_e (MIS-weighted against area-light sampling unless the previous vertex was the
/// camera or a delta lobe), crosses a `null` surface without counting a bounce, or scatters by
/// the BSDF: next-event estimation to a light, then a BSDF sample, β ← β·f·|cos θ_i|/pdf.
/// Next-event estimation at every vertex (medium or non-delta surface) picks the environment with
/// probability ½ and the area lights with ½ when both are sampled (else the one that is), with a
/// 1D selection number drawn before the 2D light sample when area lights exist. Shadow rays are
/// blocked by every surface but `null` ones, and carry the media's transmittance between them.
/// At surface vertices the product strategy's environment share is the sky hierarchy alone (the
/// phase lobe has no meaning there).
///
/// Radiance cache (render.radiance_cache, cache/radiance_cache.h). When a camera path's first
/// scattering vertex is a Lambert, Phong or Ward surface, the path ends there with
///   L = L_e + (direct light: n next-event samples and one BSDF sample, MIS-weighted as n·p_light
///        against p_bsdf, the BSDF ray weighted by the media's transmittance to the light it
///        meets; with mis "none" the light samples alone; the BSDF ray follows mirrors and
///        glass to the light it meets, weight 1) + Σ_i λ_i c_i(ω_o),
/// λ the cache's HSH coefficients of the incoming indirect radiance, c the BRDF table of the
/// surface (cache/hsh_brdf_table.h); where no record is valid the path goes on as without cache.
/// The records are made by the constructor, before any pixel: camera rays through pixel centres,
/// coarse to fine (every 16th pixel, then 8th, …, 1st), each visible cacheable point not yet
/// covered by a record gets one, from N stratified hemisphere rays traced by Li as record paths:
/// paths that leave out what the shading point's next-event estimation adds (the emission of
/// area lights, and the environment when it is light-sampled, met before any scattering) and
/// what its BSDF ray takes through mirrors and glass (any light met after delta surfaces alone).
/// The order is fixed and each ray has its own numbers, so the cache, and the image, do not
/// depend on the thread count.
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "shvol/cache/hsh_brdf_table.h"
#include "shvol/cache/radiance_cache.h"
#include "shvol/lights/product_sampler.h"
#include "shvol/render/effects.h"
#include "shvol/render/phase_weight_moments.h"
#include "shvol/render/scene.h"
#include "shvol/sampling/sobol_sampler.h"
#include "shvol/surfaces/area_lights.h"

namespace shvol {

/// Numbers from a sampler or a medium that no path can use: a NaN or negative pdf, value or
/// transmittance, a direction that is not finite, a NaN or negative flight distance. The path
/// (or light sample) that meets one is dropped, as a pdf of 0 drops it: its light is lost, and
/// the image is too dark by its share. Each is a defect (the loader refuses the parameters that
/// could make one), so they are counted by source and warned of, never dropped silently. The
/// BSDF and sky samplers pass a NaN density on rather than turn it into "no sample" (a pdf of
/// 0); a negative one stays a failed draw there, as their own failed branches are. An infinite
/// value is not counted here: the sample it makes is, as non-finite; an infinite pdf adds 0.
struct InvalidDraws {
    uint64_t phase = 0;          ///< phase-function samples and evaluations
    uint64_t bsdf = 0;           ///< BSDF samples and evaluations
    uint64_t light = 0;          ///< light samples (environment, emitting surfaces)
    uint64_t flight = 0;         ///< free-flight distances
    uint64_t transmittance = 0;  ///< transmittance estimates of shadow rays
    uint64_t total() const { return phase + bsdf + light + flight + transmittance; }
    void add(const InvalidDraws& o);
    /// f(key, words, count) for each source, in the order above: the stats' key and the
    /// warning's words (one list for both).
    template <typename F>
    void forEachSource(F&& f) const {
        f("phase", "from phase functions", phase);
        f("bsdf", "from BSDFs", bsdf);
        f("light", "from light sampling", light);
        f("flight", "free-flight distances", flight);
        f("transmittance", "transmittances", transmittance);
    }
};

/// The render's warning of d's draws, naming the sources with a count ("… (12 from phase
/// functions, 3 transmittances): …"), or "" if there are none.
std::string invalidDrawsWarning(const InvalidDraws& d);

/// Counters of the paths a thread traced, summed over threads into the render statistics.
struct PathCounters {
    uint64_t paths = 0;
    uint64_t scatteringEvents = 0;  ///< real collisions that scattered
    uint64_t phaseSamples = 0;
    uint64_t lightSamples = 0;       ///< light directions drawn at scattering events
    uint64_t productSamples = 0;     ///< of those, drawn by the product sampler
    uint64_t productPdfs = 0;        ///< product pdfs evaluated for the MIS weight of escapes
    uint64_t transmittanceRays = 0;  ///< shadow rays whose transmittance was estimated
    uint64_t surfaceHits = 0;        ///< surface points reached (null crossings included)
    uint64_t surfaceEvents = 0;      ///< of those, BSDF scattering events
    uint64_t areaLightSamples = 0;   ///< points drawn on emitting surfaces
    uint64_t shadowRays = 0;         ///< occlusion queries against the surfaces
    uint64_t cacheLookups = 0;       ///< radiance-cache queries at camera paths' first vertices
    uint64_t cacheHits = 0;          ///< of those, answered by the cache (the path ended)
    uint64_t cacheLookupNs = 0;      ///< time spent in them (steady clock)
    uint64_t nonFiniteSamples = 0;   ///< samples discarded because Li was NaN or Inf
    uint64_t truncatedPaths = 0;     ///< paths ended by max_depth (the light beyond it is lost)
    InvalidDraws invalid;            ///< unusable draws met (and dropped)
    TrackingCounters tracking;
    /// Camera paths by their SH-sampled phase weights' compounded second moment (counted only
    /// where a medium's phase is SH-sampled with "evaluate": "exact" and m₂ > 1).
    PhaseWeightMoments phaseWeights;
    void add(const PathCounters& o);
};

/// The share of paths ended by max_depth that is exceeded with 95% confidence: the one-sided lower
/// bound of a Poisson count of `truncated` (the λ with P(N ≥ truncated | λ) = 0.05, the inverse of
/// the regularised gamma function P(truncated, λ) at 0.05), over `paths`; 0 for none. One path of
/// 768 gives 0.0067%, five of 1536 0.13%, nine of nine 52%.
double truncatedShareLowerBound(uint64_t truncated, uint64_t paths);

class VolumePathIntegrator {
  public:
    /// At most this many `null` surfaces are crossed per ray (a guard against rays caught
    /// between coincident null surfaces).
    static constexpr int kMaxNullCrossings = 1024;
    /// A surface whose BRDF table gets its lobe's albedo wrong by more than this fraction
    /// (HshBrdfTable::albedoError) is path traced, not cached.
    static constexpr double kMaxTableAlbedoError = 0.1;
    /// Builds what the scene's effects need: the sky hierarchy for the wavelet and product
    /// strategies, for product sampling each medium's zonal phase lobe, and the radiance cache
    /// (BRDF tables, then records). `stop`, when given, is asked before each BRDF table and
    /// each record (a render's Ctrl-C): once it says true the cache is left part-filled, and
    /// must not be rendered with (the renderer then takes no sample).
    explicit VolumePathIntegrator(const Scene& scene, std::function<bool()> stop = {});
    /// Radiance arriving along −ray.d at ray.o (i.e. seen looking along ray.d). `Sampler` is
    /// a sample stream, Rng (independent numbers) or SobolSampler (sampling/sobol_sampler.h):
    /// per flight through active media a 2D pair for the free flight's first two numbers (its first
    /// exponential and acceptance test), then per bounce a 2D light sample (with next-event
    /// estimation) and a 2D phase sample, in that order; the rest of free-flight tracking,
    /// transmittance tracking and Russian roulette draw from its rng().
    /// A camera path, or a record path of the radiance cache (see the file comment).
    enum class PathKind { Camera, CacheRecord };
    template <typename Sampler>
    Spectrum Li(Ray ray, Sampler& sampler, PathCounters& c, PathKind kind = PathKind::Camera) const;
    const Effects& effects() const { return effects_; }
    /// The sky hierarchy (wavelet and product strategies only; else null).
    const SkyHierarchy* sky() const { return sky_.get(); }
    /// The product sampler (product strategy only; else null).
    const ProductSampler* product() const { return product_.get(); }
    /// Next-event estimation's light sample at a point x on a surface: the sky (by the scene's
    /// strategy; product sampling, which needs a phase lobe, as wavelet there) with probability
    /// environmentShare(), else the area lights. Direction, the radiance along it and the
    /// solid-angle density, the choice included (pdf 0: no sample). For the χ² test of this
    /// composition (its parts have their own).
    LightSample sampleLightsAtSurface(const Vec3& x, Rng& rng) const;
    /// The same at a scattering event in media[medium] at x on a path travelling along d (the
    /// product strategy's lobe is that medium's phase function around d), and the density that
    /// MIS gives an environment direction w there (choice included, as sampleLightsAtSurface's
    /// pdf). For the χ² test of light sampling in media.
    LightSample sampleLightsInMedium(const Vec3& x, const Vec3& d, size_t medium, Rng& rng) const;
    double environmentPdfInMedium(const Vec3& d, size_t medium, const Vec3& w) const;
    /// Probability that next-event estimation picks the environment (0 without NEE towards it,
    /// ½ beside area lights).
    double environmentShare() const;
    /// Seconds spent building the light-sampling structures.
    double setupSeconds() const { return setupSeconds_; }
    /// The radiance cache (null when not used), and what building it cost.
    const RadianceCache* radianceCache() const { return cache_.get(); }
    struct CacheBuild {
        double tableSeconds = 0, fillSeconds = 0;
        /// Each BRDF table's projection and peak errors, in the scene's order.
        std::vector<BrdfTableErrors> tableErrors;
        /// Surfaces whose lobe their BRDF table does not hold (HshBrdfTable::albedoError above
        /// kMaxTableAlbedoError): path traced, not cached; with that error, in the scene's order.
        std::vector<std::pair<std::string, double>> uncached;
        size_t tableBytes = 0;
        PathCounters counters;  ///< of the record paths
        /// Each record's irradianceRelativeError, in the order the records were made.
        std::vector<float> recordErrors;
    };
    const CacheBuild& cacheBuild() const { return cacheBuild_; }

  private:
    /// A medium's phase lobe for product sampling: zonal coefficients and defensive share β.
    struct Lobe {
        std::vector<double> p;
        int bands = 0;  ///< significant bands of p (ProductSampler::significantBands)
        double beta = 0;
    };
    /// The lobe of the current scattering event, rotated to the propagation direction.
    struct EventLobe {
        ProductSampler::ZonalLobe lobe;
        double beta = 0;
    };
    /// lobe = media[medium]'s product lobe around the path's direction d (product strategy).
    void setEventLobe(size_t medium, const Vec3& d, EventLobe& lobe) const;
    /// A light direction drawn at a scattering event: towards the environment (dist = ∞) or
    /// to the point y (normal ny) of an emitter at distance dist. pdf includes the choice of
    /// light.
    struct LightDraw {
        Vec3 wi;
        Spectrum Le;
        double pdf;
        double dist = NoHit;
        Vec3 y{0, 0, 0}, ny{0, 0, 1};
    };
    /// Where a vertex is: it decides the environment strategy (the product needs a phase lobe).
    enum class Vertex { Medium, Surface };
    template <typename Sampler>
    LightDraw sampleLights(const Vec3& x, Vertex v, const EventLobe& lobe, Sampler& sampler,
                           PathCounters& c) const;
    /// ls, or (counted in c.invalid.light) a draw of pdf 0 where it is not usable (InvalidDraws).
    static LightDraw usableLightDraw(LightDraw ls, PathCounters& c);
    LightDraw sampleEnvironment(Vertex v, const EventLobe& lobe, const Vec2& u,
                                PathCounters& c) const;
    /// Density of sampleLights for the environment direction w (choice included).
    double environmentPdf(Vertex v, const EventLobe& lobe, const Vec3& w, PathCounters& c) const;
    /// The MIS weight of a strategy with density pa against one with density pb.
    double misWeight(double pa, double pb) const;

    /// A set of bounded media the path is inside: bit mediumBit_[k] for media[k].
    using Inside = uint64_t;
    bool active(size_t medium, Inside inside) const {
        return mediumBit_[medium] < 0 || ((inside >> mediumBit_[medium]) & 1);
    }
    /// Whether a flight inside `inside` crosses any medium (then it draws its flight numbers, so
    /// that a flight outside every bounded medium leaves the sample stream as it is).
    bool anyActive(Inside inside) const {
        for (size_t i = 0; i < mediumBit_.size(); ++i)
            if (active(i, inside)) return true;
        return false;
    }
    /// Whether no light can be seen from inside `inside`: the set holds a medium bounded by a
    /// delta surface that is not a `null` one (closed, as boundaries are), which blocks every
    /// shadow ray to the sky and to lamps outside it, and no emitting surface's bounds meet the
    /// boundary's. Next-event estimation is skipped there: it drew a light sample and traced a
    /// shadow ray for nothing at every vertex inside (fog in a glass ball with NEE on: about
    /// twice the time, helper 108; milk_glass, whose lamp is outside: 1.72×, helper 169).
    bool sealed(Inside inside) const { return (inside & sealed_) != 0; }
    /// The bounded media containing p (asked of Embree), and the same answered from the cache
    /// for the camera position.
    Inside insideOf(const Vec3& p) const;
    Inside insideAt(const Vec3& p) const;
    /// `inside` after a ray along d crosses the surface of `hit`.
    Inside crossed(const SurfaceHit& hit, const Vec3& d, Inside inside) const;

    /// Nearest real collision in [0, tMax) over the active media; sets *medium to its index (−1:
    /// none). `first` gives the first two numbers (FlightNumbers) of the first active medium
    /// whose bounds the ray meets; it is not computed if there is none.
    double sampleCollision(const Ray& ray, double tMax, Inside inside, Rng& rng,
                           const DeferredPair& first, PathCounters& c, int* medium) const;
    /// Whether the ray meets the bounds of media[i] within [0, tMax] (else σ_t = 0 along it).
    bool meets(size_t i, const Ray& ray, double tMax) const {
        return mediumBounds_[i].hits(ray, tMax);
    }
    /// Product of the active media's transmittance estimates along [0, tMax), by `est` (the
    /// scene's render.transmittance unless given).
    double transmittance(const Ray& ray, double tMax, Inside inside, Rng& rng, PathCounters& c,
                         std::optional<TransmittanceEstimator> est = std::nullopt) const;
    /// Transmittance from x (a surface point with normal ng when ng ≠ 0) to the light of ls:
    /// 0 when a surface other than a `null` one is in the way.
    double visibility(const Vec3& x, const Vec3& ng, const LightDraw& ls, Inside inside, Rng& rng,
                      PathCounters& c) const;

    const Scene& scene_;
    Effects effects_;
    std::unique_ptr<const SkyHierarchy> sky_;
    std::unique_ptr<const ProductSampler> product_;
    std::vector<Lobe> lobes_;  ///< per medium (product sampling)
    /// Per medium: ln m₂ of its SH-sampled phase weights where they are not 1, else 0; and
    /// whether any is not (then camera paths are counted in PathCounters::phaseWeights).
    std::vector<double> phaseLnM2_;
    bool phaseWeights_ = false;
    std::vector<Bounds3> mediumBounds_;             ///< per medium (Medium::bounds)
    std::unique_ptr<const AreaLights> areaLights_;  ///< when some surface emits
    std::vector<int> mediumBit_;   ///< per medium: its bit in Inside, or −1 if unbounded
    std::vector<int> boundaryOf_;  ///< per bounded medium bit: its surface
    /// What the light-sampling strategy needs, in setupSeconds(): an image sky's texel tables
    /// (environment strategy), or buildSkySamplers().
    void buildLightSamplers();
    /// The sky hierarchy, and for the product strategy its sampler and the media's phase lobes.
    void buildSkySamplers();
    /// The cache's first pass (constructor): records at visible cacheable points.
    void buildRadianceCache(const std::function<bool()>& stop);
    /// What a record ray meets first: the first surface that is not a `null` one, or, where the
    /// media along the ray let less than kOpaqueTransmittance through (ratio tracking), their
    /// first real collision, drawn by delta tracking (where the ray's light is absorbed or
    /// scattered), if it lies more than a mean free path away (σ_t there × distance ≥ 1; nearer
    /// ones, in a deep fog, ruled R's harmonic mean): a dense fog is as much an occluder to a
    /// record as a wall, and taken for a miss it let records reach across and under it (a floor
    /// beside a cube of σ_t 50: −3.5%; helper 108). A thin fog's collisions are not: at every
    /// distance, near ones dominated the harmonic mean R (a Cornell box of thin fog made its 20,000
    /// records in 23 s, against 2547 in 2.9 s). Sets the point W and its normal nW (−ray.d for a
    /// collision); false if the ray meets nothing. rng draws the tracking's numbers.
    bool firstMet(const Ray& ray, Rng& rng, Vec3* W, Vec3* nW) const;
    /// Walks the ray past `null` surfaces to the first other one (*end; true), or out of the
    /// scene (false), calling stretch(ray, tMax, inside) → bool for each stretch through active
    /// media: false stops the walk (false).
    template <typename Stretch>
    bool walkToSolid(Ray ray, Stretch&& stretch, SurfaceHit* end) const;
    static constexpr double kOpaqueTransmittance = 0.1;
    /// The irradiance ∫ L cos θ dω that next-event estimation adds at a record's point (hit, with
    /// the records' normal n) and its records leave out, from 16 light samples drawn with rng: the
    /// light a record's noise is measured against besides its own (irradianceRelativeError). 0
    /// without next-event estimation. Draws no path can use are counted in the cache build's.
    double directIrradiance(const SurfaceHit& hit, const Vec3& n, Rng rng);
    /// Outgoing radiance from the cache at a camera path's first surface vertex; false if no record
    /// is valid there.
    bool cachedRadiance(const SurfaceHit& hit, const Vec3& wo, Spectrum* L, PathCounters& c) const;
    std::unique_ptr<RadianceCache> cache_;
    std::vector<std::shared_ptr<const HshBrdfTable>> tables_;  ///< per surface; null: not cached
    CacheBuild cacheBuild_;
    Vec3 cameraPosition_;
    Inside cameraInside_ = 0;  ///< the bounded media containing the camera position
    Inside sealed_ = 0;        ///< bounded media whose boundary hides every light (sealed)
    /// Some surface is a mirror or glass: a cached vertex follows its BSDF sample through such
    /// surfaces to the light it meets, and records leave that light out (Li).
    bool deltaSurfaces_ = false;
    double setupSeconds_ = 0;
};

}  // namespace shvol
