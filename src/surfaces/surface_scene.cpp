#include "shvol/surfaces/surface_scene.h"

#include <embree3/rtcore.h>

#include <chrono>
#include <cmath>
#include <cstddef>
#include <limits>

#include "shvol/core/error.h"

namespace shvol {

namespace {

/// Nearest root t ∈ (t0, t1) of |o + t d − c|² = r² (d unit), or NaN. The roots are computed as
/// t = b ∓ √disc with b = (c − o)·d and disc = r² − |(o − c) + b d|², the form that keeps
/// precision when the ray starts far from a small sphere (pbrt-v4 §6.8.1).
double sphereRoot(const Vec3& o, const Vec3& d, const Vec3& c, double r, double t0, double t1) {
    const double b = (c - o).dot(d);
    const double disc = r * r - ((o - c) + b * d).squaredNorm();
    if (disc < 0) return std::numeric_limits<double>::quiet_NaN();
    const double q = std::sqrt(disc);
    if (b - q > t0 && b - q < t1) return b - q;
    if (b + q > t0 && b + q < t1) return b + q;
    return std::numeric_limits<double>::quiet_NaN();
}

/// t ∈ (t0, t1) where the ray meets the disk of centre c, or NaN.
double diskRoot(const Vec3& o, const Vec3& d, const Surface& s, const Vec3& c, double t0,
                double t1) {
    const double dn = d.dot(s.normal);
    if (dn == 0) return std::numeric_limits<double>::quiet_NaN();
    const double t = (c - o).dot(s.normal) / dn;
    if (!(t > t0 && t < t1)) return std::numeric_limits<double>::quiet_NaN();
    if ((o + t * d - c).squaredNorm() > s.radius * s.radius)
        return std::numeric_limits<double>::quiet_NaN();
    return t;
}

/// A sphere or disk as Embree user geometry: its centre in Embree's space divided by the scale
/// (the scene's minus the origin of Embree's space, below), and the scale.
struct AnalyticGeometry {
    const Surface* surface;
    Vec3 center;
    double scale;
};

double analyticRoot(const AnalyticGeometry& g, const Vec3& o, const Vec3& d, double t0, double t1) {
    const Surface& s = *g.surface;
    return s.kind == Surface::Kind::Sphere ? sphereRoot(o, d, g.center, s.radius, t0, t1)
                                           : diskRoot(o, d, s, g.center, t0, t1);
}

// Embree user geometry for spheres and disks, intersected in double precision in Embree's space
// divided by its scale (exactly: a power of 2). Only rtcIntersect1 and rtcOccluded1 are used,
// so every callback sees one ray (N == 1).
void analyticBounds(const RTCBoundsFunctionArguments* a) {
    const AnalyticGeometry& g = *static_cast<const AnalyticGeometry*>(a->geometryUserPtr);
    const Surface& s = *g.surface;
    Vec3 half = Vec3::Constant(s.radius);
    if (s.kind == Surface::Kind::Disk)  // extent of a disk along axis i: r √(1 − n_i²)
        for (int i = 0; i < 3; ++i) half[i] = s.radius * safeSqrt(1 - s.normal[i] * s.normal[i]);
    const Vec3 lo = (g.center - half) * g.scale, hi = (g.center + half) * g.scale;
    const float inf = std::numeric_limits<float>::infinity();
    // Rounded outwards, so the float box contains the double shape.
    a->bounds_o->lower_x = std::nextafter(float(lo.x()), -inf);
    a->bounds_o->lower_y = std::nextafter(float(lo.y()), -inf);
    a->bounds_o->lower_z = std::nextafter(float(lo.z()), -inf);
    a->bounds_o->upper_x = std::nextafter(float(hi.x()), inf);
    a->bounds_o->upper_y = std::nextafter(float(hi.y()), inf);
    a->bounds_o->upper_z = std::nextafter(float(hi.z()), inf);
}

/// An intersect context that carries the ray in double precision to the analytic shapes'
/// callbacks (Embree passes the context given to rtcIntersect1 and rtcOccluded1 on to them;
/// its rtcInitIntersectContext page: data may be appended to it). From the float ray Embree
/// hands them, a point of a medium inside a sphere within float rounding of its surface was
/// rounded onto or beyond it, and the ray leaving the sphere from there met nothing.
struct DoubleRayContext {
    RTCIntersectContext rtc;
    Vec3 o, d;  ///< the ray in Embree's space divided by its scale (the scene's, less its origin)
};

const DoubleRayContext& doubleRay(const RTCIntersectContext* c) {
    static_assert(offsetof(DoubleRayContext, rtc) == 0);
    return *reinterpret_cast<const DoubleRayContext*>(c);
}

void analyticIntersect(const RTCIntersectFunctionNArguments* a) {
    if (!a->valid[0]) return;
    RTCRayHit& rh = *reinterpret_cast<RTCRayHit*>(a->rayhit);
    const AnalyticGeometry& g = *static_cast<const AnalyticGeometry*>(a->geometryUserPtr);
    const DoubleRayContext& r = doubleRay(a->context);
    const double t = analyticRoot(g, r.o, r.d, rh.ray.tnear / g.scale, rh.ray.tfar / g.scale);
    if (std::isnan(t)) return;
    rh.ray.tfar = float(t * g.scale);
    rh.hit.u = rh.hit.v = 0;
    rh.hit.Ng_x = rh.hit.Ng_y = rh.hit.Ng_z = 0;  // recomputed in double by intersect()
    rh.hit.primID = a->primID;
    rh.hit.geomID = a->geomID;
    rh.hit.instID[0] = a->context->instID[0];
}

void analyticOccluded(const RTCOccludedFunctionNArguments* a) {
    if (!a->valid[0]) return;
    RTCRay& ray = *reinterpret_cast<RTCRay*>(a->ray);
    const AnalyticGeometry& g = *static_cast<const AnalyticGeometry*>(a->geometryUserPtr);
    const DoubleRayContext& r = doubleRay(a->context);
    if (!std::isnan(analyticRoot(g, r.o, r.d, ray.tnear / g.scale, ray.tfar / g.scale)))
        ray.tfar = -std::numeric_limits<float>::infinity();
}

}  // namespace

struct SurfaceScene::Embree {
    RTCDevice device = nullptr;
    RTCScene scene = nullptr;
    /// Embree's space is the scene's less `origin`, the centre of the surfaces' box, times
    /// `scale`, the power of 2 that brings the largest coordinate magnitude R of the surfaces
    /// there into [1, 2). Its float triangle test multiplies three lengths, which overflowed
    /// (3.4·10³⁸) once edges and distances reached about 10¹³, and then missed triangles;
    /// scaled by a power of 2 every float operation is exact as before, so a scene gets the hits
    /// it would get at R ≈ 1, whatever its size. Centred, a scene far from the scene's origin
    /// is as precise as at it: the floats, and ε, follow its extent, not its distance (a glass
    /// sphere of radius 1 at 10⁶ had ε = 15 and trapped its paths).
    Vec3 origin{0, 0, 0};
    double scale = 1;
    std::vector<AnalyticGeometry> analytic;  ///< user data of the spheres and disks
    /// The ray in Embree's space: positions less `origin`, and distances, times `scale` (its
    /// direction unscaled).
    RTCRay toRtc(const Ray& ray, double tMax) const {
        RTCRay r;
        const Vec3 o = (ray.o - origin) * scale;
        r.org_x = float(o.x()), r.org_y = float(o.y()), r.org_z = float(o.z());
        r.dir_x = float(ray.d.x()), r.dir_y = float(ray.d.y()), r.dir_z = float(ray.d.z());
        r.tnear = 0;
        r.tfar = tMax * scale < double(std::numeric_limits<float>::max())
                     ? float(tMax * scale)
                     : std::numeric_limits<float>::infinity();
        r.time = 0;
        r.mask = 0xFFFFFFFFu;
        r.id = 0;
        r.flags = 0;
        return r;
    }
    /// The context of a query along the ray, with the ray in double precision in Embree's space
    /// divided by its scale (what the analytic shapes' callbacks intersect).
    DoubleRayContext context(const Ray& ray) const {
        DoubleRayContext c;
        rtcInitIntersectContext(&c.rtc);
        c.o = ray.o - origin;
        c.d = ray.d.normalized();
        return c;
    }
    ~Embree() {
        if (scene) rtcReleaseScene(scene);
        if (device) rtcReleaseDevice(device);
    }
    [[noreturn]] void fail(const char* what) const {
        throw Error(std::string("Embree: ") + what + ": error " +
                    std::to_string(int(rtcGetDeviceError(device))));
    }
};

SurfaceScene::SurfaceScene(std::vector<Surface> surfaces)
    : rtc_(std::make_unique<Embree>()), surfaces_(std::move(surfaces)) {
    const auto start = std::chrono::steady_clock::now();
    // No "threads=N" in the configuration: Embree would enforce it with a TBB global_control,
    // which limits every TBB loop of the process (the render's too) while the device lives.
    rtc_->device = rtcNewDevice(nullptr);
    if (!rtc_->device) throw Error("Embree: could not create a device");
    rtc_->scene = rtcNewScene(rtc_->device);
    rtcSetSceneFlags(rtc_->scene, RTC_SCENE_FLAG_ROBUST);
    lo_ = Vec3::Constant(std::numeric_limits<double>::infinity());
    hi_ = -lo_;
    for (const Surface& s : surfaces_) {
        hasNull_ = hasNull_ || s.bsdf.type == BsdfType::Null;
        nullEmitters_ = nullEmitters_ || (s.bsdf.type == BsdfType::Null && s.emits());
        if (!(s.reach() <= kMaxSurfaceCoordinate))
            throw Error(s.name + ": " + surfaceReachMessage(s.reach()));
        // (A disk's box is its sphere's: a bound, enough for ε and the cache's grid.)
        const Bounds3 b = s.bounds();
        lo_ = lo_.cwiseMin(b.lo), hi_ = hi_.cwiseMax(b.hi);
    }
    const Vec3 origin = rtc_->origin = surfaces_.empty() ? Vec3::Zero() : Vec3(0.5 * (lo_ + hi_));
    const double R = surfaces_.empty() ? 0 : 0.5 * (hi_ - lo_).maxCoeff();
    const double scale = rtc_->scale = R > 0 ? std::ldexp(1.0, -std::ilogb(R)) : 1.0;
    // ε: 2⁻¹⁶ R, and at least 32 steps of a double at the surfaces' farthest coordinate, or a
    // point moved off its surface could round back onto it (the Cornell box moved to 10¹⁴, where
    // a step is 0.0156 and 2⁻¹⁶ R 0.0042, rendered 6.8% too bright).
    const double farthest =
        surfaces_.empty() ? 0 : std::max(lo_.cwiseAbs().maxCoeff(), hi_.cwiseAbs().maxCoeff());
    epsilon_ = std::max(std::ldexp(R > 0 ? R : 1.0, -16),
                        farthest > 0 ? std::ldexp(1.0, std::ilogb(farthest) - 47) : 0.0);
    rtc_->analytic.reserve(surfaces_.size());  // (their addresses are Embree's user data)
    // Embree geometry masks (Debian's Embree is built with EMBREE_RAY_MASK, which CMakeLists.txt
    // checks): a ray sees the geometries whose mask shares a bit with its own. Every surface that
    // is not null has bit 0; null surfaces get bits 1–31, a bit no null surface whose box comes
    // within 2ε of theirs has (greedily, in order: only surfaces that can meet at one place need
    // bits of their own), or, where all 31 are taken around one, a shared one.
    const double margin = 2 * epsilon_;
    std::vector<Bounds3> nullBox(surfaces_.size());
    bits_.assign(surfaces_.size(), 1u);
    for (size_t i = 0, shared = 0; i < surfaces_.size(); ++i) {
        if (surfaces_[i].bsdf.type != BsdfType::Null) continue;
        const Bounds3 b = surfaces_[i].bounds();
        nullBox[i] = {b.lo - Vec3::Constant(margin), b.hi + Vec3::Constant(margin)};
        unsigned taken = 1;
        for (size_t k = 0; k < i; ++k)
            if (bits_[k] != 1 && nullBox[i].meets(nullBox[k])) taken |= bits_[k];
        unsigned bit = 2;
        while (bit != 0 && (taken & bit)) bit <<= 1;
        bits_[i] = bit != 0 ? bit : 2u << (shared++ % 31);
    }
    for (size_t i = 0; i < surfaces_.size(); ++i) {
        const Surface& s = surfaces_[i];
        RTCGeometry g;
        if (s.kind == Surface::Kind::Mesh || s.kind == Surface::Kind::Rectangle) {
            g = rtcNewGeometry(rtc_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
            const TriangleMesh& m = s.mesh;
            auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
                g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), m.p.size()));
            auto* idx = static_cast<unsigned*>(
                rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                        3 * sizeof(unsigned), m.triangleCount()));
            if (!v || !idx) rtc_->fail("could not allocate a mesh buffer");
            for (size_t k = 0; k < m.p.size(); ++k)
                for (int j = 0; j < 3; ++j) v[3 * k + j] = float((m.p[k][j] - origin[j]) * scale);
            std::copy(m.indices.begin(), m.indices.end(), idx);
            triangles_ += m.triangleCount();
        } else {
            g = rtcNewGeometry(rtc_->device, RTC_GEOMETRY_TYPE_USER);
            rtcSetGeometryUserPrimitiveCount(g, 1);
            rtc_->analytic.push_back({&s, s.center - origin, scale});
            rtcSetGeometryUserData(g, &rtc_->analytic.back());
            rtcSetGeometryBoundsFunction(g, analyticBounds, nullptr);
            rtcSetGeometryIntersectFunction(g, analyticIntersect);
            rtcSetGeometryOccludedFunction(g, analyticOccluded);
        }
        rtcSetGeometryMask(g, bits_[i]);
        rtcCommitGeometry(g);
        rtcAttachGeometryByID(rtc_->scene, g, unsigned(i));
        rtcReleaseGeometry(g);
    }
    rtcCommitScene(rtc_->scene);
    if (rtcGetDeviceError(rtc_->device) != RTC_ERROR_NONE) rtc_->fail("building the BVH");
    static_assert(256 * kMaxSurfaceCoordinate < 1.8e18, "far origins stay within Embree's range");
    buildSeconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

