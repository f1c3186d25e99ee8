#pragma once
// Error history of plain cycles against the converged solution: the honest measure of the
// first cycles from a zero start.
//
// From a zero initial guess the error is the whole smooth deformation (a body sagging under
// gravity) and its residual is just the load; the first cycle removes most of that error but
// leaves a rougher remainder whose residual can be larger (armadillo at 128 cells: the residual
// grows 14x in cycle 1 while the error drops to 0.23-0.39 of the solution per component). So the
// residual ratio of the first cycle says nothing about divergence; this history does.
#include <vector>

#include "mgelastic/grid/multigrid.hpp"

namespace mgelastic::grid {

struct ErrorHistory {
  // Relative 2-norm of x_c - x* over the finest level's interior unknowns (all fields), for
  // c = 0 (the initial guess) .. cycles; x* from a double, FGMRES-accelerated solve to 1e-10.
  std::vector<double> relative_error;
  double reference_residual = 0;  // relative residual the reference solve reached
};

template <int Dim, typename Scalar>
ErrorHistory error_history(const ElasticityProblem<Dim>& problem, const MultigridOptions& options,
                           int cycles);

}  // namespace mgelastic::grid
