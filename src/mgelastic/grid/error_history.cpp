#include "mgelastic/grid/error_history.hpp"

#include <cmath>

namespace mgelastic::grid {
namespace {

template <int Dim, typename Scalar>
double relative_error(const Multigrid<Dim, Scalar>& mg, const Multigrid<Dim, double>& reference) {
  const Level<Dim, Scalar>& level = mg.finest();
  double error = 0, norm = 0;
  for (int f = 0; f <= Dim; ++f)
    for (std::size_t k = 0; k < level.size(); ++k) {
      if (level.kind(f, k) != VarKind::INTERIOR) continue;
      const double exact = reference.solution(f, static_cast<std::ptrdiff_t>(k));
      const double d = mg.solution(f, static_cast<std::ptrdiff_t>(k)) - exact;
      error += d * d;
      norm += exact * exact;
    }
  return norm > 0 ? std::sqrt(error / norm) : std::sqrt(error);
}

}  // namespace

template <int Dim, typename Scalar>
ErrorHistory error_history(const ElasticityProblem<Dim>& problem, const MultigridOptions& options,
                           int cycles) {
  Multigrid<Dim, double> reference(problem, options);
  const SolveReport solved = reference.solve_accelerated(1e-10, 400);
  ErrorHistory history;
  history.reference_residual = solved.residuals.back() / solved.residuals.front();
  Multigrid<Dim, Scalar> mg(problem, options);
  history.relative_error.push_back(relative_error(mg, reference));
  for (int c = 0; c < cycles; ++c) {
    mg.vcycle();
    history.relative_error.push_back(relative_error(mg, reference));
  }
  return history;
}

template ErrorHistory error_history<2, float>(const ElasticityProblem<2>&, const MultigridOptions&,
                                              int);
template ErrorHistory error_history<2, double>(const ElasticityProblem<2>&, const MultigridOptions&,
                                               int);
template ErrorHistory error_history<3, float>(const ElasticityProblem<3>&, const MultigridOptions&,
                                              int);
template ErrorHistory error_history<3, double>(const ElasticityProblem<3>&, const MultigridOptions&,
                                               int);

}  // namespace mgelastic::grid
