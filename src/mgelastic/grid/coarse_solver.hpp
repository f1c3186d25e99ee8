#pragma once
// Exact solve on the coarsest level (Algorithm 1, line 8): sparse Cholesky (SuiteSparse
// CHOLMOD) of the non-augmented system A = -S, factored once; pressures recovered exactly and
// traction variables back-substituted so the coarse correction is defined at boundary variables.
#include <memory>

#include "mgelastic/core/error.hpp"
#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {

// The coarsest-level matrix is singular (or numerically so).
class SingularCoarseLevel : public Error {
 public:
  using Error::Error;
};

template <int Dim, typename Scalar>
class CoarseSolver {
 public:
  explicit CoarseSolver(const Level<Dim, Scalar>& level);
  ~CoarseSolver();
  CoarseSolver(CoarseSolver&&) noexcept;
  CoarseSolver& operator=(CoarseSolver&&) noexcept;

  // Solves with the level's current right-hand side and overwrites level.x.
  void solve(Level<Dim, Scalar>& level) const;
  // Memory of the Cholesky factor's values and row indices.
  std::size_t factor_bytes() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

}  // namespace mgelastic::grid
