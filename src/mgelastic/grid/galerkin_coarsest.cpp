#include "mgelastic/grid/galerkin_coarsest.hpp"

#include <Eigen/SparseCore>
#include <Eigen/SparseLU>
#include <algorithm>
#include <utility>
#include <vector>

#include "mgelastic/core/error.hpp"
#include "mgelastic/grid/boundary_smoother.hpp"
#include "mgelastic/grid/live_chunks.hpp"
#include "mgelastic/grid/residual.hpp"
#include "mgelastic/grid/transfer.hpp"

namespace mgelastic::grid {

CoarsestOperator coarsest_operator(const std::string& name, const std::string& pointer) {
  if (name == "rediscretized") return CoarsestOperator::REDISCRETIZED;
  if (name == "galerkin") return CoarsestOperator::GALERKIN;
  if (name == "galerkin_band") return CoarsestOperator::GALERKIN_BAND;
  throw Error("must be 'rediscretized', 'galerkin' or 'galerkin_band' (got '" + name + "')",
              {.pointer = pointer});
}

namespace {

using Unknown = std::pair<int, std::ptrdiff_t>;  // field, flat index

template <int Dim, typename Scalar>
std::vector<Unknown> interior_unknowns(const Level<Dim, Scalar>& level) {
  std::vector<Unknown> unknowns;
  for (int f = 0; f <= Dim; ++f)
    for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(level.size()); ++k)
      if (level.kind(f, k) == VarKind::INTERIOR) unknowns.emplace_back(f, k);
  return unknowns;
}

// Zeroes x or b of a level (Dim + 1 fields) where they hold memory (live_chunks.hpp).
template <typename Fields>
void zero(Fields& fields, const LiveChunks& live) {
  for (auto& field : fields) zero_live(field, live);
}

// Columns of M such that (M v)_i = -r_i at `rows` for a residual r of x = the probe, b = 0.
template <int Dim, typename Scalar>
void append_column(const Level<Dim, Scalar>& level, const std::vector<Unknown>& rows, int column,
                   double scale, std::vector<Eigen::Triplet<double>>& entries,
                   const std::vector<char>* keep = nullptr) {
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (keep && !(*keep)[i]) continue;
    const double v = -static_cast<double>(level.r[rows[i].first][rows[i].second]);
    if (v != 0) entries.emplace_back(static_cast<int>(i), column, scale * v);
  }
}

}  // namespace

template <int Dim, typename Scalar>
struct GalerkinCoarseSolver<Dim, Scalar>::Impl {
  std::vector<Unknown> unknowns;
  Eigen::SparseLU<Eigen::SparseMatrix<double>> lu;
};

