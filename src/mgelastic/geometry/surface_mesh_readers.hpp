#pragma once
// Readers of triangle surface meshes. Polygons with more than three corners are fan-triangulated
// from their first corner; the result holds every vertex of the file (unused ones included) and
// the triangles in file order. Malformed files throw mgelastic::Error naming the file and the line
// (text) or the byte offset (binary data), and the face index where one is at fault: missing file,
// malformed number, index out of range, counts that do not match, truncated binary data, NaN or
// infinite coordinates, a mesh without triangles.
//
// Formats:
//  - Wavefront `.obj`: `v x y z [w]`, `f` with `i`, `i/t`, `i//n`, `i/t/n` corners, 1-based or
//    negative (relative to the last vertex) indices; texture, normal, group, material, smoothing
//    and the other statements of the OBJ specification are ignored, any other keyword is an
//    error. A face may only use vertices defined before it.
//  - STL `.stl`, ASCII or binary. Binary is recognized by its size, 84 + 50 n bytes for the n
//    triangles its header announces (binary files may begin with "solid" too). Corners with
//    identical coordinates are welded into one vertex.
//  - PLY `.ply`: ascii, binary_little_endian, binary_big_endian. Vertex x, y, z of any numeric
//    type; faces from the list property `vertex_indices` (or `vertex_index`) of any integer types;
//    all other elements and properties are skipped by their declared types.
//  - Object File Format `.off` (also COFF, NOFF, CNOFF): counts line, vertices, then
//    `n i1 ... in` faces with 0-based indices; colours and normals after the data are ignored.
#include <filesystem>

#include "mgelastic/geometry/triangle_mesh.hpp"

namespace mgelastic::geometry {

// Chooses the reader by extension (case-insensitive): .obj, .stl, .ply, .off.
TriangleMesh read_surface_mesh(const std::filesystem::path& path);

TriangleMesh read_obj(const std::filesystem::path& path);
TriangleMesh read_stl(const std::filesystem::path& path);
TriangleMesh read_ply(const std::filesystem::path& path);
TriangleMesh read_off(const std::filesystem::path& path);

}  // namespace mgelastic::geometry
