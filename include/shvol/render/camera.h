#pragma once
/// \file Pinhole (perspective) and orthographic cameras.
#include <cmath>

#include "shvol/core/ray.h"

namespace shvol {

struct Camera {
    enum class Type { Perspective, Orthographic } type = Type::Perspective;
    Vec3 position{0, -4, 0}, target{0, 0, 0}, up{0, 0, 1};
    double fovDegrees = 40;  ///< perspective: vertical field of view
    double extent = 2;       ///< orthographic: width of the view in scene units
    int width = 320, height = 240;

    /// What every ray of the camera shares, computed once per render instead of once per ray:
    /// the ray through film point (px, py) starts at origin + px·dx + py·dy (orthographic) and
    /// points along direction + px·dx + py·dy (perspective).
    struct Frame {
        Type type;
        Vec3 origin, direction, dx, dy;
        /// Ray through the continuous film point (px, py): px ∈ [0, width) left→right,
        /// py ∈ [0, height) top→bottom. Direction is unit length.
        Ray generateRay(double px, double py) const {
            const Vec3 offset = px * dx + py * dy;
            if (type == Type::Orthographic) return {origin + offset, direction};
            const Vec3 d = direction + offset;
            return {origin, d * (1 / std::sqrt(d.squaredNorm()))};
        }
    };
    Frame frame() const;
};

}  // namespace shvol
