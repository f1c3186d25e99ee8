#include "mgelastic/grid/residual_blocks.hpp"

#include <algorithm>
#include <map>
#include <numeric>

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

// visit(k, square) for the squared residual of every row with a nonzero residual, stencil rows
// (all fields of a point together, lattice row by lattice row, evaluated in batches in
// parallel) first, then band momentum and band pressure rows; k is the row's flat index.
template <int Dim, typename Scalar, typename Visit>
void for_each_squared_residual(const Level<Dim, Scalar>& level, const Visit& visit) {
  const auto row_length = static_cast<std::uint32_t>(level.lattice.padded(0));
  const std::size_t rows = level.size() / row_length;
  constexpr std::size_t kBatch = 256;  // lattice rows evaluated together
  std::vector<double> values((Dim + 1) * kBatch * row_length);
  std::vector<Stretch> stretches;
  for (std::size_t first = 0; first < rows; first += kBatch) {
    const std::size_t count = std::min(kBatch, rows - first);
    stretches.clear();
    for (std::size_t i = 0; i < count; ++i)
      stretches.push_back({static_cast<std::ptrdiff_t>((first + i) * row_length), row_length});
    const std::size_t n = count * row_length;
    std::array<double*, Dim + 1> r;
    for (int f = 0; f <= Dim; ++f) r[f] = values.data() + f * n;
    stencil_residual_at(level, stretches, r);
    for (std::size_t i = 0; i < n; ++i) {
      double square = 0;
      for (int f = 0; f <= Dim; ++f) square += r[f][i] * r[f][i];
      if (square > 0) visit(static_cast<std::ptrdiff_t>(first * row_length + i), square);
    }
  }
  const auto band_rows = [&](std::size_t count, const auto& target, const auto& evaluate) {
    std::vector<std::uint32_t> all(count);
    std::iota(all.begin(), all.end(), 0u);
    std::vector<double> value(count);
    evaluate(all, value.data());
    for (std::size_t m = 0; m < count; ++m)
      if (value[m] != 0) visit(static_cast<std::ptrdiff_t>(target[m]), value[m] * value[m]);
  };
  band_rows(level.band_kernel.rows(), level.band_kernel.target,
            [&](const auto& all, double* out) { band_residual_at(level, all, out); });
  band_rows(level.band_p.rows(), level.band_p.target_index,
            [&](const auto& all, double* out) { band_pressure_residual_at(level, all, out); });
}

}  // namespace

template <int Dim, typename Scalar>
std::vector<ResidualBlock<Dim>> residual_blocks(const Level<Dim, Scalar>& level, int block,
                                                std::size_t count) {
  if (block < 1) throw Error("residual blocks need a block size of at least one cell");
  // Cubes keyed by their first cell (a std::map: equal sums keep coordinate order through the
  // stable sort below).
  std::map<std::array<int, Dim>, double> sums;
  double total = 0;
  for_each_squared_residual(level, [&](std::ptrdiff_t k, double square) {
    const IVec<Dim> s = level.lattice.coords(k);
    std::array<int, Dim> first;
    for (int a = 0; a < Dim; ++a) first[a] = s[a] / block * block;
    sums[first] += square;
    total += square;
  });
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

template std::vector<ResidualBlock<2>> residual_blocks<2, float>(const Level<2, float>&, int,
                                                                 std::size_t);
template std::vector<ResidualBlock<2>> residual_blocks<2, double>(const Level<2, double>&, int,
                                                                  std::size_t);
template std::vector<ResidualBlock<3>> residual_blocks<3, float>(const Level<3, float>&, int,
                                                                 std::size_t);
template std::vector<ResidualBlock<3>> residual_blocks<3, double>(const Level<3, double>&, int,
                                                                  std::size_t);
template ResidualShares<2> residual_shares<2>(const Level<2, double>&);
template ResidualShares<3> residual_shares<3>(const Level<3, double>&);

}  // namespace mgelastic::grid
