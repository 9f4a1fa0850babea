#include "shvol/core/ray.h"

namespace shvol {

Interval intersectBox(const Ray& ray, const Vec3& lo, const Vec3& hi, double tMax) {
    double t0 = 0, t1 = tMax;
    for (int a = 0; a < 3; ++a) {
        const double inv = 1.0 / ray.d[a];  // ±inf for axis-parallel rays is handled by IEEE
        double tn = (lo[a] - ray.o[a]) * inv, tf = (hi[a] - ray.o[a]) * inv;
        if (tn > tf) std::swap(tn, tf);
        // NaN (0·inf when the origin lies on a slab plane) must not widen the interval.
        if (tn > t0) t0 = tn;
        if (tf < t1) t1 = tf;
        if (t0 > t1) return {};
    }
    return {t0, t1};
}

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
