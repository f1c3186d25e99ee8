#pragma once
// The synthetic elastic box of the paper's benchmarks (Sec. 9.1, Figs. 10-11, 22-23):
// an N^d box of cells with
//   MIXED:     the slab x < N/8 of Dirichlet (fixed) cells, every other boundary traction-free;
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
};

template <int Dim>
ElasticityProblem<Dim> make_box_problem(const BoxSpec& spec);

}  // namespace mgelastic::grid
