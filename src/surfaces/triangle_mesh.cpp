#include "shvol/surfaces/triangle_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <tuple>

#include "shvol/core/error.h"
#include "shvol/core/ray.h"

namespace shvol {

namespace {

/// "(x, y, …)", with any NaN written "nan" (the C library writes "-nan" for some). `exact`:
/// each coordinate with as many digits as tell it from its neighbours (at least 6).
template <typename V>
std::string str(const V& v, bool exact = false) {
    std::ostringstream s;
    for (int i = 0; i < v.size(); ++i) {
        s << (i ? ", " : "(");
        if (std::isnan(v[i])) {
            s << "nan";
            continue;
        }
        char b[32];
        for (int digits = 6; digits <= 17; ++digits) {
            std::snprintf(b, sizeof b, "%.*g", digits, double(v[i]));
            if (!exact || std::strtod(b, nullptr) == double(v[i])) break;
        }
        s << b;
    }
    s << ")";
    return s.str();
}

/// A closed-mesh defect shown by triangle f: "FILE: PLACE: what" (the file when places has one).
std::string defectAt(const MeshPlaces& places, size_t f, const std::string& what) {
    return (places.file.empty() ? "" : places.file + ": ") + places.ofTriangle(f) + ": " + what;
}

/// Directed edge (a, b) as one sortable key.
uint64_t edgeKey(uint32_t a, uint32_t b) {
    return (uint64_t(a) << 32) | b;
}

/// Each vertex's stand-in at its position: the first vertex of an equal position. A file gives
/// a vertex per distinct corner (an OBJ's v/vt/vn, a PLY's seams), so the faces of a
/// flat-shaded cube share positions, not vertices. (Positions must be finite: validateMesh.)
std::vector<uint32_t> weldByPosition(const TriangleMesh& mesh) {
    std::vector<uint32_t> order(mesh.p.size()), weld(mesh.p.size());
    for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
        const Vec3 &p = mesh.p[a], &q = mesh.p[b];
        return std::tie(p.x(), p.y(), p.z(), a) < std::tie(q.x(), q.y(), q.z(), b);
    });
    for (size_t k = 0; k < order.size(); ++k)
        weld[order[k]] =
            k > 0 && mesh.p[order[k]] == mesh.p[order[k - 1]] ? weld[order[k - 1]] : order[k];
    return weld;
}

/// The shells of a mesh: its faces joined across the edges they share (of welded vertices),
/// each with its signed volume and its area. A shell's volume is summed about its own first
/// corner, not an origin whose terms p0 · (p1 × p2) cancel far from the shell (a glass mesh of
/// size 1 at 10⁶ from the origin got a volume of random sign, and was turned inside out).
struct Shells {
    std::vector<uint32_t> ofFace;      ///< per face, its shell's first face
    std::vector<double> volume, area;  ///< per shell, indexed by its first face
};
Shells shellsOf(const TriangleMesh& mesh, const std::vector<uint32_t>& weld) {
    const size_t nt = mesh.triangleCount();
    const auto corner = [&](size_t f, int j) { return weld[mesh.indices[3 * f + j % 3]]; };
    // Undirected edges with their faces, sorted; faces that share one are one shell.
    std::vector<std::pair<uint64_t, uint32_t>> edges;
    edges.reserve(3 * nt);
    for (size_t f = 0; f < nt; ++f)
        for (int j = 0; j < 3; ++j) {
            const uint32_t a = corner(f, j), b = corner(f, j + 1);
            edges.emplace_back(edgeKey(std::min(a, b), std::max(a, b)), uint32_t(f));
        }
    std::sort(edges.begin(), edges.end());
    Shells s;
    s.ofFace.resize(nt);
    for (uint32_t f = 0; f < nt; ++f) s.ofFace[f] = f;
    const auto root = [&](uint32_t f) {
        while (s.ofFace[f] != f) f = s.ofFace[f] = s.ofFace[s.ofFace[f]];
        return f;
    };
    for (size_t i = 1; i < edges.size(); ++i)
        if (edges[i].first == edges[i - 1].first) {
            const uint32_t a = root(edges[i].second), b = root(edges[i - 1].second);
            s.ofFace[std::max(a, b)] = std::min(a, b);  // (the first face stays the root)
        }
    for (uint32_t f = 0; f < nt; ++f) s.ofFace[f] = root(f);
    s.volume.assign(nt, 0), s.area.assign(nt, 0);
    for (size_t f = 0; f < nt; ++f) {
        const uint32_t r = s.ofFace[f];
        const Vec3& o = mesh.p[corner(r, 0)];
        const Vec3 p0 = mesh.p[corner(f, 0)] - o, p1 = mesh.p[corner(f, 1)] - o,
                   p2 = mesh.p[corner(f, 2)] - o;
        s.volume[r] += p0.dot(p1.cross(p2));  // (6 V until the end: one rounding less)
        s.area[r] += 0.5 * (p1 - p0).cross(p2 - p0).norm();
    }
    for (double& v : s.volume) v /= 6;
    return s;
}

