#include "mgelastic/geometry/marching_cubes.hpp"

#include <algorithm>
#include <array>
#include <climits>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "mgelastic/core/error.hpp"

namespace mgelastic::geometry {
namespace {

// Keeps edge vertices off the samples (see the header): 1e-6 s is far below the O(s^2)
// interpolation error and far above round-off of coordinates.
constexpr double kEdgeClamp = 1e-6;
constexpr double kMaxSamples = 2147483648.0;  // 2^31
// Samples at least this many spacings from the surface are no corner of a cube it crosses
// (> sqrt(3)): their sign is all the extraction needs (Extractor::sample_slab).
constexpr double kFarSpacings = 2.0;

using Tetrahedron = std::array<int, 4>;  // cube corners c = dx + 2 dy + 4 dz

Eigen::Vector3d corner_offset(int c) {
  return Eigen::Vector3d(c & 1, (c >> 1) & 1, c >> 2);
}

// The six Kuhn tetrahedra 0 -> e_p0 -> e_p0 + e_p1 -> (1,1,1), one per axis permutation p, each
// ordered so that its signed volume is positive.
const std::array<Tetrahedron, 6>& kuhn_tetrahedra() {
  static const std::array<Tetrahedron, 6> tets = [] {
    std::array<Tetrahedron, 6> result{};
    std::array<int, 3> p{0, 1, 2};
    for (auto& tet : result) {
      tet = {0, 1 << p[0], (1 << p[0]) | (1 << p[1]), 7};
      Eigen::Matrix3d m;
      for (int a = 0; a < 3; ++a) m.col(a) = corner_offset(tet[a + 1]) - corner_offset(tet[0]);
      if (m.determinant() < 0) std::swap(tet[1], tet[2]);
      std::next_permutation(p.begin(), p.end());
    }
    return result;
  }();
  return tets;
}

// Makes `order` an even permutation of (0, 1, 2, 3) by swapping its last two entries if needed.
void make_even(std::array<int, 4>& order) {
  int inversions = 0;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) inversions += order[a] > order[b];
  if (inversions % 2) std::swap(order[2], order[3]);
}

struct SampleLattice {
  Point origin;
  double spacing = 1;
  Eigen::Vector3i samples;
  Point position(const Eigen::Vector3d& index) const { return origin + spacing * index; }
};

SampleLattice make_lattice(const BoundingBox& box, double spacing) {
  require(spacing > 0 && std::isfinite(spacing), "spacing", "must be positive and finite");
  if (box.isEmpty() || !box.min().allFinite() || !box.max().allFinite())
    throw Error("the bounding box is empty or not finite", {.pointer = "box"});
  SampleLattice lattice;
  lattice.spacing = spacing;
  // Cells covering the box plus one on each side; the samples number one more than the cells.
  const Eigen::Vector3d cells = (box.sizes() / spacing).array().ceil() + 2;
  const double total = (cells.array() + 1).prod();
  if (!(total <= kMaxSamples))
    throw Error("the sampling lattice would have " + std::to_string(total) +
                    " samples (limit 2^31); increase the spacing",
                {.pointer = "spacing"});
  lattice.samples = (cells.array() + 1).cast<int>();
  lattice.origin = box.center() - 0.5 * spacing * cells;
  return lattice;
}

// Builds the mesh one layer of cubes at a time from two slabs of samples, so memory grows with
// one slab rather than with the whole lattice.
class Extractor {
 public:
  Extractor(const Shape& shape, const SampleLattice& lattice) : m_shape(shape), m_lattice(lattice) {
    const std::size_t slab = std::size_t(lattice.samples[0]) * lattice.samples[1];
    m_lower.resize(slab);
    m_upper.resize(slab);
    m_lower_ids.assign(7 * slab, -1);
    m_upper_ids.assign(7 * slab, -1);
  }

