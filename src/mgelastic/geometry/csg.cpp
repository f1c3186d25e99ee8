#include "mgelastic/geometry/csg.hpp"

#include <algorithm>
#include <limits>

#include "mgelastic/core/error.hpp"

namespace mgelastic::geometry {
namespace {

enum class Operation { UNION, INTERSECTION, DIFFERENCE };

class Csg final : public Shape {
 public:
  Csg(Operation op, std::vector<ShapePtr> children) : m_op(op), m_children(std::move(children)) {}
  double signed_distance(const Point& p) const override {
    double d = m_children.front()->signed_distance(p);
    for (std::size_t i = 1; i < m_children.size(); ++i) {
      const double c = m_children[i]->signed_distance(p);
      switch (m_op) {
        case Operation::UNION:
          d = std::min(d, c);
          break;
        case Operation::INTERSECTION:
          d = std::max(d, c);
          break;
        case Operation::DIFFERENCE:
          d = std::max(d, -c);
          break;
      }
    }
    return d;
  }
  BoundingBox bounding_box() const override {
    BoundingBox box = m_children.front()->bounding_box();
    for (std::size_t i = 1; i < m_children.size(); ++i) {
      if (m_op == Operation::UNION) box.extend(m_children[i]->bounding_box());
      if (m_op == Operation::INTERSECTION) box = box.intersection(m_children[i]->bounding_box());
    }
    return box;
  }

 private:
  Operation m_op;
  std::vector<ShapePtr> m_children;
};

ShapePtr make(Operation op, std::vector<ShapePtr> children, std::size_t least, const char* name) {
  if (children.size() < least)
    throw Error("needs at least " + std::to_string(least) + " shapes",
                ErrorContext{.pointer = name});
  return std::make_shared<Csg>(op, std::move(children));
}

}  // namespace

ShapePtr make_union(std::vector<ShapePtr> children) {
  return make(Operation::UNION, std::move(children), 1, "union");
}
ShapePtr make_intersection(std::vector<ShapePtr> children) {
  return make(Operation::INTERSECTION, std::move(children), 2, "intersection");
}
ShapePtr make_difference(std::vector<ShapePtr> children) {
  return make(Operation::DIFFERENCE, std::move(children), 2, "difference");
}

}  // namespace mgelastic::geometry
