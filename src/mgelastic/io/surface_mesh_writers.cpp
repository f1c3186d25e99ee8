#include "mgelastic/io/surface_mesh_writers.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <bit>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <limits>
#include <ostream>
#include <string>
#include <vector>

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

// The shortest text that reads back to the same value (std::to_chars).
template <typename T>
void append_number(std::string& text, T value) {
  char number[32];
  text.append(number, std::to_chars(number, number + sizeof number, value).ptr);
}

// `prefix` and the row's three values, shortest round-trip text, one line per row. Formatting is
// the cost of a text mesh (a 256-cell body's 2.9 M triangles: 160 MB), so blocks of rows are
// formatted in parallel, a batch at a time, and written in order.
template <typename Matrix>
void write_rows(std::ostream& out, const char* prefix, const Matrix& rows,
                typename Matrix::Scalar offset = 0) {
  constexpr Eigen::Index kBlockRows = 8192, kBatchBlocks = 32;
  std::vector<std::string> blocks(kBatchBlocks);
  for (Eigen::Index first = 0; first < rows.rows(); first += kBlockRows * kBatchBlocks) {
    const auto count = static_cast<std::ptrdiff_t>(
        std::min(kBatchBlocks, (rows.rows() - first + kBlockRows - 1) / kBlockRows));
#pragma omp parallel for schedule(dynamic, 1)
    for (std::ptrdiff_t b = 0; b < count; ++b) {
      std::string& text = blocks[static_cast<std::size_t>(b)];
      text.clear();
      const Eigen::Index begin = first + b * kBlockRows;
      const Eigen::Index end = std::min(begin + kBlockRows, rows.rows());
      for (Eigen::Index r = begin; r < end; ++r) {
        text += prefix;
        for (int k = 0; k < 3; ++k) {
          // (x + 0.0 would turn -0.0 into 0.0)
          append_number(text, offset == 0 ? rows(r, k) : rows(r, k) + offset);
          text += k < 2 ? ' ' : '\n';
        }
      }
    }
    for (std::ptrdiff_t b = 0; b < count; ++b) out << blocks[static_cast<std::size_t>(b)];
  }
}

void write_ply_ascii_data(std::ostream& out, const SurfaceVertices& vertices,
                          const SurfaceTriangles& triangles) {
  write_rows(out, "", vertices);
  write_rows(out, "3 ", triangles);
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
    out << "# written by mgelastic\n";
    write_rows(out, "v ", vertices);
    write_rows(out, "f ", triangles, 1);
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
