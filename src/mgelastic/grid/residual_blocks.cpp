#include "mgelastic/grid/residual_blocks.hpp"

#include <algorithm>
#include <map>

#include "mgelastic/core/error.hpp"
#include "mgelastic/grid/residual.hpp"

namespace mgelastic::grid {

namespace {

template <int Dim>
std::array<FieldArray<double>, Dim + 1> residual_of(const Level<Dim, double>& level) {
  std::array<FieldArray<double>, Dim + 1> r;
  std::array<double*, Dim + 1> out;
  for (int f = 0; f <= Dim; ++f) {
    r[f].assign(level.size(), 0.0);
    out[f] = r[f].data();
  }
  residual_into<Dim, double, double>(level, out);
  return r;
}

// Whether one of the variable's cells (two for a face of axis `field` < Dim, one for a
// pressure) or a face neighbor of one has the given type.
template <int Dim>
bool touches(const Level<Dim, double>& level, int field, std::ptrdiff_t k, CellType type) {
  const auto& lattice = level.lattice;
  const auto n = static_cast<std::ptrdiff_t>(level.size());
  auto near = [&](std::ptrdiff_t cell) {
    if (level.cells[cell] == type) return true;
    for (int a = 0; a < Dim; ++a) {
      const std::ptrdiff_t s = lattice.stride(a);
      if (cell - s >= 0 && level.cells[cell - s] == type) return true;
      if (cell + s < n && level.cells[cell + s] == type) return true;
    }
    return false;
  };
  if (near(k)) return true;
  return field < Dim && k - lattice.stride(field) >= 0 && near(k - lattice.stride(field));
}

}  // namespace

template <int Dim>
std::vector<ResidualBlock<Dim>> residual_blocks(const Level<Dim, double>& level, int block,
                                                std::size_t count) {
  if (block < 1) throw Error("residual blocks need a block size of at least one cell");
  const auto r = residual_of(level);
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

template <int Dim>
ResidualShares<Dim> residual_shares(const Level<Dim, double>& level) {
  const auto r = residual_of(level);
  ResidualShares<Dim> shares;
  double total = 0;
  for (int f = 0; f <= Dim; ++f) {
    for (std::size_t k = 0; k < level.size(); ++k) {
      const double square = r[f][k] * r[f][k];
      if (square == 0) continue;
      const auto kk = static_cast<std::ptrdiff_t>(k);
      shares.field[f] += square;
      if (touches(level, f, kk, CellType::DIRICHLET))
        shares.next_to_dirichlet += square;
      else if (touches(level, f, kk, CellType::EXTERIOR))
        shares.next_to_exterior += square;
      else
        shares.elsewhere += square;
      total += square;
    }
  }
  if (total == 0) return shares;
  for (double& s : shares.field) s /= total;
  shares.next_to_dirichlet /= total;
  shares.next_to_exterior /= total;
  shares.elsewhere /= total;
  return shares;
}

template std::vector<ResidualBlock<2>> residual_blocks<2>(const Level<2, double>&, int,
                                                          std::size_t);
template std::vector<ResidualBlock<3>> residual_blocks<3>(const Level<3, double>&, int,
                                                          std::size_t);
template ResidualShares<2> residual_shares<2>(const Level<2, double>&);
template ResidualShares<3> residual_shares<3>(const Level<3, double>&);

}  // namespace mgelastic::grid
