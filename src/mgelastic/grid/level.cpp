#include "mgelastic/grid/level.hpp"

#include <algorithm>
#include <optional>
#include <string>
#include <type_traits>
#include <unordered_map>

#include <omp.h>
#include <Eigen/Dense>
#include <cstdlib>

#include "mgelastic/core/bytes.hpp"
#include "mgelastic/grid/explicit_rows.hpp"
#include "mgelastic/grid/huge_pages.hpp"

namespace mgelastic::grid {
namespace {

template <int Dim>
bool all_interior(const std::vector<CellType>& cells, std::initializer_list<std::ptrdiff_t> ks) {
  return std::all_of(ks.begin(), ks.end(),
                     [&](std::ptrdiff_t k) { return cells[k] == CellType::INTERIOR; });
}

template <int Dim>
struct Classifier {
  const Lattice<Dim>& lattice;
  const std::vector<CellType>& cells;

  bool interior(std::ptrdiff_t k) const { return cells[k] == CellType::INTERIOR; }
  bool dirichlet(std::ptrdiff_t k) const { return cells[k] == CellType::DIRICHLET; }

  // Face kind ignoring whether the face is referenced (TRACTION is decided afterwards).
  VarKind face_kind(int axis, std::ptrdiff_t k) const {
    if (lattice.coords(k)[axis] == 0) return VarKind::INACTIVE;
    const std::ptrdiff_t a = k - lattice.stride(axis);
    if (interior(a) && interior(k)) return VarKind::INTERIOR;
    if (dirichlet(a) || dirichlet(k)) return VarKind::DIRICHLET;
    return VarKind::INACTIVE;
  }

  // Distributive smoothing of u_axis at face k is valid when its uniform stencil and its
  // distribution touch interior variables only (Sec. 5.2): all 12 (3D) cells around it interior.
  bool distributive_face(int axis, std::ptrdiff_t k) const {
    const std::ptrdiff_t si = lattice.stride(axis);
    if (!(interior(k) && interior(k - si) && interior(k + si) && interior(k - 2 * si)))
      return false;
    for (int j = 0; j < Dim; ++j) {
      if (j == axis) continue;
      const std::ptrdiff_t sj = lattice.stride(j);
      if (!(interior(k + sj) && interior(k - sj) && interior(k - si + sj) && interior(k - si - sj)))
        return false;
    }
    return true;
  }

  // The pressure of an interior cell is relaxed distributively unless a face neighbor is
  // exterior (a traction boundary gradient makes its row non-standard). Next to Dirichlet cells
  // the distribution is restricted to the active variables (Sec. 5.3, last remark), which keeps
  // the band pivots free of the lambda-dominated Schur terms near constraints.
  bool distributive_cell(std::ptrdiff_t k) const {
    if (!interior(k)) return false;
    for (int j = 0; j < Dim; ++j) {
      const std::ptrdiff_t sj = lattice.stride(j);
      if (cells[k + sj] == CellType::EXTERIOR || cells[k - sj] == CellType::EXTERIOR) return false;
    }
    return true;
  }
};

// Marks every face variable referenced by an interior equation's uniform stencil; the ones that
// are neither interior nor Dirichlet are the traction boundary variables of Sec. 5.1.
template <int Dim, typename Scalar>
void mark_traction_variables(Level<Dim, Scalar>& level) {
  const auto& lat = level.lattice;
  auto mark = [&](int axis, std::ptrdiff_t k) {
    if (level.kind(axis, k) == VarKind::INACTIVE) level.codes.set_kind(axis, k, VarKind::TRACTION);
  };
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(lat.size()); ++k) {
    if (level.kind(Dim, k) == VarKind::INTERIOR) {
      for (int i = 0; i < Dim; ++i) {
        mark(i, k);
        mark(i, k + lat.stride(i));
      }
    }
    for (int i = 0; i < Dim; ++i) {
      if (level.kind(i, k) != VarKind::INTERIOR) continue;
      const std::ptrdiff_t si = lat.stride(i);
      for (int j = 0; j < Dim; ++j) {
        const std::ptrdiff_t sj = lat.stride(j);
        mark(i, k + sj);
        mark(i, k - sj);
        if (j == i) continue;
        mark(j, k);
        mark(j, k - si);
        mark(j, k + sj);
        mark(j, k - si + sj);
      }
    }
  }
}

// Fig. 8 of the paper: fine interior faces whose residual restricts onto, or whose correction is
// prolongated from, coarse faces that carry no interior equation.
template <int Dim>
struct RelocationTest {
  const Lattice<Dim>& fine;
  Lattice<Dim> coarse;
  const std::vector<CellType>& coarse_cells;
  // Per coarse cell: it and its 3^Dim - 1 neighbours are interior. Every coarse face classify
  // looks at lies between cells within one cell of the fine location's parent, so where the
  // parent is deep the answer is {false, false} without the search (most of a body).
  std::vector<std::uint8_t> deep = interior_neighbourhoods();

  std::vector<std::uint8_t> interior_neighbourhoods() const {
    const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(coarse.size());
    std::vector<std::uint8_t> v(n), eroded(n);
    for (std::ptrdiff_t k = 0; k < n; ++k) v[k] = coarse_cells[k] == CellType::INTERIOR;
    for (int a = 0; a < Dim; ++a) {  // erosion by one cell along each axis in turn
      const std::ptrdiff_t sa = coarse.stride(a);
#pragma omp parallel for schedule(static)
      for (std::ptrdiff_t k = 0; k < n; ++k) {
        const int t = coarse.coords(k)[a];
        eroded[k] = t > 0 && t + 1 < coarse.padded(a) && v[k] && v[k - sa] && v[k + sa];
      }
      v.swap(eroded);
    }
    return v;
  }

  std::ptrdiff_t parent(const IVec<Dim>& s) const {
    IVec<Dim> c;
    for (int a = 0; a < Dim; ++a) c[a] = (s[a] - 1) / 2 + 1;
    return coarse.index(c);
  }

