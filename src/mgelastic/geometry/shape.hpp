#pragma once
// A solid region of space: the common interface of analytic primitives, CSG combinations and
// closed triangle meshes. Signed distance is negative inside.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <memory>
#include <vector>

namespace mgelastic::geometry {

using Point = Eigen::Vector3d;
using BoundingBox = Eigen::AlignedBox3d;

class Shape {
 public:
  virtual ~Shape() = default;
  // Signed distance to the boundary (negative inside). Exact for primitives; CSG combinations
  // return the usual min/max bound, which is exact outside of concave creases.
  virtual double signed_distance(const Point& p) const = 0;
  // signed_distance(p), given `known` = signed_distance(q) at a point q nearby (a voxelization
  // row's previous query): a shape may take p's side from q's where the two points' surface-free
  // balls overlap. The value is signed_distance(p)'s either way.
  virtual double signed_distance_near(const Point& p, const Point& /*q*/, double /*known*/) const {
    return signed_distance(p);
  }
  virtual bool contains(const Point& p) const { return signed_distance(p) <= 0.0; }
  // A box containing the whole region.
  virtual BoundingBox bounding_box() const = 0;
  // The triangles of a closed surface that bounds the region, when the region has one:
  // contains() is then constant on every connected piece of space off the triangles, so one
  // query decides a whole piece (the voxelization's cells away from the surface). Null for
  // primitives, CSG and meshes with holes, non-manifold or misoriented edges.
  virtual const std::vector<std::array<Point, 3>>* closed_surface() const { return nullptr; }
};

using ShapePtr = std::shared_ptr<const Shape>;

}  // namespace mgelastic::geometry
