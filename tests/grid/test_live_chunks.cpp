// Fields that follow an embedded body (live_chunks.hpp): which chunks are live, that the
// released pages stay released through setup, cycles and solves, and that releasing changes no
// result.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <utility>
#include <vector>

#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/live_chunks.hpp"
#include "mgelastic/grid/multigrid.hpp"
#include "mgelastic/grid/residual.hpp"
#include "mgelastic/grid/transfer.hpp"

namespace mgelastic::grid {
namespace {

// A ball of radius 0.3 in the unit box (n^3 cells), its cells below y = 0.3 fixed, under
// gravity: most of the box is far from the body.
ElasticityProblem<3> ball_problem(int n, double poisson_ratio) {
  ElasticityProblem<3> problem;
  problem.lattice = Lattice<3>(IVec<3>::Constant(n), 1.0 / n);
  problem.material = {1e5, poisson_ratio};
  problem.cells.assign(problem.lattice.size(), CellType::EXTERIOR);
  const Vec<3> center = Vec<3>::Constant(0.5);
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(problem.lattice.size()); ++k) {
    if (!problem.lattice.is_real(problem.lattice.coords(k))) continue;
    const Vec<3> c = problem.lattice.cell_center(k);
    if ((c - center).norm() < 0.3)
      problem.cells[k] = c.y() < 0.3 ? CellType::DIRICHLET : CellType::INTERIOR;
  }
  problem.body_force = [](const Vec<3>&) { return Vec<3>(0.0, -1e3, 0.0); };
  return problem;
}

// Pages in the address stretches that are present and mapped by this process alone.
long mapped_pages(const std::vector<std::pair<std::uintptr_t, std::uintptr_t>>& stretches) {
  const int fd = open("/proc/self/pagemap", O_RDONLY);
  if (fd < 0) return -1;
  const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  long mapped = 0;
  for (const auto& [begin, end] : stretches)
    for (std::uintptr_t p = begin; p < end; p += page) {
      std::uint64_t entry = 0;
      if (pread(fd, &entry, sizeof entry, static_cast<off_t>(p / page * sizeof entry)) !=
          sizeof entry) {
        close(fd);
        return -1;
      }
      const bool present = (entry >> 63) & 1, exclusive = (entry >> 56) & 1;
      mapped += present && exclusive;
    }
  close(fd);
  return mapped;
}

// Whether a read of a never-written anonymous page maps the shared zero page (no memory of its
// own), as the release of dead pages assumes. Some kernels give every read fault a page of its
// own (seen: Linux 6.18 on the project's virtual machines, 2026-12-06); there a released page
// that a kernel reads (a stencil's neighbour, a zero load) holds memory again, and the page
// table cannot tell it from a written one.
bool reads_map_the_zero_page() {
  const auto page = static_cast<std::size_t>(sysconf(_SC_PAGESIZE));
  void* p = mmap(nullptr, page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) return false;
  const char value = *static_cast<const volatile char*>(p);
  const auto begin = reinterpret_cast<std::uintptr_t>(p);
  const long mapped = value == 0 ? mapped_pages({{begin, begin + page}}) : -1;
  munmap(p, page);
  return mapped == 0;
}

// Pages in the address stretches that are mapped to memory of their own (written since they
// were released); reading a released page maps the shared zero page, which holds none. -1 where
// the page table cannot be read or cannot tell reads from writes (reads_map_the_zero_page).
long written_pages(const std::vector<std::pair<std::uintptr_t, std::uintptr_t>>& stretches) {
  static const bool distinguishes = reads_map_the_zero_page();
  if (!distinguishes) return -1;
  return mapped_pages(stretches);
}

constexpr const char* kNoPageTable =
    "the page table cannot tell released pages that were read from written ones here "
    "(/proc/self/pagemap unreadable, or read faults map pages of their own)";

// Pages of v that overlap no live chunk and were written since they were released.
template <typename T>
long written_dead_pages(const FieldArray<T>& v, const LiveChunks& live) {
  return written_pages(released_stretches(v, live));
}

template <typename Scalar>
long written_dead_pages(const Level<3, Scalar>& level) {
  long written = 0;
  for (int f = 0; f <= 3; ++f)
    for (const auto* field : {&level.x[f], &level.b[f], &level.r[f]}) {
      const long w = written_dead_pages(*field, level.live);
      if (w < 0) return -1;
      written += w;
    }
  return written;
}

// Every variable's chunk is live, and so are the chunks of its neighbours along y and z (the
// row-wise kernels write there).
TEST(LiveChunks, HoldEveryVariableAndItsNeighbourRows) {
  const ElasticityProblem<3> problem = ball_problem(40, 0.3);
  const auto level = build_level<3, float>(problem.lattice, problem.cells, problem.material,
                                           problem.boundary_stress, nullptr);
  ASSERT_FALSE(level.live.all_live());
  EXPECT_LT(level.live.live_count(), level.live.live.size());
  const std::ptrdiff_t sy = level.lattice.stride(1), sz = level.lattice.stride(2);
  const auto n = static_cast<std::ptrdiff_t>(level.size());
  for (int f = 0; f <= 3; ++f)
    for (std::ptrdiff_t k = 0; k < n; ++k) {
      if (level.kind(f, k) == VarKind::INACTIVE) continue;
      for (std::ptrdiff_t d : {std::ptrdiff_t{0}, -sy, sy, -sz, sz})
        if (k + d >= 0 && k + d < n) {
          ASSERT_TRUE(level.live.any_live(k + d, k + d + 1)) << k;
        }
    }
  std::size_t released = 0;
  for (int f = 0; f <= 3; ++f) released += released_bytes(level.x[f], level.live);
  EXPECT_GT(released, 0u);
}

// Each row's span runs from its first to its last point with a variable (none: {0, 0}).
TEST(LiveChunks, RowSpansRunFromTheFirstToTheLastVariable) {
  const ElasticityProblem<3> problem = ball_problem(40, 0.3);
  const auto level = build_level<3, float>(problem.lattice, problem.cells, problem.material,
                                           problem.boundary_stress, nullptr);
  const std::ptrdiff_t n = level.lattice.padded(0);
  ASSERT_EQ(level.live.row_length, n);
  ASSERT_EQ(level.live.span.size(), level.size() / static_cast<std::size_t>(n));
  std::size_t spanned = 0;
  for (std::size_t row = 0; row < level.live.span.size(); ++row) {
    std::ptrdiff_t first = n, last = -1;
    for (std::ptrdiff_t i = 0; i < n; ++i)
      for (int f = 0; f <= 3; ++f)
        if (level.kind(f, static_cast<std::ptrdiff_t>(row) * n + i) != VarKind::INACTIVE)
          first = std::min(first, i), last = std::max(last, i);
    const auto expected = last < 0
                              ? std::array<std::int32_t, 2>{0, 0}
                              : std::array<std::int32_t, 2>{static_cast<std::int32_t>(first),
                                                            static_cast<std::int32_t>(last + 1)};
    ASSERT_EQ(level.live.span[row], expected) << row;
    spanned += static_cast<std::size_t>(expected[1] - expected[0]);
  }
  EXPECT_LT(spanned, level.live.live_count() * kLiveChunk);  // the spans skip most live points
  // A box keeps no spans: every chunk is live.
  BoxSpec spec;
  spec.cells = 16;
  const ElasticityProblem<3> box = make_box_problem<3>(spec);
  const auto full =
      build_level<3, float>(box.lattice, box.cells, box.material, box.boundary_stress, nullptr);
  EXPECT_TRUE(full.live.all_live());
  EXPECT_TRUE(full.live.span.empty());
}

// The prolongation visits only the spans: the same correction bit for bit as over whole rows.
TEST(LiveChunks, ProlongationOverTheSpansEqualsTheWholeRows) {
  Multigrid<3, float> multigrid(ball_problem(40, 0.45));
  ASSERT_GE(multigrid.levels(), 2);
  Level<3, float> coarse = multigrid.level(1);
  std::uint32_t state = 12345;
  for (int f = 0; f <= 3; ++f)
    for (std::size_t k = 0; k < coarse.size(); ++k)
      if (coarse.kind(f, static_cast<std::ptrdiff_t>(k)) != VarKind::INACTIVE) {
        state = state * 1664525u + 1013904223u;
        coarse.x[f][k] = static_cast<float>(state >> 8) / float(1 << 24) - 0.5f;
      }
  Level<3, float> spans = multigrid.level(0), rows = multigrid.level(0);
  ASSERT_FALSE(spans.live.span.empty());
  rows.live.span.clear();
  prolongate_correction(coarse, spans);
  prolongate_correction(coarse, rows);
  std::size_t moved = 0;
  for (int f = 0; f <= 3; ++f)
    for (std::size_t k = 0; k < spans.size(); ++k) {
      ASSERT_EQ(spans.x[f][k], rows.x[f][k]) << f << " " << k;
      moved += spans.x[f][k] != 0 ? 1 : 0;
    }
  EXPECT_GT(moved, 1000u);
}

// The fields of every level are zero in their dead chunks (live_chunks.hpp's invariant).
void expect_zero_in_dead_chunks(const Multigrid<3, float>& multigrid) {
  for (int l = 0; l < multigrid.levels(); ++l) {
    const Level<3, float>& level = multigrid.level(l);
    for (int f = 0; f <= 3; ++f)
      for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(level.size()); ++k)
        if (!level.live.any_live(k, k + 1)) {
          ASSERT_TRUE(level.x[f][k] == 0 && level.b[f][k] == 0 &&
                      (level.r[f].empty() || level.r[f][k] == 0))
              << l;
        }
  }
}

