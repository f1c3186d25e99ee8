#include "mgelastic/grid/corotated_acceleration.hpp"

#include <Eigen/QR>

namespace mgelastic::grid {

Eigen::VectorXd AndersonMixing::mix(const Eigen::VectorXd& x, const Eigen::VectorXd& gx) {
  m_f.push_back(gx - x);
  m_g.push_back(gx);
  if (static_cast<int>(m_g.size()) > m_depth + 1) {
    m_f.pop_front();
    m_g.pop_front();
  }
  const int columns = static_cast<int>(m_g.size()) - 1;
  if (columns == 0) return gx;
  Eigen::MatrixXd df(x.size(), columns), dg(x.size(), columns);
  for (int c = 0; c < columns; ++c) {
    df.col(c) = m_f[c + 1] - m_f[c];
    dg.col(c) = m_g[c + 1] - m_g[c];
  }
  // Rank-revealing QR: nearly parallel differences (a stagnating iteration) get zero weight
  // instead of a huge, cancelling combination.
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(df);
  qr.setThreshold(1e-10);
  const Eigen::VectorXd gamma = qr.solve(m_f.back());
  if (!gamma.allFinite()) return gx;
  return gx - dg * gamma;
}

void AndersonMixing::reset() {
  m_f.clear();
  m_g.clear();
}

}  // namespace mgelastic::grid
