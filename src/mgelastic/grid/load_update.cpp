#include "mgelastic/grid/load_update.hpp"

#include <algorithm>
#include <string>

#include "mgelastic/core/error.hpp"
#include "mgelastic/grid/boundary_smoother.hpp"
#include "mgelastic/grid/explicit_rows.hpp"

namespace mgelastic::grid {
namespace {

template <int Dim>
double stress(const BoundaryStress<Dim>& sigma, int i, int j, const Vec<Dim>& where) {
  return sigma ? sigma(i, j, where) : 0.0;
}

// The builder the level's rows came from. Row constants depend only on the cell typing and
// sigma (explicit_rows.cpp), but the other arguments are the build's too, so a row rebuilt here
// is the build's row.
template <int Dim, typename Scalar>
RowBuilder<Dim> row_builder(const Level<Dim, Scalar>& level, const BoundaryStress<Dim>& sigma) {
  return RowBuilder<Dim>(level.lattice, level.cells, static_cast<double>(level.mu), sigma,
                         static_cast<double>(level.inertia),
                         level.cell_weight.empty() ? nullptr : &level.cell_weight,
                         level.dirichlet_zero_depth, &level.dirichlet_wall_layers);
}

// Band momentum rows: by their targets in the compact kernel (the CSR form may be dropped,
// drop_band_csr), and in the CSR form where it is still held, row for row (same order).
template <int Dim, typename Scalar>
void replace_band_constants(Level<Dim, Scalar>& level, const RowBuilder<Dim>& builder) {
  BandKernel<Scalar>& kernel = level.band_kernel;
  for (std::size_t m = 0; m < kernel.rows(); ++m)
    kernel.constant[m] =
        static_cast<Scalar>(builder.momentum(kernel.field[m], kernel.target[m]).constant);
  if (level.band_u.rows() == kernel.rows()) level.band_u.constant = kernel.constant;
  SparseRows<Scalar>& pressure = level.band_p;
  for (std::size_t m = 0; m < pressure.rows(); ++m)
    pressure.constant[m] = static_cast<Scalar>(builder.pressure(pressure.target_index[m]).constant);
}

// The traction rules hold sigma at the points build_traction_rules (level.cpp) sampled it:
// normal faces at their centers, thin cells at their centers, shear candidates at the edge
// between the face and its partner, as h sigma / mu signed against the candidate's sign.
template <int Dim, typename Scalar>
void replace_rule_stresses(Level<Dim, Scalar>& level, const BoundaryStress<Dim>& sigma) {
  const auto& lat = level.lattice;
  const auto n = static_cast<std::uint32_t>(level.size());
  for (auto& rule : level.traction.normal) {
    const int i = static_cast<int>(rule.face / n);
    rule.sigma = static_cast<Scalar>(stress(sigma, i, i, lat.face_center(i, rule.face % n)));
  }
  for (auto& rule : level.traction.thin) {
    const int i = static_cast<int>(rule.lower / n);
    rule.sigma = static_cast<Scalar>(stress(sigma, i, i, lat.cell_center(rule.cell % n)));
  }
  const double h = lat.h, mu = level.mu;
  for (auto& rule : level.traction.shear) {
    const int i = static_cast<int>(rule.face / n);
    for (auto& candidate : level.traction.candidates(rule)) {
      // `plus` is u_j at the edge's own flat index (level.cpp add_shear_rule).
      const int j = static_cast<int>(candidate.plus / n);
      const double value = stress(sigma, i, j, lat.edge_center(i, j, candidate.plus % n));
      candidate.sigma_term =
          static_cast<Scalar>(candidate.sign < 0 ? h * value / mu : -h * value / mu);
    }
  }
}

template <int Dim>
bool same_lattice(const Lattice<Dim>& a, const Lattice<Dim>& b) {
  return a.cells == b.cells && a.h == b.h && a.origin == b.origin;
}

}  // namespace

template <int Dim, typename Scalar>
void write_load_right_hand_side(const ElasticityProblem<Dim>& problem, Level<Dim, Scalar>& level) {
  // Zero loads write nothing: b's pages that hold only zeros stay released (level.hpp).
  for (auto& b : level.b) zero_live_where_nonzero(b, level.live);
  for (const VariableLoad& load : problem.variable_loads)
    level.b[load.component][load.face] -= static_cast<Scalar>(load.density);
  if (!problem.body_force) return;
  for (int i = 0; i < Dim; ++i) {
    for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(level.size()); ++k) {
      if (level.kind(i, k) != VarKind::INTERIOR) continue;
      const auto f = static_cast<Scalar>(problem.body_force(level.lattice.face_center(i, k))[i]);
      if (f != Scalar(0)) level.b[i][k] -= f;
    }
  }
}

template <int Dim, typename Scalar>
void replace_boundary_stress(Level<Dim, Scalar>& level, const BoundaryStress<Dim>& sigma) {
  replace_band_constants(level, row_builder(level, sigma));
  replace_rule_stresses(level, sigma);
}

template <int Dim, typename Scalar>
void check_same_system(const Level<Dim, Scalar>& level, const ElasticityProblem<Dim>& problem) {
  const auto refuse = [](const std::string& what) {
    throw Error("new loads must come with the problem the solver was built from; its " + what +
                    " differs (build a new solver instead)",
                {.pointer = "loads"});
  };
  if (!same_lattice(level.lattice, problem.lattice)) refuse("lattice");
  if (level.cells != problem.cells) refuse("cell typing");
  if (level.mu != static_cast<Scalar>(problem.material.mu()) ||
      level.lambda != static_cast<Scalar>(problem.material.lambda()))
    refuse("material");
  if (level.inertia != static_cast<Scalar>(problem.inertia)) refuse("inertia");
  for (const VariableLoad& load : problem.variable_loads)
    if (load.component < 0 || load.component >= Dim || load.face < 0 ||
        load.face >= static_cast<std::ptrdiff_t>(level.size()))
      throw Error("a variable load lies off the lattice (component " +
                      std::to_string(load.component) + ", face " + std::to_string(load.face) + ")",
                  {.pointer = "loads"});
}

template <int Dim, typename Scalar>
void replace_loads(Level<Dim, Scalar>& level, const ElasticityProblem<Dim>& problem) {
  check_same_system(level, problem);
  replace_boundary_stress(level, problem.boundary_stress);
  write_load_right_hand_side(problem, level);
  back_substitute_traction(level);
}

#define MGELASTIC_INSTANTIATE(D, S)                                                          \
  template void write_load_right_hand_side<D, S>(const ElasticityProblem<D>&, Level<D, S>&); \
  template void replace_boundary_stress<D, S>(Level<D, S>&, const BoundaryStress<D>&);       \
  template void check_same_system<D, S>(const Level<D, S>&, const ElasticityProblem<D>&);    \
  template void replace_loads<D, S>(Level<D, S>&, const ElasticityProblem<D>&);
MGELASTIC_INSTANTIATE(2, float)
MGELASTIC_INSTANTIATE(2, double)
MGELASTIC_INSTANTIATE(3, float)
MGELASTIC_INSTANTIATE(3, double)
#undef MGELASTIC_INSTANTIATE

}  // namespace mgelastic::grid
