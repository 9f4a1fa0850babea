#pragma once
/// \file The surfaces of a scene in one Embree 3 BVH: closest hit and occlusion along rays.
///
/// Triangles (meshes, rectangles) are Embree triangle geometry; disks and spheres are Embree user
/// geometry intersected in double precision. Embree intersects triangles in single precision;
/// the hit point is then recomputed in double from the shape (barycentric combination of the
/// triangle's vertices, projection onto the sphere, the disk's plane), so it lies on the surface
/// to double rounding, and rays leaving a surface start ε off it on the side they leave by: at
/// p ± ε n_g, or off a sphere along the ray itself (spawn(hit, d)).
/// ε = 2⁻¹⁶ · (largest coordinate magnitude of the scene's surfaces, measured from the centre of
/// their box, where Embree's space has its origin), which exceeds the error of Embree's float
/// vertices (2⁻²⁴ relative) by 2⁸, at every scene scale (tests at 1e−4 and 1e4) and distance
/// from the scene's origin.
/// Surfaces must lie within ±kMaxSurfaceCoordinate (surface.h); rays may start anywhere (a ray
/// from far away, beyond 2⁸ times that magnitude from the centre, is traced from where it
/// enters the surfaces' box, where Embree's float intersection keeps its precision).
#include <cstdint>
#include <limits>
#include <memory>
#include <new>
#include <vector>

#include "shvol/core/ray.h"
#include "shvol/surfaces/surface.h"

namespace shvol {

/// tMax of a ray without end.
inline constexpr double NoHit = std::numeric_limits<double>::infinity();

/// A ray's nearest surface point.
struct SurfaceHit {
    double t = 0;      ///< distance along the ray
    Vec3 p;            ///< the point, on the surface
    Vec3 ng;           ///< unit geometric normal, on the shape's front side
    Vec3 ns;           ///< unit shading normal (interpolated vertex normals, else n_g), ns·ng > 0
    Vec2 uv{0, 0};     ///< texture coordinates (vertex uvs, else the barycentrics)
    int surface = -1;  ///< index into SurfaceScene::surfaces()
    uint32_t primitive = 0;
};

class SurfaceScene {
  public:
    /// Builds the BVH. Throws shvol::Error if Embree fails (naming its error).
    explicit SurfaceScene(std::vector<Surface> surfaces);
    ~SurfaceScene();
    SurfaceScene(const SurfaceScene&) = delete;
    SurfaceScene& operator=(const SurfaceScene&) = delete;

