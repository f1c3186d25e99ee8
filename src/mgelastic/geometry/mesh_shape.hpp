#pragma once
// A solid bounded by a triangle surface mesh.
//
//   contains(p)        = w(p) > 1/2, w the generalized winding number (winding_number.hpp);
//   signed_distance(p) = -+ min_t dist(p, t), the exact distance to the closest triangle (BVH
//                        query), negative where contains(p).
//
// Acceptance policy, applied in this order when the shape is built (rejections throw
// mgelastic::Error naming the source file and the reason):
//  1. Indices out of range or non-finite coordinates: rejected.
//  2. No triangles: rejected.
//  3. No volume: |signed volume| <= 1e-9 * (bounding box diagonal)^3 (a flat sheet, a single
//     triangle in a plane through its box centre, all-degenerate triangles): rejected.
//  4. Inside-out (signed volume < 0): every triangle is flipped; inside_out_flipped() says so and
//     facts() describes the flipped mesh.
//  5. Ambiguous winding number: w is evaluated at the 8 x 8 x 8 cell centres of the bounding box;
//     a sample is ambiguous when |w - round(w)| > 0.25. More than 5 % ambiguous samples means the
//     surface does not separate inside from outside (large holes, an open sheet, orientation
//     conflicts): rejected, with the boundary/non-manifold/inconsistent edge counts in the message.
// Everything else is accepted: closed consistent meshes, and meshes with small holes, non-manifold
// edges, a few misoriented triangles or several components, whose defects facts() reports and
// which the winding number still classifies. All queries are const and thread-safe.
#include <filesystem>
#include <memory>
#include <string>

#include "mgelastic/geometry/shape.hpp"
#include "mgelastic/geometry/triangle_bvh.hpp"
#include "mgelastic/geometry/triangle_mesh.hpp"
#include "mgelastic/geometry/winding_number.hpp"

namespace mgelastic::geometry {

class MeshShape : public Shape {
 public:
  // Applies the policy above; `source` names the mesh in error messages (usually its file).
  MeshShape(TriangleMesh mesh, std::string source);

  double signed_distance(const Point& p) const override;
  // On a closed, edge-manifold, consistently oriented mesh w is an integer constant on each
  // piece of space the surface bounds, so where the balls |x - p| < d(p) and |x - q| < |d(q)|
  // (both free of the surface) overlap, p lies on q's side and its winding number is skipped.
  // Other meshes, whose w varies continuously through holes, always evaluate it.
  double signed_distance_near(const Point& p, const Point& q, double known) const override;
  bool contains(const Point& p) const override { return winding_number(p) > 0.5; }
  BoundingBox bounding_box() const override { return m_facts.bounding_box; }
  // The (reordered) triangles where the mesh is closed, edge-manifold and consistently oriented.
  const std::vector<Triangle>* closed_surface() const override {
    return m_sides_constant ? &m_bvh->triangles() : nullptr;
  }

  double winding_number(const Point& p) const { return (*m_winding)(p); }
  double unsigned_distance(const Point& p) const;
  const MeshFacts& facts() const { return m_facts; }
  bool inside_out_flipped() const { return m_flipped; }
  const std::string& source() const { return m_source; }

 private:
  void reject_ambiguous_winding() const;

  std::string m_source;
  MeshFacts m_facts;
  bool m_flipped = false;
  bool m_sides_constant = false;  // closed, edge-manifold, consistently oriented
  std::shared_ptr<const TriangleBvh> m_bvh;
  std::unique_ptr<const WindingNumber> m_winding;
};

ShapePtr make_mesh_shape(TriangleMesh mesh, const std::string& source);
// Reads the file by extension (read_surface_mesh) and builds the shape.
ShapePtr load_mesh_shape(const std::filesystem::path& path);

}  // namespace mgelastic::geometry
