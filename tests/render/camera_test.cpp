// Camera::Frame::generateRay (precomputed film steps) against the camera model written out per
// ray, for both camera types, and the field of view it must have.
#include "shvol/render/camera.h"

#include <gtest/gtest.h>

#include <cmath>

namespace shvol {
namespace {

/// The ray through film point (px, py), from the camera's parameters with no precomputation.
Ray referenceRay(const Camera& c, double px, double py) {
    const Vec3 forward = (c.target - c.position).normalized();
    const Vec3 right = forward.cross(c.up).normalized();
    const Vec3 up = right.cross(forward);
    const double aspect = double(c.width) / c.height;
    const double sx = 2 * px / c.width - 1, sy = 1 - 2 * py / c.height;
    if (c.type == Camera::Type::Orthographic)
        return {c.position + sx * 0.5 * c.extent * right + sy * 0.5 * c.extent / aspect * up,
                forward};
    const double t = std::tan(0.5 * c.fovDegrees * Pi / 180);
    return {c.position, (forward + sx * t * aspect * right + sy * t * up).normalized()};
}

Camera camera(Camera::Type type) {
    Camera c;
    c.type = type;
    c.position = Vec3(0.3, -3.2, 0.7);
    c.target = Vec3(-0.1, 0.2, 0.05);
    c.up = Vec3(0.1, 0, 1);
    c.fovDegrees = 36;
    c.extent = 2.5;
    c.width = 160, c.height = 240;
    return c;
}

}  // namespace

TEST(Camera, GenerateRayMatchesTheModel) {
    for (Camera::Type type : {Camera::Type::Perspective, Camera::Type::Orthographic}) {
        const Camera c = camera(type);
        const Camera::Frame f = c.frame();
        for (double px : {0.0, 0.5, 37.25, 80.0, 159.999})
            for (double py : {0.0, 1.5, 120.0, 239.75}) {
                const Ray a = f.generateRay(px, py), b = referenceRay(c, px, py);
                EXPECT_LT((a.o - b.o).norm(), 1e-12) << px << " " << py;
                EXPECT_LT((a.d - b.d).norm(), 1e-12) << px << " " << py;
                EXPECT_NEAR(a.d.norm(), 1.0, 1e-14);
            }
    }
}

// The vertical field of view: rays through the top and bottom film edges at the centre column
// are fovDegrees apart.
TEST(Camera, VerticalFieldOfView) {
    const Camera c = camera(Camera::Type::Perspective);
    const Camera::Frame f = c.frame();
    const Vec3 top = f.generateRay(80, 0).d, bottom = f.generateRay(80, 240).d;
    EXPECT_NEAR(std::acos(top.dot(bottom)) * 180 / Pi, 36.0, 1e-10);
}

// A camera 10^300 from its target, with an up of 10^300: its frame must not overflow (a plain
// norm squares the components) and gives the camera the nearby one has.
TEST(Camera, FarCameraHasAFiniteFrame) {
    Camera near = camera(Camera::Type::Perspective), far = near;
    near.position = Vec3(0, -3, 0), near.target = Vec3(0, 0, 0), near.up = Vec3(0, 0, 1);
    far.position = Vec3(0, -1e300, 0), far.target = Vec3(0, 0, 0), far.up = Vec3(0, 0, 1e300);
    const Ray a = near.frame().generateRay(37.25, 120), b = far.frame().generateRay(37.25, 120);
    ASSERT_TRUE(b.d.allFinite());
    EXPECT_LT((a.d - b.d).norm(), 1e-12);
    EXPECT_EQ(b.o, far.position);
}

}  // namespace shvol