  bool coarse_face_interior(int axis, const IVec<Dim>& stored) const {
    for (int a = 0; a < Dim; ++a)
      if (stored[a] < 1 || stored[a] > coarse.cells[a] + (a == axis ? 1 : 0)) return false;
    const std::ptrdiff_t k = coarse.index(stored);
    return coarse_cells[k] == CellType::INTERIOR &&
           coarse_cells[k - coarse.stride(axis)] == CellType::INTERIOR;
  }

  // One or two coarse stored coordinates along an axis (fixed storage: classify runs for every
  // face of the lattice, and per-call vectors made it a third of the level build).
  struct Coordinates {
    std::array<int, 2> value{};
    int count = 0;
  };

  // along[a] lists the coarse stored coordinates touched along axis a.
  bool all_coarse_interior(int axis, const std::array<Coordinates, Dim>& along) const {
    IVec<Dim> s;
    bool ok = true;
    auto recurse = [&](auto&& self, int a) -> void {
      if (!ok) return;
      if (a == Dim) {
        ok = coarse_face_interior(axis, s);
        return;
      }
      for (int i = 0; i < along[a].count; ++i) {
        s[a] = along[a].value[i];
        self(self, a + 1);
      }
    };
    recurse(recurse, 0);
    return ok;
  }

  bool coarse_parent_interior(std::ptrdiff_t k) const {
    IVec<Dim> s = fine.coords(k);
    for (int a = 0; a < Dim; ++a) s[a] = (s[a] - 1) / 2 + 1;
    return coarse_cells[coarse.index(s)] == CellType::INTERIOR;
  }

  // Returns {restricts onto a coarse non-equation, prolongates from a coarse boundary variable}.
  std::pair<bool, bool> classify(int axis, std::ptrdiff_t k) const {
    const IVec<Dim> s = fine.coords(k);
    if (deep[parent(s)]) return {false, false};
    std::array<Coordinates, Dim> restrict_to, prolong_from;
    for (int a = 0; a < Dim; ++a) {
      const int c = s[a] - 1;  // unpadded face (a == axis) or cell coordinate
      if (a == axis) {
        restrict_to[a] = (c % 2 == 0) ? Coordinates{{c / 2 + 1, 0}, 1}
                                      : Coordinates{{(c - 1) / 2 + 1, (c + 1) / 2 + 1}, 2};
        prolong_from[a] = restrict_to[a];
      } else {
        const int m = c / 2;
        restrict_to[a] = {{m + 1, 0}, 1};
        prolong_from[a] = {{m + 1, (c % 2 == 0 ? m - 1 : m + 1) + 1}, 2};
      }
    }
    return {!all_coarse_interior(axis, restrict_to), !all_coarse_interior(axis, prolong_from)};
  }
};

template <typename Scalar>
void append_row(SparseRows<Scalar>& rows, std::uint32_t target, const ExplicitRow& row,
                std::size_t size) {
  rows.target.push_back(target);
  rows.target_field.push_back(static_cast<std::uint8_t>(target / size));
  rows.target_index.push_back(static_cast<std::uint32_t>(target % size));
  for (const RowTerm& t : row.terms) {
    rows.column_field.push_back(static_cast<std::uint8_t>(t.variable / size));
    rows.column_index.push_back(static_cast<std::uint32_t>(t.variable % size));
    rows.value.push_back(static_cast<Scalar>(t.coefficient));
  }
  rows.start.push_back(static_cast<std::uint32_t>(rows.entries()));
  rows.constant.push_back(static_cast<Scalar>(row.constant));
}

// Grows the band of eliminated pressures by `layers` cells into the distributive region (face
// neighbors). The paper notes that its asymptotic rate on weakly constrained scans improves with
// a more intense boundary smoother; one extra layer lets the band sweeps reach the wedges where a
// Dirichlet region cuts a body at a shallow angle (bunny at 64 cells: 0.67 -> 0.45 per cycle,
// docs/embedded-geometry.md), at some cost on boxes (32^3: 0.233 -> 0.247).
template <int Dim, typename Scalar>
void widen_band_cells(Level<Dim, Scalar>& level, int layers) {
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(level.size());
  auto pressure = [&](std::ptrdiff_t k) { return level.relaxation(Dim, k); };
  for (int layer = 0; layer < layers; ++layer) {
    std::vector<std::ptrdiff_t> grown;
    for (std::ptrdiff_t k = 0; k < n; ++k) {
      if (pressure(k) != Relaxation::DISTRIBUTIVE) continue;
      for (int j = 0; j < Dim; ++j) {
        const std::ptrdiff_t sj = level.lattice.stride(j);
        if (pressure(k + sj) == Relaxation::BAND || pressure(k - sj) == Relaxation::BAND) {
          grown.push_back(k);
          break;
        }
      }
    }
    for (std::ptrdiff_t k : grown) level.codes.set_relaxation(Dim, k, Relaxation::BAND);
  }
}

// Partly filled cells and their face neighbors join the band: then every row whose stencil
// touches a weighted stress is an explicit (weighted) band row, and the distributive sweeps,
// which assume the constant-coefficient stencil, never see one.
template <int Dim, typename Scalar>
void band_partly_filled_cells(Level<Dim, Scalar>& level) {
  if (level.cell_weight.empty()) return;
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(level.size());
  auto partial = [&](std::ptrdiff_t k) {
    return level.cells[k] == CellType::INTERIOR && level.cell_weight[k] != 1.0;
  };
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    if (level.relaxation(Dim, k) != Relaxation::DISTRIBUTIVE) continue;
    bool touches = partial(k);
    for (int j = 0; j < Dim && !touches; ++j) {
      const std::ptrdiff_t sj = level.lattice.stride(j);
      touches = partial(k + sj) || partial(k - sj);
    }
    if (touches) level.codes.set_relaxation(Dim, k, Relaxation::BAND);
  }
}

