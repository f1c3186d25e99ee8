#include "mgelastic/grid/corotated_newton_krylov.hpp"

#include <cmath>
#include <utility>

namespace mgelastic::grid {

MinimalResidualCombination::MinimalResidualCombination(Eigen::VectorXd initial_residual)
    : m_initial(std::move(initial_residual)), m_residual(m_initial) {}

void MinimalResidualCombination::add(Eigen::VectorXd direction, Eigen::VectorXd image) {
  m_z.push_back(std::move(direction));
  const double norm = image.norm();
  if (!(norm > 0) || !std::isfinite(norm)) return;  // weight zero
  const auto kept = static_cast<Eigen::Index>(m_q.size());
  Eigen::VectorXd h = Eigen::VectorXd::Zero(kept);
  for (int pass = 0; pass < 2; ++pass)  // twice is enough (Giraud et al.)
    for (Eigen::Index i = 0; i < kept; ++i) {
      const double c = m_q[static_cast<std::size_t>(i)].dot(image);
      image -= c * m_q[static_cast<std::size_t>(i)];
      h[i] += c;
    }
  const double rest = image.norm();
  // Rank-revealing: a direction the preconditioner repeats (a converged inner solve) must not
  // get a huge, cancelling coefficient.
  if (!(rest > 1e-10 * norm)) return;
  image /= rest;
  m_r.conservativeResize(kept + 1, kept + 1);
  m_r.row(kept).setZero();
  m_r.col(kept).head(kept) = h;
  m_r(kept, kept) = rest;
  m_q_dot_r0.push_back(image.dot(m_initial));
  m_residual -= image.dot(m_residual) * image;
  m_q.push_back(std::move(image));
  m_kept.push_back(static_cast<int>(m_z.size()) - 1);
}

Eigen::VectorXd MinimalResidualCombination::coefficients() const {
  const auto kept = static_cast<Eigen::Index>(m_q.size());
  const Eigen::Map<const Eigen::VectorXd> g(m_q_dot_r0.data(), kept);
  const Eigen::VectorXd a =
      kept > 0 ? Eigen::VectorXd(m_r.triangularView<Eigen::Upper>().solve(g)) : Eigen::VectorXd();
  Eigen::VectorXd all = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(m_z.size()));
  for (Eigen::Index i = 0; i < kept; ++i) all[m_kept[static_cast<std::size_t>(i)]] = a[i];
  return all;
}

Eigen::VectorXd MinimalResidualCombination::correction() const {
  const Eigen::VectorXd a = coefficients();
  Eigen::VectorXd d = Eigen::VectorXd::Zero(m_initial.size());
  for (std::size_t c = 0; c < m_z.size(); ++c)
    if (a[static_cast<Eigen::Index>(c)] != 0) d += a[static_cast<Eigen::Index>(c)] * m_z[c];
  return d;
}

}  // namespace mgelastic::grid
