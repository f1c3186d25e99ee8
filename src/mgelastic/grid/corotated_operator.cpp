#include "mgelastic/grid/corotated_operator.hpp"

#include <omp.h>
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include "mgelastic/core/error.hpp"
#include "mgelastic/grid/residual.hpp"

namespace mgelastic::grid {
namespace {

struct Term {
  std::uint32_t variable;
  double coefficient;
};

// Sinks of the row builder: Row collects the terms of one equation; RowEvaluation applies
// them to the level's current x on the fly (the non-linear residual needs no stored rows).
struct Row {
  // A momentum row has up to ~450 raw terms (2 Dim stresses, each up to Dim^2 averaged
  // gradients); fixed storage keeps the builder's inner loop free of capacity checks.
  static constexpr int kCapacity = 1024;
  std::array<Term, kCapacity> terms;
  int count = 0;
  double constant = 0.0;
  void add(std::uint32_t variable, double coefficient) {
    if (count < kCapacity) terms[count++] = {variable, coefficient};
  }
  void clear() {
    count = 0;
    constant = 0.0;
  }
};

template <int Dim>
struct RowEvaluation {
  const Level<Dim, double>* level;
  double value = 0.0;  // row . x
  double constant = 0.0;
  void add(std::uint32_t variable, double coefficient) {
    value += coefficient * level->at(variable);
  }
  void clear() { value = constant = 0.0; }
};

// At most four lattice indices (the cells around an edge, the edges around a cell's face pair):
// no heap allocation in the row builder's inner loops.
struct Quad {
  std::array<std::ptrdiff_t, 4> items{};
  int count = 0;
  void push_back(std::ptrdiff_t k) { items[count++] = k; }
  bool empty() const { return count == 0; }
  std::size_t size() const { return static_cast<std::size_t>(count); }
  const std::ptrdiff_t* begin() const { return items.data(); }
  const std::ptrdiff_t* end() const { return items.data() + count; }
};

template <int Dim>
class CorotatedRowBuilder {
 public:
  CorotatedRowBuilder(const Level<Dim, double>& level, const std::vector<Matrix<Dim>>& rotations,
                      const BoundaryStress<Dim>& sigma, bool homogeneous,
                      CorotatedStress form = CorotatedStress::SYMMETRIZED)
      : m_level(level),
        m_lat(level.lattice),
        m_rot(rotations),
        m_sigma(sigma),
        m_homogeneous(homogeneous),
        m_symmetrized(form == CorotatedStress::SYMMETRIZED),
        m_mu(level.mu),
        m_inv_h(1.0 / level.lattice.h) {}

  // P_ii at a cell and P_ij at an (i, j) edge for the level's current x, exactly as a momentum
  // row adds them (traction values included).
  double normal_stress(int i, std::ptrdiff_t cell) const {
    RowEvaluation<Dim> stress{&m_level};
    add_normal_stress(i, cell, 1.0, stress);
    return stress.value + stress.constant;
  }
  double shear_stress(int i, int j, std::ptrdiff_t edge) const {
    RowEvaluation<Dim> stress{&m_level};
    add_shear_stress(i, j, edge, 1.0, stress);
    return stress.value + stress.constant;
  }

  template <typename Sink>
  void momentum(int i, std::ptrdiff_t k, Sink& row) const {
    row.clear();
    const std::ptrdiff_t si = m_lat.stride(i);
    add_normal_stress(i, k, m_inv_h, row);
    add_normal_stress(i, k - si, -m_inv_h, row);
    for (int j = 0; j < Dim; ++j) {
      if (j == i) continue;
      add_shear_stress(i, j, k + m_lat.stride(j), m_inv_h, row);
      add_shear_stress(i, j, k, -m_inv_h, row);
    }
    if (m_level.inertia != 0.0) row.add(u(i, k), -m_level.inertia);
  }

