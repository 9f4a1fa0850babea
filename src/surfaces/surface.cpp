#include "shvol/surfaces/surface.h"

namespace shvol {

double Surface::area() const {
    switch (kind) {
        case Kind::Sphere:
            return FourPi * radius * radius;
        case Kind::Disk:
            return Pi * radius * radius;
        default:
            return surfaceArea(mesh);
    }
}

Surface Surface::rectangle(const Eigen::Affine3d& toWorld) {
    Surface s;
    s.kind = Kind::Rectangle;
    for (const Vec3& c : {Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(-1, 1, 0)})
        s.mesh.p.push_back(toWorld * c);
    s.mesh.uv = {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)};
    s.mesh.indices = {0, 1, 2, 0, 2, 3};  // counter-clockwise seen from +z
    return s;
}

Surface Surface::disk(const Eigen::Affine3d& toWorld) {
    Surface s;
    s.kind = Kind::Disk;
    s.center = toWorld * Vec3::Zero();
    s.normal =
        (toWorld.linear() * Vec3::UnitX()).cross(toWorld.linear() * Vec3::UnitY()).normalized();
    s.radius = (toWorld.linear() * Vec3::UnitX()).norm();
    return s;
}

Surface Surface::sphere(const Vec3& center, double radius) {
    Surface s;
    s.kind = Kind::Sphere;
    s.center = center;
    s.radius = radius;
    return s;
}

}  // namespace shvol
