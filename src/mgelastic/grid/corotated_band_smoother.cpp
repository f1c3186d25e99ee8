#include "mgelastic/grid/corotated_band_smoother.hpp"

#include <Eigen/Dense>
#include <cmath>

namespace mgelastic::grid {
namespace {

// One row scattered into a dense array over all variables, so the Schur entries of a row cost
// one read per term instead of a search of the row (the blocks need (2d)^2 of them per cell).
class DenseRow {
 public:
  DenseRow(const CorotatedRows& rows, std::size_t variables) : m_rows(rows), m_value(variables) {}
  void load(std::uint32_t m) {
    unload();
    m_loaded = m;
    for (std::uint32_t e = m_rows.start[m]; e < m_rows.start[m + 1]; ++e)
      m_value[m_rows.column[e]] += m_rows.value[e];
  }
  double operator[](std::uint32_t variable) const { return m_value[variable]; }

 private:
  void unload() {
    if (m_loaded == UINT32_MAX) return;
    for (std::uint32_t e = m_rows.start[m_loaded]; e < m_rows.start[m_loaded + 1]; ++e)
      m_value[m_rows.column[e]] = 0;
  }
  const CorotatedRows& m_rows;
  std::vector<double> m_value;
  std::uint32_t m_loaded = UINT32_MAX;
};

}  // namespace

// Field pointers and the smoother's data, so the inner loops read x without vector indirection.
template <int Dim>
struct CorotatedBandSmoother<Dim>::Sweep {
  const CorotatedBandSmoother& smoother;
  const CorotatedRows& rows;
  std::uint32_t n;
  std::array<double*, Dim + 1> x;
  std::array<const double*, Dim + 1> b;

  Sweep(const CorotatedBandSmoother& s, const CorotatedRows& r, Level<Dim, double>& level)
      : smoother(s), rows(r), n(static_cast<std::uint32_t>(level.size())) {
    for (int f = 0; f <= Dim; ++f) {
      x[f] = level.x[f].data();
      b[f] = level.b[f].data();
    }
  }
  double& at(std::uint32_t v) const { return GlobalSplit<Dim>{n}(x, v); }

  double residual(std::uint32_t m) const {
    double value = rows.constant[m];
    for (std::uint32_t e = rows.start[m]; e < rows.start[m + 1]; ++e)
      value += rows.value[e] * at(rows.column[e]);
    const std::uint32_t t = rows.target[m];
    return GlobalSplit<Dim>{n}(b, t) - value;
  }

  // Moves the row's variable and keeps the eliminated pressures exact.
  void move(std::uint32_t m, double delta) const {
    at(rows.target[m]) += delta;
    for (std::uint32_t e = smoother.m_factor_start[m]; e < smoother.m_factor_start[m + 1]; ++e)
      at(smoother.m_factor_variable[e]) -= smoother.m_factor[e] * delta;
  }

  void relax_row(std::uint32_t m) const {
    const double inverse = smoother.m_inverse_pivot[m];
    if (inverse != 0) move(m, residual(m) * inverse);
  }

