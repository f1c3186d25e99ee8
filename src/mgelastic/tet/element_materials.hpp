#pragma once
// Per-element material parameters (structure of arrays), so a body can be heterogeneous, e.g.
// the paper's horse with stiff legs and soft knees. Arrays have one entry per tetrahedron.
#include <Eigen/Core>
#include <map>

#include "mgelastic/tet/linear_tet_element.hpp"

namespace mgelastic::tet {

struct ElementMaterials {
  Eigen::VectorXd youngs_modulus;
  Eigen::VectorXd poisson_ratio;
  Eigen::VectorXd density;

  int size() const { return static_cast<int>(youngs_modulus.size()); }
  ElasticMaterial operator[](int element) const;

  static ElementMaterials uniform(int element_count, const ElasticMaterial& material);
  // Material by element tag (e.g. Gmsh physical group); tags missing from the map get `fallback`.
  static ElementMaterials from_tags(const Eigen::VectorXi& tags,
                                    const std::map<int, ElasticMaterial>& by_tag,
                                    const ElasticMaterial& fallback);
};

// Throws Error naming the element unless the arrays have `element_count` entries and every
// element's parameters are valid (see check_material).
void check_materials(const ElementMaterials& materials, int element_count);

}  // namespace mgelastic::tet
