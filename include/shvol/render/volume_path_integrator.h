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
/// Russian roulette on max(β) after rrDepth scattering events. Without scattering (albedo 0 or
/// max depth 0) a camera ray returns T̂·L_env directly: no collision or phase sample is drawn.
#include <memory>
#include <vector>

#include "shvol/lights/product_sampler.h"
#include "shvol/render/effects.h"
#include "shvol/render/scene.h"
#include "shvol/sampling/sobol_sampler.h"

namespace shvol {

/// Per-thread counters, summed into the render statistics.
struct PathCounters {
    uint64_t paths = 0;
    uint64_t scatteringEvents = 0;  ///< real collisions that scattered
    uint64_t phaseSamples = 0;
    uint64_t lightSamples = 0;       ///< light directions drawn at scattering events
    uint64_t productSamples = 0;     ///< of those, drawn by the product sampler
    uint64_t productPdfs = 0;        ///< product pdfs evaluated for the MIS weight of escapes
    uint64_t transmittanceRays = 0;  ///< shadow rays whose transmittance was estimated
    uint64_t nonFiniteSamples = 0;   ///< samples discarded because Li was NaN or Inf
    TrackingCounters tracking;
    void add(const PathCounters& o);
};

class VolumePathIntegrator {
  public:
    /// Builds what the scene's effects need: the sky hierarchy for the wavelet and product
    /// strategies, and for product sampling each medium's zonal phase lobe.
    explicit VolumePathIntegrator(const Scene& scene);
    /// Radiance arriving along −ray.d at ray.o (i.e. seen looking along ray.d). `Sampler` is
    /// a sample stream, Rng (independent numbers) or SobolSampler (sampling/sobol_sampler.h):
    /// per bounce a 2D light sample (with next-event estimation), a 2D phase sample and a 1D
    /// Russian-roulette number, in that order; free-flight and transmittance tracking draw from
    /// its rng().
    template <typename Sampler>
    Spectrum Li(Ray ray, Sampler& sampler, PathCounters& c) const;
    const Effects& effects() const { return effects_; }
    /// The sky hierarchy (wavelet and product strategies only; else null).
    const SkyHierarchy* sky() const { return sky_.get(); }
    /// The product sampler (product strategy only; else null).
    const ProductSampler* product() const { return product_.get(); }
    /// Seconds spent building the light-sampling structures.
    double setupSeconds() const { return setupSeconds_; }

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
    /// A light direction drawn at a scattering event.
    struct LightDraw {
        Vec3 wi;
        Spectrum Le;
        double pdf;
    };
    LightDraw sampleLight(const EventLobe& lobe, const Vec2& u, PathCounters& c) const;
    double lightPdf(const EventLobe& lobe, const Vec3& w, PathCounters& c) const;
    /// The MIS weight of a strategy with density pa against one with density pb.
    double misWeight(double pa, double pb) const;

    /// Nearest real collision over all media; sets *medium to its index (−1: none).
    double sampleCollision(const Ray& ray, Rng& rng, PathCounters& c, int* medium) const;
    /// Product of the media's transmittance estimates along the whole ray.
    double transmittance(const Ray& ray, Rng& rng, PathCounters& c) const;

    const Scene& scene_;
    Effects effects_;
    std::unique_ptr<const SkyHierarchy> sky_;
    std::unique_ptr<const ProductSampler> product_;
    std::vector<Lobe> lobes_;  ///< per medium (product sampling)
    double setupSeconds_ = 0;
};

}  // namespace shvol
