#pragma once
// A diagnostic coarse operator: the coarsest level's rows replaced by the Galerkin product of
// the level above,
//   A_c = P^T A_f P / 2^d (stored as P^T A_f P, the right-hand side scaled to match),
// with P the V-cycle's own prolongation (prolongate_correction after the coarse traction
// back-substitution) and A_f the fine level's residual operator (band rows, stencils, traction
// rules), both applied to unit vectors: one probe per coarse unknown, so small problems only.
// The right-hand side stays the V-cycle's restriction. GALERKIN_BAND keeps the coarse level's
// own rows off its band (the rows a production version would replace). It answers whether a
// coarse operator is what limits a two-level rate (bench vcycle --max-levels 2
// --coarsest-operator ...): docs/notes/2026-12-06-misaligned-clamps.md.
//
// Layout: the unknowns are the coarse INTERIOR variables of every field (u_0 .. u_{d-1}, p),
// the matrix is factored by sparse LU (Eigen::SparseLU; P^T A P is not symmetric where the
// traction rules make P one-sided).
#include <memory>
#include <string>

#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {

// (The production form, Galerkin displacement terms computed locally on every coarse level, is
// galerkin_band_rows.hpp.)
enum class CoarsestOperator { REDISCRETIZED, GALERKIN, GALERKIN_BAND };

// "rediscretized", "galerkin" or "galerkin_band"; throws Error naming `pointer` otherwise.
CoarsestOperator coarsest_operator(const std::string& name, const std::string& pointer);

template <int Dim, typename Scalar>
class GalerkinCoarseSolver {
 public:
  // Probes with the levels' x and b (left zero) and r (released afterwards); throws Error when
  // the product is singular.
  GalerkinCoarseSolver(Level<Dim, Scalar>& fine, Level<Dim, Scalar>& coarse, bool band_only);
  ~GalerkinCoarseSolver();
  GalerkinCoarseSolver(GalerkinCoarseSolver&&) noexcept;
  GalerkinCoarseSolver& operator=(GalerkinCoarseSolver&&) noexcept;

  // Solves with coarse.b and overwrites coarse.x (traction variables back-substituted).
  void solve(Level<Dim, Scalar>& coarse) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> m_impl;
};

}  // namespace mgelastic::grid
