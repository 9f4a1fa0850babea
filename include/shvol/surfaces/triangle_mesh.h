#pragma once
/// \file An indexed triangle mesh as read from OBJ or PLY (io/mesh_file.h), and its checks.
///
/// Triangles are counter-clockwise seen from their front side, so the geometric normal of
/// triangle (p0, p1, p2) is n_g = (p1 − p0) × (p2 − p0) / |…|; a closed mesh whose triangles all
/// face outwards has a positive signed volume V = (1/6) Σ p0 · (p1 × p2).
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "shvol/core/math.h"

namespace shvol {

struct TriangleMesh {
    std::vector<Vec3> p;            ///< vertex positions
    std::vector<Vec3> n;            ///< per-vertex normals: empty, or one per vertex
    std::vector<Vec2> uv;           ///< per-vertex texture coordinates: empty, or one per vertex
    std::vector<uint32_t> indices;  ///< three vertex indices per triangle
    size_t triangleCount() const { return indices.size() / 3; }
};

/// Where a mesh's triangles and vertices are in its file, for validateMesh's messages: the file's
/// face of each triangle (a polygon is fanned into several), how the file's faces and the
/// mesh's vertices are named ("line 9"), and whether the mesh's vertex numbers are the file's
/// (PLY) or not (OBJ, whose corners are de-duplicated into vertices). Left empty: triangle f is
/// "face f", vertex k "vertex k".
struct MeshPlaces {
    std::string file;  ///< the mesh's file, for messages that name it (closedMeshDefect)
    std::vector<uint32_t> faceOfTriangle;
    std::function<std::string(size_t face)> face;
    std::function<std::string(size_t vertex)> vertex;
    bool fileIndices = true;
    std::string note;  ///< after every place (", after the surface's transform")

    /// The place of triangle f: its file face's name ("line 9") and the note.
    std::string ofTriangle(size_t f) const;
    /// The place of vertex k, as ofTriangle.
    std::string ofVertex(size_t k) const;
};

/// Throws shvol::Error "FILE: vertex K: …" or "FILE: face K: …" (K counted from 0) for a
/// non-finite position, normal or texture coordinate, a zero normal, an index out of range, a
/// triangle of zero area (repeated vertices, or collinear: the sine of its widest angle below
/// 10⁻¹², whichever vertex comes first), or a mesh without triangles. Indices must be in range
/// for the functions below.
void validateMesh(const TriangleMesh& mesh, const std::string& file, const MeshPlaces& places = {});

/// Moves the mesh by toWorld: positions p ↦ toWorld·p, normals n ↦ M⁻ᵀ n / |M⁻ᵀ n| with M its
/// linear part (each normal normalised first too, so that one of length 10³⁰⁰ neither
/// overflows nor reads as zero).
void transformMesh(TriangleMesh& mesh, const Eigen::Affine3d& toWorld);

/// The corner (0, 1 or 2) of triangle f with the widest angle, the one opposite its longest edge
/// (the first of equals).
int widestAngle(const TriangleMesh& mesh, size_t f);

/// Rotates every triangle's indices (its winding, and so its normal, unchanged) so that its
/// widest angle comes first. The cross product (p1 − p0) × (p2 − p0) behind the geometric normal
/// and the area then has the least rounding: its relative error grows as ε / sin(angle at p0),
/// which at a needle's sharp vertex can be 1 (a triangle 10¹³ long and 1 wide has an angle of
/// 10⁻¹³ there and of 90° at the other two).
void widestAngleFirst(TriangleMesh& mesh);

/// Why the mesh is not the closed, consistently oriented surface of a solid, or "" if it is:
/// every directed edge (a, b) of a triangle must appear exactly once, and its reverse (b, a)
/// exactly once in another triangle (an oriented 2-manifold without boundary): as the mesh's
/// vertices join its triangles, or else with vertices at equal positions one vertex (a file's
/// corners with different normals or texture coordinates are distinct vertices of the mesh);
/// an edge is named by its end points (with the
/// digits that tell them apart). A shell (faces joined across shared edges) that encloses no
/// volume (|V| ≤ 10⁻⁹ A^{3/2}: both sides of one sheet) is refused too, as are shells that cross
/// one another (MeshSolidity::inwardFaces) and positions that are not finite. The message starts
/// with the place of the face that shows the defect
/// ("face 12: …", or with places from the mesh's reader "cube.obj: line 40: …").
std::string closedMeshDefect(const TriangleMesh& mesh, const MeshPlaces& places = {});

/// "FILE: PLACE: …" naming two faces with the same corners (positions), in either winding and
/// however a polygon was split (places.faceOfTriangle), or "". A ray meets either of such faces,
/// and light samples count both: an emitting mesh with them is refused (helper 143: a furnace box
/// of duplicated emitting faces rendered 2.11 for 2, a lamp of a quad and its reverse shone to
/// one side or flickered); in a mesh that does not emit they render as one, as the shared face of
/// two solids touching over it does (closedMeshDefect names that case where a solid is needed).
std::string coincidentFaces(const TriangleMesh& mesh, const MeshPlaces& places = {});

/// Signed enclosed volume (1/6) Σ p0 · (p1 × p2): positive when a closed mesh faces outwards.
/// Summed per shell (faces joined across edges, vertices welded by position) about a corner of
/// the shell: the same for closed shells, without the cancellation of terms about a far origin.
/// NaN if a position is not finite.
double signedVolume(const TriangleMesh& mesh);

/// closedMeshDefect and signedVolume of a mesh from one welding of its vertices (each of the two
/// welds and sorts the whole mesh: a mesh surface's are computed once, Surface::solidity).
struct MeshSolidity {
    std::string defect;  ///< closedMeshDefect: "" if closed
    double signedVolume = 0;
    /// Closed: the faces, in order, of the shells (faces joined across their edges) that face
    /// the wrong way for the surface of a solid. A shell faces outwards, or, nested inside an
    /// odd number of others (a hollow's inner wall), inwards; nesting is judged at a point of
    /// each shell by its generalised winding number (Σ solid angles / 4π, Jacobson et al. 2013)
    /// with respect to each other shell. Shells that cross one another, or touch over a face
    /// (a face's centroid on another shell), are a defect (judged at a few points of each:
    /// README), and set partsMeet; inwardFaces are still given, nesting judged only between
    /// shells that do not meet (glass whose parts meet is turned so: each such part outwards on
    /// its own, a hollow's inner wall that meets none inwards).
    std::vector<uint32_t> inwardFaces;
    bool partsMeet = false;
};
MeshSolidity meshSolidity(const TriangleMesh& mesh, const MeshPlaces& places = {});

/// Reverses every triangle's winding (its normal flips; normals and uvs stay with the vertices).
void flipWinding(TriangleMesh& mesh);

/// Area |(p1 − p0) × (p2 − p0)| / 2 of triangle f.
double triangleArea(const TriangleMesh& mesh, size_t f);
/// Total area Σ |(p1 − p0) × (p2 − p0)| / 2.
double surfaceArea(const TriangleMesh& mesh);

}  // namespace shvol
