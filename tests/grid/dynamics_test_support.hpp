#pragma once
// Shared fixtures for the grid-engine dynamics and co-rotation tests: a cantilever bar, its
// first-mode-like initial velocity, the co-rotated elastic energy and per-step rate statistics.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <functional>
#include <utility>

#include "mgelastic/grid/corotation.hpp"
#include "mgelastic/grid/level.hpp"
#include "mgelastic/grid/problem.hpp"

namespace mgelastic::grid::test {

// A bar of nx x n x n cells of size h along x; the cells with x index <= fixed are Dirichlet
// (none when fixed = 0).
inline ElasticityProblem<3> bar(int nx, int n, double h, int fixed, const Material& material) {
  ElasticityProblem<3> problem;
  problem.lattice = Lattice<3>(IVec<3>(nx, n, n), h);
  problem.material = material;
  problem.cells.assign(problem.lattice.size(), CellType::EXTERIOR);
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(problem.lattice.size()); ++k) {
    const IVec<3> s = problem.lattice.coords(k);
    if (!problem.lattice.is_real(s)) continue;
    problem.cells[k] = s[0] <= fixed ? CellType::DIRICHLET : CellType::INTERIOR;
  }
  return problem;
}

// A bar along x of n x n/4 x n/4 cells, length 1, E = 1, Dirichlet cells at x = 0 and, unless
// `cantilever`, at x = 1 (the co-rotation tests' bar).
inline ElasticityProblem<3> end_clamped_bar(int n, double nu, bool cantilever) {
  ElasticityProblem<3> problem;
  problem.lattice = Lattice<3>(IVec<3>(n, n / 4, n / 4), 1.0 / n);
  problem.material = Material{1.0, nu};
  problem.cells.assign(problem.lattice.size(), CellType::EXTERIOR);
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(problem.lattice.size()); ++k) {
    const IVec<3> s = problem.lattice.coords(k);
    if (!problem.lattice.is_real(s)) continue;
    const bool end = s[0] == 1 || (!cantilever && s[0] == n);
    problem.cells[k] = end ? CellType::DIRICHLET : CellType::INTERIOR;
  }
  return problem;
}

// The cantilever's first-mode-like velocity profile v_y = speed ((x - x0) / length)^2.
inline std::function<Vec<3>(const Vec<3>&)> bending_velocity(double x0, double length,
                                                             double speed) {
  return [=](const Vec<3>& x) {
    const double s = std::max(0.0, (x[0] - x0) / length);
    return Vec<3>(0.0, speed * s * s, 0.0);
  };
}

// Co-rotated elastic energy mu |S - I|^2 + lambda/2 tr(S - I)^2 (S = R^T F) over interior cells.
inline double corotated_energy(const Level<3, double>& level, const Material& material) {
  double energy = 0;
  const double volume = std::pow(level.lattice.h, 3);
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(level.size()); ++k) {
    if (level.cells[k] != CellType::INTERIOR) continue;
    const Matrix<3> f = cell_deformation_gradient(level, k);
    const Matrix<3> e = polar_rotation<3>(f).transpose() * f - Matrix<3>::Identity();
    energy += volume *
              (material.mu() * e.squaredNorm() + 0.5 * material.lambda() * e.trace() * e.trace());
  }
  return energy;
}

// True when every component of every velocity sample is finite.
template <typename Velocities>
bool all_finite(const Velocities& velocity) {
  for (const auto& v : velocity)
    for (double x : v)
      if (!std::isfinite(x)) return false;
  return true;
}

// Per-step residual reductions: geometric mean and worst.
class StepRates {
 public:
  void add(double rate) {
    m_worst = std::max(m_worst, rate);
    m_log_sum += std::log(rate);
    ++m_count;
  }
  std::pair<double, double> mean_and_worst() const {
    return {std::exp(m_log_sum / m_count), m_worst};
  }

 private:
  double m_worst = 0, m_log_sum = 0;
  int m_count = 0;
};

}  // namespace mgelastic::grid::test
