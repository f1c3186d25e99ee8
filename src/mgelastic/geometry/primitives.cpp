#include "mgelastic/geometry/primitives.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "mgelastic/core/error.hpp"

namespace mgelastic::geometry {
namespace {

void require_positive(double value, const char* name) {
  if (!(std::isfinite(value) && value > 0.0))
    throw Error("must be a positive number (got " + std::to_string(value) + ")",
                ErrorContext{.pointer = name});
}

class Box final : public Shape {
 public:
  Box(const Point& center, const Point& half) : m_center(center), m_half(half) {}
  double signed_distance(const Point& p) const override {
    const Point q = (p - m_center).cwiseAbs() - m_half;
    return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
  }
  BoundingBox bounding_box() const override { return {m_center - m_half, m_center + m_half}; }

 private:
  Point m_center, m_half;
};

class Sphere final : public Shape {
 public:
  Sphere(const Point& center, double radius) : m_center(center), m_radius(radius) {}
  double signed_distance(const Point& p) const override { return (p - m_center).norm() - m_radius; }
  BoundingBox bounding_box() const override {
    return {m_center.array() - m_radius, m_center.array() + m_radius};
  }

 private:
  Point m_center;
  double m_radius;
};

// Capped cylinder between end centers a and b (exact distance, Quilez).
class Cylinder final : public Shape {
 public:
  Cylinder(const Point& a, const Point& b, double r) : m_a(a), m_b(b), m_r(r) {}
  double signed_distance(const Point& p) const override {
    const Point ba = m_b - m_a, pa = p - m_a;
    const double baba = ba.dot(ba), paba = pa.dot(ba);
    const double x = (pa * baba - ba * paba).norm() - m_r * baba;
    const double y = std::abs(paba - baba * 0.5) - baba * 0.5;
    const double x2 = x * x, y2 = y * y * baba;
    const double d = std::max(x, y) < 0.0 ? -std::min(x2, y2) : (x > 0 ? x2 : 0) + (y > 0 ? y2 : 0);
    return std::copysign(std::sqrt(std::abs(d)), d) / baba;
  }
  BoundingBox bounding_box() const override {
    return {m_a.cwiseMin(m_b).array() - m_r, m_a.cwiseMax(m_b).array() + m_r};
  }

 private:
  Point m_a, m_b;
  double m_r;
};

class Capsule final : public Shape {
 public:
  Capsule(const Point& a, const Point& b, double r) : m_a(a), m_b(b), m_r(r) {}
  double signed_distance(const Point& p) const override {
    const Point ba = m_b - m_a, pa = p - m_a;
    const double denominator = ba.squaredNorm();
    const double t = denominator > 0 ? std::clamp(pa.dot(ba) / denominator, 0.0, 1.0) : 0.0;
    return (pa - t * ba).norm() - m_r;
  }
  BoundingBox bounding_box() const override {
    return {m_a.cwiseMin(m_b).array() - m_r, m_a.cwiseMax(m_b).array() + m_r};
  }

 private:
  Point m_a, m_b;
  double m_r;
};

class Torus final : public Shape {
 public:
  Torus(const Point& c, const Point& axis, double major, double minor)
      : m_c(c), m_axis(axis.normalized()), m_major(major), m_minor(minor) {}
  double signed_distance(const Point& p) const override {
    const Point q = p - m_c;
    const double along = q.dot(m_axis);
    const double radial = (q - along * m_axis).norm();
    return std::hypot(radial - m_major, along) - m_minor;
  }
  BoundingBox bounding_box() const override {
    const double r = m_major + m_minor;
    return {m_c.array() - r, m_c.array() + r};
  }

 private:
  Point m_c, m_axis;
  double m_major, m_minor;
};

class Transformed final : public Shape {
 public:
  Transformed(ShapePtr child, const Eigen::Matrix3d& rotation, const Point& translate, double scale)
      : m_child(std::move(child)), m_rotation(rotation), m_translate(translate), m_scale(scale) {}
  double signed_distance(const Point& p) const override {
    return m_scale * m_child->signed_distance(m_rotation.transpose() * (p - m_translate) / m_scale);
  }
  BoundingBox bounding_box() const override {
    const BoundingBox child = m_child->bounding_box();
    BoundingBox box;
    for (int corner = 0; corner < 8; ++corner) {
      const Point c = child.corner(static_cast<BoundingBox::CornerType>(corner));
      box.extend(Point(m_translate + m_rotation * (m_scale * c)));
    }
    return box;
  }

 private:
  ShapePtr m_child;
  Eigen::Matrix3d m_rotation;
  Point m_translate;
  double m_scale;
};

}  // namespace

ShapePtr make_box(const Point& center, const Point& size) {
  for (int a = 0; a < 3; ++a) require_positive(size[a], "size");
  return std::make_shared<Box>(center, 0.5 * size);
}

ShapePtr make_sphere(const Point& center, double radius) {
  require_positive(radius, "radius");
  return std::make_shared<Sphere>(center, radius);
}

ShapePtr make_cylinder(const Point& a, const Point& b, double radius) {
  require_positive(radius, "radius");
  require_positive((b - a).norm(), "b - a (cylinder length)");
  return std::make_shared<Cylinder>(a, b, radius);
}

ShapePtr make_capsule(const Point& a, const Point& b, double radius) {
  require_positive(radius, "radius");
  return std::make_shared<Capsule>(a, b, radius);
}

ShapePtr make_torus(const Point& center, const Point& axis, double major_radius,
                    double minor_radius) {
  require_positive(major_radius, "major_radius");
  require_positive(minor_radius, "minor_radius");
  require_positive(axis.norm(), "axis");
  return std::make_shared<Torus>(center, axis, major_radius, minor_radius);
}

ShapePtr make_transformed(ShapePtr child, const Point& translate, const Point& rotate_axis,
                          double rotate_degrees, double scale) {
  require_positive(scale, "scale");
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  if (rotate_degrees != 0.0) {
    require_positive(rotate_axis.norm(), "rotate_axis");
    rotation =
        Eigen::AngleAxisd(rotate_degrees * std::numbers::pi / 180.0, rotate_axis.normalized())
            .toRotationMatrix();
  }
  return std::make_shared<Transformed>(std::move(child), rotation, translate, scale);
}

}  // namespace mgelastic::geometry
