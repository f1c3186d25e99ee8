#pragma once
// Constructive solid geometry on signed distances: union = min, intersection = max,
// difference = max(first, -others). The result is a lower bound of the true distance away from
// the boundary (exact near it), which keeps overlap tests conservative.
#include <vector>

#include "mgelastic/geometry/shape.hpp"

namespace mgelastic::geometry {

ShapePtr make_union(std::vector<ShapePtr> children);
ShapePtr make_intersection(std::vector<ShapePtr> children);
ShapePtr make_difference(std::vector<ShapePtr> children);  // first minus the others

}  // namespace mgelastic::geometry