  template <typename Sink>
  void pressure(std::ptrdiff_t c, Sink& row) const {
    row.clear();
    const double lambda = m_level.lambda;
    if (lambda <= 0) {  // incompressibility term absent: p is identically zero
      row.add(u(Dim, c), 1.0);
      return;
    }
    const Matrix<Dim>& r = m_rot[c];
    for (int i = 0; i < Dim; ++i) {
      const std::ptrdiff_t si = m_lat.stride(i);
      if (const auto where = traction_face(i, c)) {
        // mu R_ii G_ii with 2 mu G_ii = sigma - 2 mu (1 - R_ii) + mu R_ii p (P_ii = sigma).
        row.add(u(Dim, c), 0.5 * m_mu * r(i, i) * r(i, i));
        if (!m_homogeneous)
          row.constant += 0.5 * r(i, i) * (sigma(i, i, *where) - 2 * m_mu * (1 - r(i, i)));
      } else {
        row.add(u(i, c + si), m_mu * r(i, i) * m_inv_h);
        row.add(u(i, c), -m_mu * r(i, i) * m_inv_h);
      }
      for (int j = 0; j < Dim; ++j) {
        if (j != i) add_cell_shear_gradient(i, j, c, row);
      }
    }
    row.add(u(Dim, c), m_mu * m_mu / lambda);
    if (!m_homogeneous) row.constant -= m_mu * (Dim - r.trace());
  }

  // Where the traction condition fixing P_ii of `cell` holds (explicit_rows.cpp), or none.
  std::optional<Vec<Dim>> traction_face(int i, std::ptrdiff_t cell) const {
    const std::ptrdiff_t si = m_lat.stride(i);
    const bool lower = exterior(cell - si), upper = exterior(cell + si);
    if (lower && upper) return m_lat.cell_center(cell);
    if (lower) return m_lat.face_center(i, cell);
    if (upper) return m_lat.face_center(i, cell + si);
    return std::nullopt;
  }

  // Interior cells incident to edge (i, j) at e, or none when one of them is exterior.
  std::optional<Quad> edge_cells(int i, int j, std::ptrdiff_t e) const {
    const std::ptrdiff_t si = m_lat.stride(i), sj = m_lat.stride(j);
    Quad cells;
    for (std::ptrdiff_t c : {e, e - si, e - sj, e - si - sj}) {
      if (m_level.cells[c] == CellType::EXTERIOR) return std::nullopt;
      if (m_level.cells[c] == CellType::INTERIOR) cells.push_back(c);
    }
    return cells;
  }

 private:
  std::uint32_t u(int field, std::ptrdiff_t k) const { return m_level.global(field, k); }
  double sigma(int i, int j, const Vec<Dim>& x) const {
    return m_sigma && !m_homogeneous ? m_sigma(i, j, x) : 0.0;
  }
  bool exterior(std::ptrdiff_t c) const { return m_level.cells[c] == CellType::EXTERIOR; }
  bool known(int axis, std::ptrdiff_t k) const {
    const VarKind kind = m_level.kind(axis, k);
    return kind == VarKind::INTERIOR || kind == VarKind::DIRICHLET;
  }

  // weight * P_ii(cell), P_ii = 2 mu G_ii + 2 mu (1 - R_ii) - mu R_ii p.
  template <typename Sink>
  void add_normal_stress(int i, std::ptrdiff_t cell, double weight, Sink& row) const {
    if (const auto where = traction_face(i, cell)) {
      row.constant += weight * sigma(i, i, *where);
      return;
    }
    if (m_symmetrized) {
      add_symmetrized_stress(i, i, m_rot[cell], weight, row, [&](int a, int b, double w) {
        add_cell_gradient(a, b, cell, w, row);
      });
      row.add(u(Dim, cell), -weight * m_mu * m_rot[cell](i, i));
      return;
    }
    const double rii = m_rot[cell](i, i);
    row.add(u(i, cell + m_lat.stride(i)), weight * 2 * m_mu * m_inv_h);
    row.add(u(i, cell), -weight * 2 * m_mu * m_inv_h);
    row.add(u(Dim, cell), -weight * m_mu * rii);
    if (!m_homogeneous) row.constant += weight * 2 * m_mu * (1 - rii);
  }