SurfaceScene::~SurfaceScene() = default;

/// Embree intersects triangles in float, relative to the ray's origin: from a distance D its
/// error is about 2⁻²⁴·D, which exceeds ε = 2⁻¹⁶·R (R the surfaces' largest coordinate
/// magnitude from the centre of their box) beyond D ≈ 2⁸·R, and beyond ±FLT_LARGE = 1.844·10¹⁸ it
/// refuses the ray (an assertion). A ray from farther than 2⁸·R = 2²⁴·ε (≤ 2.56·10¹⁷; a distant
/// camera, a point of a medium placed far off) can meet the surfaces only inside their box: it is
/// traced from where it enters the box, widened so that the new origin lies off every surface
/// (*tEntry ≥ 0 the distance to it), or not at all (false) if it misses the box or is NaN. The
/// entry point's coordinate across the face it enters by is set to that face: o + t·d there would
/// lose all digits below the origin's magnitude (2⁸ at 2·10¹⁸), enough to start inside a small
/// surface.
bool SurfaceScene::startNear(const Ray& ray, double tMax, Ray* moved, double* tEntry) const {
    *moved = ray, *tEntry = 0;
    const double farOrigin = std::ldexp(epsilon_, 24);  // 2⁸·R
    if (((ray.o - rtc_->origin).array().abs() <= farOrigin).all())
        return true;  // (false for NaN too)
    const Vec3 pad = Vec3::Constant(std::max(16 * epsilon_, 1e-3 * (hi_ - lo_).maxCoeff()));
    const Vec3 lo = lo_ - pad, hi = hi_ + pad;
    int face;  // the origin is outside the box (farther than 2⁸·R): the ray enters by a face
    const Interval i = intersectBox(ray, lo, hi, tMax, &face);
    if (i.empty()) return false;
    *moved = Ray{ray(i.t0), ray.d}, *tEntry = i.t0;
    if (face >= 0) moved->o[face] = ray.d[face] > 0 ? lo[face] : hi[face];
    return ((moved->o - rtc_->origin).array().abs() <= farOrigin).all();
}

