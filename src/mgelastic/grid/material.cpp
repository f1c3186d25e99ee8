#include "mgelastic/grid/material.hpp"

#include <cmath>
#include <sstream>

#include "mgelastic/core/error.hpp"

namespace mgelastic::grid {

void validate(const Material& material) {
  const double e = material.youngs_modulus;
  const double nu = material.poisson_ratio;
  std::ostringstream value;
  value.precision(17);
  if (!(std::isfinite(e) && e > 0.0)) {
    value << e;
    throw Error("must be a positive finite number (got " + value.str() + ")",
                ErrorContext{.pointer = "youngs_modulus"});
  }
  if (!(std::isfinite(nu) && nu >= 0.0 && nu < 0.5)) {
    value << nu;
    throw Error("must lie in [0, 0.5) (got " + value.str() + ")",
                ErrorContext{.pointer = "poisson_ratio"});
  }
}

}  // namespace mgelastic::grid