  // weight * P_ij(edge), P_ij = 2 mu G_ij - 2 mu <R_ij> - mu <R_ij p> (edge means).
  template <typename Sink>
  void add_shear_stress(int i, int j, std::ptrdiff_t e, double weight, Sink& row) const {
    const auto cells = edge_cells(i, j, e);
    if (!cells) {
      row.constant += weight * sigma(i, j, m_lat.edge_center(i, j, e));
      return;
    }
    if (cells->empty()) return;  // an edge between Dirichlet cells only: never a row's stress
    if (m_symmetrized) {
      Matrix<Dim> mean = Matrix<Dim>::Zero();
      for (std::ptrdiff_t c : *cells) mean += m_rot[c];
      mean /= static_cast<double>(cells->size());
      add_symmetrized_stress(i, j, mean, weight, row, [&](int a, int b, double w) {
        add_edge_gradient(a, b, i, j, e, w, row);
      });
      const double share = weight / static_cast<double>(cells->size());
      for (std::ptrdiff_t c : *cells) row.add(u(Dim, c), -share * m_mu * m_rot[c](i, j));
      return;
    }
    row.add(u(i, e), weight * 2 * m_mu * m_inv_h);
    row.add(u(i, e - m_lat.stride(j)), -weight * 2 * m_mu * m_inv_h);
    const double share = weight / static_cast<double>(cells->size());
    for (std::ptrdiff_t c : *cells) {
      const double rij = m_rot[c](i, j);
      row.add(u(Dim, c), -share * m_mu * rij);
      if (!m_homogeneous) row.constant -= share * 2 * m_mu * rij;
    }
  }

  // weight * (mu G_ij + mu (R G^T R)_ij + mu ((I - R)^2)_ij), the p-free part of the symmetrized
  // stress mu R (R^T F + F^T R - 2 I) - mu p R; `gradient(a, b, w)` adds w G_ab at the location.
  template <typename Sink, typename Gradient>
  void add_symmetrized_stress(int i, int j, const Matrix<Dim>& r, double weight, Sink& row,
                              const Gradient& gradient) const {
    for (int a = 0; a < Dim; ++a)
      for (int b = 0; b < Dim; ++b) {
        // (R G^T R)_ij = sum_ab R_ia G_ba R_bj.
        // Zero coefficients too (R = I has many): the rows keep one pattern for every R, so a
        // refresh rewrites values only.
        double c = r(i, a) * r(b, j);
        if (b == i && a == j) c += 1.0;
        gradient(b, a, weight * m_mu * c);
      }
    if (!m_homogeneous) {
      const Matrix<Dim> d = Matrix<Dim>::Identity() - r;
      row.constant += weight * m_mu * (d * d)(i, j);
    }
  }

  // w G_ab at the center of cell c. A diagonal gradient across a traction face follows from
  // P_aa = sigma (2 mu G_aa = sigma - 2 mu (1 - R_aa) + mu R_aa p); an off-diagonal one is the
  // mean over the cell's edges with known faces, or its rigid value R_ab without any.
  template <typename Sink>
  void add_cell_gradient(int a, int b, std::ptrdiff_t c, double w, Sink& row) const {
    const std::ptrdiff_t sa = m_lat.stride(a);
    if (a == b) {
      const auto where =
          m_level.cells[c] == CellType::INTERIOR ? traction_face(a, c) : std::nullopt;
      if (!where) {
        row.add(u(a, c + sa), w * m_inv_h);
        row.add(u(a, c), -w * m_inv_h);
        return;
      }
      const double raa = m_rot[c](a, a);
      row.add(u(Dim, c), 0.5 * w * raa);
      if (!m_homogeneous) row.constant += w * (sigma(a, a, *where) / (2 * m_mu) - (1 - raa));
      return;
    }
    const std::ptrdiff_t sb = m_lat.stride(b);
    Quad edges;
    for (std::ptrdiff_t e : {c, c + sa, c + sb, c + sa + sb})
      if (known(a, e) && known(a, e - sb)) edges.push_back(e);
    if (edges.empty()) {
      if (!m_homogeneous) row.constant += w * m_rot[c](a, b);
      return;
    }
    const double share = w * m_inv_h / static_cast<double>(edges.size());
    for (std::ptrdiff_t e : edges) {
      row.add(u(a, e), share);
      row.add(u(a, e - sb), -share);
    }
  }

