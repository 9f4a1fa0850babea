#pragma once
/// \file Pinhole (perspective) and orthographic cameras.
#include "shvol/core/ray.h"

namespace shvol {

struct Camera {
    enum class Type { Perspective, Orthographic } type = Type::Perspective;
    Vec3 position{0, -4, 0}, target{0, 0, 0}, up{0, 0, 1};
    double fovDegrees = 40;  ///< perspective: vertical field of view
    double extent = 2;       ///< orthographic: width of the view in scene units
    int width = 320, height = 240;

    /// What every ray of the camera shares (its frame and the tangent of the half field of
    /// view), computed once per render instead of once per ray.
    struct Frame {
        Type type;
        Vec3 position, forward, right, up;
        double aspect, tanHalf, extent;
        int width, height;
        /// Ray through the continuous film point (px, py): px ∈ [0, width) left→right,
        /// py ∈ [0, height) top→bottom. Direction is unit length.
        Ray generateRay(double px, double py) const;
    };
    Frame frame() const;
};

}  // namespace shvol
