#include "mgelastic/tet/element_materials.hpp"

#include <string>

#include "mgelastic/core/error.hpp"

namespace mgelastic::tet {

ElasticMaterial ElementMaterials::operator[](int e) const {
  return {youngs_modulus[e], poisson_ratio[e], density[e]};
}

ElementMaterials ElementMaterials::uniform(int count, const ElasticMaterial& material) {
  return {Eigen::VectorXd::Constant(count, material.youngs_modulus),
          Eigen::VectorXd::Constant(count, material.poisson_ratio),
          Eigen::VectorXd::Constant(count, material.density)};
}

ElementMaterials ElementMaterials::from_tags(const Eigen::VectorXi& tags,
                                             const std::map<int, ElasticMaterial>& by_tag,
                                             const ElasticMaterial& fallback) {
  ElementMaterials materials = uniform(static_cast<int>(tags.size()), fallback);
  for (int e = 0; e < tags.size(); ++e) {
    const auto found = by_tag.find(tags[e]);
    if (found == by_tag.end()) continue;
    materials.youngs_modulus[e] = found->second.youngs_modulus;
    materials.poisson_ratio[e] = found->second.poisson_ratio;
    materials.density[e] = found->second.density;
  }
  return materials;
}

void check_materials(const ElementMaterials& materials, int element_count) {
  if (materials.youngs_modulus.size() != element_count ||
      materials.poisson_ratio.size() != element_count || materials.density.size() != element_count)
    throw Error(
        "material arrays need one entry per element (" + std::to_string(element_count) + ")",
        ErrorContext{std::string(), -1, "materials"});
  for (int e = 0; e < element_count; ++e)
    check_material(materials[e], "materials: element " + std::to_string(e));
}

}  // namespace mgelastic::tet