bool SurfaceScene::intersect(const Ray& ray, double tMax, SurfaceHit* hit, unsigned hidden) const {
    Ray moved;
    double tEntry;
    if (!startNear(ray, tMax, &moved, &tEntry) ||
        !intersectInRange(moved, tMax - tEntry, hit, hidden))
        return false;
    hit->t += tEntry;
    return true;
}

bool SurfaceScene::inSlab(const Ray& ray, double tMax, const SurfaceHit& at, unsigned hidden,
                          NullCrossings* nulls, SurfaceHit* solid) const {
    // From the hit point itself (a point of the ray taken from a far origin is off by more than
    // the slab: a camera 10¹³ away saw the sky through a floor again), back to the ray's origin
    // at most.
    // (`at` may be *solid: what is needed of it is read first.)
    const double d = jump(ray, at), back = std::min(d, at.t), ahead = std::min(d, tMax - at.t);
    const double start = at.t - back;
    const Ray slab{at.p - back * ray.d, ray.d};
    bool found = false;
    for (SurfaceHit next;
         nulls->count < NullCrossings::kMax && intersect(slab, back + ahead, &next, hidden);) {
        next.t += start;
        if (bits_[size_t(next.surface)] == 1) {  // the first solid one; then the null ones only
            *solid = next, found = true;
            hidden |= 1u;
            continue;
        }
        nulls->add(next);
        hidden |= bits_[size_t(next.surface)];
    }
    return found;
}