template <int Dim, typename Scalar>
void classify_relaxation(Level<Dim, Scalar>& level, const std::vector<CellType>* coarse_cells,
                         FieldArray<std::uint8_t>& pre, FieldArray<std::uint8_t>& post,
                         int band_layers) {
  const Classifier<Dim> classifier{level.lattice, level.cells};
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(level.size());
  std::optional<RelocationTest<Dim>> relocation;
  if (coarse_cells) {
    IVec<Dim> coarse_n;
    for (int a = 0; a < Dim; ++a) coarse_n[a] = (level.lattice.cells[a] + 1) / 2;
    relocation.emplace(RelocationTest<Dim>{
        level.lattice, Lattice<Dim>(coarse_n, 2 * level.lattice.h), *coarse_cells});
  }
  // Eliminated pressures (relaxed exactly, Schur pivots in the band): cells with an exterior
  // neighbor (traction-modified pressure rows) and cells whose coarse parent is not interior
  // (Fig. 8: the coarse grid cannot correct them, so they must be relaxed robustly here).
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    if (level.kind(Dim, k) != VarKind::INTERIOR) continue;
    const bool relocated = relocation && !relocation->coarse_parent_interior(k);
    level.codes.set_relaxation(Dim, k,
                               classifier.distributive_cell(k) && !relocated
                                   ? Relaxation::DISTRIBUTIVE
                                   : Relaxation::BAND);
  }
  widen_band_cells(level, band_layers);
  band_partly_filled_cells(level);
  // Band faces: non-uniform footprint, next to an eliminated pressure (a psi step there would
  // be undone by the exact pressure update and over-relax u), or in the Fig. 8 sets.
  // Decided in parallel (reads only), then written: codes hold all fields of a cell in one word.
  std::vector<std::uint8_t> band(n);
  for (int i = 0; i < Dim; ++i) {
    const std::ptrdiff_t si = level.lattice.stride(i);
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t k = 0; k < n; ++k) {
      if (level.kind(i, k) != VarKind::INTERIOR) continue;
      band[k] = !classifier.distributive_face(i, k) ||
                level.relaxation(Dim, k) == Relaxation::BAND ||
                level.relaxation(Dim, k - si) == Relaxation::BAND;
      if (relocation) {
        const auto [restricts_badly, prolongs_badly] = relocation->classify(i, k);
        // Written where set only: the flags start as calloc's zeros, and the pages of the
        // (few) faces with a flag are all they map.
        if (restricts_badly) pre[i * n + k] = 1;
        if (prolongs_badly) post[i * n + k] = 1;
        band[k] = band[k] || restricts_badly || prolongs_badly;
      }
    }
    for (std::ptrdiff_t k = 0; k < n; ++k)
      if (level.kind(i, k) == VarKind::INTERIOR)
        level.codes.set_relaxation(i, k, band[k] ? Relaxation::BAND : Relaxation::DISTRIBUTIVE);
  }
}

template <int Dim, typename Scalar>
double fill_weight(const Level<Dim, Scalar>& level, std::ptrdiff_t cell) {
  return level.cell_weight.empty() ? 1.0 : level.cell_weight[cell];
}

template <typename T>
void append(std::vector<T>& to, const std::vector<T>& from) {
  to.insert(to.end(), from.begin(), from.end());
}

// Appends `from` (rows with their own start{0}) to `to`.
template <typename Scalar>
void append_rows(SparseRows<Scalar>& to, const SparseRows<Scalar>& from) {
  const auto offset = static_cast<std::uint32_t>(to.entries());
  for (std::size_t r = 1; r < from.start.size(); ++r) to.start.push_back(from.start[r] + offset);
  append(to.target, from.target);
  append(to.value, from.value);
  append(to.constant, from.constant);
  append(to.target_field, from.target_field);
  append(to.column_field, from.column_field);
  append(to.target_index, from.target_index);
  append(to.column_index, from.column_index);
}

// Room for the rows of all parts at once (no regrowth while they are joined).
template <typename Scalar, typename Part>
std::size_t reserve_rows(SparseRows<Scalar>& to, const std::vector<Part>& parts) {
  std::size_t rows = to.rows(), entries = to.entries();
  for (const Part& part : parts) rows += part.rows.rows(), entries += part.rows.entries();
  for (auto* v : {&to.target, &to.start, &to.target_index}) v->reserve(rows + 1);
  to.constant.reserve(rows);
  to.target_field.reserve(rows);
  to.value.reserve(entries);
  to.column_field.reserve(entries);
  to.column_index.reserve(entries);
  return rows;
}

// Room for `rows` rows of at most `entries_per_row` entries in a part's rows: no regrowth, whose
// copies would fault in fresh pages (several microseconds each on a virtual machine). Capacity
// that no row fills costs no memory (large blocks are mapped on their own, heap_policy.hpp).
template <typename Scalar>
void reserve_part_rows(SparseRows<Scalar>& rows, std::size_t count, std::size_t entries_per_row) {
  for (auto* v : {&rows.target, &rows.start, &rows.target_index}) v->reserve(count + 1);
  rows.constant.reserve(count);
  rows.target_field.reserve(count);
  rows.value.reserve(count * entries_per_row);
  rows.column_field.reserve(count * entries_per_row);
  rows.column_index.reserve(count * entries_per_row);
}

// Band variables of fields [first, last] at lattice points [begin, end).
template <int Dim, typename Scalar>
std::size_t band_variables(const Level<Dim, Scalar>& level, int first, int last,
                           std::ptrdiff_t begin, std::ptrdiff_t end) {
  std::size_t count = 0;
  for (std::ptrdiff_t k = begin; k < end; ++k)
    for (int f = first; f <= last; ++f) count += level.relaxation(f, k) == Relaxation::BAND;
  return count;
}

// Builds part(t, begin, end) for T contiguous ranges of [0, n), one per thread, and returns the
// parts in range order: joined in that order they are the serial build's, for any thread count.
template <typename Part, typename Build>
std::vector<Part> build_in_ranges(std::ptrdiff_t n, Build&& build) {
  const int threads = std::max(1, omp_get_max_threads());
  std::vector<Part> parts(static_cast<std::size_t>(threads));
#pragma omp parallel num_threads(threads)
  {
    const auto t = static_cast<std::ptrdiff_t>(omp_get_thread_num());
    const auto count = static_cast<std::ptrdiff_t>(omp_get_num_threads());
    build(parts[static_cast<std::size_t>(t)], n * t / count, n * (t + 1) / count);
  }
  return parts;
}

