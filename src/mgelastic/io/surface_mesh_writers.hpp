#pragma once
// Writers of triangle surface meshes, the counterparts of geometry's surface mesh readers.
// `vertices` is (V x 3), one position per row; `triangles` is (T x 3), 0-based vertex indices per
// row, counter-clockwise seen from outside. Every file is written atomically; ASCII numbers are
// the shortest text that reads back to the same double (std::to_chars), formatted in parallel.
#include <Eigen/Core>
#include <filesystem>

namespace mgelastic::io {

using SurfaceVertices = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
using SurfaceTriangles = Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>;

// Wavefront OBJ: `v x y z` and 1-based `f a b c`.
void write_obj(const std::filesystem::path& path, const SurfaceVertices& vertices,
               const SurfaceTriangles& triangles);

// PLY with double x, y, z and `list uchar int vertex_indices`; ascii, or binary_little_endian.
void write_ply(const std::filesystem::path& path, const SurfaceVertices& vertices,
               const SurfaceTriangles& triangles, bool binary);

// Binary STL (little endian): corners as float32, so coordinates round to single precision;
// normals are the triangles' right-hand unit normals (zero for degenerate triangles).
void write_stl_binary(const std::filesystem::path& path, const SurfaceVertices& vertices,
                      const SurfaceTriangles& triangles);

}  // namespace mgelastic::io
