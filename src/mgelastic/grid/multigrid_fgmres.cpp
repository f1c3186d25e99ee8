// Krylov acceleration of the multigrid cycle: right-preconditioned flexible GMRES (Saad 1993)
// on the augmented system L* x = b of the finest level, with one V- or W-cycle (zero initial
// guess) as the preconditioner. Vectors hold the interior variables only (InteriorVariables,
// field by field in lattice order); passes over them run on all threads, with sums blocked so
// that they do not depend on the thread count.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "mgelastic/core/cancellation.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/core/timer.hpp"
#include "mgelastic/grid/boundary_smoother.hpp"
#include "mgelastic/grid/huge_pages.hpp"
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

// Interior variables lie in live chunks (live_chunks.hpp), so the dead ones are skipped.
template <int Dim, typename T>
InteriorVariables<Dim> interior_variables(const Level<Dim, T>& level) {
  if (level.size() > std::numeric_limits<std::uint32_t>::max())
    throw Error("the Krylov solve indexes lattice points with 32 bits; this lattice has " +
                    std::to_string(level.size()),
                {.pointer = "solver/accelerate"});
  InteriorVariables<Dim> v;
  const auto size = static_cast<std::ptrdiff_t>(level.size());
  for (int f = 0; f <= Dim; ++f) {
    const FieldKinds kind = level.codes.kinds(f);
    for_each_live_chunk(level.live, 0, size, [&](std::ptrdiff_t lo, std::ptrdiff_t hi) {
      for (std::ptrdiff_t k = lo; k < hi; ++k)
        if (kind[k] == VarKind::INTERIOR) v.points[f].push_back(static_cast<std::uint32_t>(k));
    });
    v.offset[f + 1] = v.offset[f] + static_cast<std::ptrdiff_t>(v.points[f].size());
  }
  return v;
}

// out = the interior values of `fields` (out's scalar: the fields' or wider, so it is exact).
template <int Dim, typename T, typename V>
void gather(const InteriorVariables<Dim>& vars, const std::array<FieldArray<T>, Dim + 1>& fields,
            Eigen::Matrix<V, Eigen::Dynamic, 1>& out) {
  out.resize(vars.size());
  for (int f = 0; f <= Dim; ++f) {
    const T* from = fields[f].data();
    const std::uint32_t* points = vars.points[f].data();
    V* to = out.data() + vars.offset[f];
    const auto count = static_cast<std::ptrdiff_t>(vars.points[f].size());
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < count; ++i) to[i] = static_cast<V>(from[points[i]]);
  }
}

// The interior values of `fields` = scale * in (the other values are left alone).
template <int Dim, typename T, typename V>
void scatter(const InteriorVariables<Dim>& vars, const Eigen::Matrix<V, Eigen::Dynamic, 1>& in,
             std::array<FieldArray<T>, Dim + 1>& fields, double scale = 1) {
  for (int f = 0; f <= Dim; ++f) {
    T* to = fields[f].data();
    const std::uint32_t* points = vars.points[f].data();
    const V* from = in.data() + vars.offset[f];
    const auto count = static_cast<std::ptrdiff_t>(vars.points[f].size());
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < count; ++i)
      to[points[i]] = static_cast<T>(scale * static_cast<double>(from[i]));
  }
}

// The interior values of `fields` = 0.
template <int Dim, typename T>
void zero_interior(const InteriorVariables<Dim>& vars, std::array<FieldArray<T>, Dim + 1>& fields) {
  for (int f = 0; f <= Dim; ++f) {
    T* to = fields[f].data();
    const std::uint32_t* points = vars.points[f].data();
    const auto count = static_cast<std::ptrdiff_t>(vars.points[f].size());
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < count; ++i) to[points[i]] = T(0);
  }
}

// w = (origin - the interior values of `fields`) * inverse: an operator product from the residual
// fields (one pass, no gathered copy of them).
template <int Dim>
void difference_into(const InteriorVariables<Dim>& vars, const Eigen::VectorXd& origin,
                     const std::array<FieldArray<double>, Dim + 1>& fields, double inverse,
                     Eigen::VectorXd& w) {
  for (int f = 0; f <= Dim; ++f) {
    const double* from = fields[f].data();
    const std::uint32_t* points = vars.points[f].data();
    const double* o = origin.data() + vars.offset[f];
    double* to = w.data() + vars.offset[f];
    const auto count = static_cast<std::ptrdiff_t>(vars.points[f].size());
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < count; ++i) to[i] = (o[i] - from[points[i]]) * inverse;
  }
}

