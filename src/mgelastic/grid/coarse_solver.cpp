#include "mgelastic/grid/coarse_solver.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/UmfPackSupport>

#include "mgelastic/core/blas_threads.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/grid/boundary_smoother.hpp"
#include "mgelastic/grid/nonaugmented_system.hpp"

namespace mgelastic::grid {

// Supernodal Cholesky that also reports CHOLMOD's reciprocal condition estimate of its factor.
class CoarseCholesky : public Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>> {
 public:
  double reciprocal_condition() { return cholmod_rcond(m_cholmodFactor, &cholmod()); }
  std::size_t factor_bytes() const {
    const cholmod_factor* f = m_cholmodFactor;
    if (!f) return 0;
    if (f->is_super) return f->xsize * sizeof(double) + f->ssize * sizeof(int);
    return f->nzmax * (sizeof(double) + sizeof(int));
  }
};

template <int Dim, typename Scalar>
struct CoarseSolver<Dim, Scalar>::Impl {
  NonAugmentedSystem<Dim> system;
  CoarseCholesky cholesky;
  // Galerkin band rows (galerkin_band_rows.hpp) next to stencil rows make the matrix
  // unsymmetric (its symmetric part diverges in a V-cycle): LU instead.
  Eigen::UmfPackLU<Eigen::SparseMatrix<double>> lu;
  bool use_lu = false;
  std::size_t lu_bytes = 0;  // L and U values and row indices
};

template <int Dim, typename Scalar>
CoarseSolver<Dim, Scalar>::CoarseSolver(const Level<Dim, Scalar>& level)
    : m_impl(std::make_unique<Impl>()) {
  // Coarse boundary conditions are homogeneous: no traction values, zero Dirichlet values.
  m_impl->system = assemble_nonaugmented(level, BoundaryStress<Dim>{});
  if (m_impl->system.u_variables.empty())
    throw Error("the coarsest grid level has no interior variable", {.pointer = "grid"});
  // Quiet: a failed factorization is reported by the exception below (or handled by the caller).
  m_impl->cholesky.cholmod().print = 0;
  const SingleThreadedBlas one_blas_thread;  // results independent of the thread count
  if (level.galerkin_band_rows) {
    m_impl->use_lu = true;
    m_impl->lu.compute(m_impl->system.matrix);
    if (m_impl->lu.info() != Eigen::Success)
      throw SingularCoarseLevel(
          "the coarsest-level system with Galerkin band rows is singular (is every part of the "
          "body held by a Dirichlet region?)",
          {.pointer = "grid"});
    m_impl->lu_bytes = static_cast<std::size_t>(m_impl->lu.matrixL().nonZeros() +
                                                m_impl->lu.matrixU().nonZeros()) *
                       (sizeof(double) + sizeof(int));
    return;
  }
  m_impl->cholesky.compute(m_impl->system.matrix);
  // A body part that can move without strain on this level (not held, or a coarse sheet one cell
  // thick whose shear is traction-free) makes the matrix singular; rounding may still let the
  // factorization through, so the condition estimate decides too.
  if (m_impl->cholesky.info() != Eigen::Success ||
      !(m_impl->cholesky.reciprocal_condition() > 1e-13))
    throw SingularCoarseLevel(
        "the coarsest-level system is singular (is every part of the body held by a "
        "Dirichlet region?)",
        {.pointer = "grid"});
}

template <int Dim, typename Scalar>
CoarseSolver<Dim, Scalar>::~CoarseSolver() = default;
template <int Dim, typename Scalar>
CoarseSolver<Dim, Scalar>::CoarseSolver(CoarseSolver&&) noexcept = default;
template <int Dim, typename Scalar>
CoarseSolver<Dim, Scalar>& CoarseSolver<Dim, Scalar>::operator=(CoarseSolver&&) noexcept = default;

template <int Dim, typename Scalar>
void CoarseSolver<Dim, Scalar>::solve(Level<Dim, Scalar>& level) const {
  const Eigen::VectorXd rhs = m_impl->system.right_hand_side(level);
  const SingleThreadedBlas one_blas_thread;
  const Eigen::VectorXd u = m_impl->use_lu ? Eigen::VectorXd(m_impl->lu.solve(rhs))
                                           : Eigen::VectorXd(m_impl->cholesky.solve(rhs));
  m_impl->system.scatter(u, level);
  back_substitute_traction(level);
}

template <int Dim, typename Scalar>
std::size_t CoarseSolver<Dim, Scalar>::factor_bytes() const {
  if (m_impl->use_lu) return m_impl->lu_bytes;
  return m_impl->cholesky.factor_bytes();
}

template class CoarseSolver<2, float>;
template class CoarseSolver<2, double>;
template class CoarseSolver<3, float>;
template class CoarseSolver<3, double>;

}  // namespace mgelastic::grid