// Mixed precision on the ball: the same residuals with and without released pages, the released
// pages of every level (and of the double solution level) never written in setup, cycles or a
// solve, and the fields zero there.
TEST(LiveChunks, ReleasedPagesStayReleasedAndChangeNoResult) {
  const ElasticityProblem<3> problem = ball_problem(48, 0.45);
  MultigridOptions dense_options;
  dense_options.release_dead_pages = false;
  Multigrid<3, float> sparse(problem), dense(problem, dense_options);
  ASSERT_GT(dense.bytes(), sparse.bytes());
  std::vector<double> sparse_residuals{sparse.residual()}, dense_residuals{dense.residual()};
  for (int cycle = 0; cycle < 4; ++cycle) {
    sparse_residuals.push_back(sparse.vcycle());
    dense_residuals.push_back(dense.vcycle());
  }
  EXPECT_EQ(sparse_residuals, dense_residuals);
  const SolveReport report = sparse.solve(1e-9, 40);
  EXPECT_TRUE(report.converged);
  expect_zero_in_dead_chunks(sparse);
  const long written = written_dead_pages(sparse.solution_level());
  if (written < 0) GTEST_SKIP() << kNoPageTable;
  EXPECT_EQ(written, 0);
  for (int l = 0; l < sparse.levels(); ++l) EXPECT_EQ(written_dead_pages(sparse.level(l)), 0) << l;
  // The check sees a write: a zero stored into a released page maps a page of its own.
  Level<3, float>& fine = sparse.level(0);
  const auto stretches = released_stretches(fine.x[0], fine.live);
  ASSERT_FALSE(stretches.empty());
  *reinterpret_cast<float*>(stretches.front().first) = 0.0f;
  EXPECT_GT(written_dead_pages(fine), 0);
}

