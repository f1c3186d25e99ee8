#include "mgelastic/io/synthetic_lattice_frame.hpp"

#include <cmath>
#include <vector>

namespace mgelastic::io {

ImageData synthetic_lattice_frame(int n) {
  ImageData image;
  image.cells = Eigen::Vector3i(n, n, n);
  image.spacing = 1.0 / n;
  const std::size_t points = std::size_t(n + 1) * (n + 1) * (n + 1);
  const std::size_t cells = std::size_t(n) * n * n;
  std::vector<double> u(3 * points), type(cells), pressure(cells), von_mises(cells);
  for (std::size_t p = 0; p < points; ++p)
    for (int k = 0; k < 3; ++k) u[3 * p + k] = 1e-3 * std::sin(1e-4 * double(p) + k);
  for (std::size_t c = 0; c < cells; ++c) {
    type[c] = (c / n) % n < std::size_t(n) / 8 ? 0 : 1;
    pressure[c] = type[c] * 1e3 * std::cos(1e-5 * double(c));
    von_mises[c] = type[c] * 2e3 * std::sin(3e-5 * double(c));
  }
  image.point_data.push_back({"displacement", 3, std::move(u), VtkScalar::FLOAT32});
  image.cell_data = {{"cell_type", 1, std::move(type), VtkScalar::UINT8},
                     {"pressure", 1, std::move(pressure), VtkScalar::FLOAT32},
                     {"von_mises", 1, std::move(von_mises), VtkScalar::FLOAT32}};
  return image;
}

}  // namespace mgelastic::io
