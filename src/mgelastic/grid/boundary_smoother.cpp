#include "mgelastic/grid/boundary_smoother.hpp"

#include "mgelastic/core/error.hpp"

namespace mgelastic::grid {
namespace {

// Right-hand side minus the moved boundary stresses of band momentum row m, from the compact
// rows (band_u's CSR may be dropped).
template <int Dim, typename Scalar>
Scalar band_rhs(const Level<Dim, Scalar>& level, std::size_t m) {
  const BandKernel<Scalar>& kernel = level.band_kernel;
  return level.b[kernel.field[m]][kernel.target[m]] - kernel.constant[m];
}

// The kernels are derived from band_u and band_p: rebuilt when their rows changed (tests edit
// levels), band_u's never when its CSR was dropped (drop_band_csr).
template <int Dim, typename Scalar>
void refresh_band_pressure_kernel(Level<Dim, Scalar>& level) {
  if (level.band_p_kernel.rows() != level.band_p.rows()) build_band_pressure_kernel(level);
}
// Both; returns whether band_u's was rebuilt (its rhs then too).
template <int Dim, typename Scalar>
bool refresh_band_kernel(Level<Dim, Scalar>& level) {
  if (level.band_u.rows() != 0 && level.band_kernel.rows() != level.band_u.rows()) {
    build_band_kernel(level);      // band_p_kernel with it
    level.band_block_shapes = {};  // built from the old patterns: blocks read the rows
    return true;
  }
  refresh_band_pressure_kernel(level);
  return false;
}

// The band momentum rows as the sweeps see them (band_kernel.hpp): raw field pointers and the
// compact rows, so the inner loops do no vector indirection.
template <int Dim, typename Scalar>
struct BandSweep {
  std::array<Scalar*, Dim + 1> x;
  const BandKernel<Scalar>& kernel;
  const Scalar* block_inverse;
  const std::uint32_t* inverse_id;
  const BandBlockShapes<Scalar>* shapes = nullptr;  // the blocks' dense form, where built

  explicit BandSweep(Level<Dim, Scalar>& level)
      : kernel(level.band_kernel),
        block_inverse(level.band_block_inverse.data()),
        inverse_id(level.band_block_inverse_id.data()) {
    for (int f = 0; f <= Dim; ++f) x[f] = level.x[f].data();
    address_entries<Scalar>(level.band_kernel, {x.data(), x.size()});
    if (level.band_block_shapes.built_for(level.band_blocks.size())) {
      address_columns<Scalar>(level.band_block_shapes, {x.data(), x.size()});
      shapes = &level.band_block_shapes;
    }
  }

  Scalar residual(std::uint32_t m) const {
    return kernel.rhs[m] - kernel.addressed_row_sum(x[0], m);
  }

  // Moves the row's variable and keeps its eliminated pressures exact.
  void move(std::uint32_t m, Scalar delta) const {
    const std::uint32_t pattern = kernel.pattern[m];
    const std::ptrdiff_t self = kernel.target[m];
    x[kernel.field[m]][self] += delta;
    for (int c = 0; c < kernel.pressure_count[pattern]; ++c)
      x[Dim][self + kernel.pressure_offset[pattern][c]] -=
          kernel.pressure_factor[pattern][c] * delta;
  }

  void relax_row(std::uint32_t m) const {
    move(m, residual(m) / kernel.schur_diagonal[kernel.pattern[m]]);
  }

