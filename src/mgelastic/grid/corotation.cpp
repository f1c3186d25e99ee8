#include "mgelastic/grid/corotation.hpp"

#include <Eigen/LU>
#include <Eigen/SVD>
#include <cmath>

namespace mgelastic::grid {

template <int Dim>
Matrix<Dim> polar_rotation(const Matrix<Dim>& f) {
  if (!f.allFinite()) return Matrix<Dim>::Identity();
  const Eigen::JacobiSVD<Matrix<Dim>> svd(f, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Matrix<Dim> u = svd.matrixU();
  const Matrix<Dim>& v = svd.matrixV();
  // Singular values are sorted decreasingly: the last column belongs to the smallest one.
  if ((u * v.transpose()).determinant() < 0) u.col(Dim - 1) *= -1.0;
  return u * v.transpose();
}

template <int Dim, typename Scalar>
Matrix<Dim> cell_deformation_gradient(const Level<Dim, Scalar>& level, std::ptrdiff_t k) {
  const auto& lat = level.lattice;
  const double inv_h = 1.0 / lat.h;
  Matrix<Dim> f = Matrix<Dim>::Identity();
  auto active = [&](int axis, std::ptrdiff_t face) {
    return level.kind(axis, face) != VarKind::INACTIVE;
  };
  for (int i = 0; i < Dim; ++i) {
    const std::ptrdiff_t si = lat.stride(i);
    if (active(i, k) && active(i, k + si))
      f(i, i) += inv_h * (static_cast<double>(level.x[i][k + si]) - level.x[i][k]);
    for (int j = 0; j < Dim; ++j) {
      if (j == i) continue;
      const std::ptrdiff_t sj = lat.stride(j);
      double sum = 0;
      int count = 0;
      for (std::ptrdiff_t e : {k, k + si, k + sj, k + si + sj}) {
        if (!active(i, e) || !active(i, e - sj)) continue;
        sum += static_cast<double>(level.x[i][e]) - level.x[i][e - sj];
        ++count;
      }
      if (count > 0) f(i, j) += inv_h * sum / count;
    }
  }
  return f;
}

template <int Dim, typename Scalar>
void cell_rotations(const Level<Dim, Scalar>& level, std::vector<Matrix<Dim>>& rotations) {
  if (rotations.size() != level.size()) rotations.assign(level.size(), Matrix<Dim>::Identity());
  const auto n = static_cast<std::ptrdiff_t>(level.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t k = 0; k < n; ++k)
    if (level.cells[k] == CellType::INTERIOR)
      rotations[k] = polar_rotation<Dim>(cell_deformation_gradient(level, k));
}

template <int Dim, typename Scalar>
std::vector<Matrix<Dim>> cell_rotations(const Level<Dim, Scalar>& level) {
  std::vector<Matrix<Dim>> rotations;
  cell_rotations(level, rotations);
  return rotations;
}

template <int Dim>
std::vector<Matrix<Dim>> restrict_rotations(const Lattice<Dim>& fine,
                                            const std::vector<CellType>& fine_cells,
                                            const std::vector<Matrix<Dim>>& rotations,
                                            const Lattice<Dim>& coarse) {
  std::vector<Matrix<Dim>> result(coarse.size(), Matrix<Dim>::Identity());
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(coarse.size()); ++k) {
    const IVec<Dim> s = coarse.coords(k);
    if (!coarse.is_real(s)) continue;
    Matrix<Dim> sum = Matrix<Dim>::Zero();
    int count = 0;
    for (int child = 0; child < (1 << Dim); ++child) {
      IVec<Dim> c;
      for (int a = 0; a < Dim; ++a) c[a] = 2 * (s[a] - 1) + 1 + ((child >> a) & 1);
      if (!fine.is_real(c)) continue;
      const std::ptrdiff_t f = fine.index(c);
      if (fine_cells[f] != CellType::INTERIOR) continue;
      sum += rotations[f];
      ++count;
    }
    if (count > 0) result[k] = polar_rotation<Dim>(sum);
  }
  return result;
}

#define MGELASTIC_INSTANTIATE(D, S)                                                       \
  template Matrix<D> cell_deformation_gradient<D, S>(const Level<D, S>&, std::ptrdiff_t); \
  template std::vector<Matrix<D>> cell_rotations<D, S>(const Level<D, S>&);               \
  template void cell_rotations<D, S>(const Level<D, S>&, std::vector<Matrix<D>>&);
MGELASTIC_INSTANTIATE(2, float)
MGELASTIC_INSTANTIATE(2, double)
MGELASTIC_INSTANTIATE(3, float)
MGELASTIC_INSTANTIATE(3, double)
#undef MGELASTIC_INSTANTIATE
template Matrix<2> polar_rotation<2>(const Matrix<2>&);
template Matrix<3> polar_rotation<3>(const Matrix<3>&);
template std::vector<Matrix<2>> restrict_rotations<2>(const Lattice<2>&,
                                                      const std::vector<CellType>&,
                                                      const std::vector<Matrix<2>>&,
                                                      const Lattice<2>&);
template std::vector<Matrix<3>> restrict_rotations<3>(const Lattice<3>&,
                                                      const std::vector<CellType>&,
                                                      const std::vector<Matrix<3>>&,
                                                      const Lattice<3>&);

}  // namespace mgelastic::grid
