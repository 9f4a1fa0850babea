#include "shvol/render/camera.h"

namespace shvol {

Camera::Frame Camera::frame() const {
    Frame f;
    f.type = type;
    f.position = position;
    f.forward = (target - position).normalized();
    f.right = f.forward.cross(up).normalized();
    f.up = f.right.cross(f.forward);
    f.aspect = double(width) / height;
    f.tanHalf = std::tan(0.5 * fovDegrees * Pi / 180);
    f.extent = extent;
    f.width = width, f.height = height;
    return f;
}

Ray Camera::Frame::generateRay(double px, double py) const {
    const double sx = 2 * px / width - 1, sy = 1 - 2 * py / height;  // ∈ [−1, 1], y up
    if (type == Type::Orthographic) {
        const Vec3 o = position + sx * 0.5 * extent * right + sy * 0.5 * extent / aspect * up;
        return {o, forward};
    }
    return {position, (forward + sx * tanHalf * aspect * right + sy * tanHalf * up).normalized()};
}

}  // namespace shvol
