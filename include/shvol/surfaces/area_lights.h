#pragma once
/// \file Sampling points on emitting surfaces for next-event estimation (pbrt-v4 §12.5).
///
/// An emitter is chosen with probability proportional to its power Φ ∝ A · lum(L_e) (twice that
/// when it emits from both sides). On the emitter a point y is drawn
///  - uniformly by area on meshes, rectangles and disks (a triangle by area, then a uniform point
///    in it): p_A = 1/A, converted to solid angle at the reference point x as
///    p_ω = p_A · |x − y|² / |cos θ_y|;
///  - on a sphere seen from outside, uniformly in the cone of directions it subtends (pbrt-v4
///    §6.2.4): p_ω = 1 / (2π (1 − cos θ_max)), sin θ_max = r / |x − c|; from inside, or when it
///    emits from both sides (its far side may then shine through), by area.
/// Every pdf returned includes the probability of choosing the emitter.
#include <optional>
#include <vector>

#include "shvol/sampling/distribution_1d.h"
#include "shvol/surfaces/surface_scene.h"

namespace shvol {

/// A point y on an emitter seen from x: wi = (y − x)/|y − x|, dist = |y − x|, L_e leaving y
/// towards x, pdf over solid angle at x (0 when the sample failed).
struct AreaLightSample {
    Vec3 y, ny;  ///< the point and its geometric normal
    Vec3 wi;
    double dist = 0;
    Spectrum Le = Spectrum::Zero();
    double pdf = 0;
    int surface = -1;
};

class AreaLights {
  public:
    explicit AreaLights(const SurfaceScene& scene);
    bool empty() const { return emitters_.empty(); }
    size_t count() const { return emitters_.size(); }
    /// Draws an emitter with uSelect and a point on it with u.
    AreaLightSample sample(const Vec3& x, double uSelect, const Vec2& u) const;
    /// Solid-angle pdf at x of sample() producing the point y (normal ny) on surface s.
    double pdf(const Vec3& x, int s, const Vec3& y, const Vec3& ny) const;

  private:
    struct Emitter {
        int surface;
        std::optional<Distribution1D> triangles;  ///< meshes and rectangles: by area
        double area;
    };
    const SurfaceScene& scene_;
    std::vector<Emitter> emitters_;
    std::vector<int> emitterOf_;            ///< per surface: its index in emitters_, or −1
    std::optional<Distribution1D> select_;  ///< by power
};

}  // namespace shvol
