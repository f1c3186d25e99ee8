#include "mgelastic/grid/cycle_roofline.hpp"

#include <algorithm>
#include <utility>
#include <vector>

namespace mgelastic::grid {
namespace {

constexpr double kIndex = 4, kField = 1;  // std::uint32_t index, std::uint8_t field / kind

template <typename T>
double bytes_of(const std::vector<T>& v) {
  return static_cast<double>(v.size() * sizeof(T));
}

template <int Dim, typename Scalar>
double real_cells(const Level<Dim, Scalar>& level) {
  double cells = 1;
  for (int a = 0; a < Dim; ++a) cells *= level.lattice.cells[a];
  return cells;
}

// Band pressure rows from their compact form (Level::band_p_kernel): pattern, target, constant,
// b read and `per_row_scalars` more scalars (inverse, written values); the patterns stay cached.
template <int Dim, typename Scalar>
double band_pressure_rows_bytes(const Level<Dim, Scalar>& level, double per_row_scalars) {
  constexpr double S = sizeof(Scalar);
  return static_cast<double>(level.band_p.rows()) * (2 * kIndex + (2 + per_row_scalars) * S);
}

// Band momentum rows relaxed once each: compact row (pattern, target, field), rhs, own variable
// read + write, eliminated pressures read + write.
template <int Dim, typename Scalar>
double band_row_relaxations(const Level<Dim, Scalar>& level, std::size_t count_rows,
                            const std::vector<std::uint32_t>* subset) {
  constexpr double S = sizeof(Scalar);
  const BandKernel<Scalar>& kernel = level.band_kernel;
  double pressures = 0;
  auto add = [&](std::uint32_t m) {
    if (m < kernel.pattern.size()) pressures += kernel.pressure_count[kernel.pattern[m]];
  };
  if (subset) {
    for (std::uint32_t m : *subset) add(m);
  } else {
    for (std::uint32_t m = 0; m < kernel.pattern.size(); ++m) add(m);
  }
  return static_cast<double>(count_rows) * (2 * kIndex + kField + 3 * S) + pressures * 2 * S;
}

// refresh_band_rhs over `rows` band rows: b and constant read, rhs written.
template <typename Scalar>
double band_rhs_bytes(std::size_t rows) {
  return static_cast<double>(rows) * (kField + kIndex + 3 * sizeof(Scalar));
}

// A band_gauss_seidel call over `subset` (all band rows when null), its rhs refreshed or not
// (BandRhs; the V-cycle refreshes once per visit of a level).
template <int Dim, typename Scalar>
double band_call_bytes(const Level<Dim, Scalar>& level, int sweeps,
                       const std::vector<std::uint32_t>* subset, bool refresh = true) {
  const std::size_t rows = subset ? subset->size() : level.band_kernel.rows();
  // The exact pressure update: band pressure rows with their inverse, p written.
  const double pressures = band_pressure_rows_bytes(level, 2);
  return pressures + (refresh ? band_rhs_bytes<Scalar>(rows) : 0.0) +
         sweeps * band_row_relaxations(level, rows, subset);
}

template <int Dim, typename Scalar>
double traction_bytes(const Level<Dim, Scalar>& level) {
  constexpr double S = sizeof(Scalar);
  const auto& t = level.traction;
  double total = bytes_of(t.normal) + 4 * S * static_cast<double>(t.normal.size());
  for (const auto& rule : t.thin)
    total += sizeof(rule) + bytes_of(rule.neighbors) +
             S * static_cast<double>(rule.neighbors.size() + 3);
  total += bytes_of(t.shear) + bytes_of(t.shear_candidates) +
           S * static_cast<double>(3 * t.shear_candidates.size() + t.shear.size());
  return total;
}

// One smoothing inside a V-cycle (Sec. 5.2): band, distributive, band, traction
// back-substitution; the band rhs is current.
template <int Dim, typename Scalar>
double smoothing_band_bytes(const Level<Dim, Scalar>& level, int sweeps) {
  return 2 * band_call_bytes(level, sweeps, nullptr, false) + traction_bytes(level);
}

template <int Dim, typename Scalar>
double norm_bytes(const Level<Dim, Scalar>& level) {
  return static_cast<double>((Dim + 1) * level.size() * sizeof(Scalar));
}

}  // namespace

template <int Dim, typename Scalar>
double distributive_sweep_bytes(const Level<Dim, Scalar>& level) {
  // Block by block, the four passes in cache: x, b, the relaxation codes and the cell types
  // read once, x written once.
  constexpr double S = sizeof(Scalar), F = Dim + 1;
  return real_cells(level) * (3 * F * S + (F + 1) * kField);
}

template <int Dim, typename Scalar>
double band_gauss_seidel_bytes(const Level<Dim, Scalar>& level, int sweeps) {
  return band_call_bytes(level, sweeps, nullptr);
}

template <int Dim, typename Scalar>
double residual_bytes(const Level<Dim, Scalar>& level) {
  constexpr double S = sizeof(Scalar), F = Dim + 1;
  const double stencil = static_cast<double>(level.size()) * F * (3 * S + kField);
  // Band momentum rows from the compact form: row (pattern, target, field, constant), b read,
  // r written, the row's own neighbourhood of x (~ one cache line per row).
  const double band_u =
      static_cast<double>(level.band_kernel.rows()) * (2 * kIndex + kField + 3 * S);
  const double band = band_u + band_pressure_rows_bytes(level, 3);
  return stencil + band;
}

template <int Dim, typename Scalar>
double restriction_bytes(const Level<Dim, Scalar>& fine, const Level<Dim, Scalar>& coarse) {
  constexpr double S = sizeof(Scalar), F = Dim + 1;
  return static_cast<double>(fine.size()) * F * S +
         static_cast<double>(coarse.size()) * F * (2 * S + kField);
}

template <int Dim, typename Scalar>
double fused_residual_restriction_bytes(const Level<Dim, Scalar>& fine,
                                        const Level<Dim, Scalar>& coarse) {
  constexpr double S = sizeof(Scalar), F = Dim + 1;
  return residual_bytes(fine) - static_cast<double>(fine.size()) * F * S +
         static_cast<double>(coarse.size()) * F * (2 * S + kField);
}

template <int Dim, typename Scalar>
double prolongation_bytes(const Level<Dim, Scalar>& coarse, const Level<Dim, Scalar>& fine) {
  constexpr double S = sizeof(Scalar), F = Dim + 1;
  return static_cast<double>(coarse.size()) * F * (S + kField) +
         static_cast<double>(fine.size()) * F * (2 * S + kField);
}

// The norm of a level's residual without writing it (fresh_residual_norm).
template <int Dim, typename Scalar>
double fresh_norm_bytes(const Level<Dim, Scalar>& level) {
  return residual_bytes(level) - (Dim + 1) * sizeof(Scalar) * static_cast<double>(level.size());
}

template <int Dim, typename Scalar>
PhaseSeconds cycle_bytes(const Multigrid<Dim, Scalar>& mg) {
  PhaseSeconds bytes;
  const int coarsest = mg.levels() - 1;
  const MultigridOptions& options = mg.options();
  // Visits per level: a W-cycle visits the coarse problem twice below every level but the
  // next-to-coarsest (Multigrid::correct).
  std::vector<double> visits(mg.levels(), 1.0);
  for (int l = 0; l < coarsest; ++l)
    visits[l + 1] = visits[l] * (options.cycle == CycleType::W && l + 1 < coarsest ? 2.0 : 1.0);
  // Block-local band sweeps stream a call's rows once; its later sweeps read them from cache.
  const bool local = options.band_sweep_order == BandSweepOrder::BLOCK_LOCAL;
  const int smoothing_sweeps = local ? 1 : mg.boundary_sweeps();
  const int relocation_sweeps =
      local ? std::min(1, options.relocation_sweeps) : options.relocation_sweeps;
  for (int l = 0; l < coarsest; ++l) {
    const Level<Dim, Scalar>& level = mg.level(l);
    const Level<Dim, Scalar>& next = mg.level(l + 1);
    const double v = visits[l];
    bytes.boundary_smoothing +=
        v * (band_rhs_bytes<Scalar>(level.band_kernel.rows()) +
             2 * smoothing_band_bytes(level, smoothing_sweeps) +
             band_call_bytes(level, relocation_sweeps, &level.pre_restriction_rows, false) +
             band_call_bytes(level, relocation_sweeps, &level.post_prolongation_rows, false));
    bytes.interior_smoothing += v * 2 * distributive_sweep_bytes(level);
    if (mg.fuses_restriction(l)) {
      bytes.residual += v * fused_residual_restriction_bytes(level, next);
    } else {
      bytes.residual += v * residual_bytes(level);
      bytes.restriction += v * restriction_bytes(level, next);
    }
    bytes.prolongation += v * prolongation_bytes(next, level);
  }
  constexpr double S = sizeof(Scalar), F = Dim + 1;
  const Level<Dim, Scalar>& last = mg.level(coarsest);
  bytes.coarse_solve = visits[coarsest] * (2.0 * static_cast<double>(mg.coarse_factor_bytes()) +
                                           static_cast<double>(last.size()) * F * (2 * S + kField) +
                                           traction_bytes(last));
  // The local corrections' direct solves, once per cycle on the finest level.
  for (int i = 0; i < mg.local_corrections(); ++i)
    bytes.coarse_solve += static_cast<double>(mg.local_correction(i).apply_bytes());
  if (mg.single_precision()) {
    // The float finest level holds the solution: no refinement; the cycle's norm comes from the
    // rows without a residual array (fresh_residual_norm: no r written, no norm pass); the
    // solve's start is a float copy of x (read + written).
    const Level<Dim, Scalar>& fine = mg.finest();
    bytes.cycle_residual = fresh_norm_bytes(fine);
    bytes.solve_setup = bytes.cycle_residual + 2 * S * F * static_cast<double>(fine.size());
    return bytes;
  }
  const Level<Dim, double>& solution = mg.solution_level();
  const double n = static_cast<double>(solution.size());
  double residual_and_norm = residual_bytes(solution) + norm_bytes(solution);
  // b of a field recorded as zero (Level::zero_load) is not read; elsewhere b's pages released
  // as all-zero (record_zero_loads) read the shared zero page: no memory traffic either.
  for (int f = 0; f <= Dim; ++f)
    residual_and_norm -=
        solution.zero_load[f] ? 8 * n : static_cast<double>(solution.zero_load_bytes(f));
  if (static_cast<const void*>(&solution) != static_cast<const void*>(&mg.finest())) {
    // Add the float correction and zero it for the next cycle in the same pass (kind read, e
    // read + written, x read + written); the residual is written to and its norm read from the
    // float level's b (residual_into), not a double r.
    bytes.refinement = n * F * (kField + 2 * S + 16) + traction_bytes(solution);
    residual_and_norm -= 2 * n * F * (8 - S);
  }
  bytes.cycle_residual = residual_and_norm;
  bytes.solve_setup = residual_and_norm + 2 * 8 * F * n;
  return bytes;
}

namespace {

PhaseRoofline roofline_row(std::string name, double seconds, double bytes, double triad) {
  const double gb_per_s = seconds > 0 ? bytes / seconds / 1e9 : 0.0;
  return {std::move(name), seconds, bytes, gb_per_s, triad > 0 ? gb_per_s / triad : 0.0};
}

}  // namespace

template <int Dim, typename Scalar>
CycleRoofline cycle_roofline(const Multigrid<Dim, Scalar>& mg, const SolveReport& report,
                             double triad_gb_per_s) {
  const double cycles = std::max(1, report.cycles());
  const PhaseSeconds& seconds = mg.phase_seconds();
  PhaseSeconds bytes = cycle_bytes(mg);
  bytes.solve_setup /= cycles;  // once per solve
  if (mg.refinements() > 0) {
    // Mixed precision refines only on some cycles (MultigridOptions::refinement_reduction); the
    // others end with the float correction problem's residual norm.
    const double refined = mg.refinements() / cycles;
    bytes.refinement *= refined;
    bytes.cycle_residual =
        bytes.cycle_residual * refined + fresh_norm_bytes(mg.finest()) * mg.float_norms() / cycles;
  }
  CycleRoofline table;
  table.triad_gb_per_s = triad_gb_per_s;
  double phase_sum = 0, byte_sum = 0;
  for (int phase = 0; phase < PhaseSeconds::count; ++phase) {
    const double s = seconds[phase] / cycles;
    table.phases.push_back(
        roofline_row(PhaseSeconds::names[phase], s, bytes[phase], triad_gb_per_s));
    phase_sum += s;
    byte_sum += bytes[phase];
  }
  const double cycle_seconds = report.seconds / cycles;
  table.total = roofline_row("cycle", cycle_seconds, byte_sum, triad_gb_per_s);
  table.unattributed_seconds = cycle_seconds - phase_sum;
  return table;
}

#define MGELASTIC_INSTANTIATE(D, S)                                                                \
  template PhaseSeconds cycle_bytes<D, S>(const Multigrid<D, S>&);                                 \
  template CycleRoofline cycle_roofline<D, S>(const Multigrid<D, S>&, const SolveReport&, double); \
  template double distributive_sweep_bytes<D, S>(const Level<D, S>&);                              \
  template double band_gauss_seidel_bytes<D, S>(const Level<D, S>&, int);                          \
  template double residual_bytes<D, S>(const Level<D, S>&);                                        \
  template double restriction_bytes<D, S>(const Level<D, S>&, const Level<D, S>&);                 \
  template double fused_residual_restriction_bytes<D, S>(const Level<D, S>&, const Level<D, S>&);  \
  template double prolongation_bytes<D, S>(const Level<D, S>&, const Level<D, S>&);
MGELASTIC_INSTANTIATE(2, float)
MGELASTIC_INSTANTIATE(2, double)
MGELASTIC_INSTANTIATE(3, float)
MGELASTIC_INSTANTIATE(3, double)
#undef MGELASTIC_INSTANTIATE

}  // namespace mgelastic::grid
