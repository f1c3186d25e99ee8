#pragma once
// The synthetic elastic box of the paper's benchmarks (Sec. 9.1, Figs. 10-11, 22-23):
// an N^d box of cells with
//   MIXED:     a slab of Dirichlet (fixed) cells at x = 0, N/8 cells thick unless clamp_cells says
//              otherwise, every other boundary traction-free;
//   DIRICHLET: a layer of Dirichlet cells all around the box,
// loaded by a uniform gravity-like body force.
#include "mgelastic/grid/problem.hpp"

namespace mgelastic::grid {

enum class BoxBoundary { MIXED, DIRICHLET };

struct BoxSpec {
  int cells = 32;
  double poisson_ratio = 0.3;
  double youngs_modulus = 1e5;  // Pa
  double size = 1.0;            // m, edge length of the box
  double body_force = 1e3;      // N/m^3, along -y
  BoxBoundary boundary = BoxBoundary::MIXED;
  // MIXED: thickness of the Dirichlet slab in cells, 1 .. cells - 1; 0 = cells / 8 (the paper's).
  // A thickness that is not a multiple of 2^(levels - 1) puts the finest clamp between coarse
  // faces (the "misaligned clamp" of docs/grid-engine.md), as on most embedded bodies.
  int clamp_cells = 0;
};

// The MIXED slab's thickness in cells: clamp_cells, or cells / 8 (at least 1) where it is 0.
int clamp_thickness(const BoxSpec& spec);

template <int Dim>
ElasticityProblem<Dim> make_box_problem(const BoxSpec& spec);

}  // namespace mgelastic::grid
