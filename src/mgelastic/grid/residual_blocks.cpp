#include "mgelastic/grid/residual_blocks.hpp"

#include <algorithm>
#include <map>

#include "mgelastic/core/error.hpp"
#include "mgelastic/grid/residual.hpp"

namespace mgelastic::grid {

template <int Dim>
std::vector<ResidualBlock<Dim>> residual_blocks(const Level<Dim, double>& level, int block,
                                                std::size_t count) {
  if (block < 1) throw Error("residual blocks need a block size of at least one cell");
  std::array<std::vector<double>, Dim + 1> r;
  std::array<double*, Dim + 1> out;
  for (int f = 0; f <= Dim; ++f) {
    r[f].assign(level.size(), 0.0);
    out[f] = r[f].data();
  }
  residual_into<Dim, double, double>(level, out);
  // Cubes keyed by their first cell (a std::map: equal sums keep coordinate order through the
  // stable sort below).
  std::map<std::array<int, Dim>, double> sums;
  double total = 0;
  for (std::size_t k = 0; k < level.size(); ++k) {
    double square = 0;
    for (int f = 0; f <= Dim; ++f) square += r[f][k] * r[f][k];
    if (square == 0) continue;
    const IVec<Dim> s = level.lattice.coords(static_cast<std::ptrdiff_t>(k));
    std::array<int, Dim> first;
    for (int a = 0; a < Dim; ++a) first[a] = s[a] / block * block;
    sums[first] += square;
    total += square;
  }
  std::vector<ResidualBlock<Dim>> blocks;
  for (const auto& [first, sum] : sums) blocks.push_back({first, sum / total});
  std::stable_sort(blocks.begin(), blocks.end(),
                   [](const auto& a, const auto& b) { return a.share > b.share; });
  if (blocks.size() > count) blocks.resize(count);
  return blocks;
}

template std::vector<ResidualBlock<2>> residual_blocks<2>(const Level<2, double>&, int,
                                                          std::size_t);
template std::vector<ResidualBlock<3>> residual_blocks<3>(const Level<3, double>&, int,
                                                          std::size_t);

}  // namespace mgelastic::grid