/// Why a shell of a closed mesh encloses no volume, or "". Such a shell is both sides of a
/// sheet (a triangle given in both windings, say): every edge has its opposite, yet which side
/// of it is inside depends on which of two coincident triangles a ray hits (a medium bounded by
/// one filled the half-space beyond it). Shells are judged by |V| ≤ 10⁻⁹ A^{3/2}.
std::string emptyShell(const Shells& s, const MeshPlaces& places) {
    for (size_t f = 0; f < s.ofFace.size(); ++f) {
        const uint32_t r = s.ofFace[f];
        if (std::abs(s.volume[r]) <= 1e-9 * s.area[r] * std::sqrt(s.area[r]))
            return defectAt(places, f,
                            "the part of the mesh this face belongs to encloses no volume: both "
                            "sides of one sheet, not the surface of a solid");
    }
    return "";
}

/// The sum of the shells' volumes.
double volumeOf(const Shells& s) {
    double v = 0;
    for (size_t f = 0; f < s.ofFace.size(); ++f)
        if (s.ofFace[f] == f) v += s.volume[f];
    return v;
}

}  // namespace

int widestAngle(const TriangleMesh& mesh, size_t f) {
    const uint32_t* t = &mesh.indices[3 * f];
    // The widest angle is opposite the longest edge; edge j runs from vertex j + 1 to j + 2.
    double longest = -1;
    int w = 0;
    for (int j = 0; j < 3; ++j) {
        const double l = (mesh.p[t[(j + 2) % 3]] - mesh.p[t[(j + 1) % 3]]).squaredNorm();
        if (l > longest) longest = l, w = j;
    }
    return w;
}

void widestAngleFirst(TriangleMesh& mesh) {
    for (size_t f = 0; f < mesh.triangleCount(); ++f) {
        uint32_t* t = &mesh.indices[3 * f];
        std::rotate(t, t + widestAngle(mesh, f), t + 3);
    }
}

void transformMesh(TriangleMesh& mesh, const Eigen::Affine3d& toWorld) {
    for (Vec3& p : mesh.p) p = toWorld * p;
    const Eigen::Matrix3d m = toWorld.linear().inverse().transpose();
    for (Vec3& n : mesh.n) n = (m * n.stableNormalized()).stableNormalized();
}

std::string MeshPlaces::ofTriangle(size_t f) const {
    const size_t k = f < faceOfTriangle.size() ? faceOfTriangle[f] : f;
    return (face ? face(k) : "face " + std::to_string(k)) + note;
}

std::string MeshPlaces::ofVertex(size_t k) const {
    return (vertex ? vertex(k) : "vertex " + std::to_string(k)) + note;
}

namespace {
/// (p1 − p0) × (p2 − p0) of triangle f: twice its vector area.
Vec3 cross(const TriangleMesh& mesh, size_t f) {
    const uint32_t* t = &mesh.indices[3 * f];
    return (mesh.p[t[1]] - mesh.p[t[0]]).cross(mesh.p[t[2]] - mesh.p[t[0]]);
}

/// Calls polygon(a, b) for the triangles [a, b) of each file face of more than one triangle
/// (places.faceOfTriangle; none when it does not cover the mesh).
template <typename Polygon>
void forEachPolygon(const TriangleMesh& mesh, const MeshPlaces& places, Polygon&& polygon) {
    const std::vector<uint32_t>& ofFace = places.faceOfTriangle;
    if (ofFace.size() != mesh.triangleCount()) return;
    for (size_t a = 0, b; a < ofFace.size(); a = b) {
        for (b = a + 1; b < ofFace.size() && ofFace[b] == ofFace[a];) ++b;
        if (b - a > 1) polygon(a, b);
    }
}
}  // namespace