// Zeros for a level's band-row constants (boundary stresses moved to the right-hand side), swapped
// in while a cycle must solve the homogeneous correction problem, a linear map of its right-hand
// side. A level that holds the solution (one level in double precision) keeps the traction loads
// there; with them the preconditioner was affine, B(v) = B_0 (v - c), and for a tip-loaded
// cantilever |c| ~ 1e6 |v| made every preconditioned vector the same one. The zeros are made
// once per solve; a Scope swaps them in and back in O(1).
template <int Dim, typename Scalar>
class HomogeneousBand {
 public:
  explicit HomogeneousBand(Level<Dim, Scalar>& level)
      : m_level(level),
        m_kernel(level.band_kernel.constant.size(), Scalar(0)),
        m_pressure(level.band_p.constant.size(), Scalar(0)),
        m_csr(level.band_u.constant.size(), Scalar(0)) {}

  class Scope {
   public:
    explicit Scope(HomogeneousBand* band) : m_band(band) {
      if (m_band) m_band->swap();
    }
    ~Scope() {
      if (m_band) m_band->swap();
    }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    HomogeneousBand* m_band;
  };

 private:
  void swap() {
    m_level.band_kernel.constant.swap(m_kernel);
    m_level.band_p.constant.swap(m_pressure);
    m_level.band_u.constant.swap(m_csr);
  }
  Level<Dim, Scalar>& m_level;
  std::vector<Scalar> m_kernel, m_pressure, m_csr;
};

template <int Dim, typename T>
void zero_fields(std::array<FieldArray<T>, Dim + 1>& fields, const LiveChunks& live) {
  for (FieldArray<T>& field : fields) zero_live_where_nonzero(field, live);
}

// v as n values, its storage kept when it has that size already, else fresh on transparent huge
// pages (advised before the first touch): the basis vectors are tens of megabytes each, and 4 KiB
// pages cost a fault each on first write.
template <typename V>
Eigen::Matrix<V, Eigen::Dynamic, 1>& sized(Eigen::Matrix<V, Eigen::Dynamic, 1>& v,
                                           std::ptrdiff_t n) {
  if (v.size() == n) return v;
  v = Eigen::Matrix<V, Eigen::Dynamic, 1>(n);  // uninitialized: no page touched yet
  advise_huge_pages(v.data(), static_cast<std::size_t>(n) * sizeof(V));
  return v;
}

// Blocked so that the sums do not depend on the thread count.
constexpr std::ptrdiff_t kDotBlock = std::ptrdiff_t{1} << 14;

// a . b in double (b: a double or a float basis vector).
template <typename V>
double dot(const Eigen::VectorXd& a, const Eigen::Matrix<V, Eigen::Dynamic, 1>& b) {
  const std::ptrdiff_t n = a.size(), blocks = (n + kDotBlock - 1) / kDotBlock;
  std::vector<double> partial(static_cast<std::size_t>(blocks));
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t q = 0; q < blocks; ++q) {
    const std::ptrdiff_t lo = q * kDotBlock, count = std::min(kDotBlock, n - lo);
    partial[static_cast<std::size_t>(q)] =
        a.segment(lo, count).dot(b.segment(lo, count).template cast<double>());
  }
  double sum = 0;
  for (double p : partial) sum += p;
  return sum;
}

double norm(const Eigen::VectorXd& a) {
  return std::sqrt(dot(a, a));
}

// y += alpha x.
template <typename V>
void add_scaled(Eigen::VectorXd& y, double alpha, const Eigen::Matrix<V, Eigen::Dynamic, 1>& x) {
  const std::ptrdiff_t n = y.size();
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t lo = 0; lo < n; lo += kDotBlock) {
    const std::ptrdiff_t count = std::min(kDotBlock, n - lo);
    y.segment(lo, count) += alpha * x.segment(lo, count).template cast<double>();
  }
}

// The power of two nearest to `value` (1 for zero or a value that is not finite).
double power_of_two_near(double value) {
  if (!(value > 0) || !std::isfinite(value)) return 1.0;
  return std::exp2(std::round(std::log2(value)));
}

}  // namespace

