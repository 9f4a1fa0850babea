#include "shvol/surfaces/area_lights.h"

namespace shvol {

namespace {

/// 1 − cos θ_max of the cone a sphere (radius r, centre at distance dc > r) subtends, written as
/// sin²θ_max / (1 + cos θ_max) so that it keeps its precision for distant spheres.
double oneMinusCosMax(double r, double dc) {
    const double sin2 = sqr(r / dc);
    return sin2 / (1 + safeSqrt(1 - sin2));
}

/// Whether points of the sphere are drawn in the cone it subtends at x: from outside, and only
/// when its far side cannot emit towards x (a two-sided emitter behind a null or glass surface
/// could), else by area. A point of the sphere itself (a shading point on it, lit from inside or
/// out) is not outside: its distance from the centre is r only to rounding, and the cone's near
/// root would be the point itself, lit by the front of the surface it lies on.
bool byCone(const Surface& s, const Vec3& x) {
    return !s.twoSidedEmission && (x - s.center).norm() > s.radius * (1 + 1e-9);
}

}  // namespace

AreaLights::AreaLights(const SurfaceScene& scene)
    : scene_(scene), emitterOf_(scene.surfaces().size(), -1) {
    std::vector<double> power;
    for (size_t i = 0; i < scene.surfaces().size(); ++i) {
        const Surface& s = scene.surfaces()[i];
        if (!s.emits()) continue;
        Emitter e{int(i), std::nullopt, 0};
        if (s.kind == Surface::Kind::Mesh || s.kind == Surface::Kind::Rectangle) {
            const TriangleMesh& m = s.mesh;
            std::vector<double> a(m.triangleCount());
            for (size_t k = 0; k < a.size(); ++k) e.area += a[k] = triangleArea(m, k);
            e.triangles.emplace(a.data(), int(a.size()));
        } else {
            e.area = s.area();
        }
        emitterOf_[i] = int(emitters_.size());
        power.push_back(e.area * (s.twoSidedEmission ? 2 : 1) *
                        std::max(luminance(s.emission), 1e-9 * s.emission.maxCoeff()));
        emitters_.push_back(std::move(e));
    }
    if (!power.empty()) select_.emplace(power.data(), int(power.size()));
}

AreaLightSample AreaLights::sample(const Vec3& x, double uSelect, const Vec2& u) const {
    AreaLightSample ls;
    double density;  // of the continuous position; the emitter's probability is its pmf
    int i;
    // The position inside the chosen bin is again uniform: it picks the triangle.
    const double xs = select_->sampleContinuous(uSelect, &density, &i);
    const double pmf = select_->pmf(i);
    const double uNext = std::clamp(xs * select_->count() - i, 0.0, std::nextafter(1.0, 0.0));
    const Emitter& e = emitters_[i];
    const Surface& s = scene_.surfaces()[e.surface];
    ls.surface = e.surface;
    if (s.kind == Surface::Kind::Sphere && byCone(s, x)) {
        const Vec3 toC = s.center - x;
        const double dc = toC.norm();
        const double omc = oneMinusCosMax(s.radius, dc);
        const double oneMinusCos = u.x() * omc;
        const double cosTheta = 1 - oneMinusCos;
        const double sin2Theta = oneMinusCos * (2 - oneMinusCos);
        const Frame f(toC / dc);
        // sin θ from 1 − cos θ itself: from the rounded cos θ it lost its digits for distant
        // spheres (relative 10⁻⁴ at r/d = 10⁻⁶, where cos θ rounds in steps of 10⁻⁴ of
        // 1 − cos θ_max; the direction then disagreed with dist by 1.6·10⁻⁹ of 50).
        ls.wi = f.toWorld(
            sphericalDirection2Pi(AngleCosine{cosTheta, oneMinusCos, 2 - oneMinusCos}, u.y()));
        // Nearest point of the sphere along wi (the root is clamped at the silhouette).
        ls.dist = dc * cosTheta - safeSqrt(sqr(s.radius) - dc * dc * sin2Theta);
        ls.ny = (x + ls.dist * ls.wi - s.center).normalized();
        ls.y = s.center + s.radius * ls.ny;
        ls.pdf = pmf / (TwoPi * omc);
        ls.Le = s.Le(ls.ny, -ls.wi);
        return ls;
    }
    switch (s.kind) {
        case Surface::Kind::Sphere:
            ls.ny = sphericalDirection2Pi(1 - 2 * u.x(), u.y());
            ls.y = s.center + s.radius * ls.ny;
            break;
        case Surface::Kind::Disk: {
            const Frame f(s.normal);
            const double r = s.radius * std::sqrt(u.x());
            const Vec2 cs = cosSin2Pi(u.y());
            ls.y = s.center + f.toWorld(Vec3(r * cs.x(), r * cs.y(), 0));
            ls.ny = s.normal;
            break;
        }
        default: {
            const TriangleMesh& m = s.mesh;
            const int k = e.triangles->sampleDiscrete(uNext);
            const uint32_t* t = &m.indices[3 * size_t(k)];
            // Uniform in the triangle: b0 = 1 − √u₁, b1 = u₂ √u₁ (pbrt-v3 §13.6.5).
            const double su = std::sqrt(u.x());
            const double b0 = 1 - su, b1 = u.y() * su;
            const Vec3 &p0 = m.p[t[0]], &p1 = m.p[t[1]], &p2 = m.p[t[2]];
            ls.y = b0 * p0 + b1 * p1 + (1 - b0 - b1) * p2;
            ls.ny = (p1 - p0).cross(p2 - p0).normalized();
            break;
        }
    }
    const Vec3 d = ls.y - x;
    ls.dist = d.norm();
    if (!(ls.dist > 0)) return AreaLightSample{};
    ls.wi = d / ls.dist;
    const double cosY = std::abs(ls.ny.dot(ls.wi));
    if (!(cosY > 0)) return AreaLightSample{};
    ls.pdf = pmf / e.area * ls.dist * ls.dist / cosY;
    ls.Le = s.Le(ls.ny, -ls.wi);
    return ls;
}

double AreaLights::pdf(const Vec3& x, int surface, const Vec3& y, const Vec3& ny) const {
    const int i = emitterOf_[surface];
    if (i < 0) return 0;
    const Emitter& e = emitters_[i];
    const Surface& s = scene_.surfaces()[surface];
    const double pmf = select_->pmf(i);
    if (s.kind == Surface::Kind::Sphere && byCone(s, x))
        return pmf / (TwoPi * oneMinusCosMax(s.radius, (s.center - x).norm()));
    const Vec3 d = y - x;
    const double dist2 = d.squaredNorm();
    const double cosY = std::abs(ny.dot(d)) / std::sqrt(dist2);
    return cosY > 0 ? pmf / e.area * dist2 / cosY : 0;
}

}  // namespace shvol
