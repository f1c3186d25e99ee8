#pragma once
// Isotropic linear material: Lame parameters from Young's modulus and Poisson's ratio (Sec. 2.1).

namespace mgelastic::grid {

struct Material {
  double youngs_modulus = 1.0;
  double poisson_ratio = 0.3;

  double mu() const { return youngs_modulus / (2.0 + 2.0 * poisson_ratio); }
  double lambda() const {
    return youngs_modulus * poisson_ratio / ((1.0 + poisson_ratio) * (1.0 - 2.0 * poisson_ratio));
  }
};

// Throws mgelastic::Error naming the value unless E > 0 and 0 <= nu < 0.5 (both finite).
void validate(const Material& material);

}  // namespace mgelastic::grid
