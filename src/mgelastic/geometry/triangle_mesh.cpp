#include "mgelastic/geometry/triangle_mesh.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

#include "mgelastic/core/disjoint_sets.hpp"
#include "mgelastic/core/error.hpp"

namespace mgelastic::geometry {
namespace {

// A directed edge as (undirected key, direction), so sorting groups the uses of each edge.
struct EdgeUse {
  std::uint64_t key;
  bool forward;
  bool operator<(const EdgeUse& other) const { return key < other.key; }
};

std::vector<EdgeUse> edge_uses(const TriangleMesh& mesh) {
  std::vector<EdgeUse> uses;
  uses.reserve(3 * mesh.triangle_count());
  for (Eigen::Index t = 0; t < mesh.triangle_count(); ++t) {
    const auto& f = mesh.triangles.row(t);
    // A triangle with a repeated corner is a segment, not a face: it bounds nothing.
    if (f(0) == f(1) || f(1) == f(2) || f(2) == f(0)) continue;
    for (int k = 0; k < 3; ++k) {
      const auto a = static_cast<std::uint64_t>(f(k));
      const auto b = static_cast<std::uint64_t>(f((k + 1) % 3));
      uses.push_back({std::min(a, b) << 32 | std::max(a, b), a < b});
    }
  }
  std::sort(uses.begin(), uses.end());
  return uses;
}

void count_edges(const TriangleMesh& mesh, MeshFacts& facts) {
  const std::vector<EdgeUse> uses = edge_uses(mesh);
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    const std::size_t n = j - i;
    if (n == 1) ++facts.boundary_edges;
    if (n >= 3) ++facts.non_manifold_edges;
    // An interior edge of an oriented surface is walked once in each direction.
    if (n == 2 && uses[i].forward == uses[i + 1].forward) ++facts.inconsistent_edges;
    i = j;
  }
  facts.closed = facts.boundary_edges == 0;
  facts.manifold = facts.non_manifold_edges == 0;
  facts.consistently_oriented = facts.inconsistent_edges == 0;
}

int count_components(const TriangleMesh& mesh) {
  std::vector<int> parent(mesh.vertex_count());
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<bool> used(mesh.vertex_count(), false);
  for (Eigen::Index t = 0; t < mesh.triangle_count(); ++t) {
    const int r = find_root(parent, mesh.triangles(t, 0));
    for (int k = 0; k < 3; ++k) {
      used[mesh.triangles(t, k)] = true;
      parent[find_root(parent, mesh.triangles(t, k))] = r;
    }
  }
  int components = 0;
  for (int v = 0; v < static_cast<int>(parent.size()); ++v)
    components += used[v] && find_root(parent, v) == v ? 1 : 0;
  return components;
}

bool is_degenerate(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  // Relative to the longest edge, so the test does not depend on the model's units.
  const double longest =
      std::max({(b - a).squaredNorm(), (c - b).squaredNorm(), (a - c).squaredNorm()});
  return (b - a).cross(c - a).norm() <= 1e-12 * longest;
}

void measure_triangles(const TriangleMesh& mesh, MeshFacts& facts) {
  for (Eigen::Index t = 0; t < mesh.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k)
      facts.bounding_box.extend(mesh.vertices.row(mesh.triangles(t, k)).transpose().eval());
  // Volume of the cone from the box centre to each triangle: origin-independent when closed, and
  // taken about a nearby point so large coordinates do not cancel catastrophically.
  const Eigen::Vector3d origin = facts.bounding_box.center();
  double six_volume = 0.0;
  for (Eigen::Index t = 0; t < mesh.triangle_count(); ++t) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.triangles(t, 0)).transpose() - origin;
    const Eigen::Vector3d b = mesh.vertices.row(mesh.triangles(t, 1)).transpose() - origin;
    const Eigen::Vector3d c = mesh.vertices.row(mesh.triangles(t, 2)).transpose() - origin;
    six_volume += a.dot(b.cross(c));
    const auto& f = mesh.triangles.row(t);
    if (f(0) == f(1) || f(1) == f(2) || f(2) == f(0) || is_degenerate(a, b, c))
      ++facts.degenerate_triangles;
  }
  facts.signed_volume = six_volume / 6.0;
}

}  // namespace

void check_triangle_mesh(const TriangleMesh& mesh, const std::string& source) {
  for (Eigen::Index v = 0; v < mesh.vertex_count(); ++v)
    if (!mesh.vertices.row(v).allFinite())
      throw Error("vertex " + std::to_string(v) + " has a non-finite coordinate",
                  ErrorContext{.file = source});
  for (Eigen::Index t = 0; t < mesh.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k)
      if (mesh.triangles(t, k) < 0 || mesh.triangles(t, k) >= mesh.vertex_count())
        throw Error("triangle " + std::to_string(t) + ": vertex index " +
                        std::to_string(mesh.triangles(t, k)) + " out of range [0, " +
                        std::to_string(mesh.vertex_count()) + ")",
                    ErrorContext{.file = source});
}

MeshFacts mesh_facts(const TriangleMesh& mesh) {
  MeshFacts facts;
  facts.vertex_count = mesh.vertex_count();
  facts.triangle_count = mesh.triangle_count();
  count_edges(mesh, facts);
  facts.components = count_components(mesh);
  measure_triangles(mesh, facts);
  return facts;
}

void flip_orientation(TriangleMesh& mesh) {
  mesh.triangles.col(1).swap(mesh.triangles.col(2));
}

}  // namespace mgelastic::geometry
