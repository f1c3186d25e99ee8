#include "mgelastic/grid/nonaugmented_system.hpp"

#include <unordered_map>

#include "mgelastic/grid/explicit_rows.hpp"

namespace mgelastic::grid {
namespace {

using Triplets = std::vector<Eigen::Triplet<double>>;

template <int Dim, typename Scalar>
void number_unknowns(const Level<Dim, Scalar>& level, NonAugmentedSystem<Dim>& system,
                     std::vector<std::int32_t>& index) {
  const auto n = static_cast<std::ptrdiff_t>(level.size());
  index.assign((Dim + 1) * n, -1);
  for (int f = 0; f <= Dim; ++f) {
    auto& list = f < Dim ? system.u_variables : system.p_variables;
    for (std::ptrdiff_t k = 0; k < n; ++k) {
      if (level.kind(f, k) != VarKind::INTERIOR) continue;
      index[f * n + k] = static_cast<std::int32_t>(list.size());
      list.push_back(level.global(f, k));
    }
  }
}

}  // namespace

template <int Dim, typename Scalar>
NonAugmentedSystem<Dim> assemble_nonaugmented(const Level<Dim, Scalar>& level,
                                              const BoundaryStress<Dim>& sigma) {
  NonAugmentedSystem<Dim> system;
  std::vector<std::int32_t> index;
  number_unknowns(level, system, index);
  const auto nu = static_cast<Eigen::Index>(system.u_variables.size());
  const auto np = static_cast<Eigen::Index>(system.p_variables.size());
  const double mu = level.mu, lambda = level.lambda;
  const RowBuilder<Dim> builder(level.lattice, level.cells, mu, sigma, level.inertia,
                                level.cell_weight.empty() ? nullptr : &level.cell_weight,
                                level.dirichlet_zero_depth, &level.dirichlet_wall_layers);
  const auto n = level.size();
  Triplets a, g;
  // Galerkin band rows (galerkin_band_rows.hpp) are read from band_u, the rest from the builder.
  std::unordered_map<std::uint32_t, std::uint32_t> band_row;
  if (level.galerkin_band_rows) band_row = rows_by_target(level.band_u);
  system.u_constant.setZero(nu);
  system.p_constant.setZero(np);
  system.inverse_pressure_diagonal.setZero(np);
  system.pressure_weight.setOnes(np);
  for (Eigen::Index row = 0; row < nu; ++row) {
    const std::uint32_t var = system.u_variables[row];
    const auto band = band_row.find(var);
    const ExplicitRow r = band == band_row.end()
                              ? builder.momentum(static_cast<int>(var / n), var % n)
                              : stored_row(level, level.band_u, band->second);
    system.u_constant[row] = r.constant;
    for (const RowTerm& t : r.terms) {
      const std::int32_t col = index[t.variable];
      if (t.variable / n == static_cast<std::uint32_t>(Dim)) {
        g.emplace_back(row, col, t.coefficient);
      } else if (col >= 0) {
        a.emplace_back(row, col, t.coefficient);
      } else {
        system.u_constant[row] += t.coefficient * level.at(t.variable);  // Dirichlet value
      }
    }
  }
  for (Eigen::Index row = 0; row < np; ++row) {
    const ExplicitRow r = builder.pressure(system.p_variables[row] % n);
    system.p_constant[row] = r.constant;
    for (const RowTerm& t : r.terms)
      if (index[t.variable] < 0) system.p_constant[row] += t.coefficient * level.at(t.variable);
    system.inverse_pressure_diagonal[row] = lambda / (mu * mu + lambda * r.pressure_extra);
    if (!level.cell_weight.empty())
      system.pressure_weight[row] = level.cell_weight[system.p_variables[row] % n];
  }
  Eigen::SparseMatrix<double> l_phi(nu, nu);
  l_phi.setFromTriplets(a.begin(), a.end());
  system.coupling.resize(nu, np);
  system.coupling.setFromTriplets(g.begin(), g.end());
  const Eigen::SparseMatrix<double> schur_part =
      system.coupling *
      system.inverse_pressure_diagonal.cwiseQuotient(system.pressure_weight).asDiagonal() *
      system.coupling.transpose();
  system.matrix = -(l_phi - schur_part);
  system.matrix.makeCompressed();
  return system;
}

template <int Dim>
template <typename Scalar>
Eigen::VectorXd NonAugmentedSystem<Dim>::right_hand_side(const Level<Dim, Scalar>& level) const {
  Eigen::VectorXd bu(u_variables.size()), bp(p_variables.size());
  for (std::size_t i = 0; i < u_variables.size(); ++i) {
    const auto v = u_variables[i];
    bu[i] = level.b[v / level.size()][v % level.size()];
  }
  for (std::size_t i = 0; i < p_variables.size(); ++i)
    bp[i] = level.b[Dim][p_variables[i] % level.size()];
  const Eigen::VectorXd cu = bu - u_constant;
  const Eigen::VectorXd cp = bp - p_constant;
  // S u = c_u - G D^-1 c_p, negated for the SPD form.
  return -(cu - coupling * inverse_pressure_diagonal.cwiseProduct(cp));
}

template <int Dim>
template <typename Scalar>
void NonAugmentedSystem<Dim>::scatter(const Eigen::VectorXd& u, Level<Dim, Scalar>& level) const {
  for (std::size_t i = 0; i < u_variables.size(); ++i)
    level.at(u_variables[i]) = static_cast<Scalar>(u[i]);
  Eigen::VectorXd bp(p_variables.size());
  for (std::size_t i = 0; i < p_variables.size(); ++i)
    bp[i] = level.b[Dim][p_variables[i] % level.size()];
  const Eigen::VectorXd p = inverse_pressure_diagonal.cwiseProduct(
      bp - p_constant - (coupling.transpose() * u).cwiseQuotient(pressure_weight));
  for (std::size_t i = 0; i < p_variables.size(); ++i)
    level.at(p_variables[i]) = static_cast<Scalar>(p[i]);
}

#define MGELASTIC_INSTANTIATE(D, S)                                                             \
  template NonAugmentedSystem<D> assemble_nonaugmented<D, S>(const Level<D, S>&,                \
                                                             const BoundaryStress<D>&);         \
  template Eigen::VectorXd NonAugmentedSystem<D>::right_hand_side<S>(const Level<D, S>&) const; \
  template void NonAugmentedSystem<D>::scatter<S>(const Eigen::VectorXd&, Level<D, S>&) const;
MGELASTIC_INSTANTIATE(2, float)
MGELASTIC_INSTANTIATE(2, double)
MGELASTIC_INSTANTIATE(3, float)
MGELASTIC_INSTANTIATE(3, double)
#undef MGELASTIC_INSTANTIATE

template struct NonAugmentedSystem<2>;
template struct NonAugmentedSystem<3>;

}  // namespace mgelastic::grid