template <int Dim, typename Scalar>
GalerkinCoarseSolver<Dim, Scalar>::GalerkinCoarseSolver(Level<Dim, Scalar>& fine,
                                                        Level<Dim, Scalar>& coarse, bool band_only)
    : m_impl(std::make_unique<Impl>()) {
  auto& unknowns = m_impl->unknowns;
  unknowns = interior_unknowns(coarse);
  const std::vector<Unknown> fine_unknowns = interior_unknowns(fine);
  const int n = static_cast<int>(unknowns.size());
  const int nf = static_cast<int>(fine_unknowns.size());
  ensure_residual_storage(fine);
  ensure_residual_storage(coarse);
  // Which coarse rows are Galerkin rows; the others keep the level's own rows.
  std::vector<char> galerkin_row(unknowns.size(), 1), own_row(unknowns.size(), 0);
  if (band_only)
    for (std::size_t i = 0; i < unknowns.size(); ++i) {
      galerkin_row[i] =
          coarse.relaxation(unknowns[i].first, unknowns[i].second) == Relaxation::BAND;
      own_row[i] = !galerkin_row[i];
    }
  // Per coarse unknown j: P e_j (the fine x after the prolongation) and A_f P e_j. The residuals
  // read b = 0; the probes write only x.
  std::vector<Eigen::Triplet<double>> p_entries, ap_entries, own_entries;
  zero(fine.b, fine.live);
  zero(coarse.b, coarse.live);
  for (int j = 0; j < n; ++j) {
    zero(fine.x, fine.live);
    zero(coarse.x, coarse.live);
    coarse.x[unknowns[j].first][unknowns[j].second] = Scalar(1);
    back_substitute_traction(coarse);
    if (band_only) {
      // The coarse level's own rows, at the Galerkin rows' scale (2^d).
      update_residual(coarse);
      append_column(coarse, unknowns, j, double(1 << Dim), own_entries, &own_row);
    }
    prolongate_correction(coarse, fine);
    back_substitute_traction(fine);
    update_residual(fine);
    for (int i = 0; i < nf; ++i) {
      const auto [f, k] = fine_unknowns[static_cast<std::size_t>(i)];
      if (fine.x[f][k] != 0) p_entries.emplace_back(i, j, static_cast<double>(fine.x[f][k]));
    }
    append_column(fine, fine_unknowns, j, 1.0, ap_entries);
  }
  Eigen::SparseMatrix<double> p(nf, n), ap(nf, n);
  p.setFromTriplets(p_entries.begin(), p_entries.end());
  ap.setFromTriplets(ap_entries.begin(), ap_entries.end());
  const Eigen::SparseMatrix<double> galerkin = (p.transpose() * ap).pruned();
  std::vector<Eigen::Triplet<double>> entries = std::move(own_entries);
  for (int c = 0; c < galerkin.outerSize(); ++c)
    for (Eigen::SparseMatrix<double>::InnerIterator it(galerkin, c); it; ++it)
      if (galerkin_row[static_cast<std::size_t>(it.row())])
        entries.emplace_back(static_cast<int>(it.row()), c, it.value());
  // An unknown no fine variable sees (a coarse variable whose prolongation lands only on
  // Dirichlet or traction variables) keeps a zero correction.
  std::vector<char> row_used(unknowns.size(), 0), column_used(unknowns.size(), 0);
  for (const auto& e : entries) row_used[e.row()] = column_used[e.col()] = 1;
  for (int i = 0; i < n; ++i)
    if (!row_used[i] || !column_used[i]) entries.emplace_back(i, i, 1.0);
  Eigen::SparseMatrix<double> a(n, n);
  a.setFromTriplets(entries.begin(), entries.end());
  m_impl->lu.compute(a);
  zero(fine.x, fine.live);
  zero(coarse.x, coarse.live);
  for (auto* level : {&fine, &coarse})
    for (auto& field : level->r) FieldArray<Scalar>().swap(field);
  if (m_impl->lu.info() != Eigen::Success)
    throw Error("the Galerkin coarsest operator is singular", {.pointer = "coarsest_operator"});
}

template <int Dim, typename Scalar>
GalerkinCoarseSolver<Dim, Scalar>::~GalerkinCoarseSolver() = default;
template <int Dim, typename Scalar>
GalerkinCoarseSolver<Dim, Scalar>::GalerkinCoarseSolver(GalerkinCoarseSolver&&) noexcept = default;
template <int Dim, typename Scalar>
GalerkinCoarseSolver<Dim, Scalar>& GalerkinCoarseSolver<Dim, Scalar>::operator=(
    GalerkinCoarseSolver&&) noexcept = default;

template <int Dim, typename Scalar>
void GalerkinCoarseSolver<Dim, Scalar>::solve(Level<Dim, Scalar>& coarse) const {
  const auto& unknowns = m_impl->unknowns;
  // The matrix holds P^T A P, 2^d times the coarse rows' scale (P^T = 2^d R in the interior),
  // so the restricted right-hand side is scaled by 2^d too.
  Eigen::VectorXd rhs(static_cast<Eigen::Index>(unknowns.size()));
  for (std::size_t i = 0; i < unknowns.size(); ++i)
    rhs[static_cast<Eigen::Index>(i)] =
        (1 << Dim) * static_cast<double>(coarse.b[unknowns[i].first][unknowns[i].second]);
  const Eigen::VectorXd e = m_impl->lu.solve(rhs);
  for (auto& field : coarse.x) zero_live(field, coarse.live);
  for (std::size_t i = 0; i < unknowns.size(); ++i)
    coarse.x[unknowns[i].first][unknowns[i].second] =
        static_cast<Scalar>(e[static_cast<Eigen::Index>(i)]);
  back_substitute_traction(coarse);
}

template class GalerkinCoarseSolver<2, float>;
template class GalerkinCoarseSolver<2, double>;
template class GalerkinCoarseSolver<3, float>;
template class GalerkinCoarseSolver<3, double>;

}  // namespace mgelastic::grid
