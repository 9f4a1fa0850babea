#include "shvol/core/ray.h"

namespace shvol {

Interval intersectSphere(const Ray& ray, const Vec3& c, double r, double tMax) {
    // Numerically robust form (Haines et al., Ray Tracing Gems ch. 7): use the projected
    // closest-approach distance rather than b² − 4ac.
    const Vec3 f = ray.o - c;
    const double b = -f.dot(ray.d);
    const Vec3 l = f + b * ray.d;
    const double disc = r * r - l.squaredNorm();
    if (disc < 0) return {};
    const double q = b + std::copysign(std::sqrt(disc), b);
    double ta = q, tb = (f.squaredNorm() - r * r) / (q == 0 ? 1e-300 : q);
    if (ta > tb) std::swap(ta, tb);
    Interval iv{std::max(ta, 0.0), std::min(tb, tMax)};
    return iv.empty() ? Interval{} : iv;
}

}  // namespace shvol
