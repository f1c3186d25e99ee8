#include "mgelastic/grid/corotated_distributive_smoother.hpp"

#include <array>
#include <cmath>

namespace mgelastic::grid {
namespace {

template <int Dim>
bool relaxed_distributively(const Level<Dim, double>& level, std::uint32_t target) {
  const auto n = static_cast<std::uint32_t>(level.size());
  const std::uint32_t field = target / n;
  if (field == Dim && level.lambda <= 0) return false;  // p = 0 rows
  return level.relaxation(field, target % n) == Relaxation::DISTRIBUTIVE;
}

}  // namespace

template <int Dim>
CorotatedDistributiveSmoother<Dim>::CorotatedDistributiveSmoother(const Level<Dim, double>& level,
                                                                  const CorotatedRows& rows) {
  build_distribution(level, rows);
  build_diagonal(level, rows);
}

// Column m of M: the row's own variable, for q steps the -2 Lap_h + c/mu pressure stencil over
// pressure unknowns, and the transposed coupling terms of the other field's rows over mu
// (pressure rows' u terms for psi steps, momentum rows' p terms for q steps).
template <int Dim>
void CorotatedDistributiveSmoother<Dim>::build_distribution(const Level<Dim, double>& level,
                                                            const CorotatedRows& rows) {
  const auto n = static_cast<std::uint32_t>(level.size());
  const std::size_t count = rows.rows();
  std::vector<std::uint8_t> relaxed(count, 0);
  for (std::size_t m = 0; m < count; ++m)
    relaxed[m] = relaxed_distributively(level, rows.target[m]);
  const auto coupled_row = [&](std::size_t a, std::uint32_t e) -> std::int32_t {
    const std::uint32_t v = rows.column[e];
    const std::int32_t b = rows.row_of[v];
    if (b < 0 || !relaxed[b]) return -1;
    const bool a_pressure = rows.target[a] / n == Dim, v_pressure = v / n == Dim;
    return a_pressure != v_pressure ? b : -1;
  };
  // Transpose of the u-p coupling blocks, restricted to relaxed rows (counting sort).
  std::vector<std::uint32_t> coupling_start(count + 1, 0);
  for (std::size_t a = 0; a < count; ++a)
    for (std::uint32_t e = rows.start[a]; e < rows.start[a + 1]; ++e)
      if (const std::int32_t b = coupled_row(a, e); b >= 0) ++coupling_start[b + 1];
  for (std::size_t m = 0; m < count; ++m) coupling_start[m + 1] += coupling_start[m];
  std::vector<std::uint32_t> coupling_variable(coupling_start.back());
  std::vector<double> coupling_weight(coupling_start.back());
  std::vector<std::uint32_t> fill(coupling_start.begin(), coupling_start.end() - 1);
  const double inv_mu = 1.0 / level.mu;
  for (std::size_t a = 0; a < count; ++a)
    for (std::uint32_t e = rows.start[a]; e < rows.start[a + 1]; ++e)
      if (const std::int32_t b = coupled_row(a, e); b >= 0) {
        coupling_variable[fill[b]] = rows.target[a];
        coupling_weight[fill[b]++] = rows.value[e] * inv_mu;
      }

  const double inv_h2 = 1.0 / (level.lattice.h * level.lattice.h);
  const double p_center = 4 * Dim * inv_h2 + level.inertia * inv_mu;
  for (std::size_t m = 0; m < count; ++m) {
    if (relaxed[m]) {
      const std::uint32_t t = rows.target[m];
      const bool pressure = t / n == Dim;
      m_variable.push_back(t);
      m_weight.push_back(pressure ? p_center : 1.0);
      if (pressure)
        for (int j = 0; j < Dim; ++j)
          for (const std::ptrdiff_t s : {-level.lattice.stride(j), level.lattice.stride(j)}) {
            const auto neighbor = static_cast<std::uint32_t>(t + s);
            if (rows.row_of[neighbor] < 0) continue;
            m_variable.push_back(neighbor);
            m_weight.push_back(-2 * inv_h2);
          }
      for (std::uint32_t e = coupling_start[m]; e < coupling_start[m + 1]; ++e) {
        m_variable.push_back(coupling_variable[e]);
        m_weight.push_back(coupling_weight[e]);
      }
      ++m_relaxed;
    }
    m_start.push_back(static_cast<std::uint32_t>(m_variable.size()));
  }
}

// (LM)_mm = L_m . M e_m, with row m scattered into a dense array of all variables.
template <int Dim>
void CorotatedDistributiveSmoother<Dim>::build_diagonal(const Level<Dim, double>& level,
                                                        const CorotatedRows& rows) {
  std::vector<double> dense((Dim + 1) * level.size(), 0.0);
  m_inverse_diagonal.assign(rows.rows(), 0.0);
  for (std::size_t m = 0; m < rows.rows(); ++m) {
    if (m_start[m] == m_start[m + 1]) continue;
    for (std::uint32_t e = rows.start[m]; e < rows.start[m + 1]; ++e)
      dense[rows.column[e]] = rows.value[e];
    double diagonal = 0;
    for (std::uint32_t e = m_start[m]; e < m_start[m + 1]; ++e)
      diagonal += m_weight[e] * dense[m_variable[e]];
    for (std::uint32_t e = rows.start[m]; e < rows.start[m + 1]; ++e) dense[rows.column[e]] = 0;
    // A vanishing or non-finite pivot (degenerate rotations) leaves the row to the band smoother
    // rather than producing Inf.
    if (std::isfinite(diagonal) && std::abs(diagonal) > 0) m_inverse_diagonal[m] = 1.0 / diagonal;
  }
}

template <int Dim>
void CorotatedDistributiveSmoother<Dim>::sweep(Level<Dim, double>& level,
                                               const CorotatedRows& rows) const {
  const auto n = static_cast<std::uint32_t>(level.size());
  std::array<double*, Dim + 1> x;
  for (int f = 0; f <= Dim; ++f) x[f] = level.x[f].data();
  const auto at = [&](std::uint32_t v) -> double& { return GlobalSplit<Dim>{n}(x, v); };
  const auto relax = [&](int field, std::ptrdiff_t k) {
    const std::int32_t m = rows.row_of[level.global(field, k)];
    if (m < 0 || m_inverse_diagonal[m] == 0) return;
    double value = rows.constant[m];
    for (std::uint32_t e = rows.start[m]; e < rows.start[m + 1]; ++e)
      value += rows.value[e] * at(rows.column[e]);
    const double delta = (level.b[field][k] - value) * m_inverse_diagonal[m];
    for (std::uint32_t e = m_start[m]; e < m_start[m + 1]; ++e)
      at(m_variable[e]) += m_weight[e] * delta;
  };
  // The linear sweep's order (distributive_smoother.hpp): block by block, u_1 .. u_d, then p.
  const int fields = level.lambda > 0 ? Dim + 1 : Dim;
  for (const auto& color : level.blocks.colors) {
    const auto count = static_cast<std::ptrdiff_t>(color.size());
#pragma omp parallel for schedule(dynamic, 1)
    for (std::ptrdiff_t block = 0; block < count; ++block)
      for (int field = 0; field < fields; ++field)
        for_each_in_block(level.lattice, color[block], [&](std::ptrdiff_t k) { relax(field, k); });
  }
}

template class CorotatedDistributiveSmoother<2>;
template class CorotatedDistributiveSmoother<3>;

}  // namespace mgelastic::grid