bool SurfaceScene::resolveCrossing(const Ray& ray, double tMax, SurfaceHit* hit,
                                   NullCrossings* nulls) const {
    nulls->count = 0;
    if (bits_[size_t(hit->surface)] == 1) {
        // A light with a null BSDF (a decal, a portal) in the plane of the surface hit.
        if (nullEmitters_) nullsAt(ray, *hit, nulls);
        return true;
    }
    nulls->add(*hit);
    return inSlab(ray, tMax, *hit, bits_[size_t(hit->surface)], nulls, hit);
}

void SurfaceScene::nullsAt(const Ray& ray, const SurfaceHit& hit, NullCrossings* nulls) const {
    nulls->count = 0;
    SurfaceHit unused;
    inSlab(ray, NoHit, hit, 1u, nulls, &unused);
}

bool SurfaceScene::intersectInRange(const Ray& ray, double tMax, SurfaceHit* hit,
                                    unsigned hidden) const {
    DoubleRayContext ctx = rtc_->context(ray);
    RTCRayHit rh;
    rh.ray = rtc_->toRtc(ray, tMax);
    rh.ray.mask = ~hidden;
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    rtcIntersect1(rtc_->scene, &ctx.rtc, &rh);
    if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
    const Surface& s = surfaces_[rh.hit.geomID];
    hit->surface = int(rh.hit.geomID);
    hit->primitive = rh.hit.primID;
    hit->ns = Vec3::Zero();  // set below only from vertex normals
    switch (s.kind) {
        case Surface::Kind::Sphere: {
            const Vec3 q = ray(rh.ray.tfar / rtc_->scale) - s.center;
            hit->ng = q.normalized();
            hit->p = s.center + s.radius * hit->ng;
            hit->uv = Vec2(sphericalPhi(hit->ng) * Inv2Pi, safeAcos(hit->ng.z()) * InvPi);
            break;
        }
        case Surface::Kind::Disk: {
            hit->t = (s.center - ray.o).dot(s.normal) / ray.d.dot(s.normal);
            hit->p = ray(hit->t);
            hit->p -= (hit->p - s.center).dot(s.normal) * s.normal;  // onto the plane
            hit->ng = s.normal;
            hit->uv = Vec2(0, 0);
            break;
        }
        default: {
            const TriangleMesh& m = s.mesh;
            const uint32_t* tri = &m.indices[3 * size_t(rh.hit.primID)];
            const Vec3 &p0 = m.p[tri[0]], &p1 = m.p[tri[1]], &p2 = m.p[tri[2]];
            // The barycentrics again in double (Möller & Trumbore 1997) for the triangle Embree
            // found, clamped into it; Embree's float ones where the ray grazes the plane.
            double b1 = rh.hit.u, b2 = rh.hit.v;
            const Vec3 e1 = p1 - p0, e2 = p2 - p0, pv = ray.d.cross(e2);
            const double det = e1.dot(pv);
            if (std::abs(det) > 1e-12 * e1.norm() * e2.norm()) {
                const Vec3 tv = ray.o - p0, qv = tv.cross(e1);
                b1 = std::clamp(tv.dot(pv) / det, 0.0, 1.0);
                b2 = std::clamp(ray.d.dot(qv) / det, 0.0, 1.0 - b1);
            }
            const double b0 = 1 - b1 - b2;
            hit->p = b0 * p0 + b1 * p1 + b2 * p2;
            hit->ng = (p1 - p0).cross(p2 - p0).normalized();
            hit->uv = m.uv.empty()
                          ? Vec2(b1, b2)
                          : Vec2(b0 * m.uv[tri[0]] + b1 * m.uv[tri[1]] + b2 * m.uv[tri[2]]);
            if (!m.n.empty()) {
                const Vec3 n = b0 * m.n[tri[0]] + b1 * m.n[tri[1]] + b2 * m.n[tri[2]];
                if (n.squaredNorm() > 0)
                    hit->ns = n.dot(hit->ng) < 0 ? -n.normalized() : n.normalized();
            }
            break;
        }
    }
    if (s.kind != Surface::Kind::Disk) hit->t = (hit->p - ray.o).dot(ray.d);
    if (hit->ns.squaredNorm() == 0) hit->ns = hit->ng;
    return true;
}

