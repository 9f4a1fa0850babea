#pragma once
/// \file Triangle meshes from OBJ (Debian's tinyobjloader) and PLY (a strict reader of our own).
///
/// Both keep per-vertex normals and texture coordinates when the file has them. Polygons with more
/// than three vertices are split into a fan (v0, v_k, v_{k+1}), which keeps their winding. Every
/// reader ends with validateMesh (surfaces/triangle_mesh.h). Errors are one shvol::Error line
/// naming the file and the place in it ("FILE: line 12: …" for text, "FILE: byte 345: …" or
/// "FILE: face 7: …" for binary data).
#include <string>
#include <string_view>

#include "shvol/surfaces/triangle_mesh.h"

namespace shvol {

/// PLY 1.0, format ascii, binary_little_endian or binary_big_endian. Elements: `vertex` with
/// float/double (or any scalar type) properties x, y, z, optional nx, ny, nz and u, v (also named
/// s, t or texture_u, texture_v); `face` with a list property vertex_indices (or vertex_index).
/// Other elements and properties are skipped, lists included. Anything else is an error: a missing
/// header line, an unknown type, a truncated body, trailing bytes, an index out of range.
///
/// Each reader validates the mesh as the file has it. Given a transform (a scene's surface), it
/// then moves the mesh there (transformMesh, which also makes the normals unit length) and, if
/// that moved it, validates it again: a triangle the transform makes degenerate or too large is
/// named at the file's place too ("FILE: line 9, after the surface's transform: …").
///
/// Given `places`, each reader also returns where the mesh's triangles are in the file, so that
/// later checks (closedMeshDefect) can name the file's line or face.
TriangleMesh parsePly(std::string_view bytes, const std::string& name,
                      const Eigen::Affine3d* toWorld = nullptr, MeshPlaces* places = nullptr);
TriangleMesh readPly(const std::string& path, const Eigen::Affine3d* toWorld = nullptr,
                     MeshPlaces* places = nullptr);

/// Wavefront OBJ: v, vn, vt and f (all shapes, groups and objects merged; materials ignored).
/// A vertex of the mesh is one distinct (v, vt, vn) triple of the faces.
TriangleMesh readObj(const std::string& path, const Eigen::Affine3d* toWorld = nullptr,
                     MeshPlaces* places = nullptr);

/// readObj or readPly by the file's extension (.obj, .ply; case-insensitive).
TriangleMesh readMesh(const std::string& path, const Eigen::Affine3d* toWorld = nullptr,
                      MeshPlaces* places = nullptr);

}  // namespace shvol
