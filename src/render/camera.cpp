#include "shvol/render/camera.h"

namespace shvol {

// The film point (px, py) maps to s = (2px/width − 1, 1 − 2py/height) ∈ [−1, 1]² (y up); the
// perspective direction is forward + s_x·tan(fov/2)·aspect·right + s_y·tan(fov/2)·up, the
// orthographic origin position + s_x·extent/2·right + s_y·extent/(2·aspect)·up.
Camera::Frame Camera::frame() const {
    // (Stable: a camera 1e300 from its target, or an up of 1e300, must not overflow the norm.)
    const Vec3 forward = (target - position).stableNormalized();
    const Vec3 right = forward.cross(up.stableNormalized()).normalized();
    const Vec3 upward = right.cross(forward);
    const double aspect = double(width) / height;
    const bool ortho = type == Type::Orthographic;
    const double tanHalf = std::tan(0.5 * fovDegrees * Pi / 180);
    // Half the film's width and height in the plane at unit distance (or in scene units).
    const double hx = ortho ? 0.5 * extent : tanHalf * aspect;
    const double hy = ortho ? 0.5 * extent / aspect : tanHalf;
    Frame f;
    f.type = type;
    f.dx = (2 * hx / width) * right;
    f.dy = (-2 * hy / height) * upward;
    const Vec3 corner = -hx * right + hy * upward;  // s = (−1, 1): the top left
    f.origin = ortho ? Vec3(position + corner) : position;
    f.direction = ortho ? forward : Vec3(forward + corner);
    return f;
}

}  // namespace shvol