    /// Nearest hit with t ∈ (0, tMax); false if none. `hidden`: Embree mask bits of surfaces the
    /// query does not see (bit(s)).
    bool intersect(const Ray& ray, double tMax, SurfaceHit* hit, unsigned hidden = 0) const;
    /// The Embree mask bit of surface s: 1 for every surface that is not null, one of bits 1–31
    /// for a null surface, which no null surface whose box comes within 2ε of its own has (while
    /// 31 suffice).
    unsigned bit(int s) const { return bits_[size_t(s)]; }
    /// The null surfaces a path crosses at one place (coincident within ε), in the order found.
    /// hit[0 … count) are constructed as they are added: built at every path vertex, an array of
    /// 16 initialised hits cost scenes without null surfaces (or without surfaces at all) stores
    /// of about 100 instructions per path (callgrind, media/plume.json).
    struct NullCrossings {
        static constexpr int kMax = 16;
        NullCrossings() {}
        void add(const SurfaceHit& h) { new (&hit[count++]) SurfaceHit(h); }
        union {
            SurfaceHit hit[kMax];
        };
        int count = 0;
    };
    /// Given the nearest hit of `ray`, a null surface's: the other surfaces within ε of it (the
    /// slab that spawn() jumps, along the ray up to tMax), one query at a time, each hiding the
    /// surfaces found before. The null ones join `nulls` after the hit's own, and the first that
    /// is not null replaces *hit. Returns whether *hit is (now) not null. Given a hit that is not
    /// null, in a scene where null surfaces emit, `nulls` gets those within ε of it. Before, a path
    /// crossed one of coincident surfaces and jumped the others: a fog's null box standing on a
    /// floor let the sky below through the floor, and of two fog boxes sharing a face one was never
    /// entered (or never left, and filled all space beyond).
    bool resolveCrossing(const Ray& ray, double tMax, SurfaceHit* hit, NullCrossings* nulls) const;
    /// The null surfaces within ε of a hit of a surface that is not null: a path spawned off it,
    /// through it (glass), would jump their crossings (fog in a glass tank, its null box on the
    /// glass, was never entered).
    void nullsAt(const Ray& ray, const SurfaceHit& hit, NullCrossings* nulls) const;
    /// Whether any surface is hit with t ∈ (0, tMax).
    bool occluded(const Ray& ray, double tMax) const;
    /// A ray from the surface point p (geometric normal ng) along the unit direction d, its
    /// origin moved by ε to the side of the surface that d leaves by.
    Ray spawn(const Vec3& p, const Vec3& ng, const Vec3& d) const {
        return Ray{p + (ng.dot(d) >= 0 ? epsilon_ : -epsilon_) * ng, d};
    }
    /// A ray leaving the surface of `hit` along the unit direction d, started ε off it as
    /// spawn(p, ng, d) is, but on a sphere by moving along d itself: the ray keeps the line its
    /// reflection or refraction gave it. Moved along the normal, the line shifted by ε·sin θ at
    /// every bounce, and between the two walls of a hollow glass ball the shifts added up (the
    /// distance of the line from the centre, which sets the angle at every later hit, grew by
    /// ε·ℓ·(1/r_in − 1/R) a round), carried rays that entered near the silhouette past the
    /// critical angle, and they were reflected totally until max_depth: 1.6% of them, whatever
    /// the depth (helper 101). Along d the origin goes as far as the slab jump() spans (ε/|cos|),
    /// inwards no further than half the chord (r·|cos|, so that a grazing ray inside a sphere
    /// still meets its far side), and along the normal by what that leaves of ε.
    Ray spawn(const SurfaceHit& hit, const Vec3& d) const {
        const Surface& s = surfaces_[size_t(hit.surface)];
        if (s.kind != Surface::Kind::Sphere) return spawn(hit.p, hit.ng, d);
        const double cosine = hit.ng.dot(d), c = std::abs(cosine);
        double along = epsilon_ / std::max(c, 1e-3);
        if (cosine < 0) along = std::min(along, s.radius * c);  // (ng points out of a sphere)
        const double normal = std::max(0.0, epsilon_ - along * c);
        return Ray{hit.p + along * d + (cosine >= 0 ? normal : -normal) * hit.ng, d};
    }
    /// p moved by ε towards the side of its surface (normal ng) that `towards` lies on.
    Vec3 offsetTowards(const Vec3& p, const Vec3& ng, const Vec3& towards) const {
        return p + (ng.dot(towards - p) >= 0 ? epsilon_ : -epsilon_) * ng;
    }
    /// A point p of a medium before the surface `hit` ahead on a ray along d, moved to lie at
    /// least ε from the surface's plane on the side the ray came from (a surface point's next
    /// ray starts ε off its surface too, spawn()). Closer, within float rounding, Embree could
    /// see the next ray's origin on the surface's other side: leaving through it, the ray met
    /// nothing, and a path in fog bounded by a glass mesh left the glass unnoticed (an albedo-1
    /// furnace of exactly 1 per path gave samples of 1/η²).
    Vec3 offSurfaceAhead(const Vec3& p, const SurfaceHit& hit, const Vec3& d) const {
        const Vec3 back = d.dot(hit.ng) < 0 ? hit.ng : Vec3(-hit.ng);
        const double h = (p - hit.p).dot(back);
        return h < epsilon_ ? Vec3(p + (epsilon_ - h) * back) : p;
    }
    /// The shadow ray from `from` to the point y of a surface (normal ny), y moved by ε towards
    /// `from` (offsetTowards); *tMax is set to its length. It is aimed at the moved point, so it
    /// ends ε/|cos| before y's surface, a margin that grows with float intersection error at
    /// grazing angles; aimed at y itself from a moved origin it would end only ε·|cos| before
    /// it, and a box's adjacent faces would shadow each other near their shared edge.
    Ray rayTo(const Vec3& from, const Vec3& y, const Vec3& ny, double* tMax) const {
        const Vec3 v = offsetTowards(y, ny, from) - from;
        *tMax = v.norm();
        return Ray{from, *tMax > 0 ? Vec3(v / *tMax) : Vec3(0, 0, 1)};
    }
    /// Whether p lies inside the closed surface s (a sphere, or a closed outward-facing mesh):
    /// decided by the side of the first hit of s along a fixed direction.
    bool inside(int s, const Vec3& p) const;

    const std::vector<Surface>& surfaces() const { return surfaces_; }
    double epsilon() const { return epsilon_; }
    /// A box containing every surface.
    const Vec3& lower() const { return lo_; }
    const Vec3& upper() const { return hi_; }
    size_t triangleCount() const { return triangles_; }
    bool hasNullSurfaces() const { return hasNull_; }
    double buildSeconds() const { return buildSeconds_; }

  private:
    bool startNear(const Ray& ray, double tMax, Ray* moved, double* tEntry) const;
    bool intersectInRange(const Ray& ray, double tMax, SurfaceHit* hit, unsigned hidden) const;
    /// How far along the ray the slab of thickness ε on either side of hit's surface reaches:
    /// what spawn() jumps (at most 10³ ε, at grazing angles). No further: a null surface found
    /// beyond it would be met again by the spawned ray (a light there was counted twice). (Into a
    /// sphere whose half chord is shorter, |cos|² < ε/r, spawn(hit, d) starts the ray short of
    /// it, so that the ray still meets the sphere's far side: a surface found in between would
    /// be met again; review.)
    double jump(const Ray& ray, const SurfaceHit& hit) const {
        return epsilon_ / std::max(std::abs(ray.d.dot(hit.ng)), 1e-3);
    }
    /// The surfaces in the slab around `at` not hidden (bits), nearest first: nulls join
    /// `nulls`; the first other one, if any, is *solid (returns true), and null ones beyond it
    /// are still found (a fog box against glass whose tank holds a fog of its own).
    bool inSlab(const Ray& ray, double tMax, const SurfaceHit& at, unsigned hidden,
                NullCrossings* nulls, SurfaceHit* solid) const;
    std::vector<unsigned> bits_;  ///< bit(s)
    struct Embree;                ///< the RTCDevice and RTCScene (Embree headers stay in the .cpp)
    std::unique_ptr<Embree> rtc_;
    std::vector<Surface> surfaces_;
    double epsilon_ = 0;
    Vec3 lo_, hi_;
    size_t triangles_ = 0;
    bool hasNull_ = false;
    bool nullEmitters_ = false;  ///< a null surface emits
    double buildSeconds_ = 0;
};

}  // namespace shvol