  // w G_ab at the (i, j) edge e (all incident cells non-exterior): natural for {a, b} = {i, j};
  // diagonal ones averaged over the incident cells; the others (3D, with the third axis t)
  // averaged over the four (a, b) edges around, those with known faces.
  template <typename Sink>
  void add_edge_gradient(int a, int b, int i, int j, std::ptrdiff_t e, double w, Sink& row) const {
    const std::ptrdiff_t sb = m_lat.stride(b);
    if (a == b) {
      const std::ptrdiff_t si = m_lat.stride(i), sj = m_lat.stride(j);
      const double share = w / 4.0;
      for (std::ptrdiff_t c : {e, e - si, e - sj, e - si - sj})
        add_cell_gradient(a, a, c, share, row);
      return;
    }
    if ((a == i && b == j) || (a == j && b == i)) {
      row.add(u(a, e), w * m_inv_h);
      row.add(u(a, e - sb), -w * m_inv_h);
      return;
    }
    // {a, b} shares one axis with {i, j}; `other` is the axis of {i, j} not in {a, b}, t the
    // third axis: move from face to center along `other`... the (a, b) edges at e, e - s_other,
    // e + s_t, e - s_other + s_t surround the (i, j) edge center.
    const int other = (a == i || b == i) ? j : i;
    const int t = 3 - i - j;
    const std::ptrdiff_t so = m_lat.stride(other), st = m_lat.stride(t);
    Quad edges;
    for (std::ptrdiff_t m : {e, e - so, e + st, e - so + st})
      if (known(a, m) && known(a, m - sb)) edges.push_back(m);
    if (edges.empty()) {
      if (!m_homogeneous) row.constant += w * m_rot[e](a, b);
      return;
    }
    const double share = w * m_inv_h / static_cast<double>(edges.size());
    for (std::ptrdiff_t m : edges) {
      row.add(u(a, m), share);
      row.add(u(a, m - sb), -share);
    }
  }

  // mu R_ij(c) <G_ij> over the cell's edges whose two u_i faces are known variables; with none
  // (one-cell-thin features) G_ij is frozen at its rigid value R_ij.
  template <typename Sink>
  void add_cell_shear_gradient(int i, int j, std::ptrdiff_t c, Sink& row) const {
    const std::ptrdiff_t si = m_lat.stride(i), sj = m_lat.stride(j);
    const double rij = m_rot[c](i, j);
    Quad edges;
    for (std::ptrdiff_t e : {c, c + si, c + sj, c + si + sj})
      if (known(i, e) && known(i, e - sj)) edges.push_back(e);
    if (edges.empty()) {
      if (!m_homogeneous) row.constant += m_mu * rij * rij;
      return;
    }
    const double w = m_mu * rij * m_inv_h / static_cast<double>(edges.size());
    for (std::ptrdiff_t e : edges) {
      row.add(u(i, e), w);
      row.add(u(i, e - sj), -w);
    }
  }

  const Level<Dim, double>& m_level;
  const Lattice<Dim>& m_lat;
  const std::vector<Matrix<Dim>>& m_rot;
  const BoundaryStress<Dim>& m_sigma;
  bool m_homogeneous, m_symmetrized;
  double m_mu, m_inv_h;
};

// Sums a row's repeated variables (a stress location shared by several terms) with a dense
// hash table and emits them in increasing variable order. One per thread, kept between builds
// (slots are emptied after use).
class RowCompressor {
 public:
  void compress(const Row& row, std::vector<std::uint32_t>& column, std::vector<double>& value) {
    if (row.count >= Row::kCapacity)
      throw std::logic_error("co-rotated row builder: more than Row::kCapacity terms");
    // Open addressing in a small table (L1-resident): a row has ~60 distinct variables.
    m_touched.clear();
    for (int t = 0; t < row.count; ++t) {
      const Term& term = row.terms[t];
      std::uint32_t slot = (term.variable * 2654435761u) >> (32 - kBits);
      while (m_key[slot] != kEmpty && m_key[slot] != term.variable) slot = (slot + 1) & kMask;
      if (m_key[slot] == kEmpty) {
        m_key[slot] = term.variable;
        m_sum[slot] = 0.0;
        m_touched.push_back(slot);
      }
      m_sum[slot] += term.coefficient;
    }
    std::sort(m_touched.begin(), m_touched.end(),
              [&](std::uint32_t a, std::uint32_t b) { return m_key[a] < m_key[b]; });
    for (std::uint32_t slot : m_touched) {
      column.push_back(m_key[slot]);
      value.push_back(m_sum[slot]);
      m_key[slot] = kEmpty;
    }
  }

