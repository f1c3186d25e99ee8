#pragma once
// Analytic solids with exact signed distance functions (negative inside), a rigid-plus-scale
// transform of any shape, and factories that validate their parameters.
#include "mgelastic/geometry/shape.hpp"

namespace mgelastic::geometry {

ShapePtr make_box(const Point& center, const Point& size);
ShapePtr make_sphere(const Point& center, double radius);
ShapePtr make_cylinder(const Point& a, const Point& b, double radius);  // capped, end centers a, b
ShapePtr make_capsule(const Point& a, const Point& b, double radius);
ShapePtr make_torus(const Point& center, const Point& axis, double major_radius,
                    double minor_radius);
// x -> translate + rotation(axis, degrees) * (scale * x), applied to `child`.
ShapePtr make_transformed(ShapePtr child, const Point& translate, const Point& rotate_axis,
                          double rotate_degrees, double scale);

}  // namespace mgelastic::geometry
