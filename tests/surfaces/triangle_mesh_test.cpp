#include "shvol/surfaces/triangle_mesh.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "shvol/surfaces/surface.h"
#include "test_util.h"

namespace shvol {
namespace {

using shvol::test::messageOf;

/// The cube [-1, 1]³, two triangles per face, facing outwards. Vertex i = (x, y, z) with bit 0
/// of i for x, bit 1 for y and bit 2 for z.
TriangleMesh cube() {
    TriangleMesh m;
    for (int i = 0; i < 8; ++i) m.p.emplace_back(i & 1 ? 1 : -1, i & 2 ? 1 : -1, i & 4 ? 1 : -1);
    const uint32_t quads[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                  {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& q : quads)
        m.indices.insert(m.indices.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
    return m;
}

/// The tetrahedron with corners 0, x, y, z, facing outwards.
TriangleMesh tetrahedron() {
    TriangleMesh m;
    m.p = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1)};
    m.indices = {0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3};
    return m;
}

void flip(TriangleMesh& m, size_t face) {
    std::swap(m.indices[3 * face + 1], m.indices[3 * face + 2]);
}

TEST(TriangleMesh, CubeIsClosedWithExactVolumeAndArea) {
    const TriangleMesh m = cube();
    EXPECT_NO_THROW(validateMesh(m, "cube.obj"));
    EXPECT_EQ(closedMeshDefect(m), "");
    EXPECT_EQ(signedVolume(m), 8.0);
    EXPECT_EQ(surfaceArea(m), 24.0);
    for (size_t f = 0; f < m.triangleCount(); ++f) {  // each normal points away from the centre
        const Vec3 p0 = m.p[m.indices[3 * f]], p1 = m.p[m.indices[3 * f + 1]],
                   p2 = m.p[m.indices[3 * f + 2]];
        EXPECT_GT((p1 - p0).cross(p2 - p0).dot(p0 + p1 + p2), 0) << "face " << f;
    }
}

TEST(TriangleMesh, TetrahedronIsClosedWithExactVolumeAndArea) {
    const TriangleMesh m = tetrahedron();
    EXPECT_NO_THROW(validateMesh(m, "tet.ply"));
    EXPECT_EQ(closedMeshDefect(m), "");
    EXPECT_DOUBLE_EQ(signedVolume(m), 1.0 / 6);
    EXPECT_DOUBLE_EQ(surfaceArea(m), 1.5 + std::sqrt(3.0) / 2);
}

TEST(TriangleMesh, FlippedMeshIsClosedWithNegativeVolume) {
    TriangleMesh c = cube(), t = tetrahedron();
    flipWinding(c);
    flipWinding(t);
    EXPECT_EQ(closedMeshDefect(c), "");
    EXPECT_EQ(closedMeshDefect(t), "");
    EXPECT_EQ(signedVolume(c), -8.0);
    EXPECT_DOUBLE_EQ(signedVolume(t), -1.0 / 6);
    EXPECT_EQ(surfaceArea(c), 24.0);
}

TEST(TriangleMesh, OpenBoxIsDetected) {
    TriangleMesh m = cube();
    m.indices.resize(m.indices.size() - 6);  // without its top (+z) face
    EXPECT_NO_THROW(validateMesh(m, "box.obj"));
    // Face 0 = (0, 4, 6): edge (4, 6) lay against the top triangle (4, 7, 6).
    EXPECT_EQ(closedMeshDefect(m),
              "face 0: edge from (-1, -1, 1) to (-1, 1, 1) has no opposite edge: the mesh is not "
              "closed");
}

TEST(TriangleMesh, NonManifoldEdgeIsDetected) {
    TriangleMesh m = cube();
    m.p.emplace_back(0, -2, -2);
    m.indices.insert(m.indices.end(), {0, 1, 8});  // a fin on the cube's edge (0, 1)
    EXPECT_NO_THROW(validateMesh(m, "fin.obj"));
    EXPECT_EQ(closedMeshDefect(m),
              "face 4: edge from (-1, -1, -1) to (1, -1, -1) appears twice (also at face 12): "
              "inconsistent winding or non-manifold");
}

TEST(TriangleMesh, InconsistentWindingIsDetected) {
    TriangleMesh m = cube();
    flip(m, 7);  // (2, 7, 3) becomes (2, 3, 7)
    const std::string d = closedMeshDefect(m);
    EXPECT_NE(d.find("appears twice"), std::string::npos) << d;
    // Face 2, (1, 3, 7), has the edge 3 → 7 that the flipped face 7 now has too.
    EXPECT_EQ(
        d.rfind("face 2: edge from (1, 1, -1) to (1, 1, 1) appears twice (also at face 7)", 0), 0u)
        << d;
    EXPECT_NE(d.find("inconsistent winding or non-manifold"), std::string::npos) << d;
    EXPECT_EQ(closedMeshDefect(TriangleMesh()), "the mesh has no triangles");
    m = cube();
    m.indices[4] = m.indices[3];
    EXPECT_EQ(closedMeshDefect(m),
              "face 1: two of its vertices at one position: degenerate triangle");
}

/// The cube with a vertex per corner of each face (24), as a file with a normal per face gives it.
TriangleMesh cubeOfSeparateFaces() {
    const TriangleMesh c = cube();
    TriangleMesh m;
    for (size_t k = 0; k < c.indices.size(); ++k) {
        if (k % 6 == 3 || k % 6 == 4) continue;  // a quad's q0 q1 q2 (k % 6 = 0, 1, 2), q3 (5)
        m.p.push_back(c.p[c.indices[k]]);
    }
    for (uint32_t q = 0; q < 6; ++q)
        m.indices.insert(m.indices.end(),
                         {4 * q, 4 * q + 1, 4 * q + 2, 4 * q, 4 * q + 2, 4 * q + 3});
    return m;
}

// Closed is a property of positions: faces that meet at a position are joined whether or not
// they share a vertex (the flat-shaded cube of any exporter was "not closed", and, wound
// inwards, not turned outwards as a glass boundary).
TEST(TriangleMesh, FacesMeetAtPositionsNotVertexNumbers) {
    TriangleMesh m = cubeOfSeparateFaces();
    ASSERT_EQ(m.p.size(), 24u);
    ASSERT_EQ(m.triangleCount(), 12u);
    EXPECT_EQ(signedVolume(m), 8.0);
    EXPECT_EQ(closedMeshDefect(m), "");
    flipWinding(m);
    EXPECT_EQ(closedMeshDefect(m), "");
    flip(m, 0);
    EXPECT_NE(closedMeshDefect(m).find("inconsistent winding or non-manifold"), std::string::npos)
        << closedMeshDefect(m);
    m = cubeOfSeparateFaces();
    m.p[0].x() = -1.0 + 1e-12;  // a crack: that corner of one face no longer meets the others
    EXPECT_NE(closedMeshDefect(m).find("the mesh is not closed"), std::string::npos)
        << closedMeshDefect(m);
    // named with the digits that tell the corner from the others' (-1 at six digits)
    EXPECT_NE(closedMeshDefect(m).find("(-0.999999999999, -1, -1)"), std::string::npos)
        << closedMeshDefect(m);
}

// Volumes are summed about the mesh, not the origin: 10⁶ away from it a unit cube's volume
// had a random sign, and a glass mesh there was turned inside out.
TEST(TriangleMesh, VolumeFarFromTheOrigin) {
    for (const double far : {1e6, 1e9, -3e12}) {
        TriangleMesh m = cube();
        for (Vec3& p : m.p) p = 0.5 * p + Vec3(far, 0.7 * far, -far);
        EXPECT_NEAR(signedVolume(m), 1.0, 1e-9) << far;
        flipWinding(m);
        EXPECT_NEAR(signedVolume(m), -1.0, 1e-9) << far;
        EXPECT_EQ(closedMeshDefect(m), "") << far;
    }
    // Two parts far apart: each summed about itself (about the centre of both, part 1's volume
    // came out negative at a distance of 10⁶).
    TriangleMesh two = cube();
    const uint32_t n = uint32_t(two.p.size());
    for (size_t k = 0; k < n; ++k) two.p.push_back(two.p[k] + Vec3(1e7, 3e6, 0));
    for (size_t k = 0, m = two.indices.size(); k < m; ++k)
        two.indices.push_back(two.indices[k] + n);
    for (Vec3& p : two.p) p *= 0.5;
    EXPECT_NEAR(signedVolume(two), 2.0, 1e-9);
    EXPECT_EQ(closedMeshDefect(two), "");
}

// Two closed cubes that touch along an edge, each with vertices of its own, are closed as their
// vertices join their faces (welded by position alone, their shared edge had four faces: refused
// as a boundary, and as inward glass left inside out).
TEST(TriangleMesh, SolidsTouchingAlongAnEdgeAreClosed) {
    TriangleMesh two = cube();
    const uint32_t n = uint32_t(two.p.size());
    for (size_t k = 0; k < n; ++k) two.p.push_back(two.p[k] + Vec3(2, 2, 0));
    for (size_t k = 0, m = two.indices.size(); k < m; ++k)
        two.indices.push_back(two.indices[k] + n);
    EXPECT_EQ(closedMeshDefect(two), "");
    EXPECT_EQ(signedVolume(two), 16.0);
    flipWinding(two);
    EXPECT_EQ(closedMeshDefect(two), "");
    EXPECT_EQ(signedVolume(two), -16.0);
    // Touching face to face they are not: a ray crosses one of the two faces there, and the
    // second solid, as a medium's boundary, was empty.
    TriangleMesh faces = cube();
    for (size_t k = 0; k < n; ++k) faces.p.push_back(faces.p[k] + Vec3(2, 0, 0));
    for (size_t k = 0, m = faces.indices.size(); k < m; ++k)
        faces.indices.push_back(faces.indices[k] + n);
    EXPECT_NE(closedMeshDefect(faces).find("solids touching over a face"), std::string::npos)
        << closedMeshDefect(faces);
}

// A part that encloses no volume is no solid's surface, though every edge has its opposite: a
// triangle in both windings was accepted, and as a boundary it let its medium fill the
// half-space beyond it.
TEST(TriangleMesh, APartWithoutVolumeIsNotClosed) {
    TriangleMesh sheet = tetrahedron();
    sheet.indices = {1, 2, 3, 1, 3, 2};
    const std::string noVolume =
        ": the part of the mesh this face belongs to encloses no volume: both sides of one "
        "sheet, not the surface of a solid";
    EXPECT_EQ(closedMeshDefect(sheet), "face 0" + noVolume);
    // Beside a cube, as a part of its own (the cube's volume would hide it in a sum).
    TriangleMesh both = cube();
    const uint32_t n = uint32_t(both.p.size());
    for (const Vec3& p : {Vec3(5, 0, 0), Vec3(6, 0, 0), Vec3(5, 1, 0)}) both.p.push_back(p);
    both.indices.insert(both.indices.end(), {n, n + 1, n + 2, n, n + 2, n + 1});
    EXPECT_EQ(closedMeshDefect(both), "face 12" + noVolume);
    // Touching the cube at one vertex: a shell of its own still (faces join across edges; joined
    // at vertices, the cube's volume hid the sheet's).
    TriangleMesh touching = cube();
    const uint32_t t = uint32_t(touching.p.size());
    for (const Vec3& p : {Vec3(3, 1, 1), Vec3(3, 3, 1)}) touching.p.push_back(p);
    touching.indices.insert(touching.indices.end(), {7, t, t + 1, 7, t + 1, t});
    EXPECT_EQ(closedMeshDefect(touching), "face 12" + noVolume);
    // A square covered on both sides by different diagonals: no triangle repeats.
    TriangleMesh square;
    square.p = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
    square.indices = {0, 1, 2, 0, 2, 3, 0, 3, 1, 1, 3, 2};
    EXPECT_NE(closedMeshDefect(square).find("encloses no volume"), std::string::npos)
        << closedMeshDefect(square);
    // A thin slab is a solid.
    TriangleMesh slab = cube();
    for (Vec3& p : slab.p) p.y() *= 1e-4;
    EXPECT_EQ(closedMeshDefect(slab), "");
}

/// A torus of nu × nv quads, two triangles each, facing outwards.
TriangleMesh torus(uint32_t nu, uint32_t nv) {
    TriangleMesh m;
    for (uint32_t i = 0; i < nu; ++i)
        for (uint32_t j = 0; j < nv; ++j) {
            const double u = TwoPi * i / nu, v = TwoPi * j / nv;
            m.p.emplace_back((2 + std::cos(v)) * std::cos(u), (2 + std::cos(v)) * std::sin(u),
                             std::sin(v));
        }
    const auto at = [&](uint32_t i, uint32_t j) { return (i % nu) * nv + j % nv; };
    for (uint32_t i = 0; i < nu; ++i)
        for (uint32_t j = 0; j < nv; ++j) {
            const uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
            m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
        }
    return m;
}

// A million triangles (a quadratic check would not end within the test's timeout).
TEST(TriangleMesh, ClosedCheckOfAMillionTriangles) {
    TriangleMesh m = torus(500, 1000);
    ASSERT_EQ(m.triangleCount(), 1000000u);
    EXPECT_EQ(closedMeshDefect(m), "");
    EXPECT_GT(signedVolume(m), 0);
    EXPECT_NEAR(signedVolume(m), 2 * Pi * Pi * 2, 0.01 * 4 * Pi * Pi);  // 2π²Rr², R = 2, r = 1
    flip(m, 999999);
    EXPECT_NE(closedMeshDefect(m).find("appears twice (also at face 999999)"), std::string::npos)
        << closedMeshDefect(m);
}

TEST(TriangleMesh, ValidateNamesTheVertex) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const double inf = std::numeric_limits<double>::infinity();
    TriangleMesh m = tetrahedron();
    m.p[3].x() = nan;
    EXPECT_EQ(messageOf([&] { validateMesh(m, "m.ply"); }),
              "m.ply: vertex 3: position (nan, 0, 1) is not finite");
    m = tetrahedron();
    m.n.assign(4, Vec3(0, 0, 1));
    EXPECT_NO_THROW(validateMesh(m, "m.ply"));
    m.n[1] = Vec3(inf, 0, 0);
    EXPECT_EQ(messageOf([&] { validateMesh(m, "m.ply"); }),
              "m.ply: vertex 1: normal (inf, 0, 0) is not finite");
    m.n[1] = Vec3(0, 0, 0);
    EXPECT_EQ(messageOf([&] { validateMesh(m, "m.ply"); }), "m.ply: vertex 1: normal is zero");
    m = tetrahedron();
    m.uv.assign(4, Vec2(0.5, 0.5));
    m.uv[2].y() = -inf;
    EXPECT_EQ(messageOf([&] { validateMesh(m, "m.ply"); }),
              "m.ply: vertex 2: texture coordinates (0.5, -inf) are not finite");
    m.uv.resize(3);
    EXPECT_EQ(messageOf([&] { validateMesh(m, "m.ply"); }),
              "m.ply: 3 texture coordinates for 4 vertices");
    m = tetrahedron();
    m.n.resize(5, Vec3(1, 0, 0));
    EXPECT_EQ(messageOf([&] { validateMesh(m, "m.ply"); }), "m.ply: 5 normals for 4 vertices");
}

// Coincident faces are found in either winding and however their polygons were split: a ray
// meets either, and light samples count an emitting one twice (helper 143: a furnace box of
// duplicated emitting faces rendered 2.11 for 2; a quad and its reverse, split by other
// diagonals, shone to one side). A polygon whose fan from its first corner folds over is refused.
TEST(TriangleMesh, CoincidentFacesAndFoldedPolygons) {
    const std::string same =
        ": coincident faces of an emitting mesh, of which a ray meets either while light samples "
        "count both; give one (a lamp lit on both sides is one face with emission_two_sided)";
    MeshPlaces file;
    file.file = "tet.obj";
    TriangleMesh m = tetrahedron();
    m.indices.insert(m.indices.end(), {m.indices[3], m.indices[4], m.indices[5]});
    EXPECT_EQ(coincidentFaces(m, file), "tet.obj: face 4: the same corners as face 1" + same);
    m.indices.resize(12);
    m.indices.insert(m.indices.end(), {m.indices[5], m.indices[4], m.indices[3]});
    EXPECT_EQ(coincidentFaces(m, file), "tet.obj: face 4: the same corners as face 1" + same);
    // Also where the corners are other vertices at the same positions (a flat-shaded file).
    m.indices.resize(12);
    m.p.push_back(m.p[m.indices[3]]);
    m.indices.insert(m.indices.end(), {uint32_t(m.p.size() - 1), m.indices[5], m.indices[4]});
    EXPECT_EQ(coincidentFaces(m, file), "tet.obj: face 4: the same corners as face 1" + same);
    // A quad (0 1 2 3) and its reverse (3 2 1 0) as a file's two faces: no triangle repeats.
    TriangleMesh panel;
    panel.p = {Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(-1, 1, 0)};
    panel.indices = {0, 1, 2, 0, 2, 3, 3, 2, 1, 3, 1, 0};
    MeshPlaces places;
    places.faceOfTriangle = {0, 0, 1, 1};
    EXPECT_EQ(coincidentFaces(panel, places), "face 1: the same corners as face 0" + same);
    EXPECT_NO_THROW(validateMesh(panel, "panel.obj", places));  // (as a mesh, it is one)
    places.faceOfTriangle = {0, 0};
    panel.indices.resize(6);
    EXPECT_EQ(coincidentFaces(panel, places), "");
    EXPECT_EQ(coincidentFaces(tetrahedron()), "");
    // An L of six corners, split from its reflex corner (from which all the others are seen) or
    // from the end of one arm, (0, 2), whose fan folds over.
    TriangleMesh ell;
    ell.p = {Vec3(1, 1, 0), Vec3(1, 2, 0), Vec3(0, 2, 0),
             Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(2, 1, 0)};  // (1, 1) reflex
    places.faceOfTriangle = {0, 0, 0, 0};
    for (uint32_t i = 1; i + 1 < 6; ++i) ell.indices.insert(ell.indices.end(), {0, i, i + 1});
    EXPECT_NO_THROW(validateMesh(ell, "ell.obj", places));
    ell.indices.clear();
    for (uint32_t i = 1; i + 1 < 6; ++i)
        ell.indices.insert(ell.indices.end(), {2, uint32_t((2 + i) % 6), uint32_t((3 + i) % 6)});
    EXPECT_EQ(messageOf([&] { validateMesh(ell, "ell.obj", places); }),
              "ell.obj: face 0: a polygon whose triangles from its first corner fold over "
              "(concave there, or the polygon crosses itself): give it as triangles, or list "
              "first a corner from which all others are seen");
    // A corner on an edge, 3·10⁻⁵ off it as an OBJ's floats round it at 1000 (its sliver faces
    // the other way: refused as a fold before helpers 144 and 145), and a twisted quad, whose
    // triangles face 106° apart but both along the quad, pass; a bow-tie, whose vector area is 0,
    // does not.
    TriangleMesh sliver;
    sliver.p = {Vec3(1000, 1000, 0), Vec3(1000.5, 1000 + 3e-5, 0), Vec3(1001, 1000, 0),
                Vec3(1001, 1001, 0), Vec3(1000, 1001, 0)};
    sliver.indices = {0, 1, 2, 0, 2, 3, 0, 3, 4};
    places.faceOfTriangle = {0, 0, 0};
    EXPECT_NO_THROW(validateMesh(sliver, "sliver.obj", places));
    TriangleMesh twisted;
    twisted.p = {Vec3(0, 0, 0), Vec3(1, 0, 0.8), Vec3(1, 1, 0), Vec3(0, 1, 0.8)};
    twisted.indices = {0, 1, 2, 0, 2, 3};
    places.faceOfTriangle = {0, 0};
    EXPECT_NO_THROW(validateMesh(twisted, "twisted.obj", places));
    TriangleMesh bowTie = twisted;
    bowTie.p = {Vec3(0, 0, 0), Vec3(1, 1, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)};
    EXPECT_NE(messageOf([&] {
                  validateMesh(bowTie, "bow.obj", places);
              }).find("bow.obj: face 0: a polygon whose triangles from its first corner fold"),
              std::string::npos);
}

TEST(TriangleMesh, ValidateNamesTheFace) {
    TriangleMesh m = cube();
    m.indices[7] = 8;
    EXPECT_EQ(messageOf([&] { validateMesh(m, "cube.obj"); }),
              "cube.obj: face 2: vertex index 8 out of range (8 vertices)");
    m = cube();
    m.indices[5] = m.indices[4];
    EXPECT_EQ(messageOf([&] { validateMesh(m, "cube.obj"); }),
              "cube.obj: face 1: repeated vertex index in (0, 6, 6): degenerate triangle");
    m = tetrahedron();
    m.p.emplace_back(2, 0, 0);
    m.indices.insert(m.indices.end(), {0, 1, 4});  // (0,0,0), (1,0,0), (2,0,0)
    EXPECT_EQ(messageOf([&] { validateMesh(m, "tet.obj"); }),
              "tet.obj: face 4: zero area (collinear vertices): degenerate triangle");
    m.indices[12] = 1;  // (1,0,0), (0,0,0), (2,0,0): p0 between the others
    m.indices[13] = 0;
    EXPECT_EQ(messageOf([&] { validateMesh(m, "tet.obj"); }),
              "tet.obj: face 4: zero area (collinear vertices): degenerate triangle");
    m = tetrahedron();
    m.p[3] = Vec3(0.1, 0.2, 0.3);
    m.p[2] = Vec3(0.3, 0.6, 0.9);  // collinear with p0, p3 up to rounding
    m.indices = {0, 3, 2};
    EXPECT_EQ(messageOf([&] { validateMesh(m, "tet.obj"); }),
              "tet.obj: face 0: zero area (collinear vertices): degenerate triangle");
    m.p[2] = Vec3(0.3, 0.6, 0.9 + 1e-9);  // thin, not degenerate
    EXPECT_NO_THROW(validateMesh(m, "tet.obj"));
    m = tetrahedron();
    m.p[1].x() = 1e300;
    m.p[2].y() = 1e300;
    EXPECT_EQ(messageOf([&] { validateMesh(m, "big.ply"); }),
              "big.ply: face 0: area is not finite (coordinates too large)");
    // Tiny triangles are judged by their shape (the products of edges of 1e-90 underflow, and
    // were called collinear); below an area of 7.5e-155 the normal's squared length underflows:
    // face 0 is a right triangle with legs `scale`, of area scale²/2 (1.3e-77: 8.5e-155; 1.2e-77:
    // 7.2e-155).
    for (const double scale : {1e-70, 1.3e-77, 1.2e-77, 1e-90, 1e-300, 1e-310}) {
        m = tetrahedron();
        for (Vec3& p : m.p) p *= scale;
        EXPECT_EQ(messageOf([&] { validateMesh(m, "tiny.ply"); }),
                  scale > 1.25e-77 ? "(no error)"
                                   : "tiny.ply: face 0: area below 7.5e-155, too small for double "
                                     "precision: scale the mesh up")
            << scale;
        m.p[2] = m.p[0] + 2 * (m.p[1] - m.p[0]);  // collinear at any scale
        EXPECT_EQ(messageOf([&] { validateMesh(m, "tiny.ply"); }),
                  "tiny.ply: face 0: zero area (collinear vertices): degenerate triangle")
            << scale;
    }
    m = tetrahedron();         // three vertices at one point (found by the OBJ fuzzer: the scale's
    m.p[1] = m.p[2] = m.p[0];  // exponent was −ilogb(0), a negated INT_MIN)
    EXPECT_EQ(messageOf([&] { validateMesh(m, "point.ply"); }),
              "point.ply: face 0: zero area (collinear vertices): degenerate triangle");
}

// Whether a triangle is degenerate does not depend on which vertex is listed first: a needle
// 10¹³ long and 1 wide (angles of 10⁻¹³, 90° and 90°) is accepted in all three rotations (the
// test used to look at the first vertex's angle only, and called it "collinear"), and a sliver
// whose widest angle is within 10⁻¹³ of π is refused in all three.
TEST(TriangleMesh, DegeneracyDoesNotDependOnTheFirstVertex) {
    TriangleMesh needle, sliver;
    needle.p = {Vec3(1e13, 0, 0), Vec3(0, 0, 0), Vec3(0, 1, 0)};
    sliver.p = {Vec3(0, 0, 0), Vec3(1, 1e-13, 0), Vec3(2, 0, 0)};
    for (int r = 0; r < 3; ++r) {
        needle.indices =
            sliver.indices = {uint32_t(r), uint32_t((r + 1) % 3), uint32_t((r + 2) % 3)};
        EXPECT_NO_THROW(validateMesh(needle, "needle.obj")) << r;
        EXPECT_EQ(messageOf([&] { validateMesh(sliver, "sliver.obj"); }),
                  "sliver.obj: face 0: zero area (collinear vertices): degenerate triangle")
            << r;
        EXPECT_EQ(widestAngle(sliver, 0), (4 - r) % 3) << r;  // vertex 1, where it is listed
    }
}

// widestAngleFirst keeps each triangle's winding and puts its widest angle first, where the
// cross product behind the normal has the least rounding: for a rotated needle it then gives
// the exact normal to 1e-12, which from the sharp vertex it misses by more than 1e-6.
TEST(TriangleMesh, WidestAngleFirstGivesTheNormalItsPrecision) {
    const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
    TriangleMesh m;
    m.p = {R * Vec3(1e13, 0, 0), Vec3(0, 0, 0), R * Vec3(0, 1, 0)};
    m.indices = {0, 1, 2};
    const Vec3 exact = R * Vec3(0, 0, -1);  // (p1 − p0) × (p2 − p0) ∝ −z before the rotation
    auto normal = [&] {
        const uint32_t* t = m.indices.data();
        return (m.p[t[1]] - m.p[t[0]]).cross(m.p[t[2]] - m.p[t[0]]).normalized();
    };
    EXPECT_GT((normal() - exact).norm(), 1e-6);
    widestAngleFirst(m);
    // Either right angle (the two edges from the sharp vertex tie in double), winding kept.
    const std::vector<uint32_t> rotated = m.indices;
    EXPECT_TRUE(rotated == (std::vector<uint32_t>{1, 2, 0}) ||
                rotated == (std::vector<uint32_t>{2, 0, 1}))
        << rotated[0] << rotated[1] << rotated[2];
    EXPECT_LT((normal() - exact).norm(), 1e-12);
    widestAngleFirst(m);  // already first: unchanged
    EXPECT_EQ(m.indices, rotated);
}

TEST(TriangleMesh, ValidateRefusesAnEmptyMesh) {
    EXPECT_EQ(messageOf([&] { validateMesh(TriangleMesh(), "e.obj"); }),
              "e.obj: the mesh has no triangles");
    TriangleMesh m = tetrahedron();
    m.indices.clear();
    EXPECT_EQ(messageOf([&] { validateMesh(m, "e.obj"); }), "e.obj: the mesh has no triangles");
    m.indices = {0, 1};
    EXPECT_EQ(messageOf([&] { validateMesh(m, "e.obj"); }),
              "e.obj: 2 vertex indices: not whole triangles");
}

/// a with b's triangles appended, b's positions scaled by `scale` and moved by `shift`, and its
/// winding reversed if `flipped`.
TriangleMesh withShell(TriangleMesh a, const TriangleMesh& b, double scale, const Vec3& shift,
                       bool flipped) {
    const uint32_t n = uint32_t(a.p.size());
    for (const Vec3& p : b.p) a.p.push_back(scale * p + shift);
    for (size_t k = 0; k < b.indices.size(); k += 3)
        a.indices.insert(a.indices.end(), {n + b.indices[k], n + b.indices[k + (flipped ? 2 : 1)],
                                           n + b.indices[k + (flipped ? 1 : 2)]});
    return a;
}

/// The faces from `first` to `first + count`.
std::vector<uint32_t> faceRange(uint32_t first, uint32_t count) {
    std::vector<uint32_t> f(count);
    for (uint32_t k = 0; k < count; ++k) f[k] = first + k;
    return f;
}

// Each shell faces outwards, or inwards nested in an odd number of others (a hollow's inner
// wall); a mesh was turned as a whole by its total volume, which left a second cube facing
// inwards beside one facing outwards (as a medium's boundary, fog filled all space behind it).
TEST(TriangleMesh, ShellsThatFaceTheWrongWayAreFound) {
    const TriangleMesh c = cube();  // 12 faces, |V| = 8
    using Faces = std::vector<uint32_t>;
    EXPECT_EQ(meshSolidity(c).inwardFaces, Faces());
    TriangleMesh inward = c;
    flipWinding(inward);
    EXPECT_EQ(meshSolidity(inward).inwardFaces, faceRange(0, 12));
    // Apart: the second, larger cube wound inwards (their volumes' sum is negative).
    const TriangleMesh apart = withShell(c, c, 2, Vec3(10, 0, 0), true);
    EXPECT_LT(signedVolume(apart), 0);
    EXPECT_EQ(meshSolidity(apart).inwardFaces, faceRange(12, 12));
    // A hollow cube: its inner wall inwards is right, outwards wrong.
    EXPECT_EQ(meshSolidity(withShell(c, c, 0.5, Vec3(0.1, 0, 0), true)).inwardFaces, Faces());
    EXPECT_EQ(meshSolidity(withShell(c, c, 0.5, Vec3(0.1, 0, 0), false)).inwardFaces,
              faceRange(12, 12));
    // A solid within the hollow faces outwards again (nested in two shells).
    const TriangleMesh hollow = withShell(c, c, 0.5, Vec3(0, 0, 0), true);
    EXPECT_EQ(meshSolidity(withShell(hollow, c, 0.2, Vec3(0, 0, 0), false)).inwardFaces, Faces());
    EXPECT_EQ(meshSolidity(withShell(hollow, c, 0.2, Vec3(0, 0, 0), true)).inwardFaces,
              faceRange(24, 12));
    // All turned: every shell the wrong way.
    TriangleMesh all = withShell(hollow, c, 0.2, Vec3(0, 0, 0), false);
    flipWinding(all);
    EXPECT_EQ(meshSolidity(all).inwardFaces, faceRange(0, 36));
    // Surface::faceOutwards turns them, and a one-sided emitter it will not turn shell by shell.
    Surface sf;
    sf.mesh = apart;
    EXPECT_TRUE(sf.faceOutwards());
    EXPECT_EQ(meshSolidity(sf.mesh).inwardFaces, Faces());
    EXPECT_EQ(signedVolume(sf.mesh), 8.0 + 64.0);
    Surface lamp;
    lamp.mesh = apart;
    lamp.emission = Spectrum::Ones();
    EXPECT_FALSE(lamp.faceOutwards());
    EXPECT_EQ(lamp.mesh.indices, apart.indices);
    lamp.twoSidedEmission = true;
    EXPECT_TRUE(lamp.faceOutwards());
    // Turned as a whole, a one-sided emitter keeps its side.
    Surface whole;
    whole.mesh = inward;
    whole.emission = Spectrum::Ones();
    EXPECT_TRUE(whole.faceOutwards());
    EXPECT_TRUE(whole.emitsFromBack);
    EXPECT_EQ(whole.solidity().inwardFaces, Faces());
    EXPECT_EQ(whole.solidity().signedVolume, 8.0);
}

// Parts of one mesh that cross each other are refused (each crossing enters or leaves the one
// medium: the overlap of two cubes was empty; helper 66); nested, apart and touching along an
// edge they are not.
TEST(TriangleMesh, PartsThatCrossAreRefused) {
    const TriangleMesh c = cube();  // [−1, 1]³
    const std::string crosses = "the part of the mesh this face belongs to crosses the part at ";
    for (const Vec3& shift : {Vec3(1, 0, 0), Vec3(1, 1, 1), Vec3(0.3, -0.2, 0.1)}) {
        // (Named from whichever part a sampled point shows it: the first, or the second.)
        const std::string d = meshSolidity(withShell(c, c, 1, shift, false)).defect;
        EXPECT_TRUE(d.rfind("face 0: " + crosses + "face 12: ", 0) == 0 ||
                    d.rfind("face 12: " + crosses + "face 0: ", 0) == 0)
            << shift.transpose() << ": " << d;
    }
    EXPECT_EQ(meshSolidity(withShell(c, c, 0.5, Vec3(0, 0, 0), true)).defect, "");
    EXPECT_EQ(meshSolidity(withShell(c, c, 1, Vec3(3, 0, 0), false)).defect, "");
    EXPECT_EQ(meshSolidity(withShell(c, c, 1, Vec3(2, 2, 0), false)).defect, "");
    EXPECT_FALSE(meshSolidity(withShell(c, c, 0.5, Vec3(0, 0, 0), true)).partsMeet);
    // Parts of fewer than 8 faces are judged at all their faces: the second tetrahedron holds
    // the first one's corner (1, 0, 0), which only its last face shows, and the first holds the
    // centroid of the second one's third face. Faces k·4/8 (0, 0, 1, 1) missed both (review).
    const TriangleMesh t = tetrahedron();
    EXPECT_TRUE(meshSolidity(withShell(t, t, 1.2, Vec3(0.7, -0.3, -0.3), false)).partsMeet);
    // Every corner is asked: [−1, 1]³ and [0, 2]³, split by diagonals that leave the corner of
    // each inside the other at no triangle's widest angle, which widestAngleFirst puts first,
    // where only the triangles' first corners were asked (and the face centroids, all outside
    // the other cube): the crossing passed, and the overlap rendered empty (helper 161).
    TriangleMesh two;
    for (const double lo : {-1.0, 0.0})
        for (int i = 0; i < 8; ++i)
            two.p.emplace_back(i & 1 ? lo + 2 : lo, i & 2 ? lo + 2 : lo, i & 4 ? lo + 2 : lo);
    for (const uint32_t base : {0u, 8u})
        for (const uint32_t k : {0, 2, 3, 0, 3, 1, 4, 5, 7, 4, 7, 6, 0, 1, 5, 0, 5, 4,
                                 2, 6, 7, 2, 7, 3, 0, 4, 6, 0, 6, 2, 1, 3, 7, 1, 7, 5})
            two.indices.push_back(base + k);
    widestAngleFirst(two);
    for (size_t f = 0; f < two.triangleCount(); ++f)  // (the case: neither corner comes first)
        EXPECT_TRUE(two.indices[3 * f] != 7 && two.indices[3 * f] != 8) << f;
    const std::string d = meshSolidity(two).defect;
    EXPECT_TRUE(d.rfind("face 0: " + crosses + "face 12: ", 0) == 0 ||
                d.rfind("face 12: " + crosses + "face 0: ", 0) == 0)
        << d;
}

// Parts that touch over a face are refused as touching, not crossing (a box standing on a
// larger one: a point on a face had winding number 0 or 1 by the sign of a zero; review), at
// the face that lies on the other part; along an edge or at a corner they are fine.
TEST(TriangleMesh, PartsThatTouchOverAFaceAreRefused) {
    const TriangleMesh c = cube();  // [−1, 1]³
    for (const Vec3& shift : {Vec3(0, 0, 1.5), Vec3(0.2, -0.3, 1.5), Vec3(0.5, 0.5, 1.5)}) {
        const MeshSolidity m = meshSolidity(withShell(c, c, 0.5, shift, false));
        EXPECT_NE(m.defect.find(": this face lies on the part of the mesh at face "),
                  std::string::npos)
            << shift.transpose() << ": " << m.defect;
        EXPECT_EQ(m.defect.find("crosses the part"), std::string::npos) << m.defect;
        EXPECT_TRUE(m.partsMeet);
    }
    EXPECT_EQ(meshSolidity(withShell(c, c, 1, Vec3(2, 2, 0), false)).defect, "");      // an edge
    EXPECT_EQ(meshSolidity(withShell(c, c, 1, Vec3(2, 2, 2), false)).defect, "");      // a corner
    EXPECT_EQ(meshSolidity(withShell(c, c, 0.5, Vec3(0, 0, 1.6), false)).defect, "");  // apart
}

// Crossing parts have no nesting to judge, but each still has an outside: its inwardFaces are
// the faces of the parts of negative volume, and Surface::faceOutwards turns them (glass whose
// parts cross is rendered, with a warning; it was left as wound once crossing became a defect).
TEST(TriangleMesh, PartsThatCrossAreEachTurnedOutwards) {
    TriangleMesh inward = cube();
    flipWinding(inward);
    // Both wound inwards, and one of each.
    const TriangleMesh both = withShell(inward, inward, 1, Vec3(1, 0, 0), false);
    const MeshSolidity m = meshSolidity(both);
    EXPECT_TRUE(m.partsMeet);
    EXPECT_NE(m.defect, "");
    EXPECT_EQ(m.inwardFaces, faceRange(0, 24));
    const TriangleMesh mixed = withShell(cube(), cube(), 1, Vec3(1, 0, 0), true);
    EXPECT_EQ(meshSolidity(mixed).inwardFaces, faceRange(12, 12));
    // A hollow whose inner wall meets no part keeps it inwards, beside a cube crossing its
    // outer wall (it was turned outwards too, filling the hollow; review).
    const TriangleMesh hollow = withShell(cube(), cube(), 0.5, Vec3(0, 0, 0), true);
    const MeshSolidity h = meshSolidity(withShell(hollow, cube(), 0.2, Vec3(1, 0, 0), false));
    EXPECT_TRUE(h.partsMeet);
    EXPECT_EQ(h.inwardFaces, std::vector<uint32_t>());
    EXPECT_EQ(meshSolidity(withShell(hollow, cube(), 0.2, Vec3(1, 0, 0), true)).inwardFaces,
              faceRange(24, 12));
    for (const TriangleMesh& mesh : {both, mixed}) {
        Surface sf;
        sf.mesh = mesh;
        EXPECT_TRUE(sf.faceOutwards());
        EXPECT_TRUE(sf.solidity().partsMeet);
        EXPECT_EQ(sf.solidity().inwardFaces, std::vector<uint32_t>());
        EXPECT_EQ(sf.solidity().signedVolume, 16.0);  // (each part's own volume, 8)
        EXPECT_EQ(sf.solidity().defect, m.defect);
    }
    // A mesh that is not closed is still left as wound.
    Surface open;
    open.mesh = inward;
    open.mesh.indices.resize(open.mesh.indices.size() - 3);
    const std::vector<uint32_t> wound = open.mesh.indices;
    EXPECT_TRUE(open.faceOutwards());
    EXPECT_EQ(open.mesh.indices, wound);
    EXPECT_FALSE(open.solidity().partsMeet);
}

// A mesh surface's solidity is the mesh's, computed once; turned inside out, its volume changes
// sign (the loader turns glass and boundaries outwards after asking).
TEST(TriangleMesh, SurfaceSolidityIsTheMeshsAndFollowsTurningInsideOut) {
    Surface s;
    s.mesh = cube();
    flipWinding(s.mesh);
    EXPECT_EQ(s.solidity().defect, closedMeshDefect(s.mesh));
    EXPECT_EQ(s.solidity().signedVolume, signedVolume(s.mesh));
    EXPECT_EQ(s.solidity().signedVolume, -8.0);
    s.turnInsideOut();
    EXPECT_EQ(s.solidity().defect, "");
    EXPECT_EQ(s.solidity().signedVolume, 8.0);
    EXPECT_EQ(signedVolume(s.mesh), 8.0);
    // An open mesh's defect, named by its places, and after turning it inside out the defect of
    // the turned mesh.
    Surface open;
    open.mesh = cube();
    open.mesh.indices.resize(open.mesh.indices.size() - 6);
    open.places.file = "box.obj";
    EXPECT_EQ(open.solidity().defect.rfind("box.obj: face 0: ", 0), 0u) << open.solidity().defect;
    // Turned, its edges run the other way: the kept defect would name them as before.
    const std::string before = open.solidity().defect;
    open.turnInsideOut();
    EXPECT_EQ(open.solidity().defect.rfind("box.obj: face 0: ", 0), 0u) << open.solidity().defect;
    EXPECT_NE(open.solidity().defect, before);
}

}  // namespace
}  // namespace shvol
