#include "shvol/sampling/warp.h"

namespace shvol {

Vec3 sampleUniformSphere(const Vec2& u) {
    return sphericalDirection(1.0 - 2.0 * u.x(), TwoPi * u.y());
}

Vec3 sampleUniformHemisphere(const Vec2& u) {
    return sphericalDirection(u.x(), TwoPi * u.y());
}

Vec3 sampleCosineHemisphere(const Vec2& u) {
    const double r = std::sqrt(u.x()), phi = TwoPi * u.y();
    const Vec2 cs = cosSin(phi);
    return {r * cs.x(), r * cs.y(), std::sqrt(1.0 - u.x())};
}

}  // namespace shvol
