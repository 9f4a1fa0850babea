#pragma once
/// \file One surface of a scene: a shape in world space, its BSDF, its emission, and the medium
/// it bounds.
///
/// Shapes are triangle meshes (from OBJ/PLY, or the two triangles of a `rectangle`), flat disks and
/// spheres. A shape's front side is the side its geometric normal n_g points to: counter-clockwise
/// winding for triangles, the disk's normal, outwards for spheres. Closed surfaces that bound a
/// medium face outwards (the loader turns a mesh's shells that face the wrong way: faceOutwards).
#include <memory>
#include <string>

#include "shvol/core/ray.h"
#include "shvol/surfaces/bsdf.h"
#include "shvol/surfaces/triangle_mesh.h"

namespace shvol {

/// The largest coordinate magnitude a surface may reach (its reach()). Embree keeps vertices in
/// float and refuses rays whose origin lies beyond ±1.844·10¹⁸ (FLT_LARGE, kernels/common/
/// ray.h); 10¹⁵ leaves room for the ε offsets of rays leaving surfaces (surface_scene.h).
inline constexpr double kMaxSurfaceCoordinate = 1e15;

/// Why a surface of reach r cannot be traced ("reaches 1e+24, beyond ±1e15 …").
std::string surfaceReachMessage(double r);
/// max_a |p_a|, NaN if a coordinate is NaN.
double reachOf(const Vec3& p);

struct Surface {
    enum class Kind { Mesh, Rectangle, Disk, Sphere };
    Kind kind = Kind::Mesh;
    TriangleMesh mesh;     ///< Mesh and Rectangle: the triangles, in world space
    Vec3 center{0, 0, 0};  ///< Disk, Sphere
    Vec3 normal{0, 0, 1};  ///< Disk: unit normal (its front side)
    /// The shape's local x axis in world space (its transform's, unit length): an anisotropic
    /// BSDF's x axis is this direction projected onto the tangent plane (Frame(n, tangent)).
    Vec3 tangent{1, 0, 0};
    Vec3 tangentY{0, 1, 0};  ///< its local y axis: the lobe's x axis where `tangent` is ⟂ it
    double radius = 1;       ///< Disk, Sphere
    Bsdf bsdf = Bsdf::lambert(Spectrum::Constant(0.5));
    Spectrum emission = Spectrum::Zero();  ///< radiance L_e leaving the front side
    bool twoSidedEmission = false;         ///< emit from the back side too
    /// The side that emits is the back, not the front: a one-sided emitter whose winding the
    /// loader turned outwards (a closed glass mesh or a medium's boundary) still emits from the
    /// side its file's winding gave.
    bool emitsFromBack = false;
    int interiorMedium = -1;  ///< the medium filling the inside of a closed surface, or −1
    std::string name;         ///< for messages and statistics, e.g. "surfaces[2]" or its "name"
    MeshPlaces places;        ///< Mesh: where its triangles are in its file (messages at load)

    bool emits() const { return emission.maxCoeff() > 0; }
    bool closed() const { return kind == Kind::Sphere || kind == Kind::Mesh; }
    /// Area of the shape.
    double area() const;
    /// A box containing the shape: its vertices', or (disk, sphere) the centre ± the radius on
    /// each axis.
    Bounds3 bounds() const;
    /// The largest coordinate magnitude the shape reaches (|centre| + radius per axis for disks
    /// and spheres; 0 for a mesh without vertices), NaN if a coordinate is NaN.
    double reach() const;
    /// Radiance leaving the surface towards w (unit, pointing away from it) at a point with
    /// geometric normal ng: L_e if w is on the front side (the back with emitsFromBack; either
    /// with twoSidedEmission), else 0.
    Spectrum Le(const Vec3& ng, const Vec3& w) const {
        const double c = emitsFromBack ? -ng.dot(w) : ng.dot(w);
        return (c > 0 || (twoSidedEmission && c < 0)) ? emission : Spectrum::Zero();
    }
    /// Reverses the mesh's winding (flipWinding), its emission staying on the side it was.
    void turnInsideOut();
    /// Turns the shells of a closed mesh that face the wrong way for a solid's surface
    /// (MeshSolidity::inwardFaces): all of them by turnInsideOut, some face by face. A one-sided
    /// emitter's side cannot follow the second (one flag for the whole surface): false, and
    /// nothing is changed. A mesh that is not closed is left as it is.
    bool faceOutwards();
    /// meshSolidity(mesh, places), computed when first asked and then kept: the loader's glass
    /// and boundary checks and the thin-surface warning each ask, and each analysis welds and
    /// sorts the whole mesh (a glass sphere of 2M triangles loaded in 6.0 s, 2.8 s of it in
    /// three such analyses). Kept while `mesh` changes only by turnInsideOut.
    const MeshSolidity& solidity() const;
    /// Sets `tangent` and `tangentY` to toWorld's x and y axes (each kept where it is zero or not
    /// finite).
    void orient(const Eigen::Affine3d& toWorld);
    /// The unit rectangle [−1, 1]² in the z = 0 plane facing +z, or the unit disk, placed by
    /// toWorld (as the rectangle and disk of Mitsuba and pbrt).
    static Surface rectangle(const Eigen::Affine3d& toWorld);
    static Surface disk(const Eigen::Affine3d& toWorld);
    static Surface sphere(const Vec3& center, double radius);

  private:
    mutable std::shared_ptr<const MeshSolidity> solidity_;  ///< (solidity())
};

}  // namespace shvol
