#include <gtest/gtest.h>

#include <random>

#include "grid_test_support.hpp"
#include "mgelastic/grid/explicit_rows.hpp"
#include "mgelastic/grid/level.hpp"
#include "mgelastic/grid/residual.hpp"
#include "mgelastic/grid/stencil.hpp"
#include "support/tolerances.hpp"

namespace mgelastic::grid {
namespace {

// L* is symmetric (Sec. 5.3): every pressure row's coefficient of u_f equals the momentum row
// of u_f's coefficient of that pressure, also next to traction corners and thin features.
template <int Dim>
void expect_symmetric_coupling(const ElasticityProblem<Dim>& problem) {
  const auto level =
      build_level<Dim, double>(problem.lattice, problem.cells, problem.material, {}, nullptr);
  const RowBuilder<Dim> builder(level.lattice, level.cells, problem.material.mu(), {});
  const auto n = level.size();
  int checked = 0;
  for (std::size_t c = 0; c < n; ++c) {
    if (level.kind(Dim, c) != VarKind::INTERIOR) continue;
    for (const RowTerm& t : builder.pressure(c).terms) {
      if (level.kind(t.variable / n, t.variable % n) != VarKind::INTERIOR) continue;
      const ExplicitRow row = builder.momentum(static_cast<int>(t.variable / n), t.variable % n);
      double g = 0;
      for (const RowTerm& m : row.terms)
        if (m.variable == level.global(Dim, c)) g = m.coefficient;
      EXPECT_NEAR(g, t.coefficient, 1e-12 * std::abs(t.coefficient));
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

TEST(ExplicitRows, PressureCouplingIsSymmetric2D) {
  expect_symmetric_coupling(test::irregular_problem<2>(24, 7, {1e5, 0.45}));
}

TEST(ExplicitRows, PressureCouplingIsSymmetric3D) {
  expect_symmetric_coupling(test::irregular_problem<3>(10, 11, {1e5, 0.45}));
}

// Away from traction boundaries the stored rows and the uniform stencil are the same operator.
TEST(ExplicitRows, MatchUniformStencilAwayFromTraction) {
  const auto problem =
      test::unit_box<3>(8, {2e4, 0.3}, [](const IVec<3>& s) { return s[0] == 1 || s[0] == 8; });
  const auto level =
      build_level<3, double>(problem.lattice, problem.cells, problem.material, {}, nullptr);
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  std::array<std::vector<double>, 4> x;
  for (auto& f : x) {
    f.resize(level.size());
    for (double& v : f) v = normal(rng);
  }
  std::array<const double*, 3> u{x[0].data(), x[1].data(), x[2].data()};
  std::array<std::ptrdiff_t, 3> s{level.lattice.stride(0), level.lattice.stride(1),
                                  level.lattice.stride(2)};
  const StencilConstants<3, double> c{level.mu, 1.0 / level.lattice.h,
                                      1.0 / (level.lattice.h * level.lattice.h)};
  const RowBuilder<3> builder(level.lattice, level.cells, problem.material.mu(), {});
  int compared = 0;
  for (std::size_t k = 0; k < level.size(); ++k) {
    const IVec<3> q = level.lattice.coords(k);
    if (level.kind(0, k) != VarKind::INTERIOR || q[1] < 3 || q[1] > 6 || q[2] < 3 || q[2] > 6)
      continue;
    double explicit_value = 0;
    for (const RowTerm& t : builder.momentum(0, k).terms)
      explicit_value += t.coefficient * x[t.variable / level.size()][t.variable % level.size()];
    const double stencil_value = momentum_row<3, double, 0>(u, x[3].data(), s, k, c);
    // Both sum ~15 terms of size mu / h^2 |x|: compare relative to that scale.
    EXPECT_NEAR(explicit_value, stencil_value,
                mgelastic::test::kStencilRoundoff * 20 * c.mu * c.inv_h2);
    ++compared;
  }
  EXPECT_GT(compared, 20);
}

}  // namespace
}  // namespace mgelastic::grid