 private:
  static constexpr int kBits = 11;  // 2048 slots for at most Row::kCapacity distinct variables
  static constexpr std::uint32_t kMask = (1u << kBits) - 1;
  static constexpr std::uint32_t kEmpty = ~0u;
  std::array<std::uint32_t, 1u << kBits> m_key = make_empty();
  std::array<double, 1u << kBits> m_sum{};
  std::vector<std::uint32_t> m_touched;
  static std::array<std::uint32_t, 1u << kBits> make_empty() {
    std::array<std::uint32_t, 1u << kBits> keys;
    keys.fill(kEmpty);
    return keys;
  }
};

// Interior variables in lattice order, all variables of one location together (a front-like
// Gauss-Seidel order for the box smoother).
template <int Dim>
void row_targets(const Level<Dim, double>& level, std::vector<std::uint32_t>& targets) {
  targets.clear();
  const auto n = static_cast<std::ptrdiff_t>(level.size());
  for (std::ptrdiff_t k = 0; k < n; ++k)
    for (int field = 0; field <= Dim; ++field)
      if (level.kind(field, k) == VarKind::INTERIOR) targets.push_back(level.global(field, k));
}

template <int Dim, typename Sink>
void build_row(const CorotatedRowBuilder<Dim>& builder, std::uint32_t target, std::size_t n,
               Sink& row) {
  const int field = static_cast<int>(target / n);
  const auto k = static_cast<std::ptrdiff_t>(target % n);
  if (field < Dim)
    builder.momentum(field, k, row);
  else
    builder.pressure(k, row);
}

}  // namespace

double CorotatedRows::coefficient(std::size_t row, std::uint32_t variable) const {
  for (std::uint32_t e = start[row]; e < start[row + 1]; ++e)
    if (column[e] == variable) return value[e];
  return 0.0;
}

namespace {

// One row built and compressed, per thread (kept between rows and builds). Reached through
// of_this_thread() inside the loops: a function-scope thread_local named in an OpenMP loop was
// the encountering thread's instance for every thread (a race on the compressor's table).
template <int Dim>
struct RowScratch {
  RowCompressor compressor;
  Row row;
  std::vector<std::uint32_t> columns;
  std::vector<double> values;
  static RowScratch& of_this_thread() {
    thread_local RowScratch scratch;
    return scratch;
  }
  void build(const CorotatedRowBuilder<Dim>& builder, std::uint32_t target, std::size_t n) {
    build_row(builder, target, n, row);
    columns.clear();
    values.clear();
    compressor.compress(row, columns, values);
  }
};

}  // namespace

template <int Dim>
void build_corotated_rows(const Level<Dim, double>& level,
                          const std::vector<Matrix<Dim>>& rotations,
                          const BoundaryStress<Dim>& sigma, bool homogeneous, CorotatedStress form,
                          CorotatedRows& rows) {
  const CorotatedRowBuilder<Dim> builder(level, rotations, sigma, homogeneous, form);
  const std::size_t n = level.size();
  // Every array is refilled in place: a refresh rebuilds the rows of every level, and fresh
  // storage cost more in page faults than the build itself.
  row_targets(level, rows.target);
  rows.row_of.assign((Dim + 1) * n, -1);
  const auto count = static_cast<std::ptrdiff_t>(rows.target.size());
  for (std::ptrdiff_t m = 0; m < count; ++m)
    rows.row_of[rows.target[m]] = static_cast<std::int32_t>(m);
  rows.constant.resize(count);
  // Rows are independent: each is built and compressed on its own and written straight to its
  // place (no thread keeps a copy of the rows; the result does not depend on the thread count).
  // A refresh changes only the values, so where the arrays already hold every row's columns one
  // pass writes the values; otherwise one pass counts each row's entries and a second writes
  // them at their offsets.
  bool same_columns = rows.start.size() == static_cast<std::size_t>(count) + 1 && count > 0;
  if (same_columns) {
#pragma omp parallel for schedule(static) reduction(&& : same_columns)
    for (std::ptrdiff_t m = 0; m < count; ++m) {
      RowScratch<Dim>& scratch = RowScratch<Dim>::of_this_thread();
      scratch.build(builder, rows.target[m], n);
      const std::uint32_t begin = rows.start[m];
      if (rows.start[m + 1] - begin != scratch.columns.size() ||
          !std::equal(scratch.columns.begin(), scratch.columns.end(),
                      rows.column.begin() + begin)) {
        same_columns = false;
        continue;
      }
      std::copy(scratch.values.begin(), scratch.values.end(), rows.value.begin() + begin);
      rows.constant[m] = scratch.row.constant;
    }
    if (same_columns) return;
  }
  rows.start.assign(count + 1, 0);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t m = 0; m < count; ++m) {
    RowScratch<Dim>& scratch = RowScratch<Dim>::of_this_thread();
    scratch.build(builder, rows.target[m], n);
    rows.start[m + 1] = static_cast<std::uint32_t>(scratch.columns.size());
  }
  std::size_t total = 0;
  for (std::ptrdiff_t m = 0; m < count; ++m) {
    total += rows.start[m + 1];
    if (total > UINT32_MAX)
      throw Error("co-rotated rows: more than 2^32 entries on a level of " + std::to_string(n) +
                  " lattice points");
    rows.start[m + 1] = static_cast<std::uint32_t>(total);
  }
  rows.column.resize(total);
  rows.value.resize(total);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t m = 0; m < count; ++m) {
    RowScratch<Dim>& scratch = RowScratch<Dim>::of_this_thread();
    scratch.build(builder, rows.target[m], n);
    std::copy(scratch.columns.begin(), scratch.columns.end(), rows.column.begin() + rows.start[m]);
    std::copy(scratch.values.begin(), scratch.values.end(), rows.value.begin() + rows.start[m]);
    rows.constant[m] = scratch.row.constant;
  }
}

