#pragma once
// Problems and rate measurements shared by the co-rotated smoother tests: the bent cantilever
// of test_corotated_multigrid.cpp and a bar twisted by 90 degrees, frozen-system rates per
// V-cycle after k = 1 Picard cycles from rest.
#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <ctime>
#include <utility>
#include <vector>

#include "dynamics_test_support.hpp"
#include "mgelastic/core/threads.hpp"
#include "mgelastic/core/timer.hpp"
#include "mgelastic/grid/corotated_multigrid.hpp"

namespace mgelastic::grid::test {

// The bent cantilever of test_corotated_multigrid.cpp (tip deflection ~0.18 of the length).
inline ElasticityProblem<3> bent_cantilever(double nu, int n = 24) {
  ElasticityProblem<3> problem = end_clamped_bar(n, nu, true);
  problem.body_force = [](const Vec<3>&) { return Vec<3>(0, -0.01, 0); };
  return problem;
}

// Both ends Dirichlet, the end at x = 1 turned by 90 degrees about the bar's axis.
inline ElasticityProblem<3> twisted_bar(double nu, int n = 24) {
  ElasticityProblem<3> problem = end_clamped_bar(n, nu, false);
  const Vec<3> axis_point(0.5, 0.125, 0.125);
  const Matrix<3> turn = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()).matrix();
  problem.dirichlet_displacement = [=](const Vec<3>& x) -> Vec<3> {
    const double s = std::clamp(x[0], 0.0, 1.0);  // 0 at the fixed end, 1 at the turned one
    return s > 0.5 ? Vec<3>((turn - Matrix<3>::Identity()) * (x - axis_point)) : Vec<3>::Zero();
  };
  return problem;
}

inline void fill_pseudo_random(FieldArray<double>& values, std::uint32_t seed, double scale) {
  for (double& v : values) {
    seed = seed * 1664525u + 1013904223u;
    v = scale * (static_cast<double>(seed >> 8) / (1u << 24) - 0.5);
  }
}

// A finest level of `problem` with pseudo-random unknowns and right-hand side, for comparing a
// co-rotated sweep at R = I with the linear engine's on the same values.
inline Level<3, double> random_level(const ElasticityProblem<3>& problem, double inertia) {
  Level<3, double> level = build_level<3, double>(problem.lattice, problem.cells, problem.material,
                                                  {}, nullptr, inertia);
  for (int f = 0; f < 4; ++f) {
    fill_pseudo_random(level.x[f], 11 + f, 0.02);
    fill_pseudo_random(level.b[f], 31 + f, 1.0);
  }
  return level;
}

// max |a.x - b.x| and max |a.x| over all fields.
inline std::pair<double, double> max_difference(const Level<3, double>& a,
                                                const Level<3, double>& b) {
  double worst = 0, largest = 0;
  for (int f = 0; f < 4; ++f)
    for (std::size_t k = 0; k < a.size(); ++k) {
      worst = std::max(worst, std::abs(a.x[f][k] - b.x[f][k]));
      largest = std::max(largest, std::abs(a.x[f][k]));
    }
  return {worst, largest};
}

inline double mean_rate(const std::vector<double>& residuals) {
  const int cycles = static_cast<int>(residuals.size()) - 1;
  return std::pow(residuals.back() / residuals.front(), 1.0 / cycles);
}

struct Measured {
  double nonlinear_rate, quasi_linear_rate, seconds_per_cycle, seconds_per_frozen_cycle;
};

// Non-linear rate: plain frozen-rotation (Picard) cycles refreshed every cycle (k = 1) from
// rest. Quasi-linear rate: then the rotations of that iterate frozen, V-cycles on the frozen
// system (the smoother's own measure, Sec. 7); process CPU seconds per frozen cycle.
inline Measured measure(const ElasticityProblem<3>& problem, CorotatedOptions options, int cycles,
                        int frozen_cycles = 6, MultigridOptions multigrid = {}) {
  options.rotation_update_every = 1 << 30;  // refreshed by hand
  options.acceleration_depth = 0;
  CorotatedMultigrid<3> corotated(problem, multigrid, options);
  std::vector<double> nonlinear{corotated.nonlinear_residual()};
  Timer timer;
  for (int cycle = 0; cycle < cycles; ++cycle) {
    corotated.refresh_rotations();
    corotated.vcycle();
    nonlinear.push_back(corotated.nonlinear_residual());
  }
  const double seconds = timer.seconds() / cycles;
  corotated.refresh_rotations();
  std::vector<double> frozen{corotated.quasi_linear_residual()};
  const std::clock_t start = std::clock();
  for (int cycle = 0; cycle < frozen_cycles; ++cycle) frozen.push_back(corotated.vcycle());
  const double frozen_seconds =
      static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC / frozen_cycles;
  return {mean_rate(nonlinear), mean_rate(frozen), seconds, frozen_seconds};
}

// The finest unknowns after `cycles` run_cycles of a co-rotated multigrid built with 1 and with 2
// threads (index = threads - 1), for thread-count independence checks.
inline std::array<std::array<FieldArray<double>, 4>, 2> solutions_with_one_and_two_threads(
    const ElasticityProblem<3>& problem, const CorotatedOptions& options, int cycles) {
  const int saved = thread_count();
  std::array<std::array<FieldArray<double>, 4>, 2> x;
  for (int threads : {1, 2}) {
    set_thread_count(threads);
    CorotatedMultigrid<3> corotated(problem, {}, options);
    corotated.run_cycles(cycles);
    x[threads - 1] = corotated.solution_level().x;
  }
  set_thread_count(saved);
  return x;
}

}  // namespace mgelastic::grid::test
