#pragma once
// Exact correction of one box of a level (a multiplicative Schwarz step): the level's residual
// equations restricted to the variables R of the box's cells, every variable outside held,
// solved directly:
//   A_RR delta_R = r_R,   x_R += delta_R,
// with A_RR the level's operator on R. Built as a level of its own over the box plus one cell
// of margin whose body cells are Dirichlet (held at a zero correction) and factored once
// (CoarseSolver: the non-augmented system, sparse Cholesky, pressures exact); traction variables
// follow by back-substitution.
//
// What for: a slow mode that sits in a small part of an embedded body (a limb that the coarse
// levels bridge or lose, the top edge of a clamp between coarse faces), which neither the
// smoothing nor the coarse correction reaches: the V-cycle's residual concentrates in a few
// cubes there after some cycles (residual_blocks.hpp), and an exact solve of a box around them
// removes it. Multigrid places such boxes itself (MultigridOptions::local_corrections).
#include <array>
#include <memory>
#include <vector>

#include "mgelastic/grid/coarse_solver.hpp"
#include "mgelastic/grid/level.hpp"
#include "mgelastic/grid/material.hpp"
#include "mgelastic/grid/residual.hpp"
#include "mgelastic/grid/residual_blocks.hpp"

namespace mgelastic::grid {

template <int Dim, typename Scalar>
class LocalCorrection {
 public:
  // The box of `level`'s cells with storage coordinates in [lo, hi) (clipped to the real cells).
  // Throws SingularCoarseLevel if the box's system is singular.
  LocalCorrection(const Level<Dim, Scalar>& level, const Material& material, double inertia,
                  IVec<Dim> lo, IVec<Dim> hi);
  // x += the box's exact correction for level's current residual (interior variables only).
  void add(Level<Dim, Scalar>& level);
  // add, then the level's traction variables follow (back_substitute_traction).
  void apply(Level<Dim, Scalar>& level);

  IVec<Dim> lo() const { return m_lo; }
  IVec<Dim> hi() const { return m_hi; }
  std::size_t unknowns() const { return m_box.interior_unknowns(); }
  std::size_t bytes() const;
  // What one apply() moves at least: the factor read twice (forward and back substitution) and
  // the box level's fields.
  std::size_t apply_bytes() const;

 private:
  IVec<Dim> m_lo, m_hi;
  Level<Dim, double> m_box;
  std::unique_ptr<CoarseSolver<Dim, double>> m_solver;
  // The box's inner cells as lattice rows of the level (stretches along x) and the box's flat
  // index of each stretch's first point.
  std::vector<Stretch> m_stretches;
  std::vector<std::ptrdiff_t> m_box_first;
  std::size_t m_points = 0;
  // Band rows of the level whose variable is in the box, and that variable's box flat index.
  std::vector<std::uint32_t> m_band_rows, m_pressure_rows;
  std::vector<std::ptrdiff_t> m_band_target, m_pressure_target;
  std::vector<double> m_scratch;
};

// Boxes for a slow mode from the residual's cubes of `cube` cells (residual_blocks, largest
// share first): the cubes taken in that order while each holds at least `min_share` and together
// they hold less than `cover`, each grown by `margin` cells on every side, merged while any two
// overlap (clusters of cubes closer than twice the margin end in one box); storage coordinates
// [lo, hi), clipped to the real cells.
template <int Dim>
std::vector<std::array<IVec<Dim>, 2>> slow_mode_boxes(const std::vector<ResidualBlock<Dim>>& cubes,
                                                      int cube, const Lattice<Dim>& lattice,
                                                      double min_share, double cover, int margin);

}  // namespace mgelastic::grid