template <typename Scalar>
struct PressureRowsPart {
  SparseRows<Scalar> rows;
  std::vector<Scalar> extra, inverse;
  std::vector<std::ptrdiff_t> cells;
};

template <typename Scalar>
struct MomentumRowsPart {
  SparseRows<Scalar> rows;
  std::vector<std::array<std::uint32_t, 2>> pressure;
  std::vector<std::array<Scalar, 2>> factor;
  std::vector<Scalar> schur;
  std::vector<std::uint32_t> pre, post;  // row numbers within the part
};

// The band's explicit rows, in lattice order (all components at one location together: Gauss-
// Seidel then sweeps the thin band like a front, which converges faster than component by
// component). Built by the threads in contiguous lattice ranges and joined in order.
template <int Dim, typename Scalar>
void build_band_rows(Level<Dim, Scalar>& level, const RowBuilder<Dim>& builder,
                     const FieldArray<std::uint8_t>& pre, const FieldArray<std::uint8_t>& post) {
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(level.size());
  const double mu = level.mu, lambda = level.lambda;
  auto pressure_parts = build_in_ranges<PressureRowsPart<Scalar>>(
      n, [&](PressureRowsPart<Scalar>& part, std::ptrdiff_t begin, std::ptrdiff_t end) {
        const std::size_t count = band_variables(level, Dim, Dim, begin, end);
        reserve_part_rows(part.rows, count, 4 * Dim);
        for (auto* v : {&part.extra, &part.inverse}) v->reserve(count);
        part.cells.reserve(count);
        for (std::ptrdiff_t k = begin; k < end; ++k) {
          if (level.relaxation(Dim, k) != Relaxation::BAND) continue;
          const ExplicitRow row = builder.pressure(k);
          append_row(part.rows, level.global(Dim, k), row, level.size());
          part.extra.push_back(static_cast<Scalar>(row.pressure_extra));
          // 1/D with D = mu^2/lambda + extra, written to stay finite (zero) at lambda = 0.
          part.inverse.push_back(
              static_cast<Scalar>(lambda / (mu * mu + lambda * row.pressure_extra)));
          part.cells.push_back(k);
        }
      });
  std::vector<std::int32_t> band_p_index(n, -1);
  const std::size_t pressure_rows = reserve_rows(level.band_p, pressure_parts);
  level.band_p_extra.reserve(pressure_rows);
  level.band_p_inverse.reserve(pressure_rows);
  for (auto& part : pressure_parts) {
    for (std::size_t r = 0; r < part.cells.size(); ++r)
      band_p_index[part.cells[r]] = static_cast<std::int32_t>(level.band_p_extra.size() + r);
    append_rows(level.band_p, part.rows);
    append(level.band_p_extra, part.extra);
    append(level.band_p_inverse, part.inverse);
    part = {};  // freed once joined (the setup's peak)
  }
  auto momentum_parts = build_in_ranges<MomentumRowsPart<Scalar>>(
      n, [&](MomentumRowsPart<Scalar>& part, std::ptrdiff_t begin, std::ptrdiff_t end) {
        const std::size_t count = band_variables(level, 0, Dim - 1, begin, end);
        reserve_part_rows(part.rows, count, 16 * Dim);
        part.pressure.reserve(count);
        part.factor.reserve(count);
        part.schur.reserve(count);
        for (std::ptrdiff_t k = begin; k < end; ++k) {
          for (int i = 0; i < Dim; ++i) {
            if (level.relaxation(i, k) != Relaxation::BAND) continue;
            const ExplicitRow row = builder.momentum(i, k);
            const std::uint32_t self = level.global(i, k);
            double schur = 0.0;
            std::array<std::uint32_t, 2> coupled{UINT32_MAX, UINT32_MAX};
            std::array<Scalar, 2> factor{0, 0};
            int m = 0;
            for (const RowTerm& t : row.terms) {
              if (t.variable == self) schur += t.coefficient;
              // Adjacent pressures relaxed distributively stay fixed during band sweeps (Sec.
              // 5.3: interior variables not being smoothed act as Dirichlet values); eliminated
              // band pressures follow u exactly, which gives the Schur-complement pivot.
              if (t.variable / n == static_cast<std::uint32_t>(Dim) &&
                  band_p_index[t.variable % n] >= 0) {
                // The pressure row's coefficient of u is this row's divided by the fill weight.
                const double inverse = level.band_p_inverse[band_p_index[t.variable % n]] /
                                       fill_weight(level, t.variable % n);
                schur -= t.coefficient * t.coefficient * inverse;
                coupled[m] = t.variable % n;
                factor[m++] = static_cast<Scalar>(inverse * t.coefficient);
              }
            }
            const auto index = static_cast<std::uint32_t>(part.rows.rows());
            part.pressure.push_back(coupled);
            part.factor.push_back(factor);
            if (!pre.empty() && pre[i * n + k]) part.pre.push_back(index);
            if (!post.empty() && post[i * n + k]) part.post.push_back(index);
            append_row(part.rows, self, row, level.size());
            part.schur.push_back(static_cast<Scalar>(schur));
          }
        }
      });
  const std::size_t momentum_rows = reserve_rows(level.band_u, momentum_parts);
  level.band_u_pressure.reserve(momentum_rows);
  level.band_u_pressure_factor.reserve(momentum_rows);
  level.band_u_schur_diagonal.reserve(momentum_rows);
  for (auto& part : momentum_parts) {
    const auto offset = static_cast<std::uint32_t>(level.band_u.rows());
    for (std::uint32_t r : part.pre) level.pre_restriction_rows.push_back(offset + r);
    for (std::uint32_t r : part.post) level.post_prolongation_rows.push_back(offset + r);
    append_rows(level.band_u, part.rows);
    append(level.band_u_pressure, part.pressure);
    append(level.band_u_pressure_factor, part.factor);
    append(level.band_u_schur_diagonal, part.schur);
    part = {};
  }
}

// Coefficient of global variable `variable` in row m (0 when absent).
template <typename Scalar>
double row_coefficient(const SparseRows<Scalar>& rows, std::uint32_t m, std::uint32_t variable,
                       std::size_t size) {
  const auto field = static_cast<std::uint8_t>(variable / size);
  const auto index = static_cast<std::uint32_t>(variable % size);
  for (std::uint32_t e = rows.start[m]; e < rows.start[m + 1]; ++e)
    if (rows.column_field[e] == field && rows.column_index[e] == index) return rows.value[e];
  return 0.0;
}