  TriangleMesh run() {
    sample_slab(0, m_lower);
    for (int k = 0; k + 1 < m_lattice.samples[2]; ++k) {
      sample_slab(k + 1, m_upper);
      m_k = k;
      for (int j = 0; j + 1 < m_lattice.samples[1]; ++j)
        for (int i = 0; i + 1 < m_lattice.samples[0]; ++i) polygonize_cube(i, j);
      // Slab k + 1 becomes the lower slab of the next layer, keeping its in-plane vertices.
      std::swap(m_lower, m_upper);
      std::swap(m_lower_ids, m_upper_ids);
      std::fill(m_upper_ids.begin(), m_upper_ids.end(), -1);
    }
    return result();
  }

 private:
  std::size_t slab_index(int i, int j) const { return std::size_t(j) * m_lattice.samples[0] + i; }

  // The signed distance on slab k, blocks of rows in parallel; the outermost layer is forced
  // outside. Narrow band: a block of kBlock x kBlock samples whose center lies farther than
  // `far` (kFarSpacings spacings) + the block's radius from the surface holds only samples at
  // least `far` away (the distance is 1-Lipschitz), corners of no cube the surface crosses;
  // such a block gets that bound with the center's sign instead of its own queries. Every corner of
  // a cube the surface crosses is within sqrt(3) s of the crossing, so the mesh equals the full
  // sampling's.
  void sample_slab(int k, std::vector<double>& slab) const {
    constexpr int kBlock = 8;
    const double far = kFarSpacings * m_lattice.spacing;
    const Eigen::Vector3i n = m_lattice.samples;
    const int blocks_x = (n[0] + kBlock - 1) / kBlock, blocks_y = (n[1] + kBlock - 1) / kBlock;
    bool finite = true;
#pragma omp parallel for schedule(dynamic, 1) reduction(&& : finite)
    for (int by = 0; by < blocks_y; ++by)
      for (int bx = 0; bx < blocks_x; ++bx) {
        const int i0 = bx * kBlock, i1 = std::min(i0 + kBlock, n[0]);
        const int j0 = by * kBlock, j1 = std::min(j0 + kBlock, n[1]);
        const Eigen::Vector3d center(0.5 * (i0 + i1 - 1), 0.5 * (j0 + j1 - 1), k);
        const double radius =
            m_lattice.spacing * std::hypot(0.5 * (i1 - 1 - i0), 0.5 * (j1 - 1 - j0));
        const double d_center = m_shape.signed_distance(m_lattice.position(center));
        finite = finite && std::isfinite(d_center);
        const double bound = std::abs(d_center) - radius;
        for (int j = j0; j < j1; ++j)
          for (int i = i0; i < i1; ++i) {
            double d = bound >= far
                           ? std::copysign(bound, d_center)
                           : m_shape.signed_distance(m_lattice.position(Eigen::Vector3d(i, j, k)));
            finite = finite && std::isfinite(d);
            const bool border =
                i == 0 || j == 0 || k == 0 || i == n[0] - 1 || j == n[1] - 1 || k == n[2] - 1;
            slab[slab_index(i, j)] = border ? std::max(d, 0.0) : d;
          }
      }
    if (!finite)
      throw Error("the signed distance is not finite on slab " + std::to_string(k),
                  {.pointer = "shape"});
  }

  double value(int i, int j, int c) const {
    const auto& slab = (c & 4) ? m_upper : m_lower;
    return slab[slab_index(i + (c & 1), j + ((c >> 1) & 1))];
  }

  void polygonize_cube(int i, int j) {
    std::array<double, 8> d;
    int inside = 0;
    for (int c = 0; c < 8; ++c) {
      d[c] = value(i, j, c);
      inside += d[c] < 0;
    }
    if (inside == 0 || inside == 8) return;
    for (const Tetrahedron& tet : kuhn_tetrahedra()) polygonize_tetrahedron(i, j, d, tet);
  }