template <int Dim>
CorotatedRows build_corotated_rows(const Level<Dim, double>& level,
                                   const std::vector<Matrix<Dim>>& rotations,
                                   const BoundaryStress<Dim>& sigma, bool homogeneous,
                                   CorotatedStress form) {
  CorotatedRows rows;
  build_corotated_rows(level, rotations, sigma, homogeneous, form, rows);
  return rows;
}

// Each stress is evaluated once (a momentum row reads 2 Dim of them, each shared by two rows),
// at the locations next to an interior face: P_ii at cells, P_ij at (i, j) edges.
template <int Dim>
double corotated_residual(Level<Dim, double>& level, const std::vector<Matrix<Dim>>& rotations,
                          const BoundaryStress<Dim>& sigma, bool homogeneous, CorotatedStress form,
                          CorotatedResidualScratch<Dim>* scratch) {
  const CorotatedRowBuilder<Dim> builder(level, rotations, sigma, homogeneous, form);
  const auto& lat = level.lattice;
  const auto n = static_cast<std::ptrdiff_t>(level.size());
  const double inv_h = 1.0 / lat.h;
  auto interior = [&](int i, std::ptrdiff_t k) { return level.kind(i, k) == VarKind::INTERIOR; };
  CorotatedResidualScratch<Dim> local;
  if (!scratch) scratch = &local;
  // [i * Dim + j][location]: written at the same locations on every call (the level's kinds),
  // zero elsewhere since their allocation.
  auto& stress = scratch->stress;
  if (stress[0].size() != static_cast<std::size_t>(n)) {
    for (auto& field : stress) allocate_zeroed(field, static_cast<std::size_t>(n));
    row_targets(level, scratch->targets);
  }
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t k = 0; k < n; ++k)
    for (int i = 0; i < Dim; ++i) {
      const std::ptrdiff_t si = lat.stride(i);
      if (interior(i, k) || (k + si < n && interior(i, k + si)))
        stress[i * Dim + i][k] = builder.normal_stress(i, k);
      for (int j = 0; j < Dim; ++j) {
        const std::ptrdiff_t sj = lat.stride(j);
        if (j != i && (interior(i, k) || (k >= sj && interior(i, k - sj))))
          stress[i * Dim + j][k] = builder.shear_stress(i, j, k);
      }
    }
  ensure_residual_storage(level);
  for (auto& field : level.r) zero_live(field, level.live);
  const std::vector<std::uint32_t>& targets = scratch->targets;
  const auto count = static_cast<std::ptrdiff_t>(targets.size());
  const GlobalSplit<Dim> split = level.split();
