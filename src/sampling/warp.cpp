#include "shvol/sampling/warp.h"

namespace shvol {

Vec3 sampleUniformSphere(const Vec2& u) {
    return sphericalDirection(1.0 - 2.0 * u.x(), TwoPi * u.y());
}

Vec3 sampleUniformHemisphere(const Vec2& u) {
    return sphericalDirection(u.x(), TwoPi * u.y());
}

}  // namespace shvol
