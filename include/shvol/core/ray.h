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

/// Slab test of a ray against an axis-aligned box, clipped to [0, tMax].
Interval intersectBox(const Ray& ray, const Vec3& lo, const Vec3& hi, double tMax);
/// Ray against a sphere (center c, radius r), clipped to [0, tMax].
Interval intersectSphere(const Ray& ray, const Vec3& c, double r, double tMax);

}  // namespace shvol
