#include "mgelastic/grid/fill_weights.hpp"


namespace mgelastic::grid {

template <int Dim>
std::vector<double> coarse_fill_weights(const Lattice<Dim>& fine,
                                        const std::vector<CellType>& fine_cells,
                                        const std::vector<double>& fine_weights,
                                        const Lattice<Dim>& coarse,
                                        const std::vector<CellType>& coarse_cells) {
  constexpr double children = 1 << Dim;
  std::vector<double> weights(coarse.size(), 0.0);
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(fine.size()); ++k) {
    const IVec<Dim> s = fine.coords(k);
    if (!fine.is_real(s) || fine_cells[k] == CellType::EXTERIOR) continue;
    IVec<Dim> cs;
    for (int a = 0; a < Dim; ++a) cs[a] = (s[a] - 1) / 2 + 1;
    weights[coarse.index(cs)] += (fine_weights.empty() ? 1.0 : fine_weights[k]) / children;
  }
  for (std::size_t c = 0; c < weights.size(); ++c) {
    if (coarse_cells[c] == CellType::EXTERIOR) weights[c] = 0.0;
    if (coarse_cells[c] == CellType::DIRICHLET) weights[c] = 1.0;
    if (coarse_cells[c] == CellType::INTERIOR && weights[c] == 0.0) weights[c] = 1.0 / children;
  }
  return weights;
}

bool all_full(const std::vector<double>& weights, const std::vector<CellType>& cells) {
  for (std::size_t c = 0; c < weights.size(); ++c)
    if (cells[c] != CellType::EXTERIOR && weights[c] != 1.0) return false;
  return true;
}

template std::vector<double> coarse_fill_weights<2>(const Lattice<2>&, const std::vector<CellType>&,
                                                    const std::vector<double>&, const Lattice<2>&,
                                                    const std::vector<CellType>&);
template std::vector<double> coarse_fill_weights<3>(const Lattice<3>&, const std::vector<CellType>&,
                                                    const std::vector<double>&, const Lattice<3>&,
                                                    const std::vector<CellType>&);

}  // namespace mgelastic::grid
