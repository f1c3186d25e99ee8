#include "mgelastic/grid/galerkin_band_rows.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <utility>

#include "mgelastic/core/error.hpp"
#include "mgelastic/grid/transfer.hpp"

namespace mgelastic::grid {
namespace {

using Expansion = std::unordered_map<std::uint32_t, LinearCombination>;

void add_scaled(LinearCombination& to, const LinearCombination& from, double weight) {
  for (const auto& [variable, value] : from.terms) to.terms.emplace_back(variable, weight * value);
}

// Adds weight times a variable of a correction as interior displacements: itself when interior,
// a traction variable's expansion when its rule came earlier, else nothing (Dirichlet and
// inactive variables read zero in corrections; pressures are left out of the Galerkin terms).
template <int Dim, typename Scalar>
void add_as_interior(LinearCombination& to, const Level<Dim, Scalar>& level,
                     const Expansion& traction, std::uint32_t global, double weight) {
  const auto field = static_cast<int>(global / level.size());
  const auto k = static_cast<std::ptrdiff_t>(global % level.size());
  if (field == Dim) return;
  const VarKind kind = level.kind(field, k);
  if (kind == VarKind::INTERIOR) {
    to.terms.emplace_back(global, weight);
  } else if (kind == VarKind::TRACTION) {
    const auto it = traction.find(global);
    if (it != traction.end()) add_scaled(to, it->second, weight);
  }
}

// The displacement part of back_substitute_traction, rule by rule in its order (a rule reads
// the values the rules before it wrote; a later rule's variable holds a value from the previous
// back-substitution, independent of this correction, and counts as zero, as in the probes).
template <int Dim, typename Scalar>
Expansion traction_expansion(const Level<Dim, Scalar>& level) {
  Expansion traction;
  for (const auto& rule : level.traction.normal) {
    LinearCombination face;
    add_as_interior(face, level, traction, rule.partner, 1.0);
    traction[rule.face] = std::move(face);
  }
  for (const auto& rule : level.traction.thin) {
    LinearCombination mean;
    for (std::uint32_t neighbor : rule.neighbors)
      add_as_interior(mean, level, traction, neighbor, 1.0 / rule.neighbors.size());
    merge_terms(mean);
    traction[rule.lower] = mean;
    traction[rule.upper] = mean;
  }
  for (const auto& rule : level.traction.shear) {
    LinearCombination sum;
    const double w = 1.0 / rule.count;
    for (const auto& c : level.traction.candidates(rule)) {
      add_as_interior(sum, level, traction, c.partner, w);
      add_as_interior(sum, level, traction, c.plus, w * c.sign);
      add_as_interior(sum, level, traction, c.minus, -w * c.sign);
    }
    merge_terms(sum);
    traction[rule.face] = std::move(sum);
  }
  return traction;
}

// Rows of P: a fine interior displacement as coarse interior displacements, cached.
template <int Dim, typename Scalar>
class Prolongation {
 public:
  Prolongation(const Level<Dim, Scalar>& coarse, const Level<Dim, Scalar>& fine)
      : m_coarse(coarse), m_fine(fine), m_traction(traction_expansion(coarse)) {}
  const LinearCombination& row(std::uint32_t fine_global) {
    const auto [it, added] = m_rows.try_emplace(fine_global);
    if (added) {
      const auto field = static_cast<int>(fine_global / m_fine.size());
      const auto k = static_cast<std::ptrdiff_t>(fine_global % m_fine.size());
      for (const auto& [variable, weight] : prolongation_row(m_coarse, m_fine, field, k).terms)
        add_as_interior(it->second, m_coarse, m_traction, variable, weight);
      merge_terms(it->second);
    }
    return it->second;
  }

 private:
  const Level<Dim, Scalar>& m_coarse;
  const Level<Dim, Scalar>& m_fine;
  Expansion m_traction;
  std::unordered_map<std::uint32_t, LinearCombination> m_rows;
};

// Momentum rows of the fine level as fine interior displacements: its band rows where it has
// one, else RowBuilder's row (the stencil).
template <int Dim, typename Scalar>
class FineRows {
 public:
  explicit FineRows(const Level<Dim, Scalar>& fine)
      : m_fine(fine),
        m_builder(fine.lattice, fine.cells, fine.mu, {}, fine.inertia,
                  fine.cell_weight.empty() ? nullptr : &fine.cell_weight, fine.dirichlet_zero_depth,
                  &fine.dirichlet_wall_layers),
        m_traction(traction_expansion(fine)),
        m_band_row(rows_by_target(fine.band_u)) {}
  LinearCombination row(std::uint32_t global) const {
    const auto it = m_band_row.find(global);
    const ExplicitRow explicit_row =
        it != m_band_row.end()
            ? stored_row(m_fine, m_fine.band_u, it->second)
            : m_builder.momentum(static_cast<int>(global / m_fine.size()),
                                 static_cast<std::ptrdiff_t>(global % m_fine.size()));
    LinearCombination out;
    for (const RowTerm& t : explicit_row.terms)
      add_as_interior(out, m_fine, m_traction, t.variable, t.coefficient);
    merge_terms(out);
    return out;
  }