template <int Dim, typename Scalar>
SolveReport Multigrid<Dim, Scalar>::solve_accelerated(double relative_tolerance, int max_cycles,
                                                      int restart) {
  using ScalarVector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;
  SolveReport report;
  Timer timer;
  Level<Dim, double>& s = solution_level();
  Level<Dim, Scalar>& fine = m_levels.front();
  // In double precision one level holds the solution and runs the cycles: the cycles overwrite
  // its loads and boundary values, so they are kept aside and put back for each true residual.
  // In mixed precision (the default) the solution level keeps them throughout.
  const bool shared_level = static_cast<const void*>(&s) == static_cast<const void*>(&fine);
  // Where the solve starts: the divergence replay's start (and, on one level, its boundary
  // values).
  const StartState& start = capture_start();
  std::array<FieldArray<double>, Dim + 1> saved_b;
  if (shared_level)
    for (int f = 0; f <= Dim; ++f) saved_b[f] = pack_live(s.b[f], s.live);
  // Every vector below keeps its storage across iterations, restarts and solves
  // (krylov_workspace.hpp). The fine level shares the solution level's variable codes: one index
  // set for both.
  if (!m_krylov) {
    m_krylov = std::make_unique<KrylovWorkspace<Dim, Scalar>>();
    m_krylov->vars = interior_variables(s);
  }
  KrylovWorkspace<Dim, Scalar>& work = *m_krylov;
  const InteriorVariables<Dim>& vars = work.vars;
  Eigen::VectorXd& x = sized(work.x, vars.size());
  gather(vars, s.x, x);
  const auto residual_into = [&](Eigen::VectorXd& out) {
    compute_residual(s);
    gather(vars, s.r, out);
  };
  // The solution level holds x (traction variables from it) and the real loads.
  const auto hold_x = [&] {
    if (shared_level) {
      restore_start(start);
      for (int f = 0; f <= Dim; ++f) unpack_live(saved_b[f], s.b[f], s.live);
    }
    scatter(vars, x, s.x);
    back_substitute_traction(s);
  };
  const auto true_residual = [&](Eigen::VectorXd& r) {
    hold_x();
    residual_into(r);
  };
  // The operator A z as a difference of residuals, r(x_I = 0) - r(x_I = a z) = a A z, with the
  // interior variables x_I set and everything else (loads, boundary values, traction variables)
  // held: no second copy of the loads, no clearing of the level per iteration. The scale a, a
  // power of two (exact) near |r(x_I = 0)|, keeps the difference from cancelling: |A z| ~ |v| = 1.
  // On a shared level the cycles overwrite b and x, so both are cleared for each product.
  Eigen::VectorXd& r_zero = sized(work.r_zero, vars.size());
  double scale = 1;
  const auto clear_shared = [&] {
    zero_fields<Dim>(s.x, s.live);
    zero_fields<Dim>(s.b, s.live);
  };
  const auto operator_origin = [&] {
    if (shared_level)
      clear_shared();
    else
      zero_interior(vars, s.x);
    residual_into(r_zero);
    scale = power_of_two_near(norm(r_zero));
  };
  const auto apply_operator = [&](const ScalarVector& z, Eigen::VectorXd& w) {
    if (shared_level) clear_shared();
    scatter(vars, z, s.x, scale);
    compute_residual(s);
    difference_into(vars, r_zero, s.r, 1.0 / scale, w);  // 1 / scale: exact, a power of two
  };
  // The cycles read only the interior values of the finest b (the scatter below writes all of
  // them) and do not write it: the rest is cleared once.
  zero_fields<Dim>(fine.b, fine.live);
  std::optional<HomogeneousBand<Dim, Scalar>> homogeneous;
  if (shared_level) homogeneous.emplace(fine);
  const auto apply_preconditioner = [&](const ScalarVector& v, ScalarVector& z) {
    zero_fields<Dim>(fine.x, fine.live);
    scatter(vars, v, fine.b);
    const typename HomogeneousBand<Dim, Scalar>::Scope zero_constants(homogeneous ? &*homogeneous
                                                                                  : nullptr);
    cycle_correction();
    gather(vars, fine.x, z);
  };
  Eigen::VectorXd& r = sized(work.r, vars.size());
  true_residual(r);
  report.residuals.push_back(norm(r));
  if (!std::isfinite(report.residuals.front()))
    throw Error("the initial residual is not finite (NaN or Inf in the loads or boundary values)",
                {.pointer = "loads"});
  const double target = relative_tolerance * report.residuals.front();
  // Divergence: back to the start (loads included), then a checked replay.
  const auto diverged = [&](const std::string& reason) {
    if (shared_level)
      for (int f = 0; f <= Dim; ++f) unpack_live(saved_b[f], s.b[f], s.live);
    fail_diverged("the accelerated solve (FGMRES) at cycle " + std::to_string(report.cycles()),
                  reason, report.residuals, start);
  };
  // The Krylov basis and its preconditioned vectors in the hierarchy's precision
  // (krylov_workspace.hpp); the vector being orthogonalized in double.
  std::vector<ScalarVector>& v = work.v;
  std::vector<ScalarVector>& z = work.z;
  Eigen::VectorXd& w = sized(work.w, vars.size());
  v.reserve(static_cast<std::size_t>(restart) + 1);  // references into them stay valid
  z.reserve(static_cast<std::size_t>(restart));
  const auto slot = [&](auto& list, int i) -> auto& {
    while (static_cast<int>(list.size()) <= i) list.emplace_back();
    return sized(list[static_cast<std::size_t>(i)], vars.size());
  };
  int cycles = 0;
  double r_norm = report.residuals.front();
  // Round-off floor: in exact arithmetic the estimate equals the true residual, so a restart
  // whose estimate reached the target while the true residual did not has met the residual of
  // x's own rounding (~eps |A| |x|, far above eps |b| for soft, finely resolved bodies). Such a
  // restart that also fails to halve the smallest true residual so far counts as stalled; two in a
  // row stop the solve (another restart would only wander around the floor).
  double smallest = r_norm;
  int stalled_restarts = 0;
  while (cycles < max_cycles && r_norm > target) {
    const int m = std::min(restart, max_cycles - cycles);
    slot(v, 0) = (r / r_norm).template cast<Scalar>();
    operator_origin();
    Eigen::MatrixXd h = Eigen::MatrixXd::Zero(m + 1, m);
    Eigen::VectorXd g = Eigen::VectorXd::Zero(m + 1), cs = Eigen::VectorXd::Zero(m),
                    sn = Eigen::VectorXd::Zero(m);
    g[0] = r_norm;
    int j = 0;
    bool estimate_reached = false;
    for (; j < m; ++j) {
      try {
        throw_if_cancelled();
      } catch (const Cancelled&) {
        hold_x();  // the solution keeps the solve's progress
        throw;
      }
      apply_preconditioner(v[j], slot(z, j));
      apply_operator(z[j], w);
      ++cycles;
      for (int i = 0; i <= j; ++i) {  // modified Gram-Schmidt
        h(i, j) = dot(w, v[i]);
        add_scaled(w, -h(i, j), v[i]);
      }
      const double beta = norm(w);
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
        estimate_reached = true;
        ++j;
        break;
      }
      slot(v, j + 1) = (w / beta).template cast<Scalar>();
    }
    // The Givens rotations left the upper triangle in h (last rotated column included).
    const Eigen::VectorXd y = h.topLeftCorner(j, j).triangularView<Eigen::Upper>().solve(g.head(j));
    for (int i = 0; i < j; ++i) add_scaled(x, y[i], z[i]);
    const double restart_norm = r_norm;
    true_residual(r);
    r_norm = norm(r);
    report.residuals.back() = r_norm;
    const std::string reason = divergence_reason(report.residuals);
    if (!reason.empty()) diverged(reason);
    // Local corrections from the restart's mean ratio per cycle and the true residual (x held).
    const double mean_ratio = std::pow(r_norm / restart_norm, 1.0 / std::max(j, 1));
    if (r_norm > target && levels() > 1 && m_local.due(j, mean_ratio, mean_ratio)) {
      Timer placing;
      const int cube = m_local.cube(fine);
      m_local.place(fine,
                    slow_mode_boxes<Dim>(residual_blocks<Dim>(s, cube, SIZE_MAX), cube, s.lattice,
                                         kLocalCorrectionMinShare, kLocalCorrectionCover, cube));
      m_phases.solve_setup += placing.seconds();
    }
    const bool at_floor = estimate_reached && r_norm > target && r_norm > 0.5 * smallest;
    stalled_restarts = at_floor ? stalled_restarts + 1 : 0;
    smallest = std::min(smallest, r_norm);
    if (stalled_restarts >= 2) {
      report.stalled = true;
      break;
    }
  }
  report.converged = r_norm <= target;
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
