#pragma once
// Rotation field of the co-rotational model (Zhu et al. 2010, Sec. 7): per cell, the rotation R
// of the polar decomposition F = R S of the deformation gradient F = I + grad u at the cell
// center. Diagonal gradients are the cell's own differences, F_ii = 1 + (u_i[k + s_i] - u_i[k])/h;
// an off-diagonal gradient d_j u_i is naturally defined on the four (i, j) edges around the cell,
// (u_i[e] - u_i[e - s_j]) / h at e in {k, k + s_i, k + s_j, k + s_i + s_j}, and is averaged over
// those whose two faces are active variables (lattice.hpp layout).
//
// This is the building block of the quasi-linear system (14): corotated_operator.hpp builds its
// rows from these rotations, corotated_multigrid.hpp refreshes them every k cycles.
#include <Eigen/Core>
#include <vector>

#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {

template <int Dim>
using Matrix = Eigen::Matrix<double, Dim, Dim>;

// R = U V^T from the SVD F = U Sigma V^T. When det(U V^T) < 0 (an inverted or reflected cell) the
// column of U of the smallest singular value is negated, which gives the proper rotation closest
// to F. Never NaN: a non-finite F gives the identity; a singular F still gives a rotation.
template <int Dim>
Matrix<Dim> polar_rotation(const Matrix<Dim>& deformation_gradient);

// F = I + grad u at the center of cell k from the level's current x (see above).
template <int Dim, typename Scalar>
Matrix<Dim> cell_deformation_gradient(const Level<Dim, Scalar>& level, std::ptrdiff_t k);

// One rotation per lattice point: the polar rotation at interior cells, identity elsewhere.
template <int Dim, typename Scalar>
std::vector<Matrix<Dim>> cell_rotations(const Level<Dim, Scalar>& level);
// The same into `rotations`, reusing its storage: only the interior cells are written, so one
// of another size is first filled with the identity, and one of the level's size must hold the
// identity at every other cell (as every earlier result for this level does).
template <int Dim, typename Scalar>
void cell_rotations(const Level<Dim, Scalar>& level, std::vector<Matrix<Dim>>& rotations);

// Rotation field of the next coarser level (2^d-to-1 cells, coarsening.hpp): the polar rotation
// of the mean of the fine children's rotations that are interior on the fine level.
template <int Dim>
std::vector<Matrix<Dim>> restrict_rotations(const Lattice<Dim>& fine,
                                            const std::vector<CellType>& fine_cells,
                                            const std::vector<Matrix<Dim>>& rotations,
                                            const Lattice<Dim>& coarse);

}  // namespace mgelastic::grid
