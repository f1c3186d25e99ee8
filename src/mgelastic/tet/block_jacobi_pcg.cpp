#include "mgelastic/tet/block_jacobi_pcg.hpp"
#include "mgelastic/tet/parallel.hpp"

#include <Eigen/LU>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "mgelastic/core/cancellation.hpp"
#include "mgelastic/core/error.hpp"

namespace mgelastic::tet {

StepSystem::StepSystem(const BlockRowMatrix<double>& stiffness, const Eigen::VectorXd& mass,
                       double mass_scale, double stiffness_scale,
                       const std::vector<char>& constrained)
    : m_stiffness(&stiffness),
      m_mass(&mass),
      m_mass_scale(mass_scale),
      m_stiffness_scale(stiffness_scale),
      m_constrained(&constrained) {}

void StepSystem::apply_unconstrained(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  m_stiffness->multiply(x, y);
  const int n = static_cast<int>(m_mass->size());
#pragma omp parallel for schedule(static) if (n >= kMinParallelItems)
  for (int v = 0; v < n; ++v)
    y.segment<3>(3 * v) =
        m_stiffness_scale * y.segment<3>(3 * v) + m_mass_scale * (*m_mass)[v] * x.segment<3>(3 * v);
}

void StepSystem::apply(const Eigen::VectorXd& x, Eigen::VectorXd& y) const {
  // P A P + (I - P) with P the projection onto free vertices.
  Eigen::VectorXd free_x = x;
  const int n = static_cast<int>(m_mass->size());
  for (int v = 0; v < n; ++v)
    if ((*m_constrained)[v]) free_x.segment<3>(3 * v).setZero();
  apply_unconstrained(free_x, y);
  for (int v = 0; v < n; ++v)
    if ((*m_constrained)[v]) y.segment<3>(3 * v) = x.segment<3>(3 * v);
}

void StepSystem::eliminate(const Eigen::VectorXd& known, Eigen::VectorXd& b) const {
  // Only the blocks coupling a free row to a constrained column contribute (the mass is
  // diagonal and constrained rows are overwritten): a pass over the pattern, not a product.
  const BlockRowMatrix<double>& k = *m_stiffness;
  const std::vector<char>& constrained = *m_constrained;
  const int n = static_cast<int>(m_mass->size());
#pragma omp parallel for schedule(static) if (n >= kMinParallelItems)
  for (int v = 0; v < n; ++v) {
    if (constrained[v]) {
      b.segment<3>(3 * v) = known.segment<3>(3 * v);
      continue;
    }
    Eigen::Vector3d coupling = Eigen::Vector3d::Zero();
    for (int e = k.row_offsets()[v]; e < k.row_offsets()[v + 1]; ++e) {
      const int c = k.block_columns()[e];
      if (constrained[c]) coupling.noalias() += k.block(e) * known.segment<3>(3 * c);
    }
    b.segment<3>(3 * v) -= m_stiffness_scale * coupling;
  }
}

void StepSystem::update_preconditioner() {
  compute_inverse_diagonal();
}

void StepSystem::compute_inverse_diagonal() const {
  const int n = static_cast<int>(m_mass->size());
  m_inverse_diagonal.resize(n);
#pragma omp parallel for schedule(static) if (n >= kMinParallelItems)
  for (int v = 0; v < n; ++v) {
    if ((*m_constrained)[v]) {
      m_inverse_diagonal[v].setIdentity();
      continue;
    }
    const Eigen::Matrix3d d = m_stiffness_scale * m_stiffness->diagonal_block(v) +
                              m_mass_scale * (*m_mass)[v] * Eigen::Matrix3d::Identity();
    // A singular block (a vertex without mass or stiffness) falls back to the identity.
    Eigen::Matrix3d inverse;
    bool invertible = false;
    d.computeInverseWithCheck(inverse, invertible, 1e-300);
    m_inverse_diagonal[v] =
        invertible && inverse.allFinite() ? inverse : Eigen::Matrix3d::Identity();
  }
}

void StepSystem::precondition(const Eigen::VectorXd& r, Eigen::VectorXd& y) const {
  const int n = static_cast<int>(m_mass->size());
  // Built on first use: steps solved by multigrid never need it.
  if (static_cast<int>(m_inverse_diagonal.size()) != n) compute_inverse_diagonal();
  y.resize(r.size());
#pragma omp parallel for schedule(static) if (n >= kMinParallelItems)
  for (int v = 0; v < n; ++v) y.segment<3>(3 * v) = m_inverse_diagonal[v] * r.segment<3>(3 * v);
}

Eigen::SparseMatrix<double> StepSystem::to_sparse() const {
  const Eigen::SparseMatrix<double> k = m_stiffness->to_sparse();
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(k.nonZeros() + size());
  const auto constrained = [this](int dof) { return (*m_constrained)[dof / 3] != 0; };
  for (int col = 0; col < k.outerSize(); ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(k, col); it; ++it)
      if (!constrained(static_cast<int>(it.row())) && !constrained(col))
        triplets.emplace_back(static_cast<int>(it.row()), col, m_stiffness_scale * it.value());
  for (int dof = 0; dof < size(); ++dof)
    triplets.emplace_back(dof, dof, constrained(dof) ? 1.0 : m_mass_scale * (*m_mass)[dof / 3]);
  Eigen::SparseMatrix<double> a(size(), size());
  a.setFromTriplets(triplets.begin(), triplets.end());
  return a;
}

namespace {

// The relative residuals of the iterations so far: all of up to 12, else the first 4 and the
// last 8 (how the iteration went before it failed).
std::string history_text(const std::vector<double>& history) {
  std::string text;
  char number[32];
  for (std::size_t i = 0; i < history.size(); ++i) {
    if (history.size() > 12 && i == 4) {
      text += " ...";
      i = history.size() - 8;
    }
    std::snprintf(number, sizeof number, "%s%.3e", text.empty() ? "" : " ", history[i]);
    text += number;
  }
  return text;
}

[[noreturn]] void fail(const std::string& reason, int iteration,
                       const std::vector<double>& history = {}) {
  throw Error(reason + " at iteration " + std::to_string(iteration) +
                  (history.empty() ? std::string()
                                   : "; relative residual history: " + history_text(history)),
              ErrorContext{std::string(), -1, "PCG"});
}

}  // namespace

PcgResult solve_pcg(const StepSystem& system, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                    const PcgSettings& settings) {
  PcgResult result;
  const double b_norm = b.norm();
  if (!std::isfinite(b_norm)) fail("non-finite right-hand side", 0);
  if (x.size() != b.size() || !x.allFinite()) x = Eigen::VectorXd::Zero(b.size());
  if (b_norm == 0.0) {
    x.setZero();
    result.converged = true;
    return result;
  }
  Eigen::VectorXd r, z, p, ap;
  system.apply(x, ap);
  r = b - ap;
  system.precondition(r, z);
  p = z;
  double rz = r.dot(z);
  std::vector<double> history;  // for the message of a failure
  for (; result.iterations < settings.max_iterations; ++result.iterations) {
    throw_if_cancelled();
    result.relative_residual = r.norm() / b_norm;
    history.push_back(result.relative_residual);
    if (!std::isfinite(result.relative_residual))
      fail("non-finite residual (NaN in the system?)", result.iterations, history);
    if (result.relative_residual > 1e8) fail("residual diverged", result.iterations, history);
    if (result.relative_residual <= settings.tolerance) break;
    system.apply(p, ap);
    const double curvature = p.dot(ap);
    if (!(curvature > 0.0))
      fail("non-positive curvature p.Ap (matrix not SPD)", result.iterations, history);
    const double alpha = rz / curvature;
    x += alpha * p;
    r -= alpha * ap;
    system.precondition(r, z);
    const double rz_next = r.dot(z);
    p = z + (rz_next / rz) * p;
    rz = rz_next;
  }
  result.relative_residual = r.norm() / b_norm;
  result.converged = result.relative_residual <= settings.tolerance;
  return result;
}

}  // namespace mgelastic::tet