// One block per eliminated cell: its band faces, with the inverse of their Schur block
//   S_loc[f][g] = A_fg - G_fc G_gc / D_c (f != g),  S_loc[f][f] = Schur diagonal of row f.
// The blocks are formed in parallel, chunk by chunk, and registered in cell order (identical
// inverses shared by their exact bytes), so the result does not depend on the thread count.
template <int Dim, typename Scalar>
void build_band_blocks(Level<Dim, Scalar>& level) {
  const auto n = static_cast<std::ptrdiff_t>(level.size());
  const auto row_of = rows_by_target(level.band_u);
  std::vector<std::uint8_t> in_block(level.band_u.rows(), 0);
  constexpr int B = 2 * Dim;
  struct Block {
    std::array<std::uint32_t, B> rows;
    std::array<Scalar, B * B> inverse;
    int count = 0;
  };
  // The block of eliminated cell e (count < 2: none).
  const auto form = [&](std::size_t e) {
    Block block;
    const std::ptrdiff_t c = level.band_p.target[e] % n;
    block.rows.fill(UINT32_MAX);
    for (int i = 0; i < Dim; ++i)
      for (std::ptrdiff_t face : {c, c + level.lattice.stride(i)}) {
        const auto it = row_of.find(level.global(i, face));
        if (it != row_of.end()) block.rows[block.count++] = it->second;
      }
    const int count = block.count;
    if (count < 2) return block;
    const auto& rows = block.rows;
    const std::uint32_t pc = level.band_p.target[e];
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, B, B> s(count, count);
    for (int a = 0; a < count; ++a) {
      for (int b = 0; b < count; ++b) {
        if (a == b) {
          s(a, a) = level.band_u_schur_diagonal[rows[a]];
          continue;
        }
        const double g_a = row_coefficient(level.band_u, rows[a], pc, level.size());
        const double g_b = row_coefficient(level.band_u, rows[b], pc, level.size());
        s(a, b) =
            row_coefficient(level.band_u, rows[a], level.band_u.target[rows[b]], level.size()) -
            g_a * g_b * level.band_p_inverse[e] / fill_weight(level, c);
      }
    }
    // S_loc is a principal block of the symmetric negative definite Schur complement.
    const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, B, B> inverse = s.inverse();
    for (int a = 0; a < B; ++a)
      for (int b = 0; b < B; ++b)
        block.inverse[a * B + b] =
            a < count && b < count ? static_cast<Scalar>(inverse(a, b)) : Scalar(0);
    return block;
  };
  std::unordered_map<std::string, std::uint32_t> inverse_ids;  // by the inverse's exact bytes
  constexpr std::size_t kChunk = std::size_t{1} << 16;         // bounds the formed blocks held
  std::vector<Block> chunk;
  for (std::size_t first = 0; first < level.band_p.rows(); first += kChunk) {
    const std::size_t count = std::min(kChunk, level.band_p.rows() - first);
    chunk.resize(count);
#pragma omp parallel for schedule(dynamic, 256)
    for (std::ptrdiff_t q = 0; q < static_cast<std::ptrdiff_t>(count); ++q)
      chunk[static_cast<std::size_t>(q)] = form(first + static_cast<std::size_t>(q));
    for (const Block& block : chunk) {
      if (block.count < 2) continue;
      const std::string key(reinterpret_cast<const char*>(block.inverse.data()),
                            sizeof block.inverse);
      const auto [it, added] =
          inverse_ids.try_emplace(key, static_cast<std::uint32_t>(inverse_ids.size()));
      if (added)
        level.band_block_inverse.insert(level.band_block_inverse.end(), block.inverse.begin(),
                                        block.inverse.end());
      level.band_block_inverse_id.push_back(it->second);
      for (int a = 0; a < block.count; ++a) in_block[block.rows[a]] = 1;
      level.band_blocks.push_back(block.rows);
    }
  }
  for (std::uint32_t m = 0; m < level.band_u.rows(); ++m)
    if (!in_block[m]) level.band_point_rows.push_back(m);
}

// Groups the band work by the colored blocks that contain each row's (or cell's) location.
template <int Dim, typename Scalar>
void build_band_schedule(Level<Dim, Scalar>& level) {
  const auto& partition = level.blocks;
  std::vector<std::pair<int, int>> slot(partition.blocks_per_axis.prod());
  for (int c = 0; c < BlockPartition<Dim>::color_count; ++c) {
    level.band_schedule[c].resize(partition.colors[c].size());
    for (std::size_t b = 0; b < partition.colors[c].size(); ++b) {
      const IVec<Dim> lo = partition.colors[c][b].lo;
      int linear = 0, stride = 1;
      for (int a = 0; a < Dim; ++a) {
        linear += ((lo[a] - 1) / partition.block_size[a]) * stride;
        stride *= partition.blocks_per_axis[a];
      }
      slot[linear] = {c, static_cast<int>(b)};
    }
  }
  // Color and index within the color of the block that holds location k.
  auto slot_at = [&](std::ptrdiff_t k) {
    const IVec<Dim> s = level.lattice.coords(k);
    int linear = 0, stride = 1;
    for (int a = 0; a < Dim; ++a) {
      linear += ((s[a] - 1) / partition.block_size[a]) * stride;
      stride *= partition.blocks_per_axis[a];
    }
    return slot[linear];
  };
  auto work_at = [&](std::ptrdiff_t k) -> typename Level<Dim, Scalar>::BandWork& {
    const auto [color, index] = slot_at(k);
    return level.band_schedule[color][index];
  };
  for (std::size_t e = 0; e < level.band_blocks.size(); ++e) {
    const std::uint32_t first_row = level.band_blocks[e][0];
    work_at(level.band_u.target_index[first_row])
        .cell_blocks.push_back(static_cast<std::uint32_t>(e));
  }
  for (std::uint32_t m : level.band_point_rows)
    work_at(level.band_u.target_index[m]).point_rows.push_back(m);
  // The Fig. 8 subsets: each row goes to the block that holds its target, like a point row.
  auto schedule_rows = [&](const std::vector<std::uint32_t>& rows,
                           typename Level<Dim, Scalar>::RowSchedule& schedule) {
    for (int c = 0; c < BlockPartition<Dim>::color_count; ++c)
      schedule[c].assign(partition.colors[c].size(), {});
    for (std::uint32_t m : rows) {
      const auto [color, index] = slot_at(level.band_u.target_index[m]);
      schedule[color][index].push_back(m);
    }
  };
  schedule_rows(level.pre_restriction_rows, level.pre_restriction_schedule);
  schedule_rows(level.post_prolongation_rows, level.post_prolongation_schedule);
}

