#pragma once
// Helpers shared by the surface mesh tests: meshes generated in code (icosphere, subdivided box),
// temporary directories, the real-mesh directory, stated tolerances.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "mgelastic/geometry/triangle_mesh.hpp"

#include "support/temp_dir.hpp"

namespace mgelastic::test {

// The hierarchical winding number with beta = 2 and second-order expansions, measured against
// the exact sum over random points (icosphere, bunny, armadillo): mean error 0.7e-3..1e-3, worst
// 3e-3..5e-3; the far-field error falls like beta^-4, so beta = 3 keeps the worst below 1e-3.
inline constexpr double kWindingMeanError = 1.5e-3;
inline constexpr double kWindingMaxError = 1e-2;
inline constexpr double kWindingMaxErrorBeta3 = 1e-3;
// An icosphere of 4 subdivisions (5120 triangles, edges of ~0.07 rad) deviates from the unit
// sphere by at most ~1e-3 (face centres lie at the in-radius); 3e-3 leaves margin.
inline constexpr double kIcosphere4Deviation = 3e-3;
// Binary STL stores float32 corners: relative rounding 2^-24 ~ 6e-8 on O(1) coordinates.
inline constexpr double kFloat32Rounding = 1e-6;

// Icosahedron subdivided `subdivisions` times (4^s * 20 triangles), vertices on the sphere,
// counter-clockwise seen from outside.
inline geometry::TriangleMesh make_icosphere(
    int subdivisions, double radius = 1.0,
    const Eigen::Vector3d& center = Eigen::Vector3d::Zero()) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Eigen::Vector3d> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                    {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                    {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<int, 3>> f = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                       {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                       {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                       {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (auto& x : v) x.normalize();
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> midpoint;
    const auto middle = [&](int a, int b) {
      const auto key = std::minmax(a, b);
      const auto [it, inserted] = midpoint.try_emplace(key, static_cast<int>(v.size()));
      if (inserted) v.push_back((v[a] + v[b]).normalized());
      return it->second;
    };
    std::vector<std::array<int, 3>> finer;
    for (const auto& [a, b, c] : f) {
      const int ab = middle(a, b), bc = middle(b, c), ca = middle(c, a);
      finer.insert(finer.end(), {{a, ab, ca}, {b, bc, ab}, {c, ca, bc}, {ab, bc, ca}});
    }
    f = std::move(finer);
  }
  geometry::TriangleMesh mesh;
  mesh.vertices.resize(static_cast<Eigen::Index>(v.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i) mesh.vertices.row(i) = center + radius * v[i];
  mesh.triangles.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (std::size_t i = 0; i < f.size(); ++i) mesh.triangles.row(i) << f[i][0], f[i][1], f[i][2];
  return mesh;
}

// The surface of the box [lo, hi], each face split into n x n squares of two triangles, vertices
// shared between faces, counter-clockwise seen from outside.
inline geometry::TriangleMesh make_box_mesh(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi,
                                            int n) {
  std::map<std::array<int, 3>, int> ids;
  std::vector<Eigen::Vector3d> v;
  std::vector<std::array<int, 3>> f;
  const auto vertex = [&](std::array<int, 3> g) {
    const auto [it, inserted] = ids.try_emplace(g, static_cast<int>(v.size()));
    if (inserted) v.push_back(lo + (hi - lo).cwiseProduct(Eigen::Vector3d(g[0], g[1], g[2]) / n));
    return it->second;
  };
  for (int d = 0; d < 3; ++d) {
    const int u = (d + 1) % 3, w = (d + 2) % 3;  // e_u x e_w = e_d
    for (int side = 0; side < 2; ++side)
      for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
          std::array<int, 4> q;
          const int corner[4][2] = {{i, j}, {i + 1, j}, {i + 1, j + 1}, {i, j + 1}};
          for (int c = 0; c < 4; ++c) {
            std::array<int, 3> g;
            g[d] = side * n;
            g[u] = corner[c][0];
            g[w] = corner[c][1];
            q[c] = vertex(g);
          }
          if (side == 0) std::swap(q[1], q[3]);  // the low face looks along -e_d
          f.push_back({q[0], q[1], q[2]});
          f.push_back({q[0], q[2], q[3]});
        }
  }
  geometry::TriangleMesh mesh;
  mesh.vertices.resize(static_cast<Eigen::Index>(v.size()), 3);
  for (std::size_t i = 0; i < v.size(); ++i) mesh.vertices.row(i) = v[i];
  mesh.triangles.resize(static_cast<Eigen::Index>(f.size()), 3);
  for (std::size_t i = 0; i < f.size(); ++i) mesh.triangles.row(i) << f[i][0], f[i][1], f[i][2];
  return mesh;
}

// The mesh without the listed triangles.
inline geometry::TriangleMesh remove_triangles(const geometry::TriangleMesh& mesh,
                                               const std::vector<int>& removed) {
  geometry::TriangleMesh out;
  out.vertices = mesh.vertices;
  out.triangles.resize(mesh.triangle_count() - static_cast<Eigen::Index>(removed.size()), 3);
  Eigen::Index row = 0;
  for (Eigen::Index t = 0; t < mesh.triangle_count(); ++t)
    if (std::find(removed.begin(), removed.end(), t) == removed.end())
      out.triangles.row(row++) = mesh.triangles.row(t);
  return out;
}

inline Eigen::Vector3d random_point(std::mt19937& rng, double extent) {
  std::uniform_real_distribution<double> u(-extent, extent);
  return Eigen::Vector3d(u(rng), u(rng), u(rng));
}

// Temporary directories of the surface-mesh tests.
class SurfaceTempDir : public TempDir {
 public:
  SurfaceTempDir() : TempDir("mgelastic_surface") {}
};

// The real-mesh directory from MGELASTIC_DATA_DIR, or empty when the variable is unset.
inline std::filesystem::path data_dir() {
  const char* dir = std::getenv("MGELASTIC_DATA_DIR");
  return dir != nullptr && *dir != '\0' ? std::filesystem::path(dir) : std::filesystem::path();
}

}  // namespace mgelastic::test
