#pragma once
#include "shvol/core/math.h"

namespace shvol {

/// r(t) = o + t·d; d is unit length everywhere in shvol so t is a distance in scene units.
struct Ray {
    Vec3 o{0, 0, 0};
    Vec3 d{0, 0, 1};
    Vec3 operator()(double t) const { return o + t * d; }
};

/// Parametric interval [t0, t1] along a ray; empty when t0 > t1.
struct Interval {
    double t0 = 0, t1 = -1;
    bool empty() const { return !(t0 <= t1); }
};

/// Slab test of a ray against an axis-aligned (closed) box, clipped to [0, tMax]. *entryAxis (if
/// given) is set to the axis whose slab sets t0, the face the ray enters by (−1: t0 = 0).
inline Interval intersectBox(const Ray& ray, const Vec3& lo, const Vec3& hi, double tMax,
                             int* entryAxis = nullptr) {
    if (entryAxis) *entryAxis = -1;
    double t0 = 0, t1 = tMax;
    for (int a = 0; a < 3; ++a) {
        // A ray parallel to the slab stays in it or out of it: decided by the origin, not by
        // 0·∞ (NaN) on a face, whose outcome would depend on the sign of the zero.
        if (ray.d[a] == 0) {
            if (ray.o[a] < lo[a] || ray.o[a] > hi[a]) return {};
            continue;
        }
        const double inv = 1.0 / ray.d[a];
        double tn = (lo[a] - ray.o[a]) * inv, tf = (hi[a] - ray.o[a]) * inv;
        if (tn > tf) std::swap(tn, tf);
        // NaN (0·inf for a subnormal component with the origin on a slab plane, or a NaN
        // direction) must not widen the interval.
        if (tn > t0) {
            t0 = tn;
            if (entryAxis) *entryAxis = a;
        }
        if (tf < t1) t1 = tf;
        if (t0 > t1) return {};
    }
    return {t0, t1};
}

/// An axis-aligned box [lo, hi]; by default all of space, and empty when lo > hi on some axis.
struct Bounds3 {
    Vec3 lo = Vec3::Constant(-INFINITY), hi = Vec3::Constant(INFINITY);
    bool isEverywhere() const {
        return (lo.array() == -INFINITY).all() && (hi.array() == INFINITY).all();
    }
    bool empty() const { return (lo.array() > hi.array()).any(); }
    /// Whether the (closed) boxes share a point; never for an empty one.
    bool meets(const Bounds3& b) const {
        return (lo.array() <= b.hi.array()).all() && (b.lo.array() <= hi.array()).all() &&
               !empty() && !b.empty();
    }
    /// Whether the ray meets the box within [0, tMax] (never, if the box is empty; always, with
    /// no slab test and whatever tMax, if it is all of space). A ray from a point of the (closed)
    /// box meets it iff tMax ≥ 0, which is what the slab test gives there too; checked first,
    /// without the slab test's three divisions, since most rays in a medium start inside its
    /// bounds.
    bool hits(const Ray& ray, double tMax) const {
        if (isEverywhere()) return true;
        if ((ray.o.array() >= lo.array()).all() && (ray.o.array() <= hi.array()).all())
            return tMax >= 0;
        return !empty() && !intersectBox(ray, lo, hi, tMax).empty();
    }
};
/// Ray against a sphere (center c, radius r), clipped to [0, tMax].
Interval intersectSphere(const Ray& ray, const Vec3& c, double r, double tMax);

}  // namespace shvol