template <int Dim, typename Scalar>
bool known_after_normal_pass(const Level<Dim, Scalar>& level, int axis, std::ptrdiff_t k) {
  const VarKind kind = level.kind(axis, k);
  if (kind == VarKind::INTERIOR || kind == VarKind::DIRICHLET) return true;
  if (kind != VarKind::TRACTION) return false;
  return level.cells[k] == CellType::INTERIOR ||
         level.cells[k - level.lattice.stride(axis)] == CellType::INTERIOR;
}

template <int Dim, typename Scalar>
void add_shear_rule(Level<Dim, Scalar>& level, const BoundaryStress<Dim>& sigma, int i,
                    std::ptrdiff_t g) {
  const auto& lat = level.lattice;
  const IVec<Dim> s = lat.coords(g);
  const std::ptrdiff_t si = lat.stride(i);
  const double h = lat.h, mu = level.mu;
  auto& candidates = level.traction.shear_candidates;
  const auto first = static_cast<std::uint32_t>(candidates.size());
  auto known = [&](int axis, std::ptrdiff_t k) { return known_after_normal_pass(level, axis, k); };
  auto stress = [&](int j, std::ptrdiff_t edge) {
    return sigma ? sigma(i, j, lat.edge_center(i, j, edge)) : 0.0;
  };
  for (int j = 0; j < Dim; ++j) {
    if (j == i) continue;
    const std::ptrdiff_t sj = lat.stride(j);
    if (s[j] >= 1 && s[i] >= 1 && known(i, g - sj) && level.kind(i, g - sj) != VarKind::TRACTION &&
        known(j, g) && known(j, g - si)) {
      candidates.push_back({level.global(i, g - sj), level.global(j, g), level.global(j, g - si),
                            Scalar(-1), static_cast<Scalar>(h * stress(j, g) / mu)});
    }
    if (s[j] + 1 <= lat.cells[j] + 1 && s[i] >= 1 && known(i, g + sj) &&
        level.kind(i, g + sj) != VarKind::TRACTION && known(j, g + sj) && known(j, g + sj - si)) {
      candidates.push_back({level.global(i, g + sj), level.global(j, g + sj),
                            level.global(j, g + sj - si), Scalar(1),
                            static_cast<Scalar>(-h * stress(j, g + sj) / mu)});
    }
  }
  const auto count = static_cast<std::uint32_t>(candidates.size()) - first;
  if (count > 0) level.traction.shear.push_back({level.global(i, g), first, count});
}

template <int Dim, typename Scalar>
void add_thin_rule(Level<Dim, Scalar>& level, const BoundaryStress<Dim>& sigma, int i,
                   std::ptrdiff_t cell) {
  const auto& lat = level.lattice;
  const std::ptrdiff_t si = lat.stride(i);
  ThinTractionRule<Scalar> rule{
      level.global(i, cell),
      level.global(i, cell + si),
      level.global(Dim, cell),
      {},
      static_cast<Scalar>(sigma ? sigma(i, i, lat.cell_center(cell)) : 0)};
  for (int j = 0; j < Dim; ++j) {
    if (j == i) continue;
    for (std::ptrdiff_t nb : {cell - lat.stride(j), cell + lat.stride(j)}) {
      for (std::ptrdiff_t face : {nb, nb + si}) {
        const VarKind kind = level.kind(i, face);
        if (kind == VarKind::INTERIOR || kind == VarKind::DIRICHLET)
          rule.neighbors.push_back(level.global(i, face));
      }
    }
  }
  level.traction.thin.push_back(std::move(rule));
}

template <int Dim, typename Scalar>
void build_traction_rules(Level<Dim, Scalar>& level, const BoundaryStress<Dim>& sigma) {
  const auto& lat = level.lattice;
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(level.size());
  for (int i = 0; i < Dim; ++i) {
    const std::ptrdiff_t si = lat.stride(i);
    for (std::ptrdiff_t g = 0; g < n; ++g) {
      if (level.kind(i, g) != VarKind::TRACTION) continue;
      const bool lower_interior = level.cells[g - si] == CellType::INTERIOR;
      const bool upper_interior = level.cells[g] == CellType::INTERIOR;
      const Scalar s = static_cast<Scalar>(sigma ? sigma(i, i, lat.face_center(i, g)) : 0);
      if (lower_interior) {
        if (level.kind(i, g - si) == VarKind::TRACTION) continue;  // thin: handled below
        level.traction.normal.push_back(
            {level.global(i, g), level.global(i, g - si), level.global(Dim, g - si), 1, s});
      } else if (upper_interior) {
        if (level.kind(i, g + si) == VarKind::TRACTION) {
          add_thin_rule(level, sigma, i, g);
          continue;
        }
        level.traction.normal.push_back(
            {level.global(i, g), level.global(i, g + si), level.global(Dim, g), -1, s});
      } else {
        add_shear_rule(level, sigma, i, g);
      }
    }
  }
}

}  // namespace

template <int Dim, typename Scalar>
std::size_t Level<Dim, Scalar>::interior_unknowns() const {
  std::size_t count = 0;
  for (int f = 0; f <= Dim; ++f) count += codes.count(f, VarKind::INTERIOR);
  return count;
}