void validateMesh(const TriangleMesh& mesh, const std::string& file, const MeshPlaces& places) {
    const size_t nv = mesh.p.size();
    if (mesh.indices.size() % 3 != 0)
        fail(file, "",
             std::to_string(mesh.indices.size()) + " vertex indices: not whole triangles");
    if (!mesh.n.empty() && mesh.n.size() != nv)
        fail(file, "",
             std::to_string(mesh.n.size()) + " normals for " + std::to_string(nv) + " vertices");
    if (!mesh.uv.empty() && mesh.uv.size() != nv)
        fail(file, "",
             std::to_string(mesh.uv.size()) + " texture coordinates for " + std::to_string(nv) +
                 " vertices");
    if (mesh.triangleCount() == 0) fail(file, "", "the mesh has no triangles");
    for (size_t k = 0; k < nv; ++k) {
        const std::string place = places.ofVertex(k);
        if (!mesh.p[k].allFinite())
            fail(file, place, "position " + str(mesh.p[k]) + " is not finite");
        if (!mesh.n.empty()) {
            if (!mesh.n[k].allFinite())
                fail(file, place, "normal " + str(mesh.n[k]) + " is not finite");
            if (mesh.n[k].cwiseAbs().maxCoeff() == 0) fail(file, place, "normal is zero");
        }
        if (!mesh.uv.empty() && !mesh.uv[k].allFinite())
            fail(file, place, "texture coordinates " + str(mesh.uv[k]) + " are not finite");
    }
    for (size_t f = 0; f < mesh.triangleCount(); ++f) {
        const std::string place = places.ofTriangle(f);
        const uint32_t* t = &mesh.indices[3 * f];
        for (int j = 0; j < 3; ++j)
            if (t[j] >= nv)
                fail(file, place,
                     "vertex index " + std::to_string(t[j]) + " out of range (" +
                         std::to_string(nv) + " vertices)");
        if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0])
            fail(file, place,
                 places.fileIndices
                     ? "repeated vertex index in (" + std::to_string(t[0]) + ", " +
                           std::to_string(t[1]) + ", " + std::to_string(t[2]) +
                           "): degenerate triangle"
                     : std::string("a vertex repeated in a triangle: degenerate triangle"));
        // Zero area, up to rounding: the widest angle within 1e-12 of π (its sine below 1e-12),
        // the three vertices on a line. Such a triangle has no reliable geometric normal; any
        // other has one, computed at that angle (widestAngleFirst). A needle, whose narrowest
        // angle is near 0, is a triangle like any other, whichever vertex is listed first.
        const int w = widestAngle(mesh, f);
        const Vec3& p0 = mesh.p[t[w]];
        const Vec3 e1 = mesh.p[t[(w + 1) % 3]] - p0, e2 = mesh.p[t[(w + 2) % 3]] - p0;
        const double c = e1.cross(e2).norm();
        if (!std::isfinite(c)) fail(file, place, "area is not finite (coordinates too large)");
        // The angle's sine on the edges scaled by a power of 2 (exactly) to a largest component
        // in [1, 2) (subnormal ones at most by 2¹⁰⁰⁰): tiny edges, whose products underflow, are
        // judged as any other. Edges of 0 (three vertices at one point) are refused as a line.
        const double m = std::max(e1.cwiseAbs().maxCoeff(), e2.cwiseAbs().maxCoeff());
        const double s = m > 0 ? std::ldexp(1.0, std::min(-std::ilogb(m), 1000)) : 0;
        const Vec3 f1 = s * e1, f2 = s * e2;
        if (!(m > 0) || !(f1.cross(f2).norm() > 1e-12 * f1.norm() * f2.norm()))
            fail(file, place, "zero area (collinear vertices): degenerate triangle");
        // The normal is the cross product normalised: its squared length must not underflow
        // (c ≥ √DBL_MIN = 1.49·10⁻¹⁵⁴, an area of 7.5·10⁻¹⁵⁵).
        if (!(c * c >= std::numeric_limits<double>::min()))
            fail(file, place,
                 "area below 7.5e-155, too small for double precision: scale the mesh up");
    }
    // A polygon is split into the fan of triangles from its first corner, which folds over where
    // the polygon is not star-shaped about that corner: a triangle of the fan faces against the
    // polygon's vector area A (the sum of its triangles' cross products, which a fold does not
    // change) and covers what is outside the polygon (helper 143: an L-shaped face covered 0.607
    // or 0.521 of a view by the corner its file listed first). A triangle against A is a fold
    // when its height along A off its longest edge exceeds 10⁻⁶ of the polygon's largest
    // coordinate: the sliver of a corner on an edge, whose side the file's rounding picks (an
    // OBJ's floats: 6·10⁻⁸ of a coordinate), and a twisted quad, whose triangles face apart but
    // both along A, pass (helpers 144, 145); a polygon whose A is 0 (a bow-tie) folds wholly.
    forEachPolygon(mesh, places, [&](size_t a, size_t b) {
        Vec3 area = Vec3::Zero();
        double reach = 0;
        for (size_t f = a; f < b; ++f) {
            area += cross(mesh, f);
            for (int j = 0; j < 3; ++j)
                reach = std::max(reach, mesh.p[mesh.indices[3 * f + j]].cwiseAbs().maxCoeff());
        }
        const Vec3 normal = area.norm() > 0 ? Vec3(area.normalized()) : Vec3::Zero();
        for (size_t f = a; f < b; ++f) {
            const uint32_t* t = &mesh.indices[3 * f];
            const double base = std::max({(mesh.p[t[1]] - mesh.p[t[0]]).norm(),
                                          (mesh.p[t[2]] - mesh.p[t[1]]).norm(),
                                          (mesh.p[t[0]] - mesh.p[t[2]]).norm()});
            if (normal == Vec3::Zero() || -cross(mesh, f).dot(normal) > 1e-6 * reach * base)
                fail(file, places.ofTriangle(f),
                     "a polygon whose triangles from its first corner fold over (concave there, "
                     "or the polygon crosses itself): give it as triangles, or list first a "
                     "corner from which all others are seen");
        }
    });
}