  void polygonize_tetrahedron(int i, int j, const std::array<double, 8>& d,
                              const Tetrahedron& tet) {
    std::array<int, 4> in{}, out{};
    int n_in = 0, n_out = 0;
    for (int v = 0; v < 4; ++v) (d[tet[v]] < 0 ? in[n_in++] : out[n_out++]) = v;
    auto vertex = [&](int a, int b) { return edge_vertex(i, j, d, tet[a], tet[b]); };
    if (n_in == 1 || n_in == 3) {
      // With the lone corner first and the order even (positive volume), the triangle on its
      // three edges faces away from it: outward when it is inside, inward (so flip) otherwise.
      std::array<int, 4> order = n_in == 1 ? std::array{in[0], out[0], out[1], out[2]}
                                           : std::array{out[0], in[0], in[1], in[2]};
      make_even(order);
      if (n_in == 3) std::swap(order[2], order[3]);
      add_triangle(vertex(order[0], order[1]), vertex(order[0], order[2]),
                   vertex(order[0], order[3]));
    } else if (n_in == 2) {
      std::array<int, 4> order{in[0], in[1], out[0], out[1]};
      make_even(order);
      const auto [a, b, c, e] = order;
      add_quad(vertex(a, c), vertex(a, e), vertex(b, e), vertex(b, c));
    }
  }

  // Vertex on the cube edge between corners ca and cb (Kuhn edges are monotone: the corner with
  // the smaller index has a subset of the other's offset bits). It is keyed by its lower sample
  // and direction, so all cubes and tetrahedra that share the edge share the vertex.
  int edge_vertex(int i, int j, const std::array<double, 8>& d, int ca, int cb) {
    if (ca > cb) std::swap(ca, cb);
    const int direction = cb - ca;  // 1..7
    auto& ids = (ca & 4) ? m_upper_ids : m_lower_ids;
    int& id = ids[7 * slab_index(i + (ca & 1), j + ((ca >> 1) & 1)) + direction - 1];
    if (id >= 0) return id;
    if (m_vertices.size() / 3 >= std::size_t(INT_MAX))
      throw Error("the surface has too many vertices; increase the spacing",
                  {.pointer = "spacing"});
    const double t = std::clamp(d[ca] / (d[ca] - d[cb]), kEdgeClamp, 1 - kEdgeClamp);
    const Eigen::Vector3d base(i, j, m_k);
    const Point x = m_lattice.position(base + corner_offset(ca) + t * corner_offset(direction));
    id = static_cast<int>(m_vertices.size() / 3);
    m_vertices.insert(m_vertices.end(), {x.x(), x.y(), x.z()});
    return id;
  }

  Point vertex_position(int id) const {
    return Point(&m_vertices[3 * std::size_t(id)]);
  }

  void add_triangle(int a, int b, int c) {
    m_triangles.insert(m_triangles.end(), {a, b, c});
  }

  // The quad (a, b, c, e) in cyclic order, cut along its shorter diagonal for better triangles.
  void add_quad(int a, int b, int c, int e) {
    const double ac = (vertex_position(a) - vertex_position(c)).squaredNorm();
    const double be = (vertex_position(b) - vertex_position(e)).squaredNorm();
    if (ac <= be) {
      add_triangle(a, b, c);
      add_triangle(a, c, e);
    } else {
      add_triangle(b, c, e);
      add_triangle(b, e, a);
    }
  }

  TriangleMesh result() const {
    TriangleMesh surface;
    surface.vertices = Eigen::Map<const Eigen::Matrix<double, -1, 3, Eigen::RowMajor>>(
        m_vertices.data(), Eigen::Index(m_vertices.size() / 3), 3);
    surface.triangles = Eigen::Map<const Eigen::Matrix<int, -1, 3, Eigen::RowMajor>>(
        m_triangles.data(), Eigen::Index(m_triangles.size() / 3), 3);
    return surface;
  }

  const Shape& m_shape;
  SampleLattice m_lattice;
  int m_k = 0;  // the current layer of cubes lies between slabs m_k and m_k + 1
  std::vector<double> m_lower, m_upper;       // samples of the two slabs, x fastest
  std::vector<int> m_lower_ids, m_upper_ids;  // 7 per sample: vertex of each outgoing edge, or -1
  std::vector<double> m_vertices;             // 3 per vertex
  std::vector<int> m_triangles;               // 3 per triangle
};

}  // namespace

TriangleMesh extract_surface(const Shape& shape, double spacing,
                             const std::optional<BoundingBox>& box) {
  const SampleLattice lattice = make_lattice(box.value_or(shape.bounding_box()), spacing);
  return Extractor(shape, lattice).run();
}

}  // namespace mgelastic::geometry