template <int Dim, typename Scalar>
std::vector<ByteShare> Level<Dim, Scalar>::byte_breakdown() const {
  const auto sum = [](const auto&... v) { return (vector_bytes(v) + ... + 0); };
  const auto nested = [&](const auto& outer) {  // a vector of vectors, or an array of them
    std::size_t total = 0;
    for (const auto& inner : outer) total += vector_bytes(inner);
    return total;
  };
  std::size_t fields = 0;
  for (int f = 0; f <= Dim; ++f) {
    for (const auto* field : {&x[f], &b[f], &r[f]})
      fields += vector_bytes(*field) - released_bytes(*field, live);
    fields -= zero_load_bytes(f);
  }
  std::size_t schedules = sum(pre_restriction_rows, post_prolongation_rows);
  for (const auto& color : band_schedule)
    for (const BandWork& work : color) schedules += sum(work.cell_blocks, work.point_rows);
  for (const auto* schedule : {&pre_restriction_schedule, &post_prolongation_schedule})
    for (const auto& color : *schedule) schedules += nested(color);
  std::size_t rules =
      sum(traction.normal, traction.thin, traction.shear, traction.shear_candidates);
  for (const auto& rule : traction.thin) rules += vector_bytes(rule.neighbors);
  const auto csr_values = [&](const SparseRows<Scalar>& rows) {
    return sum(rows.start, rows.value, rows.constant);
  };
  const auto global_indices = [&](const SparseRows<Scalar>& rows) {
    return vector_bytes(rows.target);
  };
  const auto split_indices = [&](const SparseRows<Scalar>& rows) {
    return sum(rows.target_field, rows.column_field, rows.target_index, rows.column_index);
  };
  return {
      {"fields x b r", fields},
      // Shared codes count at the level that owns them.
      {"variable codes (kind, relaxation)", codes.owns() ? codes.bytes() : 0},
      {"cells, Dirichlet wall layers, live rows",
       sum(cells, dirichlet_wall_layers, live.live, live.span)},
      {"cell weights", vector_bytes(cell_weight)},
      {"band_u CSR start/value/constant", csr_values(band_u)},
      {"band_u global target", global_indices(band_u)},
      {"band_u split field/index", split_indices(band_u)},
      {"band_u Schur diag, pressures",
       sum(band_u_schur_diagonal, band_u_pressure, band_u_pressure_factor)},
      {"band_p rows (all forms)", csr_values(band_p) + global_indices(band_p) +
                                      split_indices(band_p) + sum(band_p_extra, band_p_inverse)},
      {"band blocks, inverses, points",
       sum(band_blocks, band_block_inverse, band_block_inverse_id, band_point_rows) +
           band_block_shapes.bytes()},
      {"band kernel (patterns)", band_kernel.bytes() + band_p_kernel.bytes()},
      {"band runs", band_runs.bytes()},
      {"schedules, Fig. 8 rows", schedules},
      {"block partition", nested(blocks.colors)},
      {"traction rules", rules},
  };
}

template <int Dim, typename Scalar>
std::size_t Level<Dim, Scalar>::bytes() const {
  std::size_t total = 0;
  for (const ByteShare& share : byte_breakdown()) total += share.bytes;
  return total;
}

// The band arrays and traction rules grow by push_back, which leaves up to half of each
// allocation unused for the level's lifetime; they are trimmed once built (nothing keeps
// pointers into them: the sweeps take their views per call).
template <int Dim, typename Scalar>
void shrink_band_arrays(Level<Dim, Scalar>& level) {
  const auto shrink = [](auto&... v) { (v.shrink_to_fit(), ...); };
  for (auto* rows : {&level.band_u, &level.band_p})
    shrink(rows->target, rows->start, rows->value, rows->constant, rows->target_field,
           rows->column_field, rows->target_index, rows->column_index);
  shrink(level.band_u_schur_diagonal, level.band_u_pressure, level.band_u_pressure_factor,
         level.band_p_extra, level.band_p_inverse, level.pre_restriction_rows,
         level.post_prolongation_rows, level.band_blocks, level.band_block_inverse,
         level.band_block_inverse_id, level.band_point_rows, level.traction.normal,
         level.traction.thin, level.traction.shear, level.traction.shear_candidates);
  for (auto& rule : level.traction.thin) rule.neighbors.shrink_to_fit();
}

namespace {

template <int Dim, typename Scalar>
Level<Dim, Scalar> level_of(const Lattice<Dim>& lattice, std::vector<CellType> cells,
                            const Material& material, double inertia,
                            std::vector<double> cell_weight, double dirichlet_zero_depth,
                            std::vector<std::uint8_t> dirichlet_wall_layers) {
  Level<Dim, Scalar> level;
  level.dirichlet_zero_depth = dirichlet_zero_depth;
  level.dirichlet_wall_layers = std::move(dirichlet_wall_layers);
  level.cell_weight = std::move(cell_weight);
  level.lattice = lattice;
  level.cells = std::move(cells);
  level.mu = static_cast<Scalar>(material.mu());
  level.lambda = static_cast<Scalar>(material.lambda());
  level.inertia = static_cast<Scalar>(inertia);
  return level;
}

// x and b, zero. r stays empty until a residual array is asked for (residual.hpp:
// ensure_residual_storage); the V-cycle needs none (residual_restriction.hpp). b is handed back
// whole until written (a load writes few of its fields, a coarse level's b is the restricted
// residual).
template <int Dim, typename Scalar>
void allocate_fields(Level<Dim, Scalar>& level, bool release_dead_pages) {
  const std::size_t n = level.size();
  for (int f = 0; f <= Dim; ++f) {
    for (auto* field : {&level.x[f], &level.b[f]}) assign_zeros_sparse(*field, n, level.live);
    if (release_dead_pages) release_zero_pages(level.b[f], level.live);
  }
}

// The band rows, their kernel and the traction rules from the level's variable codes; on a
// level of the cycle also the band's blocks, schedule and runs. pre and post: the Fig. 8 flags
// per variable (empty: none).
template <int Dim, typename Scalar>
void build_rows_and_rules(Level<Dim, Scalar>& level, const Material& material,
                          const BoundaryStress<Dim>& sigma, double inertia,
                          const FieldArray<std::uint8_t>& pre, const FieldArray<std::uint8_t>& post,
                          LevelUse use) {
  const RowBuilder<Dim> builder(level.lattice, level.cells, material.mu(), sigma, inertia,
                                level.cell_weight.empty() ? nullptr : &level.cell_weight,
                                level.dirichlet_zero_depth, &level.dirichlet_wall_layers);
  build_band_rows(level, builder, pre, post);
  build_band_kernel(level);
  level.blocks = partition_into_blocks(level.lattice);
  build_traction_rules(level, sigma);
  if (use == LevelUse::CYCLE) {
    build_band_blocks(level);
    build_band_schedule(level);
    build_band_runs(level);
    build_band_block_shapes(level);
  }
  shrink_band_arrays(level);
}

}  // namespace

