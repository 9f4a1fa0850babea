#include "shvol/surfaces/surface.h"

#include <cmath>
#include <cstdio>
#include <memory>

namespace shvol {

std::string surfaceReachMessage(double r) {
    static_assert(kMaxSurfaceCoordinate == 1e15, "the message names the bound");
    char b[160];
    std::snprintf(b, sizeof b,
                  "coordinates reach %.4g, beyond ±1e15 (the ray tracer's range; scale the scene "
                  "down)",
                  r);
    return b;
}

double reachOf(const Vec3& p) {
    // (Not cwiseAbs().maxCoeff(): it would drop a NaN coordinate.)
    double r = 0;
    for (int a = 0; a < 3; ++a)
        r = std::isnan(p[a]) || std::isnan(r) ? NAN : std::max(r, std::abs(p[a]));
    return r;
}

double Surface::reach() const {
    if (kind == Kind::Disk || kind == Kind::Sphere) return reachOf(center) + radius;
    double r = 0;
    for (const Vec3& p : mesh.p) {
        const double q = reachOf(p);
        r = std::isnan(q) || std::isnan(r) ? NAN : std::max(r, q);
    }
    return r;
}

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

Bounds3 Surface::bounds() const {
    if (kind == Kind::Disk || kind == Kind::Sphere)
        return {center - Vec3::Constant(radius), center + Vec3::Constant(radius)};
    Bounds3 b{Vec3::Constant(INFINITY), Vec3::Constant(-INFINITY)};  // empty
    for (const Vec3& p : mesh.p) b.lo = b.lo.cwiseMin(p), b.hi = b.hi.cwiseMax(p);
    return b;
}

void Surface::turnInsideOut() {
    flipWinding(mesh);
    emitsFromBack = !emitsFromBack;
    // The volume changes sign, and the shells that faced the wrong way are the others now; a
    // defect's message would name its edges the other way round.
    if (!solidity_ || (!solidity_->defect.empty() && !solidity_->partsMeet)) {
        solidity_ = nullptr;
        return;
    }
    MeshSolidity m{solidity_->defect, -solidity_->signedVolume, {}, solidity_->partsMeet};
    const std::vector<uint32_t>& was = solidity_->inwardFaces;
    for (uint32_t f = 0, k = 0; f < mesh.triangleCount(); ++f)
        if (k < was.size() && was[k] == f)
            ++k;
        else
            m.inwardFaces.push_back(f);
    solidity_ = std::make_shared<const MeshSolidity>(std::move(m));
}

bool Surface::faceOutwards() {
    if (kind != Kind::Mesh || (!solidity().defect.empty() && !solidity().partsMeet)) return true;
    const std::vector<uint32_t>& inward = solidity().inwardFaces;
    if (inward.empty()) return true;
    if (inward.size() == mesh.triangleCount()) {
        turnInsideOut();
        return true;
    }
    if (emits() && !twoSidedEmission) return false;
    for (const uint32_t f : inward) std::swap(mesh.indices[3 * f + 1], mesh.indices[3 * f + 2]);
    solidity_ = nullptr;  // (computed again if asked: the volume changed)
    return true;
}

const MeshSolidity& Surface::solidity() const {
    if (!solidity_) solidity_ = std::make_shared<const MeshSolidity>(meshSolidity(mesh, places));
    return *solidity_;
}

Surface Surface::rectangle(const Eigen::Affine3d& toWorld) {
    Surface s;
    s.kind = Kind::Rectangle;
    for (const Vec3& c : {Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(-1, 1, 0)})
        s.mesh.p.push_back(toWorld * c);
    s.mesh.uv = {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)};
    s.mesh.indices = {0, 1, 2, 0, 2, 3};  // counter-clockwise seen from +z
    s.orient(toWorld);
    return s;
}

Surface Surface::disk(const Eigen::Affine3d& toWorld) {
    Surface s;
    s.kind = Kind::Disk;
    s.center = toWorld * Vec3::Zero();
    s.normal =
        (toWorld.linear() * Vec3::UnitX()).cross(toWorld.linear() * Vec3::UnitY()).normalized();
    s.radius = (toWorld.linear() * Vec3::UnitX()).norm();
    s.orient(toWorld);
    return s;
}

void Surface::orient(const Eigen::Affine3d& toWorld) {
    if (const Vec3 x = toWorld.linear() * Vec3::UnitX(); x.allFinite() && x.norm() > 0)
        tangent = x.normalized();
    if (const Vec3 y = toWorld.linear() * Vec3::UnitY(); y.allFinite() && y.norm() > 0)
        tangentY = y.normalized();
}

Surface Surface::sphere(const Vec3& center, double radius) {
    Surface s;
    s.kind = Kind::Sphere;
    s.center = center;
    s.radius = radius;
    return s;
}

}  // namespace shvol
