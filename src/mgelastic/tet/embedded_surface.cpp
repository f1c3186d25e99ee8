#include "mgelastic/tet/embedded_surface.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "mgelastic/core/error.hpp"
#include "mgelastic/tet/parallel.hpp"

namespace mgelastic::tet {
namespace {

// Inside means every barycentric >= -kInside; points on shared faces or edges then find a tet
// despite rounding.
constexpr double kInside = 1e-12;

using Vec3 = Eigen::Vector3d;

// Barycentric coordinates of p in the tet with corners c (columns), unclamped.
Eigen::Vector4d barycentric(const Eigen::Matrix<double, 3, 4>& c, const Vec3& p) {
  Eigen::Matrix3d edges;
  edges << c.col(1) - c.col(0), c.col(2) - c.col(0), c.col(3) - c.col(0);
  const Vec3 l = edges.partialPivLu().solve(p - c.col(0));
  return {1.0 - l.sum(), l[0], l[1], l[2]};
}

// Closest point to p on triangle abc (Ericson, Real-Time Collision Detection, Sec. 5.1.5): the
// Voronoi region of p decides between a corner, an edge and the interior.
Vec3 closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0)
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denominator = 1.0 / (va + vb + vc);
  return a + ab * (vb * denominator) + ac * (vc * denominator);
}

// Distance from p to the solid tet: zero inside, else to the nearest of its four faces.
double distance_to_tet(const Eigen::Matrix<double, 3, 4>& c, const Vec3& p,
                       const Eigen::Vector4d& w) {
  if (w.minCoeff() >= 0) return 0.0;
  constexpr int kFaces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  double best = std::numeric_limits<double>::infinity();
  for (const auto& f : kFaces)
    best =
        std::min(best, (p - closest_on_triangle(p, c.col(f[0]), c.col(f[1]), c.col(f[2]))).norm());
  return best;
}

// Uniform bins over the mesh's bounding box; each holds the tets whose bounding box overlaps it
// (compressed rows: bin b holds items[start[b] .. start[b + 1])).
struct TetBins {
  Vec3 origin;
  double size = 0.0;
  Eigen::Vector3i dims;
  std::vector<int> start, items;

  Eigen::Vector3i cell_of(const Vec3& p) const {
    Eigen::Vector3i c;
    for (int a = 0; a < 3; ++a)
      c[a] = std::clamp(static_cast<int>(std::floor((p[a] - origin[a]) / size)), 0, dims[a] - 1);
    return c;
  }
  int index(const Eigen::Vector3i& c) const { return c[0] + dims[0] * (c[1] + dims[1] * c[2]); }
};

// Bin edge: the mean largest extent of the tets' boxes (one cube edge for a regular tet grid), so a
// bin holds a few dozen tets at most; grown when that would make more bins than tets.
TetBins bin_tets(const geometry::TetMesh& mesh) {
  TetBins bins;
  const Vec3 lo = mesh.vertices.colwise().minCoeff(), hi = mesh.vertices.colwise().maxCoeff();
  double mean_extent = 0.0;
  for (int t = 0; t < mesh.tet_count(); ++t) {
    const Eigen::Matrix<double, 3, 4> c = mesh.corners(t);
    mean_extent += (c.rowwise().maxCoeff() - c.rowwise().minCoeff()).maxCoeff();
  }
  mean_extent /= mesh.tet_count();
  const Vec3 extent = (hi - lo).cwiseMax(1e-300);
  bins.size = std::max(mean_extent, std::cbrt(extent.prod() / mesh.tet_count()));
  bins.origin = lo;
  for (int a = 0; a < 3; ++a)
    bins.dims[a] = std::max(1, static_cast<int>(std::ceil(extent[a] / bins.size)));
  const auto for_bins = [&](int t, auto&& visit) {
    const Eigen::Matrix<double, 3, 4> c = mesh.corners(t);
    const Eigen::Vector3i a = bins.cell_of(c.rowwise().minCoeff()),
                          b = bins.cell_of(c.rowwise().maxCoeff());
    for (int k = a[2]; k <= b[2]; ++k)
      for (int j = a[1]; j <= b[1]; ++j)
        for (int i = a[0]; i <= b[0]; ++i) visit(bins.index({i, j, k}));
  };
  bins.start.assign(static_cast<std::size_t>(bins.dims.prod()) + 1, 0);
  for (int t = 0; t < mesh.tet_count(); ++t) for_bins(t, [&](int b) { ++bins.start[b + 1]; });
  for (std::size_t b = 1; b < bins.start.size(); ++b) bins.start[b] += bins.start[b - 1];
  bins.items.resize(bins.start.back());
  std::vector<int> fill(bins.start.begin(), bins.start.end() - 1);
  for (int t = 0; t < mesh.tet_count(); ++t) for_bins(t, [&](int b) { bins.items[fill[b]++] = t; });
  return bins;
}

struct Binding {
  int tet = -1;
  Eigen::Vector4d weights = Eigen::Vector4d::Constant(-std::numeric_limits<double>::infinity());
  double distance = std::numeric_limits<double>::infinity();
};

