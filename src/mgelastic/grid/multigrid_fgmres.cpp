// Krylov acceleration of the multigrid cycle: right-preconditioned flexible GMRES (Saad 1993)
// on the augmented system L* x = b of the finest level, with one V- or W-cycle (zero initial
// guess) as the preconditioner. Vectors are indexed like the level's global variables
// (field * size + k) and vanish outside interior variables.
#include <Eigen/Dense>
#include <cmath>
#include <type_traits>
#include <utility>

#include "mgelastic/core/cancellation.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/core/timer.hpp"
#include "mgelastic/grid/boundary_smoother.hpp"
#include "mgelastic/grid/multigrid.hpp"
#include "mgelastic/grid/residual.hpp"

namespace mgelastic::grid {

template <int Dim, typename Scalar>
Level<Dim, double>& Multigrid<Dim, Scalar>::solution_level() {
  m_solution_residual_current = false;  // the caller may change x or b
  Level<Dim, double>& level = solution_storage();
  // b's released zero pages may be written from now on: count them again (conservative).
  level.forget_zero_loads();
  return level;
}

template <int Dim, typename Scalar>
Level<Dim, double>& Multigrid<Dim, Scalar>::solution_storage() {
  return const_cast<Level<Dim, double>&>(std::as_const(*this).solution_level());
}

template <int Dim, typename Scalar>
const Level<Dim, double>& Multigrid<Dim, Scalar>::solution_level() const {
  if constexpr (std::is_same_v<Scalar, double>) {
    return m_solution ? *m_solution : m_levels.front();
  } else {
    if (!m_solution)
      throw Error(
          "single precision (float-only) solves have no double solution level: time "
          "integration, Krylov acceleration and reactions need precision 'float' (mixed) or "
          "'double'",
          {.pointer = "solver/precision"});
    return *m_solution;
  }
}

namespace {

template <int Dim, typename T>
void for_each_interior(const Level<Dim, T>& level, const auto& f) {
  const std::size_t n = level.size();
  for (int field = 0; field <= Dim; ++field)
    for (std::size_t k = 0; k < n; ++k)
      if (level.kind(field, k) == VarKind::INTERIOR) f(field, k, field * n + k);
}

template <int Dim>
Eigen::VectorXd residual_vector(Level<Dim, double>& level) {
  compute_residual(level);
  Eigen::VectorXd r = Eigen::VectorXd::Zero((Dim + 1) * level.size());
  for_each_interior(level, [&](int f, std::size_t k, std::size_t g) { r[g] = level.r[f][k]; });
  return r;
}

}  // namespace

template <int Dim, typename Scalar>
SolveReport Multigrid<Dim, Scalar>::solve_accelerated(double relative_tolerance, int max_cycles,
                                                      int restart) {
  SolveReport report;
  Timer timer;
  Level<Dim, double>& s = solution_level();
  Level<Dim, Scalar>& fine = m_levels.front();
  const auto saved_x = s.x;
  const auto saved_b = s.b;
  Eigen::VectorXd x = Eigen::VectorXd::Zero((Dim + 1) * s.size());
  for_each_interior(s, [&](int f, std::size_t k, std::size_t g) { x[g] = s.x[f][k]; });
  // The operator without boundary data: A z = r(0) - r(z) with b = 0 and zero Dirichlet values.
  auto load = [&](const Eigen::VectorXd& z) {
    for (int f = 0; f <= Dim; ++f) {
      zero_live(s.x[f], s.live);
      zero_live(s.b[f], s.live);
    }
    for_each_interior(s, [&](int f, std::size_t k, std::size_t g) { s.x[f][k] = z[g]; });
  };
  load(Eigen::VectorXd::Zero(x.size()));
  const Eigen::VectorXd r_zero = residual_vector(s);
  auto apply_operator = [&](const Eigen::VectorXd& z) {
    load(z);
    return Eigen::VectorXd(r_zero - residual_vector(s));
  };
  auto apply_preconditioner = [&](const Eigen::VectorXd& v) {
    for (int f = 0; f <= Dim; ++f) {
      zero_live(fine.x[f], fine.live);
      zero_live(fine.b[f], fine.live);
    }
    for_each_interior(fine, [&](int f, std::size_t k, std::size_t g) {
      fine.b[f][k] = static_cast<Scalar>(v[g]);
    });
    cycle_correction();
    Eigen::VectorXd z = Eigen::VectorXd::Zero(v.size());
    for_each_interior(fine, [&](int f, std::size_t k, std::size_t g) { z[g] = fine.x[f][k]; });
    return z;
  };
  // True residual of the current x (with the real boundary data).
  auto true_residual = [&]() {
    assign_live(s.x, saved_x, s.live);
    assign_live(s.b, saved_b, s.live);
    for_each_interior(s, [&](int f, std::size_t k, std::size_t g) { s.x[f][k] = x[g]; });
    back_substitute_traction(s);
    return residual_vector(s);
  };
  Eigen::VectorXd r = true_residual();
  report.residuals.push_back(r.norm());
  if (!std::isfinite(report.residuals.front()))
    throw Error("the initial residual is not finite (NaN or Inf in the loads or boundary values)",
                {.pointer = "loads"});
  const double target = relative_tolerance * report.residuals.front();
  // Divergence: back to the start (s.b was cleared for the operator), then a checked replay.
  const auto diverged = [&](const std::string& reason) {
    assign_live(s.b, saved_b, s.live);
    fail_diverged("the accelerated solve (FGMRES) at cycle " + std::to_string(report.cycles()),
                  reason, report.residuals, StartState{.solution = saved_x, .single = {}});
  };
  int cycles = 0;
  while (cycles < max_cycles && r.norm() > target) {
    const int m = std::min(restart, max_cycles - cycles);
    std::vector<Eigen::VectorXd> v{r / r.norm()}, z;
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(m + 1, m);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(m + 1), cs = Eigen::VectorXd::Zero(m),
                    sn = Eigen::VectorXd::Zero(m);
    g[0] = r.norm();
    int j = 0;
    for (; j < m; ++j) {
      throw_if_cancelled();
      z.push_back(apply_preconditioner(v[j]));
      Eigen::VectorXd w = apply_operator(z[j]);
      ++cycles;
      for (int i = 0; i <= j; ++i) {  // modified Gram-Schmidt
        h(i, j) = w.dot(v[i]);
        w -= h(i, j) * v[i];
      }
      const double beta = w.norm();
      h(j + 1, j) = beta;
      for (int i = 0; i < j; ++i) {  // previous Givens rotations
        const double t = cs[i] * h(i, j) + sn[i] * h(i + 1, j);
        h(i + 1, j) = -sn[i] * h(i, j) + cs[i] * h(i + 1, j);
        h(i, j) = t;
      }
      const double denominator = std::hypot(h(j, j), h(j + 1, j));
      cs[j] = h(j, j) / denominator;
      sn[j] = h(j + 1, j) / denominator;
      h(j, j) = denominator;
      h(j + 1, j) = 0.0;
      g[j + 1] = -sn[j] * g[j];
      g[j] = cs[j] * g[j];
      report.residuals.push_back(std::abs(g[j + 1]));
      if (!std::isfinite(g[j + 1])) diverged("the residual estimate is not finite");
      if (std::abs(g[j + 1]) <= target || beta == 0.0) {  // converged, or exact (breakdown)
        ++j;
        break;
      }
      v.push_back(w / beta);
    }
    // The Givens rotations left the upper triangle in h (last rotated column included).
    const Eigen::VectorXd y = h.topLeftCorner(j, j).triangularView<Eigen::Upper>().solve(g.head(j));
    for (int i = 0; i < j; ++i) x += y[i] * z[i];
    r = true_residual();
    report.residuals.back() = r.norm();
    const std::string reason = divergence_reason(report.residuals);
    if (!reason.empty()) diverged(reason);
  }
  report.converged = r.norm() <= target;
  report.seconds = timer.seconds();
  return report;
}

#define MGELASTIC_INSTANTIATE(D, S)                                         \
  template Level<D, double>& Multigrid<D, S>::solution_level();             \
  template const Level<D, double>& Multigrid<D, S>::solution_level() const; \
  template Level<D, double>& Multigrid<D, S>::solution_storage();           \
  template SolveReport Multigrid<D, S>::solve_accelerated(double, int, int);
MGELASTIC_INSTANTIATE(2, float)
MGELASTIC_INSTANTIATE(2, double)
MGELASTIC_INSTANTIATE(3, float)
MGELASTIC_INSTANTIATE(3, double)
#undef MGELASTIC_INSTANTIATE

}  // namespace mgelastic::grid