  // Solves the band faces of one eliminated cell together: delta = S_loc^-1 r.
  void relax_block(const std::array<std::uint32_t, 2 * Dim>& members, std::size_t block) const {
    constexpr int B = 2 * Dim;
    std::array<Scalar, B> r{};
    if (shapes) {
      alignas(32) Scalar sums[BandBlockShapes<Scalar>::kLanes];
      shapes->row_sums(x[0], kernel.target[members[0]], block, sums);
      for (int a = 0; a < B && members[a] != UINT32_MAX; ++a)
        r[a] = kernel.rhs[members[a]] - sums[a];
    } else {
      for (int a = 0; a < B && members[a] != UINT32_MAX; ++a) r[a] = residual(members[a]);
    }
    const Scalar* inverse = block_inverse + static_cast<std::size_t>(inverse_id[block]) * B * B;
    for (int a = 0; a < B && members[a] != UINT32_MAX; ++a) {
      Scalar delta = 0;
      for (int b = 0; b < B; ++b) delta += inverse[a * B + b] * r[b];
      move(members[a], delta);
    }
  }
};

// `sweeps` sweeps over a colored schedule in `order` (boundary_smoother.hpp): relax(block)
// relaxes one block's rows once; the blocks of one color run in parallel.
template <typename Schedule, typename Relax>
void sweep_colored(const Schedule& schedule, int sweeps, BandSweepOrder order, Relax&& relax) {
  const bool local = order == BandSweepOrder::BLOCK_LOCAL;  // AUTOMATIC is resolved by the caller
  for (int sweep = 0; sweep < (local ? 1 : sweeps); ++sweep) {
    for (const auto& color : schedule) {
      const auto count = static_cast<std::ptrdiff_t>(color.size());
#pragma omp parallel for schedule(dynamic, 1)
      for (std::ptrdiff_t b = 0; b < count; ++b)
        for (int pass = 0; pass < (local ? sweeps : 1); ++pass) relax(color[b]);
    }
  }
}

// One block's items of a run schedule (band_runs.hpp), in order.
template <int Dim, typename Scalar>
void relax_block_items(const Level<Dim, Scalar>& level, const BandSweep<Dim, Scalar>& band,
                       const std::vector<std::uint32_t>& items) {
  const BandRuns<Dim, Scalar>& runs = level.band_runs;
  for (const std::uint32_t item : items) {
    const std::uint32_t index = item & kBandItemIndexMask;
    switch (static_cast<BandItem>(item & ~kBandItemIndexMask)) {
      case BandItem::RUN: {
        const BandRun& run = runs.runs[index];
        relax_band_run<Dim, Scalar>(band.x, band.kernel, runs.shapes[run.shape], run,
                                    runs.rows.data());
        break;
      }
      case BandItem::CELL_BLOCK:
        band.relax_block(level.band_blocks[index], index);
        break;
      case BandItem::POINT_ROW:
        band.relax_row(index);
        break;
    }
  }
}

}  // namespace

template <int Dim, typename Scalar>
void refresh_band_rhs(Level<Dim, Scalar>& level) {
  refresh_band_kernel(level);
  auto& rhs = level.band_kernel.rhs;
  const auto count = static_cast<std::ptrdiff_t>(level.band_kernel.rows());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t m = 0; m < count; ++m) rhs[m] = band_rhs(level, m);
}

BandSweepOrder band_sweep_order(const std::string& name) {
  if (name == "auto") return BandSweepOrder::AUTOMATIC;
  if (name == "block_local") return BandSweepOrder::BLOCK_LOCAL;
  if (name == "band_wide") return BandSweepOrder::BAND_WIDE;
  throw Error("unknown band sweep order '" + name + "' (auto, block_local or band_wide)",
              {.pointer = "solver/smoother_order"});
}

template <int Dim, typename Scalar>
void update_band_pressures(Level<Dim, Scalar>& level) {
  const auto& rows = level.band_p;
  const auto count = static_cast<std::ptrdiff_t>(rows.rows());
  refresh_band_pressure_kernel(level);
  std::array<Scalar*, Dim + 1> x;
  for (int f = 0; f <= Dim; ++f) x[f] = level.x[f].data();
  address_entries<Scalar>(level.band_p_kernel, {x.data(), x.size()});
  // Each eliminated pressure depends on u only: independent updates, read through the compact
  // rows (the same products in the same order as band_p's: a few bytes per row instead of ~70).
  const BandKernel<Scalar>& kernel = level.band_p_kernel;
  const Scalar* b = level.b[Dim].data();
  const Scalar* inverse = level.band_p_inverse.data();
  const Scalar* constant = rows.constant.data();
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t m = 0; m < count; ++m) {
    const std::uint32_t k = kernel.target[m];
    x[Dim][k] = inverse[m] * ((b[k] - constant[m]) - kernel.addressed_row_sum(x[0], m));
  }
}

template <int Dim, typename Scalar>
void band_gauss_seidel(Level<Dim, Scalar>& level, int sweeps,
                       const std::vector<std::uint32_t>* subset, BandSweepOrder order,
                       BandRhs rhs) {
  if (refresh_band_kernel(level)) rhs = BandRhs::REFRESH;  // a rebuilt kernel's rhs is zero
  update_band_pressures(level);
  if (rhs == BandRhs::REFRESH && subset)
    for (std::uint32_t m : *subset) level.band_kernel.rhs[m] = band_rhs(level, m);
  else if (rhs == BandRhs::REFRESH)
    refresh_band_rhs(level);
  const BandSweep<Dim, Scalar> band(level);
  const BandRuns<Dim, Scalar>& runs = level.band_runs;
  if (subset) {
    for (int sweep = 0; sweep < sweeps; ++sweep)
      for (std::uint32_t m : *subset) band.relax_row(m);
  } else if (runs.valid_for(level.band_kernel.rows())) {
    sweep_colored(runs.schedule, sweeps, order, [&](const std::vector<std::uint32_t>& items) {
      relax_block_items(level, band, items);
    });
  } else {
    sweep_colored(level.band_schedule, sweeps, order,
                  [&](const typename Level<Dim, Scalar>::BandWork& work) {
                    for (std::uint32_t e : work.cell_blocks)
                      band.relax_block(level.band_blocks[e], e);
                    for (std::uint32_t m : work.point_rows) band.relax_row(m);
                  });
  }
}

