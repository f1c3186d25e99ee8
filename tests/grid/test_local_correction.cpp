#include "mgelastic/grid/local_correction.hpp"
#include "mgelastic/grid/local_corrections.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "grid_test_support.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/core/threads.hpp"
#include "mgelastic/grid/coarsening.hpp"
#include "mgelastic/grid/convergence_rate.hpp"
#include "mgelastic/grid/multigrid.hpp"
#include "mgelastic/grid/residual.hpp"

namespace mgelastic::grid {
namespace {

double max_abs(const Level<3, double>& level, const std::function<bool(int, std::ptrdiff_t)>& in) {
  double m = 0;
  for (int f = 0; f <= 3; ++f)
    for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(level.size()); ++k)
      if (in(f, k)) m = std::max(m, std::abs(level.r[f][k]));
  return m;
}

bool inside(const IVec<3>& s, const IVec<3>& lo, const IVec<3>& hi) {
  return (s.array() >= lo.array()).all() && (s.array() < hi.array()).all();
}

// After the correction, every row of a variable of the box's cells (those of the outermost
// cell layer excepted: their lower faces border the held margin) holds exactly, and rows
// farther than the operator's reach from the box keep their residual.
TEST(LocalCorrection, SolvesTheBoxRowsExactlyAndLeavesFarRowsAlone) {
  const auto problem = test::clamped_ball(24);
  const auto coarse_cells = coarsen_cells(problem.lattice, problem.cells);
  auto level =
      build_level<3, double>(problem.lattice, problem.cells, problem.material, {}, &coarse_cells);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  for (int f = 0; f <= 3; ++f)
    for (std::size_t k = 0; k < level.size(); ++k) {
      level.x[f][k] = level.kind(f, k) == VarKind::INTERIOR ? uniform(rng) : 0.0;
      level.b[f][k] = 0.0;
    }
  back_substitute_traction(level);
  // A box across the ball's surface: band rows, traction variables and exterior cells inside.
  const IVec<3> lo(4, 8, 14), hi(12, 16, 24);
  LocalCorrection<3, double> local(level, problem.material, 0.0, lo, hi);
  EXPECT_GT(local.unknowns(), 500u);
  update_residual(level);
  const auto before = level.r;
  const auto far = [&](std::ptrdiff_t k) {
    const IVec<3> s = level.lattice.coords(k);
    return !inside(s, lo - IVec<3>::Constant(4), hi + IVec<3>::Constant(4));
  };
  local.apply(level);
  update_residual(level);
  const auto deep = [&](int f, std::ptrdiff_t k) {
    return level.kind(f, k) == VarKind::INTERIOR &&
           inside(level.lattice.coords(k), lo + IVec<3>::Ones(), hi - IVec<3>::Ones());
  };
  double scale = 0;
  for (int f = 0; f <= 3; ++f)
    for (double v : before[f]) scale = std::max(scale, std::abs(v));
  ASSERT_GT(scale, 0);
  EXPECT_LT(max_abs(level, deep), 1e-9 * scale);
  for (int f = 0; f <= 3; ++f)
    for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(level.size()); ++k)
      if (far(k)) {
        ASSERT_EQ(level.r[f][k], before[f][k]) << "field " << f << " index " << k;
      }
}

// A box over clamped cells only has no unknown: the correction refuses it, and a placement
// skips it and goes on.
TEST(LocalCorrection, BoxWithoutUnknownsIsSkipped) {
  const auto problem = test::clamped_ball(24);
  const auto coarse_cells = coarsen_cells(problem.lattice, problem.cells);
  const auto level =
      build_level<3, float>(problem.lattice, problem.cells, problem.material, {}, &coarse_cells);
  const IVec<3> lo(10, 10, 1), hi(14, 14, 4);  // the clamped cap (z < 0.2)
  using Correction = LocalCorrection<3, float>;
  EXPECT_THROW(Correction(level, problem.material, 0.0, lo, hi), Error);
  LocalCorrections<3, float> corrections(4, problem.material, 0.0);
  EXPECT_NO_THROW(corrections.place(level, {{lo, hi}}));
  EXPECT_EQ(corrections.size(), 0);
}

// The two fingers' slow mode (test::two_fingers): the corrections solve() places there lift the
// rate far below the plain cycle's.
TEST(LocalCorrection, MultigridPlacesBoxesWhereASlowModeSits) {
  const auto problem = test::two_fingers(32);
  MultigridOptions plain;
  plain.local_corrections = 0;
  Multigrid<3, float> without(problem, plain);
  const auto slow = without.run_cycles(30);
  MultigridOptions options;
  options.local_corrections = 4;
  Multigrid<3, float> with(problem, options);
  const auto fast = with.run_cycles(30);
  const double slow_rate = convergence_rate(slow.residuals);
  const double fast_rate = convergence_rate(fast.residuals);
  std::printf("two fingers 32^3: plain V(1,1) rate %.3f, with local corrections %.3f (%d box)\n",
              slow_rate, fast_rate, with.local_corrections());
  EXPECT_EQ(without.local_corrections(), 0);
  EXPECT_GE(with.local_corrections(), 1);
  EXPECT_LT(fast_rate, slow_rate - 0.1);
}

// The boxes, their placement and their solves do not depend on the thread count: the same
// residuals and solution, bit for bit.
TEST(LocalCorrection, ResultsDoNotDependOnThreadCount) {
  const auto problem = test::two_fingers(32);
  MultigridOptions options;
  options.local_corrections = 4;
  std::vector<double> values[2];
  for (int threads : {1, 2}) {
    set_thread_count(threads);
    Multigrid<3, float> mg(problem, options);
    values[threads - 1] = mg.run_cycles(16).residuals;
    EXPECT_EQ(mg.local_corrections(), 1);
    for (int f = 0; f <= 3; ++f)
      for (std::size_t k = 0; k < mg.finest().size(); ++k)
        values[threads - 1].push_back(mg.solution(f, k));
  }
  set_thread_count(0);
  EXPECT_EQ(values[0], values[1]);
}

// A hierarchy given another's placement state and solution continues as that one does, bit for
// bit (what a checkpoint's resume relies on, sim/grid_stepper.cpp).
TEST(LocalCorrection, RestoredStateContinuesBitForBit) {
  const auto problem = test::two_fingers(32);
  MultigridOptions options;
  options.local_corrections = 4;
  Multigrid<3, float> original(problem, options);
  original.run_cycles(12);
  ASSERT_EQ(original.local_corrections(), 1);
  const auto state = original.local_correction_state();
  const auto solution = original.solution_state();
  Multigrid<3, float> resumed(problem, options);
  resumed.restore_local_correction_state(state);
  resumed.set_solution_state(solution);
  EXPECT_EQ(resumed.local_corrections(), 1);
  EXPECT_EQ(resumed.local_correction_state().integers, state.integers);
  EXPECT_EQ(original.run_cycles(8).residuals, resumed.run_cycles(8).residuals);
  auto bad = state;
  bad.integers.pop_back();
  EXPECT_THROW(resumed.restore_local_correction_state(bad), Error);
}

}  // namespace
}  // namespace mgelastic::grid
