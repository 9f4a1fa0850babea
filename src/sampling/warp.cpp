#include "shvol/sampling/warp.h"

namespace shvol {

Vec3 sampleUniformSphere(const Vec2& u) {
    return sphericalDirection2Pi(1.0 - 2.0 * u.x(), u.y());
}

Vec3 sampleUniformHemisphere(const Vec2& u) {
    return sphericalDirection2Pi(u.x(), u.y());
}

Vec3 sampleCosineHemisphere(const Vec2& u) {
    const double r = std::sqrt(u.x());
    const Vec2 cs = cosSin2Pi(u.y());
    return {r * cs.x(), r * cs.y(), std::sqrt(1.0 - u.x())};
}

}  // namespace shvol
