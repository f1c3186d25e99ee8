#include "mgelastic/grid/corotated_newton_krylov.hpp"

#include <Eigen/QR>

namespace mgelastic::grid {

MinimalResidualCombination::MinimalResidualCombination(Eigen::VectorXd initial_residual)
    : m_initial(std::move(initial_residual)), m_residual(m_initial) {}

void MinimalResidualCombination::add(const Eigen::VectorXd& direction,
                                     const Eigen::VectorXd& image) {
  m_z.push_back(direction);
  m_w.push_back(image);
  const auto columns = static_cast<Eigen::Index>(m_w.size());
  Eigen::MatrixXd w(m_initial.size(), columns);
  for (Eigen::Index c = 0; c < columns; ++c) w.col(c) = m_w[c];
  // Rank-revealing: a direction the preconditioner repeats (a converged inner solve) must not
  // get a huge, cancelling coefficient.
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(w);
  qr.setThreshold(1e-10);
  Eigen::VectorXd a = qr.solve(m_initial);
  if (!a.allFinite()) a = Eigen::VectorXd::Zero(columns);
  m_coefficients = a;
  m_residual = m_initial - w * a;
}

Eigen::VectorXd MinimalResidualCombination::correction() const {
  Eigen::VectorXd d = Eigen::VectorXd::Zero(m_initial.size());
  for (std::size_t c = 0; c < m_z.size(); ++c)
    d += m_coefficients[static_cast<Eigen::Index>(c)] * m_z[c];
  return d;
}

}  // namespace mgelastic::grid