bool SurfaceScene::occluded(const Ray& ray, double tMax) const {
    Ray moved;
    double tEntry;
    if (!startNear(ray, tMax, &moved, &tEntry)) return false;
    DoubleRayContext ctx = rtc_->context(moved);
    RTCRay r = rtc_->toRtc(moved, tMax - tEntry);
    rtcOccluded1(rtc_->scene, &ctx.rtc, &r);
    return r.tfar < 0;
}

bool SurfaceScene::inside(int s, const Vec3& p) const {
    const Surface& surf = surfaces_[s];
    if (surf.kind == Surface::Kind::Sphere) return (p - surf.center).norm() < surf.radius;
    // A direction no axis-aligned or diagonal face of a test scene is parallel to.
    Ray ray{p, Vec3(0.5773, 0.6071, 0.5461).normalized()};
    SurfaceHit hit;
    // A null surface with a mask bit of its own is queried alone: walking from hit to hit, a face
    // of another surface in the plane of one of its own jumped that one (a camera in one of two
    // fog boxes sharing a face).
    if (bits_[size_t(s)] != 1 && intersect(ray, NoHit, &hit, ~bits_[size_t(s)]) && hit.surface == s)
        return hit.ng.dot(ray.d) > 0;
    for (int crossings = 0; crossings < 100000 && intersect(ray, NoHit, &hit); ++crossings) {
        if (hit.surface == s) return hit.ng.dot(ray.d) > 0;
        ray = spawn(hit, ray.d);
    }
    return false;
}

}  // namespace shvol