 private:
  const Level<Dim, Scalar>& m_fine;
  RowBuilder<Dim> m_builder;
  Expansion m_traction;
  std::unordered_map<std::uint32_t, std::uint32_t> m_band_row;
};

// Calls f(k) for every cell k within `reach` cells (per axis) of `cell`, inside the storage.
template <int Dim, typename F>
void for_each_cell_near(const Lattice<Dim>& lattice, std::ptrdiff_t cell, int reach, F&& f) {
  const IVec<Dim> s = lattice.coords(cell);
  IVec<Dim> lo, hi;
  for (int a = 0; a < Dim; ++a) {
    lo[a] = std::max(0, s[a] - reach);
    hi[a] = std::min(lattice.padded(a) - 1, s[a] + reach);
  }
  IVec<Dim> t = lo;
  while (true) {
    f(lattice.index(t));
    int a = 0;
    for (; a < Dim && ++t[a] > hi[a]; ++a) t[a] = lo[a];
    if (a == Dim) return;
  }
}

// The two cells of band row m (the face's lower and upper cell).
template <int Dim, typename Scalar>
std::array<std::ptrdiff_t, 2> row_cells(const Level<Dim, Scalar>& level, std::size_t m) {
  const std::ptrdiff_t k = level.band_u.target_index[m];
  return {k, k - level.lattice.stride(level.band_u.target_field[m])};
}

// Coarse cells within `reach` cells of a band row's two cells. A fine variable's prolongation
// reads coarse variables of its own coarse cell's neighbors and, through the traction rules,
// theirs: every fine variable that reads a band variable lies in a marked cell.
template <int Dim, typename Scalar>
std::vector<std::uint8_t> cells_near_band(const Level<Dim, Scalar>& coarse, int reach) {
  std::vector<std::uint8_t> near(coarse.size(), 0);
  for (std::size_t m = 0; m < coarse.band_u.rows(); ++m)
    for (std::ptrdiff_t cell : row_cells(coarse, m))
      for_each_cell_near(coarse.lattice, cell, reach, [&](std::ptrdiff_t k) { near[k] = 1; });
  return near;
}

constexpr int kReach = 2;

// Whether a Dirichlet cell lies among the neighbors (3^d block) of either cell of band row m.
template <int Dim, typename Scalar>
bool next_to_dirichlet(const Level<Dim, Scalar>& level, std::size_t m) {
  bool found = false;
  for (std::ptrdiff_t cell : row_cells(level, m))
    for_each_cell_near(level.lattice, cell, 1, [&](std::ptrdiff_t k) {
      found = found || level.cells[k] == CellType::DIRICHLET;
    });
  return found;
}

}  // namespace

CoarseBandRows coarse_band_rows(const std::string& name, const std::string& pointer) {
  if (name == "rediscretized") return CoarseBandRows::REDISCRETIZED;
  if (name == "galerkin_coarsest") return CoarseBandRows::GALERKIN_COARSEST;
  if (name == "galerkin") return CoarseBandRows::GALERKIN;
  throw Error("must be 'rediscretized', 'galerkin_coarsest' or 'galerkin' (got '" + name + "')",
              {.pointer = pointer});
}

template <int Dim, typename Scalar>
std::vector<std::vector<RowTerm>> galerkin_band_displacement_terms(
    const Level<Dim, Scalar>& fine, const Level<Dim, Scalar>& coarse,
    const std::vector<char>* wanted) {
  const auto& band = coarse.band_u;
  const auto row_of = rows_by_target(band);
  Prolongation<Dim, Scalar> prolongation(coarse, fine);
  // Columns of P at the band's variables, stored by fine variable: the band rows each fine
  // interior displacement's prolongation reads, with the weights.
  std::unordered_map<std::uint32_t, std::vector<std::pair<std::uint32_t, double>>> uses;
  std::vector<std::uint32_t> fine_order;  // the fine variables in the order found
  const std::vector<std::uint8_t> near = cells_near_band(coarse, kReach);
  for (std::ptrdiff_t c = 0; c < static_cast<std::ptrdiff_t>(coarse.size()); ++c) {
    if (!near[c]) continue;
    const IVec<Dim> cs = coarse.lattice.coords(c);
    for (int child = 0; child < (1 << Dim); ++child) {
      IVec<Dim> fs;
      bool inside = true;
      for (int a = 0; a < Dim; ++a) {
        fs[a] = 2 * cs[a] - 1 + ((child >> a) & 1);
        inside = inside && fs[a] >= 0 && fs[a] < fine.lattice.padded(a);
      }
      if (!inside) continue;
      const std::ptrdiff_t kf = fine.lattice.index(fs);
      for (int i = 0; i < Dim; ++i) {
        if (fine.kind(i, kf) != VarKind::INTERIOR) continue;
        const std::uint32_t g = fine.global(i, kf);
        for (const auto& [variable, weight] : prolongation.row(g).terms) {
          const auto it = row_of.find(variable);
          if (it == row_of.end() || (wanted && !(*wanted)[it->second])) continue;
          auto& list = uses[g];
          if (list.empty()) fine_order.push_back(g);
          list.emplace_back(it->second, weight);
        }
      }
    }
  }
  // Row I = sum over the fine i of P_iI (A_f row i) P: each fine row times P once, scattered
  // into the rows that read it (merged as they grow).
  const FineRows<Dim, Scalar> fine_rows(fine);
  std::vector<LinearCombination> sums(band.rows());
  std::vector<std::size_t> merged_size(band.rows(), 0);
  for (std::uint32_t g : fine_order) {
    LinearCombination row_times_p;
    for (const auto& [j, a] : fine_rows.row(g).terms)
      add_scaled(row_times_p, prolongation.row(j), a);
    merge_terms(row_times_p);
    for (const auto& [m, weight] : uses[g]) {
      LinearCombination& sum = sums[m];
      add_scaled(sum, row_times_p, weight / (1 << Dim));
      if (sum.terms.size() > 2 * merged_size[m] + 256) {
        merge_terms(sum);
        merged_size[m] = sum.terms.size();
      }
    }
  }
  std::vector<std::vector<RowTerm>> terms(band.rows());
  for (std::size_t m = 0; m < band.rows(); ++m) {
    LinearCombination& sum = sums[m];
    merge_terms(sum);
    double largest = 0.0;
    for (const auto& term : sum.terms) largest = std::max(largest, std::abs(term.second));
    for (const auto& [variable, value] : sum.terms)
      if (std::abs(value) > 1e-12 * largest) terms[m].push_back({variable, value});
    LinearCombination().terms.swap(sum.terms);
  }
  return terms;
}

template <int Dim, typename Scalar>
void install_galerkin_band_rows(const Level<Dim, Scalar>& fine, Level<Dim, Scalar>& coarse,
                                GalerkinRowSet set) {
  std::vector<char> wanted(coarse.band_u.rows(), 1);
  if (set == GalerkinRowSet::AWAY_FROM_DIRICHLET)
    for (std::size_t m = 0; m < wanted.size(); ++m) wanted[m] = !next_to_dirichlet(coarse, m);
  const std::vector<std::vector<RowTerm>> terms =
      galerkin_band_displacement_terms(fine, coarse, &wanted);
  const SparseRows<Scalar> old = std::move(coarse.band_u);
  SparseRows<Scalar>& rows = coarse.band_u;
  rows = SparseRows<Scalar>();
  rows.target = old.target;
  rows.target_field = old.target_field;
  rows.target_index = old.target_index;
  rows.constant = old.constant;
  const auto n = coarse.size();
  auto push = [&](std::uint8_t field, std::uint32_t index, double value) {
    rows.column_field.push_back(field);
    rows.column_index.push_back(index);
    rows.value.push_back(static_cast<Scalar>(value));
  };
  for (std::size_t m = 0; m < old.rows(); ++m) {
    // Kept rows as they were; replaced ones: the Galerkin displacement terms, then the row's own
    // pressure terms (sorted by global index either way).
    double old_self = 0.0, new_self = 0.0;
    for (std::uint32_t e = old.start[m]; e < old.start[m + 1]; ++e) {
      const bool self =
          old.column_field[e] == old.target_field[m] && old.column_index[e] == old.target_index[m];
      if (self) old_self = static_cast<double>(old.value[e]);
      if (!wanted[m]) push(old.column_field[e], old.column_index[e], old.value[e]);
    }
    if (wanted[m]) {
      for (const RowTerm& t : terms[m]) {
        if (t.variable == old.target[m]) new_self = t.coefficient;
        push(static_cast<std::uint8_t>(t.variable / n), static_cast<std::uint32_t>(t.variable % n),
             t.coefficient);
      }
      for (std::uint32_t e = old.start[m]; e < old.start[m + 1]; ++e)
        if (old.column_field[e] == Dim) push(Dim, old.column_index[e], old.value[e]);
      coarse.band_u_schur_diagonal[m] = static_cast<Scalar>(
          static_cast<double>(coarse.band_u_schur_diagonal[m]) - old_self + new_self);
    }
    rows.start.push_back(static_cast<std::uint32_t>(rows.value.size()));
  }
  coarse.galerkin_band_rows = true;
  rebuild_band_sweep_data(coarse);
}

#define MGELASTIC_INSTANTIATE(D, S)                                                  \
  template std::vector<std::vector<RowTerm>> galerkin_band_displacement_terms<D, S>( \
      const Level<D, S>&, const Level<D, S>&, const std::vector<char>*);             \
  template void install_galerkin_band_rows<D, S>(const Level<D, S>&, Level<D, S>&, GalerkinRowSet);
MGELASTIC_INSTANTIATE(2, float)
MGELASTIC_INSTANTIATE(2, double)
MGELASTIC_INSTANTIATE(3, float)
MGELASTIC_INSTANTIATE(3, double)
#undef MGELASTIC_INSTANTIATE

}  // namespace mgelastic::grid