// Mixed box under gravity along -y, with and without released pages, whose level `loads` holds the
// loads: b of u_x, u_z and p released but for the partial pages at the ends, little of u_y's;
// the accounting differs by what was released (the box has no dead chunk); three cycles give the
// same residuals and write no released page (page table; skipped where it cannot be read).
template <typename Scalar>
void expect_zero_load_pages(Multigrid<3, float>& released, Multigrid<3, float>& kept,
                            const Level<3, Scalar>& loads) {
  for (int f : {0, 2, 3})
    EXPECT_GT(loads.zero_load_bytes(f), loads.b[f].size() * sizeof(Scalar) * 9 / 10) << f;
  EXPECT_LT(loads.zero_load_bytes(1), loads.b[1].size() * sizeof(Scalar) / 10);
  std::size_t zero_bytes = 0;
  for (int f = 0; f <= 3; ++f) zero_bytes += loads.zero_load_bytes(f);
  // Releasing keeps its own record of the live rows (live_chunks.hpp), counted by bytes().
  std::size_t record = 0;
  const auto count_record = [&](const auto& level) {
    record += level.live.live.capacity() + level.live.span.capacity() * sizeof(level.live.span[0]);
  };
  const Multigrid<3, float>& view = released;  // const access: the records stay
  for (int l = 0; l < view.levels(); ++l) count_record(view.level(l));
  if (!view.single_precision()) count_record(view.solution_level());
  EXPECT_EQ(kept.bytes() + record - released.bytes(), zero_bytes);
  std::vector<double> released_residuals{released.residual()}, kept_residuals{kept.residual()};
  for (int cycle = 0; cycle < 3; ++cycle) {
    released_residuals.push_back(released.vcycle());
    kept_residuals.push_back(kept.vcycle());
  }
  EXPECT_EQ(released_residuals, kept_residuals);
  for (int f = 0; f <= 3; ++f) {
    const long written = written_pages(loads.zero_load_pages[f]);
    if (written < 0) GTEST_SKIP() << kNoPageTable;
    EXPECT_EQ(written, 0) << f;
    for (const auto& [p0, p1] : loads.zero_load_pages[f])
      ASSERT_EQ(*reinterpret_cast<const Scalar*>(p0), Scalar(0)) << f;
  }
}

ElasticityProblem<3> gravity_box(double poisson_ratio) {
  BoxSpec spec;
  spec.cells = 80;  // 82^3 values of 8 bytes span two 2 MiB ranges
  spec.poisson_ratio = poisson_ratio;
  return make_box_problem<3>(spec);
}