// A tet of bin b that holds p: the first with p strictly inside, else the one holding it most
// deeply (largest least barycentric, p on shared faces); tet -1 when none does.
void best_inside(const geometry::TetMesh& mesh, const TetBins& bins, int b, const Vec3& p,
                 Binding& best) {
  for (int i = bins.start[b]; i < bins.start[b + 1]; ++i) {
    const int t = bins.items[i];
    const Eigen::Vector4d w = barycentric(mesh.corners(t), p);
    if (w.minCoeff() >= -kInside && (best.tet < 0 || w.minCoeff() > best.weights.minCoeff()))
      best = {t, w, 0.0};
    if (best.weights.minCoeff() > 0) return;  // strictly inside: no tet holds p more deeply
  }
}

// The nearest tet by rings of bins (Chebyshev distance r from p's clamped bin). A bin in ring r
// is at least (r - 1) bin edges from p on some axis, so the search stops once that exceeds the
// best distance found. Ties (a shared face, edge or corner) go to the tet that extrapolates
// least (largest least barycentric).
Binding nearest_tet(const geometry::TetMesh& mesh, const TetBins& bins, const Vec3& p) {
  Binding best;
  const Eigen::Vector3i home = bins.cell_of(p);
  const int rings = bins.dims.maxCoeff();
  for (int r = 0; r <= rings && (r - 1) * bins.size <= best.distance; ++r) {
    for (int k = home[2] - r; k <= home[2] + r; ++k)
      for (int j = home[1] - r; j <= home[1] + r; ++j)
        for (int i = home[0] - r; i <= home[0] + r; ++i) {
          const Eigen::Vector3i c(i, j, k);
          if ((c - home).cwiseAbs().maxCoeff() != r) continue;  // inner rings are done
          if ((c.array() < 0).any() || (c.array() >= bins.dims.array()).any()) continue;
          const int b = bins.index(c);
          for (int n = bins.start[b]; n < bins.start[b + 1]; ++n) {
            const int t = bins.items[n];
            const Eigen::Matrix<double, 3, 4> corners = mesh.corners(t);
            // The distance to the tet's box bounds the distance to the tet: most tets of a ring
            // are skipped without their four faces.
            const Vec3 below = corners.rowwise().minCoeff() - p,
                       above = p - corners.rowwise().maxCoeff();
            if (below.cwiseMax(above).cwiseMax(0.0).norm() > best.distance + 1e-12 * bins.size)
              continue;
            const Eigen::Vector4d w = barycentric(corners, p);
            const double d = distance_to_tet(corners, p, w);
            const double tie = 1e-12 * bins.size;
            if (d < best.distance - tie ||
                (d <= best.distance + tie && w.minCoeff() > best.weights.minCoeff()))
              best = {t, w, d};
          }
        }
  }
  return best;
}

}  // namespace

EmbeddedSurface embed_surface(const geometry::TetMesh& mesh,
                              const geometry::TriangleMesh& surface) {
  if (mesh.tet_count() == 0) throw Error("cannot embed a surface in a mesh without tetrahedra");
  const TetBins bins = bin_tets(mesh);
  EmbeddedSurface embedded;
  const auto count = static_cast<int>(surface.vertex_count());
  embedded.tet.resize(count);
  embedded.weights.resize(count, 4);
  embedded.triangles = surface.triangles;
  int outside = 0;
  double farthest = 0.0;
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : outside) reduction(max : farthest) \
    if (count >= kMinParallelElements)
  for (int s = 0; s < count; ++s) {
    const Vec3 p = surface.vertices.row(s).transpose();
    Binding b;
    best_inside(mesh, bins, bins.index(bins.cell_of(p)), p, b);
    if (b.tet < 0) {
      b = nearest_tet(mesh, bins, p);
      ++outside;
      farthest = std::max(farthest, b.distance);
    }
    embedded.tet[s] = b.tet;
    embedded.weights.row(s) = b.weights.transpose();
  }
  embedded.outside_vertices = outside;
  embedded.max_outside_distance = farthest;
  return embedded;
}

EmbeddedSurface boundary_as_embedded(const geometry::TetMesh& mesh,
                                     const geometry::TetMeshBoundary& boundary) {
  // Any tet holding the vertex will do: the weight sits on the vertex itself.
  std::vector<std::pair<int, int>> holder(mesh.vertex_count(), {-1, -1});  // (tet, corner)
  for (int t = 0; t < mesh.tet_count(); ++t)
    for (int k = 0; k < 4; ++k) holder[mesh.tets(t, k)] = {t, k};
  EmbeddedSurface embedded;
  const auto count = static_cast<Eigen::Index>(boundary.mesh_vertex.size());
  embedded.tet.resize(count);
  embedded.weights = Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor>::Zero(count, 4);
  for (Eigen::Index s = 0; s < count; ++s) {
    const auto [t, k] = holder[boundary.mesh_vertex[s]];
    embedded.tet[s] = t;
    embedded.weights(s, k) = 1.0;
  }
  embedded.triangles = boundary.triangles;
  return embedded;
}

SurfacePoints embedded_positions(const EmbeddedSurface& surface, const Eigen::MatrixX3d& positions,
                                 const Eigen::MatrixX4i& tets) {
  const auto count = static_cast<int>(surface.vertex_count());
  SurfacePoints y(count, 3);
#pragma omp parallel for if (count >= kMinParallelItems)
  for (int s = 0; s < count; ++s) {
    const int t = surface.tet[s];
    Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
    for (int k = 0; k < 4; ++k) sum += surface.weights(s, k) * positions.row(tets(t, k));
    y.row(s) = sum;
  }
  return y;
}

}  // namespace mgelastic::tet
