#include "shvol/render/camera.h"

namespace shvol {

Ray Camera::generateRay(double px, double py) const {
    const Vec3 forward = (target - position).normalized();
    const Vec3 right = forward.cross(up).normalized();
    const Vec3 upv = right.cross(forward);
    const double aspect = double(width) / height;
    const double sx = 2 * px / width - 1, sy = 1 - 2 * py / height;  // ∈ [−1, 1], y up
    if (type == Type::Orthographic) {
        const Vec3 o = position + sx * 0.5 * extent * right + sy * 0.5 * extent / aspect * upv;
        return {o, forward};
    }
    const double tanHalf = std::tan(0.5 * fovDegrees * Pi / 180);
    return {position, (forward + sx * tanHalf * aspect * right + sy * tanHalf * upv).normalized()};
}

}  // namespace shvol