// Mixed precision: the double solution level's b. The accounting counts the pages again once a
// caller takes the level for writing (and a copy has none); set_loads releases them again.
TEST(LiveChunks, ZeroLoadPagesAreReleasedAndStayUnwritten) {
  const ElasticityProblem<3> problem = gravity_box(0.45);
  MultigridOptions kept_options;
  kept_options.release_dead_pages = false;
  Multigrid<3, float> released(problem), kept(problem, kept_options);
  const Level<3, double>& solution = std::as_const(released).solution_level();
  std::size_t zero_bytes = 0;
  for (int f = 0; f <= 3; ++f) zero_bytes += solution.zero_load_bytes(f);
  expect_zero_load_pages(released, kept, solution);
  const Level<3, double> copy = solution;  // new arrays: none of them released
  for (int f = 0; f <= 3; ++f) EXPECT_EQ(copy.zero_load_bytes(f), 0u) << f;
  released.solution_level();
  for (int f = 0; f <= 3; ++f) EXPECT_EQ(solution.zero_load_bytes(f), 0u) << f;
  released.set_loads(problem);
  std::size_t again = 0;
  for (int f = 0; f <= 3; ++f) again += solution.zero_load_bytes(f);
  EXPECT_EQ(again, zero_bytes);
}

// The fields whose loads are zero (gravity along y: u_x, u_z, p) are recorded, and the residual
// does not read their b; it equals the residual that reads every b. A caller's write through
// solution_level() forgets the record, so the residual sees the new load.
TEST(LiveChunks, ZeroLoadFieldsAreNotReadUntilWritten) {
  const ElasticityProblem<3> problem = gravity_box(0.45);
  Multigrid<3, float> mg(problem);
  const Level<3, double>& solution = std::as_const(mg).solution_level();
  EXPECT_EQ(solution.zero_load, (std::array<bool, 4>{true, false, true, true}));
  Level<3, double> reads_every_b = solution;
  reads_every_b.zero_load = {};
  const double before = mg.residual();
  EXPECT_EQ(before, fresh_residual_norm(reads_every_b));
  Level<3, double>& writable = mg.solution_level();
  EXPECT_EQ(writable.zero_load, (std::array<bool, 4>{}));
  std::ptrdiff_t k = 0;
  while (writable.relaxation(0, k) != Relaxation::DISTRIBUTIVE) ++k;
  writable.b[0][k] = 1.0;
  reads_every_b.b[0][k] = 1.0;
  const double norm = mg.residual();
  EXPECT_EQ(norm, fresh_residual_norm(reads_every_b));
  EXPECT_NE(norm, before);
}

// Single precision: the float finest level holds the solution and its b the loads; level() (the
// mutable access) forgets them.
TEST(LiveChunks, ZeroLoadPagesOfTheSinglePrecisionFinestLevel) {
  const ElasticityProblem<3> problem = gravity_box(0.3);
  MultigridOptions options;
  options.mixed_precision = false;
  MultigridOptions kept_options = options;
  kept_options.release_dead_pages = false;
  Multigrid<3, float> released(problem, options), kept(problem, kept_options);
  ASSERT_TRUE(released.single_precision());
  const Level<3, float>& fine = released.finest();
  expect_zero_load_pages(released, kept, fine);
  released.level(0);
  for (int f = 0; f <= 3; ++f) EXPECT_EQ(fine.zero_load_bytes(f), 0u) << f;
}

// Clearing a right-hand side before new loads writes only the chunks holding a nonzero: pages
// released as zero stay released, and the nonzero one is cleared. zero_where_live sees both.
TEST(LiveChunks, ClearingLoadsLeavesZeroPagesUnwritten) {
  const ElasticityProblem<3> problem = gravity_box(0.3);
  Multigrid<3, float> mg(problem);
  const Level<3, double>& solution = std::as_const(mg).solution_level();
  FieldArray<double> b(solution.b[0].size(), 0.0);
  const auto released = release_zero_pages(b, solution.live);
  ASSERT_GE(released.size(), 1u);
  const std::size_t k = b.size() / 2;
  b[k] = 1.0;
  EXPECT_FALSE(zero_where_live(b, solution.live));
  zero_live_where_nonzero(b, solution.live);
  EXPECT_EQ(b[k], 0.0);
  EXPECT_TRUE(zero_where_live(b, solution.live));
  // Away from the 2 MiB range of b[k] (whose write may have faulted in a huge page).
  const auto range = reinterpret_cast<std::uintptr_t>(&b[k]) & ~std::uintptr_t((2 << 20) - 1);
  std::vector<std::pair<std::uintptr_t, std::uintptr_t>> away;
  for (const auto& [p0, p1] : released) {
    if (p0 < range) away.emplace_back(p0, std::min(p1, range));
    if (p1 > range + (2 << 20)) away.emplace_back(std::max(p0, range + (2 << 20)), p1);
  }
  ASSERT_FALSE(away.empty());
  const long written = written_pages(away);
  if (written < 0) GTEST_SKIP() << kNoPageTable;
  EXPECT_EQ(written, 0);
}

}  // namespace
}  // namespace mgelastic::grid
