#pragma once
/// \file Unbiased volumetric path tracing with delta tracking, NEE and MIS.
///
/// Along a path with throughput β, free flights are sampled by delta tracking (the nearest real
/// collision over all media: superposed Poisson processes). At a real collision in medium k,
/// β ← β·α_k and the in-scattered radiance ∫ p(ω·ω′) T L_env(ω′) dω′ is estimated twice,
/// combined with the balance heuristic (Veach 1997, §9.2):
///  - NEE: ω′ ~ p_env, contribution β·p(ω·ω′)·T̂(x, ω′)·L_env(ω′)·w_env/p_env, with
///    w_env = p_env/(p_env + p_phase) and T̂ from ratio tracking (or the closed form);
///  - phase sampling: ω′ ~ p_phase; if the next free flight escapes, the path adds
///    β·(f/p_phase)·L_env(ω′)·w_phase, w_phase = p_phase/(p_env + p_phase). Escape happens with
///    probability T, so no transmittance estimate is needed on that branch.
/// Russian roulette on max(β) after rrDepth scattering events. Without scattering (albedo 0 or
/// max depth 0) a camera ray returns T̂·L_env directly: no collision or phase sample is drawn.
#include "shvol/render/effects.h"
#include "shvol/render/scene.h"

namespace shvol {

/// Per-thread counters, summed into the render statistics.
struct PathCounters {
    uint64_t paths = 0;
    uint64_t scatteringEvents = 0;  ///< real collisions that scattered
    uint64_t phaseSamples = 0;
    uint64_t lightSamples = 0;       ///< NEE directions drawn
    uint64_t transmittanceRays = 0;  ///< shadow rays whose transmittance was estimated
    uint64_t nonFiniteSamples = 0;   ///< samples discarded because Li was NaN or Inf
    TrackingCounters tracking;
    void add(const PathCounters& o);
};

class VolumePathIntegrator {
  public:
    explicit VolumePathIntegrator(const Scene& scene);
    /// Radiance arriving along −ray.d at ray.o (i.e. seen looking along ray.d).
    Spectrum Li(Ray ray, Rng& rng, PathCounters& c) const;
    const Effects& effects() const { return effects_; }

  private:
    /// Nearest real collision over all media; sets *medium.
    double sampleCollision(const Ray& ray, Rng& rng, PathCounters& c, const Medium** medium) const;
    /// Product of the media's transmittance estimates along the whole ray.
    double transmittance(const Ray& ray, Rng& rng, PathCounters& c) const;

    const Scene& scene_;
    Effects effects_;
};

}  // namespace shvol