  // The band faces of one eliminated cell together: delta = S_loc^-1 r.
  void relax_block(std::uint32_t block) const {
    const auto& members = smoother.m_blocks[block];
    std::array<double, B> r{};
    for (int a = 0; a < B && members[a] != UINT32_MAX; ++a) r[a] = residual(members[a]);
    const double* inverse = smoother.m_block_inverse.data() + std::size_t{block} * B * B;
    for (int a = 0; a < B && members[a] != UINT32_MAX; ++a) {
      double delta = 0;
      for (int c = 0; c < B; ++c) delta += inverse[a * B + c] * r[c];
      move(members[a], delta);
    }
  }
};

template <int Dim>
CorotatedBandSmoother<Dim>::CorotatedBandSmoother(const Level<Dim, double>& level,
                                                  const CorotatedRows& rows) {
  build_pressures(level, rows);
  build_factors(level, rows);
  build_schedule(level, rows);
}

// Band membership from the linear level's classification: its band momentum rows and its
// eliminated pressures (decision 1 of docs/grid-engine.md "Smoothing" holds for R != I too).
template <int Dim>
void CorotatedBandSmoother<Dim>::build_pressures(const Level<Dim, double>& level,
                                                 const CorotatedRows& rows) {
  const auto n = static_cast<std::uint32_t>(level.size());
  m_in_band.assign(rows.rows(), 0);
  m_pressure_slot.assign(rows.rows(), -1);
  for (std::uint32_t m = 0; m < rows.rows(); ++m) {
    const std::uint32_t t = rows.target[m];
    const std::uint32_t field = t / n;
    if (level.relaxation(field, t % n) == Relaxation::DISTRIBUTIVE) continue;
    if (field < static_cast<std::uint32_t>(Dim)) {
      m_in_band[m] = 1;
      ++m_band_rows;
      continue;
    }
    const double diagonal = rows.coefficient(m, t);
    if (!std::isfinite(diagonal) || diagonal == 0) continue;  // left as it is: never Inf
    m_pressure_slot[m] = static_cast<std::int32_t>(m_pressure_rows.size());
    m_pressure_rows.push_back(m);
    m_pressure_inverse.push_back(1.0 / diagonal);
  }
}

// Per band row f, the eliminated pressures whose rows read u_f, with G'_cf / D_c (counting sort
// of the transposed pressure rows), then the Schur pivots 1 / S_ff.
template <int Dim>
void CorotatedBandSmoother<Dim>::build_factors(const Level<Dim, double>& level,
                                               const CorotatedRows& rows) {
  const std::size_t count = rows.rows();
  const auto band_row = [&](std::uint32_t e) -> std::int32_t {
    const std::int32_t b = rows.row_of[rows.column[e]];
    return b >= 0 && m_in_band[b] ? b : -1;
  };
  m_factor_start.assign(count + 1, 0);
  for (std::uint32_t m : m_pressure_rows)
    for (std::uint32_t e = rows.start[m]; e < rows.start[m + 1]; ++e)
      if (const std::int32_t b = band_row(e); b >= 0) ++m_factor_start[b + 1];
  for (std::size_t m = 0; m < count; ++m) m_factor_start[m + 1] += m_factor_start[m];
  m_factor_variable.resize(m_factor_start.back());
  m_factor.resize(m_factor_start.back());
  std::vector<std::uint32_t> fill(m_factor_start.begin(), m_factor_start.end() - 1);
  for (std::size_t s = 0; s < m_pressure_rows.size(); ++s) {
    const std::uint32_t m = m_pressure_rows[s];
    for (std::uint32_t e = rows.start[m]; e < rows.start[m + 1]; ++e)
      if (const std::int32_t b = band_row(e); b >= 0) {
        m_factor_variable[fill[b]] = rows.target[m];
        m_factor[fill[b]++] = rows.value[e] * m_pressure_inverse[s];
      }
  }
  m_inverse_pivot.assign(count, 0.0);
  DenseRow row(rows, (Dim + 1) * level.size());
  for (std::uint32_t m = 0; m < count; ++m) {
    if (!m_in_band[m]) continue;
    row.load(m);
    const double pivot = schur_entry(row, rows, m);
    // A vanishing or non-finite pivot (degenerate rotations) leaves the row as it is.
    if (std::isfinite(pivot) && pivot != 0) m_inverse_pivot[m] = 1.0 / pivot;
  }
}

// S_ab = A_ab - sum_c G_ac G'_cb / D_c over the eliminated pressures that u_b moves; `row_a`
// holds row a.
template <int Dim>
template <typename DenseRow>
double CorotatedBandSmoother<Dim>::schur_entry(const DenseRow& row_a, const CorotatedRows& rows,
                                               std::uint32_t b) const {
  double value = row_a[rows.target[b]];
  for (std::uint32_t e = m_factor_start[b]; e < m_factor_start[b + 1]; ++e)
    value -= row_a[m_factor_variable[e]] * m_factor[e];
  return value;
}

// The linear level's band schedule (band_u rows and eliminated-cell blocks) in co-rotated rows;
// a block whose Schur block is singular is relaxed point-wise instead.
template <int Dim>
void CorotatedBandSmoother<Dim>::build_schedule(const Level<Dim, double>& level,
                                                const CorotatedRows& rows) {
  const auto mapped = [&](std::uint32_t band_u_row) -> std::int32_t {
    const std::int32_t m = rows.row_of[level.band_kernel.global_target(band_u_row, level.size())];
    return m >= 0 && m_in_band[m] ? m : -1;
  };
  std::vector<std::uint8_t> scheduled(rows.rows(), 0);
  DenseRow row(rows, (Dim + 1) * level.size());
  for (std::size_t c = 0; c < m_schedule.size(); ++c) {
    m_schedule[c].resize(level.band_schedule[c].size());
    for (std::size_t w = 0; w < level.band_schedule[c].size(); ++w) {
      const auto& linear = level.band_schedule[c][w];
      Work& work = m_schedule[c][w];
      for (std::uint32_t e : linear.cell_blocks) {
        std::array<std::uint32_t, B> members;
        members.fill(UINT32_MAX);
        int size = 0;
        for (std::uint32_t r : level.band_blocks[e])
          if (r != UINT32_MAX)
            if (const std::int32_t m = mapped(r); m >= 0) members[size++] = m;
        Eigen::MatrixXd s(size, size);
        for (int a = 0; a < size; ++a) {
          row.load(members[a]);
          for (int b = 0; b < size; ++b) s(a, b) = schur_entry(row, rows, members[b]);
        }
        const Eigen::FullPivLU<Eigen::MatrixXd> lu(s);
        if (size < 2 || !lu.isInvertible() || !s.allFinite()) {
          for (int a = 0; a < size; ++a) work.point_rows.push_back(members[a]);
        } else {
          const Eigen::MatrixXd inverse = lu.inverse();
          for (int a = 0; a < B; ++a)
            for (int b = 0; b < B; ++b)
              m_block_inverse.push_back(a < size && b < size ? inverse(a, b) : 0.0);
          work.cell_blocks.push_back(static_cast<std::uint32_t>(m_blocks.size()));
          m_blocks.push_back(members);
        }
        for (int a = 0; a < size; ++a) scheduled[members[a]] = 1;
      }
      for (std::uint32_t r : linear.point_rows)
        if (const std::int32_t m = mapped(r); m >= 0) {
          work.point_rows.push_back(m);
          scheduled[m] = 1;
        }
    }
  }
  for (std::uint32_t m = 0; m < rows.rows(); ++m)
    if (m_in_band[m] && !scheduled[m]) m_unscheduled.push_back(m);
}

template <int Dim>
void CorotatedBandSmoother<Dim>::update_pressures(Level<Dim, double>& level,
                                                  const CorotatedRows& rows) const {
  const Sweep band(*this, rows, level);
  const auto count = static_cast<std::ptrdiff_t>(m_pressure_rows.size());
  // Each eliminated pressure row reads u and its own p only: independent updates.
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t s = 0; s < count; ++s) {
    const std::uint32_t m = m_pressure_rows[s];
    const std::uint32_t t = rows.target[m];
    double value = rows.constant[m];
    for (std::uint32_t e = rows.start[m]; e < rows.start[m + 1]; ++e)
      if (rows.column[e] != t) value += rows.value[e] * band.at(rows.column[e]);
    band.at(t) = (band.b[Dim][t % band.n] - value) * m_pressure_inverse[s];
  }
}

template <int Dim>
void CorotatedBandSmoother<Dim>::sweep(Level<Dim, double>& level, const CorotatedRows& rows,
                                       int sweeps) const {
  update_pressures(level, rows);
  const Sweep band(*this, rows, level);
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    // Colored blocks: the blocks of one color touch disjoint variables.
    for (const auto& color : m_schedule) {
      const auto count = static_cast<std::ptrdiff_t>(color.size());
#pragma omp parallel for schedule(dynamic, 1)
      for (std::ptrdiff_t w = 0; w < count; ++w) {
        for (std::uint32_t block : color[w].cell_blocks) band.relax_block(block);
        for (std::uint32_t m : color[w].point_rows) band.relax_row(m);
      }
    }
    for (std::uint32_t m : m_unscheduled) band.relax_row(m);
  }
}

template class CorotatedBandSmoother<2>;
template class CorotatedBandSmoother<3>;

}  // namespace mgelastic::grid