#pragma omp parallel
  {
    RowEvaluation<Dim> row{&level};
#pragma omp for schedule(static)
    for (std::ptrdiff_t m = 0; m < count; ++m) {
      const std::uint32_t t = targets[m];
      const int i = split.field(t);
      const auto k = static_cast<std::ptrdiff_t>(split.index(t, i));
      double lhs;
      if (i < Dim) {
        const auto& p = stress;
        double divergence = p[i * Dim + i][k] - p[i * Dim + i][k - lat.stride(i)];
        for (int j = 0; j < Dim; ++j)
          if (j != i) divergence += p[i * Dim + j][k + lat.stride(j)] - p[i * Dim + j][k];
        lhs = inv_h * divergence - level.inertia * level.x[i][k];
      } else {
        builder.pressure(k, row);
        lhs = row.value + row.constant;
      }
      level.r[i][k] = level.b[i][k] - lhs;
    }
  }
  // Summed in row order: the same norm for every thread count.
  double sum = 0.0;
  for (std::uint32_t t : targets)
    if (split.field(t) < Dim || level.lambda > 0) sum += split(level.r, t) * split(level.r, t);
  return std::sqrt(sum);
}

template <int Dim>
std::optional<double> corotated_stress(const Level<Dim, double>& level,
                                       const std::vector<Matrix<Dim>>& rotations,
                                       const BoundaryStress<Dim>& sigma, int i, int j,
                                       std::ptrdiff_t location, CorotatedStress form) {
  const CorotatedRowBuilder<Dim> builder(level, rotations, sigma, false, form);
  if (i == j) {
    if (builder.traction_face(i, location)) return std::nullopt;
    return builder.normal_stress(i, location);
  }
  const auto cells = builder.edge_cells(i, j, location);
  if (!cells || cells->empty()) return std::nullopt;
  return builder.shear_stress(i, j, location);
}

template <int Dim>
double corotated_residual(Level<Dim, double>& level, const CorotatedRows& rows) {
  ensure_residual_storage(level);
  for (auto& field : level.r) zero_live(field, level.live);
  const auto count = static_cast<std::ptrdiff_t>(rows.rows());
  const GlobalSplit<Dim> split = level.split();
  double sum = 0.0;
  for (std::ptrdiff_t m = 0; m < count; ++m) {
    double value = rows.constant[m];
    for (std::uint32_t e = rows.start[m]; e < rows.start[m + 1]; ++e)
      value += rows.value[e] * level.at(rows.column[e]);
    const std::uint32_t t = rows.target[m];
    const double r = split(level.b, t) - value;
    split(level.r, t) = r;
    if (split.field(t) < Dim || level.lambda > 0) sum += r * r;
  }
  return std::sqrt(sum);
}