namespace {
/// Every triangle's directed edges (a, b) of vertices weld[a], weld[b], as keys, sorted.
std::vector<uint64_t> directedEdges(const TriangleMesh& mesh, const std::vector<uint32_t>& weld) {
    std::vector<uint64_t> keys(mesh.indices.size());
    for (size_t k = 0; k < keys.size(); ++k)
        keys[k] = edgeKey(weld[mesh.indices[k]], weld[mesh.indices[k - k % 3 + (k + 1) % 3]]);
    std::sort(keys.begin(), keys.end());
    return keys;
}

/// The first face from `from` on that has the directed edge `key` of welded vertices (edgeKey),
/// or the face count.
size_t faceWithEdge(const TriangleMesh& mesh, const std::vector<uint32_t>& weld, uint64_t key,
                    size_t from) {
    for (size_t f = from; f < mesh.triangleCount(); ++f)
        for (int j = 0; j < 3; ++j)
            if (edgeKey(weld[mesh.indices[3 * f + j]], weld[mesh.indices[3 * f + (j + 1) % 3]]) ==
                key)
                return f;
    return mesh.triangleCount();
}

/// The defect of the mesh with each vertex standing for weld[vertex]; where it finds none, it
/// has computed the shells, and leaves them in *shells.
std::string defectWith(const TriangleMesh& mesh, const std::vector<uint32_t>& weld,
                       const MeshPlaces& places, Shells* shells) {
    const size_t nt = mesh.triangleCount();
    const auto corner = [&](size_t f, int j) { return weld[mesh.indices[3 * f + j % 3]]; };
    for (size_t f = 0; f < nt; ++f)
        if (corner(f, 0) == corner(f, 1) || corner(f, 1) == corner(f, 2) ||
            corner(f, 2) == corner(f, 0))
            return defectAt(places, f, "two of its vertices at one position: degenerate triangle");
    // All directed edges, sorted: O(T log T). A closed oriented manifold has every key once and
    // the reverse of every key.
    const auto edgeOf = [&](size_t f, int j) { return edgeKey(corner(f, j), corner(f, j + 1)); };
    const std::vector<uint64_t> keys = directedEdges(mesh, weld);
    const auto has = [&](uint64_t k) { return std::binary_search(keys.begin(), keys.end(), k); };
    const auto reverse = [](uint64_t k) { return (k << 32) | (k >> 32); };
    bool twice = false, open = false;
    for (size_t i = 0; i < keys.size(); ++i) {
        if (i + 1 < keys.size() && keys[i] == keys[i + 1]) twice = true;
        if (!has(reverse(keys[i]))) open = true;
        if (twice) break;
    }
    if (!twice && !open) {
        *shells = shellsOf(mesh, weld);
        return emptyShell(*shells, places);
    }
    // A defect exists: name the first face that shows it, duplicates first (they explain the
    // missing opposite edges that inconsistent winding also causes). Edges are named by their
    // end points: the vertex numbers are the loader's, not the file's.
    const auto edgeName = [&](uint64_t k) {
        return "edge from " + str(mesh.p[k >> 32], true) + " to " + str(mesh.p[uint32_t(k)], true);
    };
    for (size_t f = 0; f < nt && twice; ++f)
        for (int j = 0; j < 3; ++j) {
            const uint64_t k = edgeOf(f, j);
            const auto range = std::equal_range(keys.begin(), keys.end(), k);
            if (range.second - range.first < 2) continue;
            return defectAt(places, f,
                            edgeName(k) + " appears twice (also at " +
                                places.ofTriangle(faceWithEdge(mesh, weld, k, f + 1)) +
                                "): inconsistent winding or non-manifold");
        }
    for (size_t f = 0; f < nt; ++f)
        for (int j = 0; j < 3; ++j) {
            const uint64_t k = edgeOf(f, j);
            if (!has(reverse(k)))
                return defectAt(places, f,
                                edgeName(k) + " has no opposite edge: the mesh is not closed");
        }
    return "";  // not reached
}

/// closedMeshDefect of a mesh with finite positions, given its weldByPosition; *shells are those
/// of the mesh as it is closed (its vertices as given, else welded) wherever it has computed
/// them (else left empty).
std::string defectWelded(const TriangleMesh& mesh, const std::vector<uint32_t>& weld,
                         const MeshPlaces& places, Shells* shells) {
    // Closed as its vertices join its faces (two closed cubes that touch along an edge, each
    // with vertices of its own), or else as its positions do (a flat-shaded mesh, a vertex per
    // face corner): welded alone, the touching cubes' shared edge had four faces.
    std::vector<uint32_t> asGiven(mesh.p.size());
    for (uint32_t i = 0; i < asGiven.size(); ++i) asGiven[i] = i;
    if (!defectWith(mesh, asGiven, places, shells).empty())
        return defectWith(mesh, weld, places, shells);
    // No two vertices at one position (a smooth mesh): the welded mesh is the mesh as given.
    if (weld == asGiven) return "";
    // Closed as given. Solids of their own vertices that touch along an edge (or at a point)
    // are fine; touching over a face, a ray crosses only one of the two faces there (the second
    // solid was empty as a medium's boundary). Told apart by the edges the welded mesh has twice:
    // all on one line, or not.
    const std::vector<uint64_t> keys = directedEdges(mesh, weld);
    std::vector<uint64_t> twice;  // the edges found twice
    for (size_t i = 1; i < keys.size(); ++i)
        if (keys[i] == keys[i - 1]) twice.push_back(keys[i]);
    const auto end = [&](size_t i, bool second) {
        return mesh.p[second ? uint32_t(twice[i]) : uint32_t(twice[i] >> 32)];
    };
    for (size_t i = 1; i < twice.size(); ++i)
        for (const bool second : {false, true}) {
            const Vec3 a = end(0, true) - end(0, false), b = end(i, second) - end(0, false);
            if (!(a.cross(b).norm() > 1e-9 * a.norm() * b.norm())) continue;
            return defectAt(places, faceWithEdge(mesh, weld, twice[i], 0),
                            "solids touching over a face (at " + str(end(i, second), true) +
                                "): a ray crosses only one of the faces there; give each solid a "
                                "surface of its own");
        }
    return "";
}

/// The solid angle of triangle f seen from x, signed (positive where x lies on its back side, as
/// the inside of a closed mesh facing outwards does): Van Oosterom & Strackee 1983,
/// tan(Ω/2) = a·(b × c) / (|a||b||c| + (a·b)|c| + (a·c)|b| + (b·c)|a|), a, b, c the corners − x.
double solidAngle(const TriangleMesh& mesh, size_t f, const Vec3& x) {
    const uint32_t* t = &mesh.indices[3 * f];
    const Vec3 a = mesh.p[t[0]] - x, b = mesh.p[t[1]] - x, c = mesh.p[t[2]] - x;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    return 2 * std::atan2(a.dot(b.cross(c)),
                          la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la);
}

/// How the shells of a closed mesh lie: MeshSolidity's defect where two cross or touch over a
/// face, and its inwardFaces.
struct ShellLayout {
    std::string defect;
    std::vector<uint32_t> inwardFaces;
    bool partsMeet = false;
};

/// The shells' layout: a shell nested in k others faces outwards if k is even, inwards if odd. A
/// point lies inside another shell if its winding number with respect to that shell (Σ Ω / 4π,
/// Jacobson et al. 2013) is ±1, outside if 0; a point on it (onShell) is neither. Only shells
/// whose boxes hold the point are asked. A shell is inside another if its first face's centroid
/// is; two shells cross if of a few of one's points (a corner and the centroid of up to 8 faces
/// spread over it) some lie inside the other and some outside it (a check that can miss
/// crossings no sampled point shows: two bars crossed like a plus sign), and touch over a face
/// if one of those centroids lies on the other (touching along an edge or at a point is fine).
/// The faces layoutOf visits for the shells' corners in all, shared among the pairs of shells
/// whose boxes overlap (a corner asked of a shell visits each of its faces twice: its winding
/// number and the on-shell test), each pair asking at least 8 corners: every corner of two
/// shells of 4,000 faces each, or of a shell of a million faces against a cube. (A budget per
/// pair made a glass sphere of 79k faces with 64 bubbles of 760 faces load in 130 s, nested
/// shells asking all their corners; helper 163.)
constexpr uint64_t kWindingBudget = 1 << 25;

ShellLayout layoutOf(const TriangleMesh& mesh, const Shells& s, const MeshPlaces& places) {
    const size_t nt = mesh.triangleCount();
    std::vector<uint32_t> roots, start(nt + 1, 0), faces(nt);
    for (size_t f = 0; f < nt; ++f) {
        if (s.ofFace[f] == f) roots.push_back(uint32_t(f));
        ++start[s.ofFace[f] + 1];
    }
    ShellLayout layout;
    std::vector<uint32_t>& turned = layout.inwardFaces;
    if (roots.size() == 1) {  // (most meshes: no winding numbers)
        if (s.volume[roots[0]] < 0)
            for (uint32_t f = 0; f < nt; ++f) turned.push_back(f);
        return layout;
    }
    // The faces of each shell together (faces[start[r] …]), and each shell's box.
    for (size_t r = 0; r < nt; ++r) start[r + 1] += start[r];
    std::vector<uint32_t> next(start.begin(), start.end() - 1);
    for (uint32_t f = 0; f < nt; ++f) faces[next[s.ofFace[f]]++] = f;
    std::vector<Bounds3> box(roots.size(), {Vec3::Constant(INFINITY), Vec3::Constant(-INFINITY)});
    for (size_t i = 0; i < roots.size(); ++i)
        for (uint32_t k = start[roots[i]]; k < start[roots[i] + 1]; ++k)
            for (int j = 0; j < 3; ++j) {
                const Vec3& p = mesh.p[mesh.indices[3 * faces[k] + j]];
                box[i].lo = box[i].lo.cwiseMin(p), box[i].hi = box[i].hi.cwiseMax(p);
            }
    const auto inBox = [&](const Vec3& x, size_t o) {
        return !(x.array() < box[o].lo.array()).any() && !(x.array() > box[o].hi.array()).any();
    };
    // |winding number| of x with respect to shell o: about 1 inside, 0 outside.
    const auto winding = [&](const Vec3& x, size_t o) {
        double omega = 0;
        for (uint32_t k = start[roots[o]]; k < start[roots[o] + 1]; ++k)
            omega += solidAngle(mesh, faces[k], x);
        return std::abs(omega) / (2 * TwoPi);
    };
    // Whether x lies on shell o (a face, an edge or a corner of it, within 10⁻⁹ of its box's
    // diagonal), where its winding number is neither 0 nor 1 (a point on a face read 0 or 1 by
    // the sign of a zero; review: a box standing on a larger one was said to cross it).
    const auto onShell = [&](const Vec3& x, size_t o) {
        const double tol = 1e-9 * (box[o].hi - box[o].lo).norm();
        for (uint32_t k = start[roots[o]]; k < start[roots[o] + 1]; ++k) {
            const uint32_t* t = &mesh.indices[3 * faces[k]];
            const Vec3 corner[3] = {mesh.p[t[0]], mesh.p[t[1]], mesh.p[t[2]]};
            const Vec3 n = (corner[1] - corner[0]).cross(corner[2] - corner[0]);
            const double area2 = n.norm();
            if (!(area2 > 0) || std::abs(n.dot(x - corner[0])) > tol * area2) continue;
            bool in = true;  // on the inner side of each edge, within tol
            for (int e = 0; e < 3 && in; ++e) {
                const Vec3 edge = corner[(e + 1) % 3] - corner[e];
                in = n.dot(edge.cross(x - corner[e])) >= -tol * area2 * edge.norm();
            }
            if (in) return true;
        }
        return false;
    };
    // The pairs of shells whose boxes overlap, found by a sweep along x: only they can nest or
    // cross (asking every pair made a mesh of 20,000 separate beads 4·10⁸ pairs; review).
    std::vector<size_t> order(roots.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](size_t a, size_t b) { return box[a].lo.x() < box[b].lo.x(); });
    std::vector<std::vector<size_t>> overlapping(roots.size());
    for (size_t a = 0; a < order.size(); ++a)
        for (size_t b = a + 1; b < order.size() && box[order[b]].lo.x() <= box[order[a]].hi.x();
             ++b) {
            const Bounds3 &p = box[order[a]], &q = box[order[b]];
            if (p.meets(q)) {
                overlapping[order[a]].push_back(order[b]);
                overlapping[order[b]].push_back(order[a]);
            }
        }
    uint64_t budget = kWindingBudget, pairsLeft = 0;  // (face visits, pairs to ask)
    for (const std::vector<size_t>& o : overlapping) pairsLeft += o.size();
    for (size_t i = 0; i < roots.size(); ++i) {
        const uint32_t* t = &mesh.indices[3 * roots[i]];
        const Vec3 x = (mesh.p[t[0]] + mesh.p[t[1]] + mesh.p[t[2]]) / 3;
        const uint32_t count = start[roots[i] + 1] - start[roots[i]];
        int depth = 0;
        // Shell i's distinct corners (vertex indices), asked of each overlapping shell.
        std::vector<uint32_t> corners;
        if (!overlapping[i].empty()) {
            for (uint32_t k = start[roots[i]]; k < start[roots[i] + 1]; ++k)
                for (int j = 0; j < 3; ++j) corners.push_back(mesh.indices[3 * faces[k] + j]);
            std::sort(corners.begin(), corners.end());
            corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
        }
        for (const size_t o : overlapping[i]) {
            bool inside = false, outside = false;
            // Where x lies with respect to shell o: on it (true; neither inside nor outside),
            // else inside or outside.
            const auto classify = [&](const Vec3& x) {
                if (!inBox(x, o)) return outside = true, false;
                if (onShell(x, o)) return true;
                const double w = winding(x, o);
                inside |= w > 0.9, outside |= w < 0.1;
                return false;
            };
            uint32_t touching = nt;  // a sampled face whose centroid lies on shell o
            const uint32_t samples = std::min(count, 8u);  // (distinct faces: review)
            for (uint32_t k = 0; k < samples; ++k) {
                const uint32_t face = faces[start[roots[i]] + uint64_t(k) * count / samples];
                const uint32_t* c = &mesh.indices[3 * face];
                if (classify((mesh.p[c[0]] + mesh.p[c[1]] + mesh.p[c[2]]) / 3) && touching == nt)
                    touching = face;
            }
            // Every corner, where this pair's share of kWindingBudget allows, else corners spread
            // evenly over the shell: a corner of one cube inside another was missed where the
            // sampled faces' first corners (after widestAngleFirst) were all outside it (helper
            // 161).
            const uint64_t perPoint = 2 * uint64_t(start[roots[o] + 1] - start[roots[o]]);
            const uint64_t share = budget / std::max<uint64_t>(1, pairsLeft--);
            const size_t asked =
                std::min(corners.size(), size_t(std::max<uint64_t>(8, share / perPoint)));
            size_t k = 0;
            for (; k < asked && !(inside && outside); ++k)
                classify(mesh.p[corners[k * corners.size() / asked]]);
            budget -= std::min(budget, k * perPoint);
            // Parts that meet have no nesting: each is turned outwards on its own (a hollow's
            // inner wall that meets no part stays inwards; review: it was turned too).
            if (((inside && outside) || touching < nt) && !layout.partsMeet) {
                const std::string other = places.ofTriangle(roots[o]);
                layout.defect =
                    inside && outside
                        ? defectAt(places, roots[i],
                                   "the part of the mesh this face belongs to crosses the part "
                                   "at " +
                                       other +
                                       ": the parts of one mesh must not intersect (a ray "
                                       "would enter one solid inside the other)")
                        : defectAt(places, touching,
                                   "this face lies on the part of the mesh at " + other +
                                       ": solids touching over a face, where a ray crosses only "
                                       "one of the two faces; give each solid a surface of its "
                                       "own");
                layout.partsMeet = true;
            }
            if ((inside && outside) || touching < nt) continue;
            if (inBox(x, o) && winding(x, o) > 0.5) ++depth;
        }
        if ((s.volume[roots[i]] < 0) != (depth % 2 == 1))
            turned.insert(turned.end(), faces.begin() + start[roots[i]],
                          faces.begin() + start[roots[i] + 1]);
    }
    std::sort(turned.begin(), turned.end());
    return layout;
}

