#pragma once
/// \file The medium interface: a coarse object (virtual per ray segment, never per lookup).
///
/// Extinction σ_t(x) is grey (one value for all channels) so that one free-flight distance serves
/// RGB; the single-scattering albedo α = σ_s/σ_t is RGB. The radiative transfer equation solved
/// by the integrator is
///   L(x, ω) = ∫_0^d T(x, x_t) σ_s(x_t) ∫ p(ω·ω′) L(x_t, ω′) dω′ dt + T(x, x_d) L_env(ω),
/// with T(x, y) = exp(−∫ σ_t) and no emission.
#include <memory>
#include <string>

#include "shvol/core/ray.h"
#include "shvol/media/tracking.h"
#include "shvol/phase/phase_function.h"

namespace shvol {

/// How a transmittance along a shadow ray is estimated.
enum class TransmittanceEstimator {
    Ratio,  ///< ratio tracking (or the closed form where a medium has one)
    Delta,  ///< binary delta-tracking estimate (higher variance; for validation)
};

class Medium {
  public:
    Medium(Spectrum albedo, PhaseFunction phase) : albedo_(albedo), phase_(std::move(phase)) {}
    virtual ~Medium() = default;

    /// Distance t ∈ [0, tMax) of the first real collision along the ray, or NoCollision.
    /// Its density is σ_t(t)·T(0, t). The flight's first two uniform numbers come from `first`
    /// when it is given (a stratified pair of the path's sample stream; FlightNumbers), the
    /// others from rng.
    virtual double sampleCollision(const Ray& ray, double tMax, Rng& rng, TrackingCounters& c,
                                   const Vec2* first = nullptr) const = 0;
    /// Unbiased estimate of T(0, tMax) along the ray.
    virtual double transmittance(const Ray& ray, double tMax, TransmittanceEstimator est, Rng& rng,
                                 TrackingCounters& c) const = 0;
    /// σ_t at a world-space point (for tests and tools; not used in hot loops).
    virtual double sigmaT(const Vec3& p) const = 0;
    /// The majorant tracking uses at p (≥ sigmaT(p) everywhere; for tests and diagnostics).
    virtual double sigmaMajorant(const Vec3& p) const = 0;
    /// A world-space box outside which σ_t = 0 (all of space unless a medium knows better): the
    /// integrator skips the medium, and its flight's numbers, on rays that miss it.
    virtual Bounds3 bounds() const { return {}; }
    /// Short description for statistics ("homogeneous box", "vdb cloud.vdb:density").
    virtual std::string describe() const = 0;

    const Spectrum& albedo() const { return albedo_; }
    const PhaseFunction& phase() const { return phase_; }
    bool scatters() const { return albedo_.maxCoeff() > 0; }

  private:
    Spectrum albedo_;
    PhaseFunction phase_;
};

}  // namespace shvol
