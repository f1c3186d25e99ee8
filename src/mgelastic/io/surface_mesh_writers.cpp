#include "mgelastic/io/surface_mesh_writers.hpp"

#include <Eigen/Geometry>
#include <bit>
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <limits>
#include <ostream>
#include <string>

#include "mgelastic/core/error.hpp"
#include "mgelastic/io/atomic_file.hpp"

namespace mgelastic::io {
namespace {

// A bad index would make an unreadable file: refuse before anything is written.
void check_indices(const std::filesystem::path& path, const SurfaceVertices& vertices,
                   const SurfaceTriangles& triangles) {
  for (Eigen::Index t = 0; t < triangles.rows(); ++t)
    for (int k = 0; k < 3; ++k)
      if (triangles(t, k) < 0 || triangles(t, k) >= vertices.rows())
        throw Error("triangle " + std::to_string(t) + ": vertex index " +
                        std::to_string(triangles(t, k)) + " out of range [0, " +
                        std::to_string(vertices.rows()) + ")",
                    ErrorContext{.file = path.string()});
}

template <class T>
void write_little_endian(std::ostream& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::big)
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
  out.write(bytes, sizeof(T));
}

void write_ply_header(std::ostream& out, const SurfaceVertices& vertices,
                      const SurfaceTriangles& triangles, bool binary) {
  out << "ply\nformat " << (binary ? "binary_little_endian" : "ascii") << " 1.0\n"
      << "comment written by mgelastic\n"
      << "element vertex " << vertices.rows() << "\n"
      << "property double x\nproperty double y\nproperty double z\n"
      << "element face " << triangles.rows() << "\n"
      << "property list uchar int vertex_indices\nend_header\n";
}

void write_ply_binary_data(std::ostream& out, const SurfaceVertices& vertices,
                           const SurfaceTriangles& triangles) {
  for (Eigen::Index v = 0; v < vertices.rows(); ++v)
    for (int k = 0; k < 3; ++k) write_little_endian(out, vertices(v, k));
  for (Eigen::Index t = 0; t < triangles.rows(); ++t) {
    write_little_endian(out, std::uint8_t{3});
    for (int k = 0; k < 3; ++k) write_little_endian(out, std::int32_t{triangles(t, k)});
  }
}

void write_ply_ascii_data(std::ostream& out, const SurfaceVertices& vertices,
                          const SurfaceTriangles& triangles) {
  out << std::setprecision(std::numeric_limits<double>::max_digits10);
  for (Eigen::Index v = 0; v < vertices.rows(); ++v)
    out << vertices(v, 0) << ' ' << vertices(v, 1) << ' ' << vertices(v, 2) << '\n';
  for (Eigen::Index t = 0; t < triangles.rows(); ++t)
    out << "3 " << triangles(t, 0) << ' ' << triangles(t, 1) << ' ' << triangles(t, 2) << '\n';
}

void write_stl_triangle(std::ostream& out, const SurfaceVertices& vertices,
                        const Eigen::Vector3i& corners) {
  const Eigen::Vector3d a = vertices.row(corners[0]).transpose();
  const Eigen::Vector3d b = vertices.row(corners[1]).transpose();
  const Eigen::Vector3d c = vertices.row(corners[2]).transpose();
  const Eigen::Vector3d n = (b - a).cross(c - a).stableNormalized();
  for (int k = 0; k < 3; ++k) write_little_endian(out, static_cast<float>(n[k]));
  for (const Eigen::Vector3d& x : {a, b, c})
    for (int k = 0; k < 3; ++k) write_little_endian(out, static_cast<float>(x[k]));
  write_little_endian(out, std::uint16_t{0});  // attribute byte count
}

}  // namespace

void write_obj(const std::filesystem::path& path, const SurfaceVertices& vertices,
               const SurfaceTriangles& triangles) {
  check_indices(path, vertices, triangles);
  write_file_atomically(path, [&](std::ostream& out) {
    out << "# written by mgelastic\n"
        << std::setprecision(std::numeric_limits<double>::max_digits10);
    for (Eigen::Index v = 0; v < vertices.rows(); ++v)
      out << "v " << vertices(v, 0) << ' ' << vertices(v, 1) << ' ' << vertices(v, 2) << '\n';
    for (Eigen::Index t = 0; t < triangles.rows(); ++t)
      out << "f " << triangles(t, 0) + 1 << ' ' << triangles(t, 1) + 1 << ' ' << triangles(t, 2) + 1
          << '\n';
  });
}

void write_ply(const std::filesystem::path& path, const SurfaceVertices& vertices,
               const SurfaceTriangles& triangles, bool binary) {
  check_indices(path, vertices, triangles);
  write_file_atomically(
      path,
      [&](std::ostream& out) {
        write_ply_header(out, vertices, triangles, binary);
        if (binary) {
          write_ply_binary_data(out, vertices, triangles);
        } else {
          write_ply_ascii_data(out, vertices, triangles);
        }
      },
      binary);
}

void write_stl_binary(const std::filesystem::path& path, const SurfaceVertices& vertices,
                      const SurfaceTriangles& triangles) {
  check_indices(path, vertices, triangles);
  if (triangles.rows() > std::numeric_limits<std::uint32_t>::max())
    throw Error("too many triangles for binary STL", ErrorContext{.file = path.string()});
  write_file_atomically(
      path,
      [&](std::ostream& out) {
        // The header must not begin with "solid", which would suggest ASCII STL to other readers.
        std::string header = "binary STL written by mgelastic";
        header.resize(80, ' ');
        out.write(header.data(), 80);
        write_little_endian(out, static_cast<std::uint32_t>(triangles.rows()));
        for (Eigen::Index t = 0; t < triangles.rows(); ++t)
          write_stl_triangle(out, vertices, triangles.row(t).transpose());
      },
      true);
}

}  // namespace mgelastic::io