template <int Dim, typename Scalar>
void band_gauss_seidel(Level<Dim, Scalar>& level, int sweeps,
                       const typename Level<Dim, Scalar>::RowSchedule& schedule,
                       BandSweepOrder order, BandRhs rhs) {
  if (refresh_band_kernel(level)) rhs = BandRhs::REFRESH;  // a rebuilt kernel's rhs is zero
  update_band_pressures(level);
  const BandSweep<Dim, Scalar> band(level);
  if (rhs == BandRhs::REFRESH) {
    auto& values = level.band_kernel.rhs;
    sweep_colored(schedule, 1, order, [&](const std::vector<std::uint32_t>& rows) {
      for (std::uint32_t m : rows) values[m] = band_rhs(level, m);
    });
  }
  sweep_colored(schedule, sweeps, order, [&](const std::vector<std::uint32_t>& rows) {
    for (std::uint32_t m : rows) band.relax_row(m);
  });
}

template <int Dim, typename Scalar>
void back_substitute_traction(Level<Dim, Scalar>& level) {
  const Scalar h = static_cast<Scalar>(level.lattice.h);
  const Scalar mu = level.mu;
  // Normal rules are independent: each writes its own traction face from a face that is not
  // one (two traction faces of a cell make a thin rule) and a pressure.
  const auto& normal = level.traction.normal;
  const auto normal_count = static_cast<std::ptrdiff_t>(normal.size());
#pragma omp parallel for schedule(static) if (normal_count > 4096)
  for (std::ptrdiff_t q = 0; q < normal_count; ++q) {
    const auto& rule = normal[q];
    // P_ii = 2 mu (u_upper - u_lower) / h - mu p = sigma.
    level.at(rule.face) =
        level.at(rule.partner) + rule.sign * h * (rule.sigma + mu * level.at(rule.cell)) / (2 * mu);
  }
  for (const auto& rule : level.traction.thin) {
    Scalar mean = 0;
    for (std::uint32_t nb : rule.neighbors) mean += level.at(nb);
    if (!rule.neighbors.empty()) mean /= static_cast<Scalar>(rule.neighbors.size());
    const Scalar half_jump = h * (rule.sigma + mu * level.at(rule.cell)) / (4 * mu);
    level.at(rule.lower) = mean - half_jump;
    level.at(rule.upper) = mean + half_jump;
  }
  // Shear rules are independent too: their candidates read only faces known after the normal
  // pass (build_traction_rules), never a face set by a shear rule.
  const auto& shear = level.traction.shear;
  const auto shear_count = static_cast<std::ptrdiff_t>(shear.size());
#pragma omp parallel for schedule(static) if (shear_count > 4096)
  for (std::ptrdiff_t q = 0; q < shear_count; ++q) {
    const auto& rule = shear[q];
    Scalar sum = 0;
    for (const auto& c : level.traction.candidates(rule))
      sum += level.at(c.partner) + c.sign * (level.at(c.plus) - level.at(c.minus)) + c.sigma_term;
    level.at(rule.face) = sum / static_cast<Scalar>(rule.count);
  }
}

#define MGELASTIC_INSTANTIATE(D, S)                                                           \
  template void refresh_band_rhs<D, S>(Level<D, S>&);                                         \
  template void update_band_pressures<D, S>(Level<D, S>&);                                    \
  template void band_gauss_seidel<D, S>(Level<D, S>&, int, const std::vector<std::uint32_t>*, \
                                        BandSweepOrder, BandRhs);                             \
  template void band_gauss_seidel<D, S>(                                                      \
      Level<D, S>&, int, const typename Level<D, S>::RowSchedule&, BandSweepOrder, BandRhs);  \
  template void back_substitute_traction<D, S>(Level<D, S>&);
MGELASTIC_INSTANTIATE(2, float)
MGELASTIC_INSTANTIATE(2, double)
MGELASTIC_INSTANTIATE(3, float)
MGELASTIC_INSTANTIATE(3, double)
#undef MGELASTIC_INSTANTIATE

}  // namespace mgelastic::grid