/// Whether every position is finite.
bool finitePositions(const TriangleMesh& mesh) {
    for (const Vec3& p : mesh.p)
        if (!p.allFinite()) return false;
    return true;
}
}  // namespace

std::string coincidentFaces(const TriangleMesh& mesh, const MeshPlaces& places) {
    // Each triangle's welded corners, sorted, and each polygon's, so that a polygon given twice
    // and split by other diagonals (a quad and its reverse) is found too.
    const std::vector<uint32_t> weld = weldByPosition(mesh);
    std::vector<std::pair<std::array<uint32_t, 3>, size_t>> triangles(mesh.triangleCount());
    for (size_t f = 0; f < triangles.size(); ++f) {
        const uint32_t* t = &mesh.indices[3 * f];
        triangles[f] = {{weld[t[0]], weld[t[1]], weld[t[2]]}, f};
        std::sort(triangles[f].first.begin(), triangles[f].first.end());
    }
    std::vector<std::pair<std::vector<uint32_t>, size_t>> polygons;
    forEachPolygon(mesh, places, [&](size_t a, size_t b) {
        std::vector<uint32_t> corners;
        for (size_t f = a; f < b; ++f)
            corners.insert(corners.end(), triangles[f].first.begin(), triangles[f].first.end());
        std::sort(corners.begin(), corners.end());
        corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
        polygons.push_back({std::move(corners), a});
    });
    // The first face in the file's order that repeats an earlier one, and that one.
    size_t later = mesh.triangleCount(), earlier = 0;
    const auto firstRepeat = [&](auto& faces) {
        std::sort(faces.begin(), faces.end());
        for (size_t i = 1; i < faces.size(); ++i)
            if (faces[i].first == faces[i - 1].first && faces[i].second < later)
                later = faces[i].second, earlier = faces[i - 1].second;
    };
    firstRepeat(triangles);
    firstRepeat(polygons);
    if (later == mesh.triangleCount()) return "";
    return (places.file.empty() ? "" : places.file + ": ") + places.ofTriangle(later) +
           ": the same corners as " + places.ofTriangle(earlier) +
           ": coincident faces of an emitting mesh, of which a ray meets either while light "
           "samples count both; give one (a lamp lit on both sides is one face with "
           "emission_two_sided)";
}