template <int Dim>
void corotated_back_substitute(Level<Dim, double>& level, const std::vector<Matrix<Dim>>& rotations,
                               const BoundaryStress<Dim>& sigma, bool homogeneous) {
  const auto& lat = level.lattice;
  const double h = lat.h, mu = level.mu;
  const std::size_t n = level.size();
  auto normal_gradient = [&](std::uint32_t cell_global, int i, double s) {
    const double rii = rotations[cell_global % n](i, i);
    const double p = level.at(cell_global);
    return homogeneous ? 0.5 * rii * p : (s - 2 * mu * (1 - rii) + mu * rii * p) / (2 * mu);
  };
  for (const auto& rule : level.traction.normal) {
    const int i = static_cast<int>(rule.face / n);
    level.at(rule.face) =
        level.at(rule.partner) + rule.sign * h * normal_gradient(rule.cell, i, rule.sigma);
  }
  for (const auto& rule : level.traction.thin) {
    const int i = static_cast<int>(rule.lower / n);
    double mean = 0;
    for (std::uint32_t nb : rule.neighbors) mean += level.at(nb);
    if (!rule.neighbors.empty()) mean /= static_cast<double>(rule.neighbors.size());
    const double half_jump = 0.5 * h * normal_gradient(rule.cell, i, rule.sigma);
    level.at(rule.lower) = mean - half_jump;
    level.at(rule.upper) = mean + half_jump;
  }
  for (const auto& rule : level.traction.shear) {
    const int i = static_cast<int>(rule.face / n);
    double sum = 0;
    for (const auto& c : level.traction.candidates(rule)) {
      // P_ij = sigma at the edge between face and partner: G_ij = sigma / (2 mu) + <R_ij> +
      // <R_ij p> / 2 over the edge's interior cells.
      const int j = static_cast<int>(c.plus / n);
      const std::ptrdiff_t edge = c.plus % n;
      double g = 0;
      if (!homogeneous && sigma) g += sigma(i, j, lat.edge_center(i, j, edge)) / (2 * mu);
      const std::ptrdiff_t si = lat.stride(i), sj = lat.stride(j);
      int count = 0;
      double rotation = 0, rotated_pressure = 0;
      for (std::ptrdiff_t cell : {edge, edge - si, edge - sj, edge - si - sj}) {
        if (level.cells[cell] != CellType::INTERIOR) continue;
        rotation += rotations[cell](i, j);
        rotated_pressure += rotations[cell](i, j) * level.x[Dim][cell];
        ++count;
      }
      if (count > 0) {
        g += 0.5 * rotated_pressure / count;
        if (!homogeneous) g += rotation / count;
      }
      sum += level.at(c.partner) - c.sign * h * g;
    }
    level.at(rule.face) = sum / static_cast<double>(rule.count);
  }
}

#define MGELASTIC_INSTANTIATE(D)                                                                   \
  template CorotatedRows build_corotated_rows<D>(const Level<D, double>&,                          \
                                                 const std::vector<Matrix<D>>&,                    \
                                                 const BoundaryStress<D>&, bool, CorotatedStress); \
  template double corotated_residual<D>(Level<D, double>&, const CorotatedRows&);                  \
  template std::optional<double> corotated_stress<D>(                                              \
      const Level<D, double>&, const std::vector<Matrix<D>>&, const BoundaryStress<D>&, int, int,  \
      std::ptrdiff_t, CorotatedStress);                                                            \
  template double corotated_residual<D>(Level<D, double>&, const std::vector<Matrix<D>>&,          \
                                        const BoundaryStress<D>&, bool, CorotatedStress,           \
                                        CorotatedResidualScratch<D>*);                             \
  template void build_corotated_rows<D>(const Level<D, double>&, const std::vector<Matrix<D>>&,    \
                                        const BoundaryStress<D>&, bool, CorotatedStress,           \
                                        CorotatedRows&);                                           \
  template void corotated_back_substitute<D>(Level<D, double>&, const std::vector<Matrix<D>>&,     \
                                             const BoundaryStress<D>&, bool);
MGELASTIC_INSTANTIATE(2)
MGELASTIC_INSTANTIATE(3)
#undef MGELASTIC_INSTANTIATE

}  // namespace mgelastic::grid
