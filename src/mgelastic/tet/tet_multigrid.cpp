#include "mgelastic/tet/tet_multigrid.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <string>

#include "mgelastic/core/blas_threads.hpp"
#include "mgelastic/core/cancellation.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/core/timer.hpp"
#include "mgelastic/tet/parallel.hpp"

namespace mgelastic::tet {
namespace {

[[noreturn]] void fail_tet_multigrid(const std::string& reason) {
  throw Error(reason, ErrorContext{std::string(), -1, "TetMultigrid"});
}

// Relative diagonal shift of the coarsest Galerkin operator (see finish_coarse_update).
constexpr double kCoarsestShift = 1e-8;

}  // namespace

struct TetMultigrid::Coarsest {
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> factorization;
  bool analyzed = false;
};

TetMultigrid::TetMultigrid(const geometry::TetMesh& mesh, const std::vector<char>& constrained,
                           const BlockRowMatrix<double>& stiffness_pattern,
                           const TetMultigridSettings& settings)
    : m_settings(settings),
      m_hierarchy(mesh, constrained, settings.hierarchy),
      m_coarsest(std::make_unique<Coarsest>()) {
  if (stiffness_pattern.block_rows() != mesh.vertex_count())
    fail_tet_multigrid("stiffness pattern has " + std::to_string(stiffness_pattern.block_rows()) +
                       " block rows for " + std::to_string(mesh.vertex_count()) + " vertices");
  m_levels.resize(level_count());
  m_levels[0].matrix =
      BlockRowMatrix<double>(stiffness_pattern.row_offsets(), stiffness_pattern.block_columns());
  for (int l = 0; l + 1 < level_count(); ++l) {
    m_levels[l + 1].matrix = galerkin_pattern(m_levels[l].matrix, m_hierarchy.prolongation(l));
    if (settings.galerkin == GalerkinMethod::STREAM)
      m_levels[l].stream = std::make_unique<GalerkinStream>(
          m_levels[l].matrix, m_hierarchy.prolongation(l), m_levels[l + 1].matrix);
  }
  m_patches =
      FeaturePatches(mesh, m_hierarchy.constrained(0), m_levels[0].matrix, settings.patches);
  for (int l = 0; l < level_count(); ++l) {
    const int n = 3 * m_hierarchy.vertex_count(l);
    m_levels[l].b.setZero(n);
    m_levels[l].x.setZero(n);
    m_levels[l].r.setZero(n);
  }
}

TetMultigrid::~TetMultigrid() = default;
TetMultigrid::TetMultigrid(TetMultigrid&&) noexcept = default;
TetMultigrid& TetMultigrid::operator=(TetMultigrid&&) noexcept = default;

void TetMultigrid::update(const BlockRowMatrix<double>& stiffness,
                          const Eigen::VectorXd& vertex_mass, double mass_scale,
                          double stiffness_scale) {
  BlockRowMatrix<double>& a = m_levels[0].matrix;
  if (stiffness.block_count() != a.block_count() || vertex_mass.size() != a.block_rows())
    fail_tet_multigrid("stiffness or mass does not match the pattern given at construction");
  Timer timer;
  // A_0 = m M + k K~; constrained rows and columns replaced by the identity.
  const std::vector<char>& fixed = m_hierarchy.constrained(0);
  const int n = a.block_rows();
#pragma omp parallel for schedule(static) if (n >= kMinParallelItems)
  for (int i = 0; i < n; ++i)
    for (int k = a.row_offsets()[i]; k < a.row_offsets()[i + 1]; ++k) {
      const int j = a.block_columns()[k];
      if (fixed[i] != 0 || fixed[j] != 0)
        a.block(k).setZero();
      else
        a.block(k) = stiffness_scale * stiffness.block(k);
      if (i == j)
        a.block(k).diagonal().array() += fixed[i] != 0 ? 1.0 : mass_scale * vertex_mass[i];
    }
  m_times.fine_seconds = timer.seconds();
  update_coarse(m_settings.galerkin);
  if (!m_patches_seeded && m_settings.adaptive_patches.rounds > 0) seed_adaptive_patches();
  m_patches_seeded = true;
}

void TetMultigrid::seed_adaptive_patches() {
  // Power iterations of the error operator e <- (I - B A) e (cycles on A e = 0) find where the
  // cycle is slow; patches there, then again on the improved cycle (patch_seeds.hpp).
  const AdaptivePatchSettings& adaptive = m_settings.adaptive_patches;
  const std::vector<char>& fixed = m_hierarchy.constrained(0);
  const int n = m_hierarchy.vertex_count(0);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(3 * static_cast<Eigen::Index>(n));
  std::vector<char> seeded(n, 0);  // adaptive seeds so far
  const int max_seeds =
      std::max(1, static_cast<int>(adaptive.max_seed_fraction * static_cast<double>(n)));
  for (int round = 0; round < adaptive.rounds; ++round) {
    const SlowError slow = slow_error(
        n, fixed, [&](Eigen::VectorXd& v) { cycle(zero, v); }, adaptive.cycles,
        adaptive.random_seed + static_cast<unsigned>(round));
    m_adaptive_contractions.push_back(slow.contraction);
    if (!(slow.contraction > adaptive.target_contraction)) break;
    const Eigen::VectorXd& e = slow.e;
    const std::vector<int> seeds =
        slow_error_seeds(e, m_levels[0].matrix, fixed, seeded, adaptive.threshold, max_seeds);
    if (seeds.empty()) break;
    for (const int v : seeds) seeded[v] = 1;
    m_patches.append(
        FeaturePatches(grow_along_error(seeds, e, m_levels[0].matrix, fixed, adaptive.max_size),
                       fixed, m_levels[0].matrix),
        m_levels[0].matrix);
    m_patches.factor(m_levels[0].matrix);
  }
}

void TetMultigrid::update_coarse(GalerkinMethod method) {
  Timer timer;
  for (int l = 0; l + 1 < level_count(); ++l) {
    if (method == GalerkinMethod::STREAM && m_levels[l].stream)
      m_levels[l].stream->update(m_levels[l].matrix, m_levels[l + 1].matrix);
    else
      galerkin_naive(m_levels[l].matrix, m_hierarchy.prolongation(l), m_levels[l + 1].matrix);
    // Coarse vertices without free support have zero rows: identity keeps the level regular.
    const std::vector<char>& fixed = m_hierarchy.constrained(l + 1);
    for (int a = 0; a < m_levels[l + 1].matrix.block_rows(); ++a)
      if (fixed[a] != 0)
        m_levels[l + 1].matrix.block(m_levels[l + 1].matrix.diagonal_index(a)) =
            Eigen::Matrix3d::Identity();
  }
  m_times.galerkin_seconds = timer.seconds();
  timer.restart();
  finish_coarse_update();
  m_times.factor_seconds = timer.seconds();
}

void TetMultigrid::finish_coarse_update() {
  // Smoother blocks on every level but the coarsest.
  for (int l = 0; l + 1 < level_count(); ++l) {
    Level& level = m_levels[l];
    if (!m_settings.lexicographic) {
      if (!level.partitioned) level.smoother.build(level.matrix, m_settings.smoother);
      level.partitioned = true;
      level.smoother.factor(level.matrix, l);
      continue;
    }
    const int n = level.matrix.block_rows();
    level.inverse_diagonal.resize(n);
    bool singular = false;
    for (int i = 0; i < n; ++i) {
      bool invertible = false;
      level.matrix.diagonal_block(i).computeInverseWithCheck(level.inverse_diagonal[i], invertible,
                                                             1e-300);
      singular |= !invertible;
    }
    if (singular) fail_tet_multigrid("singular diagonal block on level " + std::to_string(l));
  }
  m_patches.factor(m_levels[0].matrix);
  // The Galerkin operator can be singular: coarse vertices outside the body whose support is a
  // single fine vertex give linearly dependent columns of P. A relative diagonal shift makes it
  // definite; it changes the correction only along directions that P maps to (almost) zero.
  Eigen::SparseMatrix<double> coarsest = m_levels.back().matrix.to_sparse();
  if (level_count() > 1)
    for (int i = 0; i < coarsest.rows(); ++i) coarsest.coeffRef(i, i) *= 1.0 + kCoarsestShift;
  const SingleThreadedBlas one_blas_thread;  // results independent of the thread count
  if (!m_coarsest->analyzed) {
    m_coarsest->factorization.analyzePattern(coarsest);
    m_coarsest->analyzed = true;
  }
  m_coarsest->factorization.factorize(coarsest);
  if (m_coarsest->factorization.info() != Eigen::Success)
    fail_tet_multigrid("coarsest operator (level " + std::to_string(level_count() - 1) +
                       ") is not positive definite");
}

void TetMultigrid::smooth(int l, const Eigen::VectorXd& b, Eigen::VectorXd& x, bool forward) const {
  const double w =
      m_settings.symmetric_sweeps ? m_settings.symmetric_relaxation : m_settings.relaxation;
  // Feature patches (fine level) after a forward sweep, before a backward one: symmetric pairs.
  const bool patches = l == 0 && m_patches.patch_count() > 0;
  if (patches && !forward) m_patches.pass(m_levels[0].matrix, b, x, false);
  if (!m_settings.lexicographic) {
    m_levels[l].smoother.sweep(m_levels[l].matrix, b, x, forward, w);
  } else {
    lexicographic_sweep(l, b, x, forward, w);
  }
  if (patches && forward) m_patches.pass(m_levels[0].matrix, b, x, true);
}

void TetMultigrid::lexicographic_sweep(int l, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                       bool forward, double w) const {
  // Block Gauss-Seidel: x_i <- D_i^{-1} (b_i - sum_{j != i} A_ij x_j), rows in order (serial).
  const BlockRowMatrix<double>& a = m_levels[l].matrix;
  const int n = a.block_rows();
  for (int step = 0; step < n; ++step) {
    const int i = forward ? step : n - 1 - step;
    Eigen::Vector3d r = b.segment<3>(3 * i);
    for (int k = a.row_offsets()[i]; k < a.row_offsets()[i + 1]; ++k) {
      const int j = a.block_columns()[k];
      if (j != i) r.noalias() -= a.block(k) * x.segment<3>(3 * j);
    }
    if (w == 1.0)
      x.segment<3>(3 * i) = m_levels[l].inverse_diagonal[i] * r;
    else
      x.segment<3>(3 * i) =
          (1.0 - w) * x.segment<3>(3 * i) + w * (m_levels[l].inverse_diagonal[i] * r);
  }
}

void TetMultigrid::sweeps(int l, int count, bool forward, bool symmetric_cycle) const {
  const Level& level = m_levels[l];
  for (int s = 0; s < count; ++s) {
    if (!m_settings.symmetric_sweeps) {
      smooth(l, level.b, level.x, forward);
    } else if (symmetric_cycle) {
      // Forward then backward on both sides: the symmetric Gauss-Seidel step is self-adjoint in
      // the A inner product, so the cycle is symmetric (a valid CG preconditioner).
      smooth(l, level.b, level.x, true);
      smooth(l, level.b, level.x, false);
    } else {
      // Mirrored (pre forward + backward, post backward + forward): not symmetric, but the
      // better stand-alone cycle (armadillo 0.215 per cycle against 0.33).
      smooth(l, level.b, level.x, forward);
      smooth(l, level.b, level.x, !forward);
    }
  }
}

void TetMultigrid::cycle_level(int l, std::vector<LevelResiduals>* trace,
                               bool symmetric_cycle) const {
  const Level& level = m_levels[l];
  const auto record = [&](double LevelResiduals::*field) {
    if (trace == nullptr) return;
    Eigen::VectorXd r;
    level.matrix.multiply(level.x, r);
    (*trace)[l].*field = (level.b - r).norm();
  };
  record(&LevelResiduals::entry);
  if (l == level_count() - 1) {
    // Coarsest: exact solve.
    const SingleThreadedBlas one_blas_thread;
    level.x = m_coarsest->factorization.solve(level.b);
    return;
  }
  // Pre-smoothing damps the oscillatory error the coarse grid cannot represent.
  sweeps(l, m_settings.pre_smoothing, true, symmetric_cycle);
  record(&LevelResiduals::pre_smoothed);
  // Residual, restricted with R = P^T.
  level.matrix.multiply(level.x, level.r);
  level.r = level.b - level.r;
  const Level& coarse = m_levels[l + 1];
  m_hierarchy.prolongation(l).restrict_to(level.r, coarse.b);
  // Coarse correction from a zero guess, prolonged and added.
  coarse.x.setZero();
  cycle_level(l + 1, trace, symmetric_cycle);
  m_hierarchy.prolongation(l).prolong_add(coarse.x, level.x);
  record(&LevelResiduals::corrected);
  // Backward post-smoothing keeps the cycle symmetric (a valid CG preconditioner).
  sweeps(l, m_settings.post_smoothing, false, symmetric_cycle);
  record(&LevelResiduals::post_smoothed);
}

void TetMultigrid::cycle(const Eigen::VectorXd& b, Eigen::VectorXd& x) const {
  if (b.size() != m_levels[0].b.size() || x.size() != b.size())
    fail_tet_multigrid("vector size mismatch");
  m_levels[0].b = b;
  m_levels[0].x = x;
  cycle_level(0, nullptr, false);
  x = m_levels[0].x;
}

void TetMultigrid::precondition(const Eigen::VectorXd& r, Eigen::VectorXd& z) const {
  m_levels[0].b = r;
  m_levels[0].x = z;
  cycle_level(0, nullptr, true);
  z = m_levels[0].x;
}

std::vector<LevelResiduals> TetMultigrid::cycle_traced(const Eigen::VectorXd& b,
                                                       Eigen::VectorXd& x) const {
  if (b.size() != m_levels[0].b.size() || x.size() != b.size())
    fail_tet_multigrid("vector size mismatch");
  std::vector<LevelResiduals> trace(level_count());
  m_levels[0].b = b;
  m_levels[0].x = x;
  cycle_level(0, &trace, false);
  x = m_levels[0].x;
  return trace;
}

void TetMultigrid::residual(const Eigen::VectorXd& b, const Eigen::VectorXd& x,
                            Eigen::VectorXd& r) const {
  r.resize(b.size());
  m_levels[0].matrix.multiply(x, r);
  r = b - r;
}

MultigridResult TetMultigrid::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x, double tolerance,
                                    int max_cycles) const {
  MultigridResult result;
  const double b_norm = b.norm();
  Eigen::VectorXd r;
  residual(b, x, r);
  result.relative_residual = b_norm > 0.0 ? r.norm() / b_norm : r.norm();
  while (result.relative_residual > tolerance && result.cycles < max_cycles) {
    throw_if_cancelled();
    cycle(b, x);
    ++result.cycles;
    residual(b, x, r);
    result.relative_residual = b_norm > 0.0 ? r.norm() / b_norm : r.norm();
    if (!std::isfinite(result.relative_residual))
      fail_tet_multigrid("V-cycle produced non-finite values");
  }
  result.converged = result.relative_residual <= tolerance;
  return result;
}