template <int Dim, typename Scalar>
Level<Dim, Scalar> build_level(const Lattice<Dim>& lattice, std::vector<CellType> cells,
                               const Material& material, const BoundaryStress<Dim>& sigma,
                               const std::vector<CellType>* coarse_cells, double inertia,
                               int band_layers, std::vector<double> cell_weight,
                               double dirichlet_zero_depth,
                               std::vector<std::uint8_t> dirichlet_wall_layers,
                               bool release_dead_pages, LevelUse use) {
  Level<Dim, Scalar> level =
      level_of<Dim, Scalar>(lattice, std::move(cells), material, inertia, std::move(cell_weight),
                            dirichlet_zero_depth, std::move(dirichlet_wall_layers));
  const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(lattice.size());
  const Classifier<Dim> classifier{level.lattice, level.cells};
  level.codes.assign(static_cast<std::size_t>(n));
  for (std::ptrdiff_t k = 0; k < n; ++k) {
    for (int i = 0; i < Dim; ++i) level.codes.set_kind(i, k, classifier.face_kind(i, k));
    if (classifier.interior(k)) level.codes.set_kind(Dim, k, VarKind::INTERIOR);
  }
  mark_traction_variables(level);
  // Traction marking is the last change of INACTIVE: the live chunks are final here.
  if (release_dead_pages) level.live = find_live_chunks<Dim>(level.lattice, level.codes);
  allocate_fields(level, release_dead_pages);
  FieldArray<std::uint8_t> pre, post;
  allocate_zeroed(pre, static_cast<std::size_t>(Dim * n));
  allocate_zeroed(post, static_cast<std::size_t>(Dim * n));
  classify_relaxation(level, coarse_cells, pre, post, band_layers);
  build_rows_and_rules(level, material, sigma, inertia, pre, post, use);
  return level;
}

template <int Dim, typename Scalar>
Level<Dim, double> build_solution_level(const Level<Dim, Scalar>& finest, const Material& material,
                                        const BoundaryStress<Dim>& sigma, double inertia,
                                        bool release_dead_pages) {
  Level<Dim, double> level =
      level_of<Dim, double>(finest.lattice, finest.cells, material, inertia, finest.cell_weight,
                            finest.dirichlet_zero_depth, finest.dirichlet_wall_layers);
  level.codes.share_from(finest.codes);
  if (release_dead_pages) level.live = finest.live;
  allocate_fields(level, release_dead_pages);
  build_rows_and_rules(level, material, sigma, inertia, {}, {}, LevelUse::RESIDUAL);
  return level;
}

template <int Dim, typename Scalar>
void rebuild_band_sweep_data(Level<Dim, Scalar>& level) {
  const auto release = [](auto&... v) { ((v = std::remove_cvref_t<decltype(v)>()), ...); };
  release(level.band_blocks, level.band_block_inverse, level.band_block_inverse_id,
          level.band_point_rows, level.band_schedule, level.band_block_shapes);
  build_band_kernel(level);
  build_band_blocks(level);
  build_band_schedule(level);
  build_band_runs(level);
  build_band_block_shapes(level);
  shrink_band_arrays(level);
}

template <int Dim, typename Scalar>
void set_dirichlet_values(Level<Dim, Scalar>& level,
                          const std::function<Vec<Dim>(const Vec<Dim>&)>& displacement) {
  if (!displacement) return;
  for (int i = 0; i < Dim; ++i) {
    for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(level.size()); ++k) {
      if (level.kind(i, k) == VarKind::DIRICHLET)
        level.x[i][k] = static_cast<Scalar>(displacement(level.lattice.face_center(i, k))[i]);
    }
  }
}

template <int Dim, typename Scalar>
void record_zero_loads(Level<Dim, Scalar>& level, bool release_pages) {
  level.forget_zero_loads();
  for (int f = 0; f <= Dim; ++f) {
    level.zero_load[f] = zero_where_live(level.b[f], level.live);
    if (release_pages) level.zero_load_pages[f] = release_zero_pages(level.b[f], level.live);
  }
}

template <int Dim, typename Scalar>
std::size_t Level<Dim, Scalar>::zero_load_bytes(int field) const {
  std::size_t bytes = 0;
  for (const auto& [p0, p1] : zero_load_pages[field]) bytes += p1 - p0;
  return bytes;
}

#define MGELASTIC_INSTANTIATE(D, S)                                                             \
  template void record_zero_loads<D, S>(Level<D, S>&, bool);                                    \
  template void rebuild_band_sweep_data<D, S>(Level<D, S>&);                                    \
  template struct Level<D, S>;                                                                  \
  template Level<D, S> build_level<D, S>(                                                       \
      const Lattice<D>&, std::vector<CellType>, const Material&, const BoundaryStress<D>&,      \
      const std::vector<CellType>*, double, int, std::vector<double>, double,                   \
      std::vector<std::uint8_t>, bool, LevelUse);                                               \
  template Level<D, double> build_solution_level<D, S>(const Level<D, S>&, const Material&,     \
                                                       const BoundaryStress<D>&, double, bool); \
  template void set_dirichlet_values<D, S>(Level<D, S>&,                                        \
                                           const std::function<Vec<D>(const Vec<D>&)>&);
MGELASTIC_INSTANTIATE(2, float)
MGELASTIC_INSTANTIATE(2, double)
MGELASTIC_INSTANTIATE(3, float)
MGELASTIC_INSTANTIATE(3, double)
#undef MGELASTIC_INSTANTIATE

}  // namespace mgelastic::grid
