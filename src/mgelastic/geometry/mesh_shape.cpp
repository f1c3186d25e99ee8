#include "mgelastic/geometry/mesh_shape.hpp"

#include <cmath>
#include <sstream>

#include "mgelastic/core/error.hpp"
#include "mgelastic/geometry/surface_mesh_readers.hpp"

namespace mgelastic::geometry {
namespace {

// Thresholds of the acceptance policy (see the header).
constexpr double RELATIVE_VOLUME_FLOOR = 1e-9;
constexpr int SAMPLES_PER_AXIS = 8;
constexpr double AMBIGUOUS_DEVIATION = 0.25;
constexpr double AMBIGUOUS_FRACTION = 0.05;

void reject_flat(const MeshFacts& facts, const std::string& source) {
  if (facts.triangle_count == 0)
    throw Error("the surface mesh has no triangles", ErrorContext{.file = source});
  const double diagonal = facts.bounding_box.diagonal().norm();
  if (std::abs(facts.signed_volume) <= RELATIVE_VOLUME_FLOOR * diagonal * diagonal * diagonal) {
    std::ostringstream reason;
    reason << "the surface mesh encloses no volume (signed volume " << facts.signed_volume
           << ", bounding box diagonal " << diagonal
           << "): a flat or open surface has no inside; a closed surface is needed";
    throw Error(reason.str(), ErrorContext{.file = source});
  }
}

}  // namespace

MeshShape::MeshShape(TriangleMesh mesh, std::string source) : m_source(std::move(source)) {
  check_triangle_mesh(mesh, m_source);
  m_facts = mesh_facts(mesh);
  reject_flat(m_facts, m_source);
  if (m_facts.signed_volume < 0.0) {
    flip_orientation(mesh);
    m_facts.signed_volume = -m_facts.signed_volume;
    m_flipped = true;
  }
  m_sides_constant = m_facts.boundary_edges == 0 && m_facts.non_manifold_edges == 0 &&
                     m_facts.inconsistent_edges == 0;
  m_bvh = std::make_shared<const TriangleBvh>(mesh);
  m_winding = std::make_unique<const WindingNumber>(m_bvh);
  reject_ambiguous_winding();
}

void MeshShape::reject_ambiguous_winding() const {
  const BoundingBox& box = m_facts.bounding_box;
  const Eigen::Vector3d cell = box.sizes() / SAMPLES_PER_AXIS;
  int ambiguous = 0;
  for (int i = 0; i < SAMPLES_PER_AXIS; ++i)
    for (int j = 0; j < SAMPLES_PER_AXIS; ++j)
      for (int k = 0; k < SAMPLES_PER_AXIS; ++k) {
        const Point p = box.min() + cell.cwiseProduct(Eigen::Vector3d(i + 0.5, j + 0.5, k + 0.5));
        const double w = winding_number(p);
        ambiguous += std::abs(w - std::round(w)) > AMBIGUOUS_DEVIATION ? 1 : 0;
      }
  const int samples = SAMPLES_PER_AXIS * SAMPLES_PER_AXIS * SAMPLES_PER_AXIS;
  if (ambiguous <= AMBIGUOUS_FRACTION * samples) return;
  std::ostringstream reason;
  reason << "inside and outside are undefined: the winding number is not clearly 0 or 1 at "
         << ambiguous << " of " << samples << " sample points in the bounding box (more than "
         << 100 * AMBIGUOUS_FRACTION << "%); the surface has " << m_facts.boundary_edges
         << " boundary edges, " << m_facts.non_manifold_edges << " non-manifold edges and "
         << m_facts.inconsistent_edges << " inconsistently oriented edges";
  throw Error(reason.str(), ErrorContext{.file = m_source});
}

double MeshShape::unsigned_distance(const Point& p) const {
  // Queries come in runs of nearby points (voxelization rows, a cell's samples): each thread's
  // last closest triangle of this shape seeds its next search (the distance does not depend on
  // it, see TriangleBvh::closest_triangle).
  thread_local const MeshShape* last_shape = nullptr;
  thread_local int last_position = -1;
  const ClosestTriangle closest =
      m_bvh->closest_triangle(p, last_shape == this ? last_position : -1);
  last_shape = this;
  last_position = closest.position;
  return std::sqrt(closest.squared_distance);
}

double MeshShape::signed_distance(const Point& p) const {
  const double d = unsigned_distance(p);
  return contains(p) ? -d : d;
}

double MeshShape::signed_distance_near(const Point& p, const Point& q, double known) const {
  const double d = unsigned_distance(p);
  // The relative margin keeps the rounding of the two distances from joining balls that only
  // touch (at a surface point between p and q).
  constexpr double kMargin = 1.0 - 1e-6;
  if (m_sides_constant && (p - q).norm() < kMargin * (d + std::abs(known)))
    return std::signbit(known) ? -d : d;
  return contains(p) ? -d : d;
}

ShapePtr make_mesh_shape(TriangleMesh mesh, const std::string& source) {
  return std::make_shared<const MeshShape>(std::move(mesh), source);
}

ShapePtr load_mesh_shape(const std::filesystem::path& path) {
  return make_mesh_shape(read_surface_mesh(path), path.string());
}

}  // namespace mgelastic::geometry