PcgResult TetMultigrid::solve_pcg(const Eigen::VectorXd& b, Eigen::VectorXd& x,
                                  const PcgSettings& settings) const {
  PcgResult result;
  const double b_norm = b.norm();
  if (b_norm == 0.0) {
    x.setZero(b.size());
    result.converged = true;
    return result;
  }
  Eigen::VectorXd r, z = Eigen::VectorXd::Zero(b.size()), p, q(b.size());
  residual(b, x, r);
  result.relative_residual = r.norm() / b_norm;
  if (result.relative_residual <= settings.tolerance) {
    result.converged = true;
    return result;
  }
  precondition(r, z);
  p = z;
  double rz = r.dot(z);
  while (result.iterations < settings.max_iterations) {
    m_levels[0].matrix.multiply(p, q);
    const double curvature = p.dot(q);
    if (!(curvature > 0.0))
      fail_tet_multigrid("MG-PCG met non-positive curvature p.Ap = " + std::to_string(curvature));
    const double alpha = rz / curvature;
    x += alpha * p;
    r -= alpha * q;
    ++result.iterations;
    result.relative_residual = r.norm() / b_norm;
    if (!std::isfinite(result.relative_residual))
      fail_tet_multigrid("MG-PCG produced non-finite values");
    if (result.relative_residual <= settings.tolerance) break;
    z.setZero();
    precondition(r, z);
    const double rz_new = r.dot(z);
    p = z + (rz_new / rz) * p;
    rz = rz_new;
  }
  result.converged = result.relative_residual <= settings.tolerance;
  return result;
}

std::size_t TetMultigrid::stream_memory_bytes() const {
  std::size_t bytes = 0;
  for (const Level& level : m_levels)
    if (level.stream) bytes += level.stream->memory_bytes();
  return bytes;
}

}  // namespace mgelastic::tet
