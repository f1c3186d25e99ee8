#pragma once
// Loads of a built level replaced in place (issue 21: loads changed between steps).
//
// A level's loads are (a) the boundary stresses sigma of its traction conditions, which the build
// wrote into the traction rules (normal, thin, shear) and into the `constant` of every band row
// (BandKernel::constant for momentum rows, band_p.constant for pressure rows, explicit_rows.hpp),
// and (b) the body force and variable loads in its right-hand side b. Nothing else of a level or
// of the coarser levels (homogeneous corrections) depends on them: cell typing, operator, blocks,
// schedules and the coarse factor stay valid, so a load change needs no hierarchy build.
#include "mgelastic/grid/level.hpp"
#include "mgelastic/grid/problem.hpp"

namespace mgelastic::grid {

// b of the finest level from the loads alone: zero, minus the variable loads, minus the body
// force at interior momentum rows (L u = div P = -f). Dirichlet values and x are untouched.
template <int Dim, typename Scalar>
void write_load_right_hand_side(const ElasticityProblem<Dim>& problem, Level<Dim, Scalar>& level);

// Recomputes every boundary-stress value of the level from `sigma`: the traction rules' sigma and
// the band rows' constants, exactly as build_level with `sigma` would have (same expressions, so
// the same bits). The level's rows and rules must be those of its build (their targets are read).
template <int Dim, typename Scalar>
void replace_boundary_stress(Level<Dim, Scalar>& level, const BoundaryStress<Dim>& sigma);

// Throws mgelastic::Error unless `problem` differs from the one `level` was built from in its
// loads only (same lattice, cells, material, inertia; variable loads on the lattice).
template <int Dim, typename Scalar>
void check_same_system(const Level<Dim, Scalar>& level, const ElasticityProblem<Dim>& problem);

// The three above, then the traction variables back-substituted from the new conditions: the
// level then holds what a build from `problem` would, with its current x as the warm start.
template <int Dim, typename Scalar>
void replace_loads(Level<Dim, Scalar>& level, const ElasticityProblem<Dim>& problem);

}  // namespace mgelastic::grid
