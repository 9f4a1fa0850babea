#pragma once
/// \file A homogeneous medium filling a box or a sphere.
///
/// Closed forms (the default): free flight t = −ln(1−u)/σ_t, transmittance T = exp(−σ_t ℓ).
/// With `tracking = true` the same medium is instead tracked against a majorant 2σ_t, so that
/// half the tentative collisions are null: this exercises delta and ratio tracking against the
/// closed form in tests and validation.
#include "shvol/media/medium.h"

namespace shvol {

struct MediumShape {
    /// Everywhere: no shape of its own, for a medium bounded by a closed surface
    /// (media[i].boundary) that the integrator makes active only inside that surface.
    enum class Type { Box, Sphere, Everywhere } type = Type::Box;
    Vec3 lo{0, 0, 0}, hi{1, 1, 1};  ///< box corners
    Vec3 center{0, 0, 0};           ///< sphere
    double radius = 1;
    Interval intersect(const Ray& ray, double tMax) const;
    bool contains(const Vec3& p) const;
};

class HomogeneousMedium final : public Medium {
  public:
    HomogeneousMedium(MediumShape shape, double sigmaT, Spectrum albedo, PhaseFunction phase,
                      bool tracking = false);
    double sampleCollision(const Ray& ray, double tMax, Rng& rng, TrackingCounters& c,
                           const Vec2* first = nullptr) const override;
    double transmittance(const Ray& ray, double tMax, TransmittanceEstimator est, Rng& rng,
                         TrackingCounters& c) const override;
    double sigmaT(const Vec3& p) const override { return shape_.contains(p) ? sigmaT_ : 0; }
    double sigmaMajorant(const Vec3& p) const override {
        return shape_.contains(p) ? (tracking_ ? 2 : 1) * sigmaT_ : 0;
    }
    Bounds3 bounds() const override;
    std::string describe() const override;

  private:
    MediumShape shape_;
    double sigmaT_;
    bool tracking_;
};

}  // namespace shvol