std::string closedMeshDefect(const TriangleMesh& mesh, const MeshPlaces& places) {
    return meshSolidity(mesh, places).defect;
}

double signedVolume(const TriangleMesh& mesh) {
    if (!finitePositions(mesh)) return std::numeric_limits<double>::quiet_NaN();
    return volumeOf(shellsOf(mesh, weldByPosition(mesh)));
}

MeshSolidity meshSolidity(const TriangleMesh& mesh, const MeshPlaces& places) {
    if (mesh.triangleCount() == 0) return {"the mesh has no triangles", 0, {}, false};
    if (!finitePositions(mesh))
        return {
            "a vertex position is not finite", std::numeric_limits<double>::quiet_NaN(), {}, false};
    const std::vector<uint32_t> weld = weldByPosition(mesh);
    Shells shells;
    std::string defect = defectWelded(mesh, weld, places, &shells);
    if (shells.ofFace.empty()) shells = shellsOf(mesh, weld);
    MeshSolidity m{std::move(defect), volumeOf(shells), {}, false};
    if (m.defect.empty()) {
        ShellLayout layout = layoutOf(mesh, shells, places);
        m.defect = std::move(layout.defect);
        m.inwardFaces = std::move(layout.inwardFaces);
        m.partsMeet = layout.partsMeet;
    }
    return m;
}

double triangleArea(const TriangleMesh& mesh, size_t f) {
    const uint32_t* t = &mesh.indices[3 * f];
    return 0.5 * (mesh.p[t[1]] - mesh.p[t[0]]).cross(mesh.p[t[2]] - mesh.p[t[0]]).norm();
}

double surfaceArea(const TriangleMesh& mesh) {
    double a = 0;
    for (size_t f = 0; f < mesh.triangleCount(); ++f) a += triangleArea(mesh, f);
    return a;
}

void flipWinding(TriangleMesh& mesh) {
    for (size_t k = 0; k + 2 < mesh.indices.size(); k += 3)
        std::swap(mesh.indices[k + 1], mesh.indices[k + 2]);
}

}  // namespace shvol
