#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/coarsening.hpp"
#include "mgelastic/grid/residual.hpp"
#include "mgelastic/grid/transfer.hpp"

namespace mgelastic::grid {
namespace {

struct TwoLevels {
  Level<3, double> fine, coarse;
};

// A box of Dirichlet walls (all cells interior inside) on two levels.
TwoLevels two_levels(int n) {
  BoxSpec spec;
  spec.cells = n;
  spec.boundary = BoxBoundary::DIRICHLET;
  const auto problem = make_box_problem<3>(spec);
  const auto coarse_cells = coarsen_cells(problem.lattice, problem.cells);
  return {
      build_level<3, double>(problem.lattice, problem.cells, problem.material, {}, &coarse_cells),
      build_level<3, double>(coarsen(problem.lattice), coarse_cells, problem.material, {},
                             nullptr)};
}

// R_i and R_p are averages (weights sum to one): a constant residual restricts to the same
// constant at every coarse equation whose stencil stays inside the fine interior.
TEST(Transfer, RestrictionPreservesConstants) {
  auto levels = two_levels(16);
  ensure_residual_storage(levels.fine);
  for (int f = 0; f <= 3; ++f)
    for (std::size_t k = 0; k < levels.fine.size(); ++k)
      levels.fine.r[f][k] = levels.fine.kind(f, k) == VarKind::INTERIOR ? 2.5 : 0.0;
  restrict_residual(levels.fine, levels.coarse);
  int checked = 0;
  for (int f = 0; f <= 3; ++f) {
    for (std::size_t k = 0; k < levels.coarse.size(); ++k) {
      const IVec<3> s = levels.coarse.lattice.coords(k);
      if (levels.coarse.kind(f, k) != VarKind::INTERIOR || s.minCoeff() < 3 || s.maxCoeff() > 6)
        continue;
      EXPECT_DOUBLE_EQ(levels.coarse.b[f][k], 2.5);
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

// The restriction as written in Sec. 6 (R_i = B2 along e_i, B1 along the others, R_p = B1),
// summed in double over the fine taps inside the storage, axis 0 outermost.
double reference_restriction(const Level<3, double>& fine, int field, const IVec<3>& s) {
  std::array<std::vector<std::pair<int, double>>, 3> taps;
  for (int a = 0; a < 3; ++a) {
    const int c = s[a] - 1;
    std::vector<std::pair<int, double>> all;
    if (a == field)
      all = {{2 * c, 0.25}, {2 * c + 1, 0.5}, {2 * c + 2, 0.25}};
    else
      all = {{2 * c + 1, 0.5}, {2 * c + 2, 0.5}};
    for (const auto& t : all)
      if (t.first >= 0 && t.first < fine.lattice.padded(a)) taps[a].push_back(t);
  }
  double sum = 0.0;
  for (const auto& [i, wi] : taps[0])
    for (const auto& [j, wj] : taps[1])
      for (const auto& [k, wk] : taps[2])
        sum += wi * wj * wk * fine.r[field][fine.lattice.index(IVec<3>(i, j, k))];
  return sum;
}

// The row-wise restriction (vectorized fast path inside the fine storage, general taps at the
// storage edges) gives the reference sums bit for bit: its weights are powers of two, so every
// product is exact and the sums add the same terms in the same order. Odd and even fine sizes
// (odd: the last coarse cell has half its fine taps outside), mixed and Dirichlet boxes.
TEST(Transfer, RowWiseRestrictionEqualsReferenceSums) {
  for (const int n : {13, 16}) {
    for (const BoxBoundary boundary : {BoxBoundary::MIXED, BoxBoundary::DIRICHLET}) {
      BoxSpec spec;
      spec.cells = n;
      spec.boundary = boundary;
      const auto problem = make_box_problem<3>(spec);
      const auto coarse_cells = coarsen_cells(problem.lattice, problem.cells);
      auto fine = build_level<3, double>(problem.lattice, problem.cells, problem.material, {},
                                         &coarse_cells);
      auto coarse = build_level<3, double>(coarsen(problem.lattice), coarse_cells, problem.material,
                                           {}, nullptr);
      std::mt19937 rng(n);
      std::normal_distribution<double> normal;
      ensure_residual_storage(fine);
      for (auto& field : fine.r)
        for (double& v : field) v = normal(rng);
      restrict_residual(fine, coarse);
      int checked = 0;
      for (int f = 0; f <= 3; ++f) {
        for (std::size_t k = 0; k < coarse.size(); ++k) {
          if (coarse.kind(f, k) != VarKind::INTERIOR) {
            ASSERT_EQ(coarse.b[f][k], 0.0);
            continue;
          }
          ASSERT_EQ(coarse.b[f][k], reference_restriction(fine, f, coarse.lattice.coords(k)))
              << "field " << f << " at " << coarse.lattice.coords(k).transpose();
          ++checked;
        }
      }
      EXPECT_GT(checked, 3 * (n / 2 - 2) * (n / 2 - 2) * (n / 2 - 2));
    }
  }
}

// Coarse taps of the prolongation along one axis (Sec. 6: linear interpolation from B2 along
// the face-centred axis, B3 along the cell-centred ones).
std::vector<std::pair<int, double>> prolongation_taps_of(int s, bool face_centered) {
  const int c = s - 1;
  if (face_centered) {
    if (c % 2 == 0) return {{c / 2 + 1, 1.0}};
    return {{(c - 1) / 2 + 1, 0.5}, {(c + 1) / 2 + 1, 0.5}};
  }
  const int m = c / 2;
  return {{m + 1, 0.75}, {(c % 2 == 0 ? m - 1 : m + 1) + 1, 0.25}};
}

// Where every coarse sample of a fine interior displacement is active (interior or traction),
// the paired row kernel adds the plain tensor-product interpolation: equal to the explicit
// weighted sum to round-off, at both parities of every axis, on a mixed box (traction samples)
// of odd and even size.
TEST(Transfer, PairedProlongationEqualsTensorProductInterpolation) {
  for (const int n : {13, 16}) {
    BoxSpec spec;
    spec.cells = n;
    spec.boundary = BoxBoundary::MIXED;
    const auto problem = make_box_problem<3>(spec);
    const auto coarse_cells = coarsen_cells(problem.lattice, problem.cells);
    auto fine =
        build_level<3, double>(problem.lattice, problem.cells, problem.material, {}, &coarse_cells);
    auto coarse = build_level<3, double>(coarsen(problem.lattice), coarse_cells, problem.material,
                                         {}, nullptr);
    std::mt19937 rng(n);
    std::normal_distribution<double> normal;
    for (auto& field : coarse.x)
      for (double& v : field) v = normal(rng);
    for (auto& field : fine.x) std::fill(field.begin(), field.end(), 0.0);
    prolongate_correction(coarse, fine);
    int checked = 0;
    double difference = 0.0;
    for (int f = 0; f < 3; ++f) {
      for (std::size_t k = 0; k < fine.size(); ++k) {
        if (fine.kind(f, k) != VarKind::INTERIOR) continue;
        const IVec<3> s = fine.lattice.coords(k);
        std::array<std::vector<std::pair<int, double>>, 3> taps;
        for (int a = 0; a < 3; ++a) taps[a] = prolongation_taps_of(s[a], a == f);
        double expected = 0.0;
        bool all_active = true;
        for (const auto& [i, wi] : taps[0])
          for (const auto& [j, wj] : taps[1])
            for (const auto& [l, wl] : taps[2]) {
              const auto ck = coarse.lattice.index(IVec<3>(i, j, l));
              const VarKind kind = coarse.kind(f, ck);
              all_active = all_active && (kind == VarKind::INTERIOR || kind == VarKind::TRACTION);
              expected += wi * wj * wl * coarse.x[f][ck];
            }
        if (!all_active) continue;
        difference = std::max(difference, std::abs(fine.x[f][k] - expected));
        ++checked;
      }
    }
    EXPECT_GT(checked, 3 * (n - 4) * (n - 4) * (n - 4));
    EXPECT_LE(difference, 1e-14);
  }
}

// P_i interpolates linearly (B2 x B3 x B3 up to scaling): a coarse linear field is reproduced
// exactly at fine interior faces away from the boundary; P_p injects cell values.
TEST(Transfer, ProlongationReproducesLinearFields) {
  auto levels = two_levels(16);
  auto linear = [](const Vec<3>& x) { return 0.3 + 1.5 * x[0] - 0.7 * x[1] + 0.2 * x[2]; };
  for (int f = 0; f < 3; ++f)
    for (std::size_t k = 0; k < levels.coarse.size(); ++k)
      if (levels.coarse.kind(f, k) != VarKind::INACTIVE)
        levels.coarse.x[f][k] = linear(levels.coarse.lattice.face_center(f, k));
  for (auto& field : levels.fine.x) std::fill(field.begin(), field.end(), 0.0);
  prolongate_correction(levels.coarse, levels.fine);
  int checked = 0;
  for (int f = 0; f < 3; ++f) {
    for (std::size_t k = 0; k < levels.fine.size(); ++k) {
      const IVec<3> s = levels.fine.lattice.coords(k);
      if (levels.fine.kind(f, k) != VarKind::INTERIOR || s.minCoeff() < 5 || s.maxCoeff() > 12)
        continue;
      EXPECT_NEAR(levels.fine.x[f][k], linear(levels.fine.lattice.face_center(f, k)), 1e-12);
      ++checked;
    }
  }
  EXPECT_GT(checked, 100);
}

// Next to a Dirichlet wall the correction vanishes on the wall itself: a coarse field that is
// linear in the distance to the wall is reproduced at the first fine layer too.
TEST(Transfer, ProlongationVanishesOnDirichletWalls) {
  auto levels = two_levels(16);
  // The coarse Dirichlet layer is two fine cells thick, so its wall is at x = 2h; test the
  // tangential component u_1 with the field 5 (x - 2h), which vanishes on that wall.
  auto field = [&](const Vec<3>& x) { return 5.0 * (x[0] - 2 * levels.fine.lattice.h); };
  for (std::size_t k = 0; k < levels.coarse.size(); ++k) {
    if (levels.coarse.kind(1, k) == VarKind::INTERIOR)
      levels.coarse.x[1][k] = field(levels.coarse.lattice.face_center(1, k));
  }
  for (auto& f : levels.fine.x) std::fill(f.begin(), f.end(), 0.0);
  prolongate_correction(levels.coarse, levels.fine);
  int checked = 0;
  for (std::size_t k = 0; k < levels.fine.size(); ++k) {
    const IVec<3> s = levels.fine.lattice.coords(k);
    // First fine layer beyond the coarse wall: fine cells 3 (stored), mid-box in y and z.
    if (s[0] != 3 || s[1] < 6 || s[1] > 10 || s[2] < 6 || s[2] > 10) continue;
    if (levels.fine.kind(1, k) != VarKind::INTERIOR) continue;
    EXPECT_NEAR(levels.fine.x[1][k], field(levels.fine.lattice.face_center(1, k)), 1e-12);
    ++checked;
  }
  EXPECT_GT(checked, 10);
}

// Coarsening of cell types (Sec. 6): Dirichlet dominates, then interior, else exterior.
TEST(Coarsening, DirichletDominatesThenInterior) {
  Lattice<2> fine(IVec<2>(4, 4), 1.0);
  std::vector<CellType> cells(fine.size(), CellType::EXTERIOR);
  cells[fine.index(IVec<2>(1, 1))] = CellType::INTERIOR;
  cells[fine.index(IVec<2>(2, 1))] = CellType::DIRICHLET;  // same coarse cell (1, 1)
  cells[fine.index(IVec<2>(3, 1))] = CellType::INTERIOR;   // coarse cell (2, 1)
  const auto coarse = coarsen_cells(fine, cells);
  const Lattice<2> coarse_lattice = coarsen(fine);
  EXPECT_EQ(coarse[coarse_lattice.index(IVec<2>(1, 1))], CellType::DIRICHLET);
  EXPECT_EQ(coarse[coarse_lattice.index(IVec<2>(2, 1))], CellType::INTERIOR);
  EXPECT_EQ(coarse[coarse_lattice.index(IVec<2>(1, 2))], CellType::EXTERIOR);
  EXPECT_DOUBLE_EQ(coarse_lattice.h, 2.0);
}

}  // namespace
}  // namespace mgelastic::grid
