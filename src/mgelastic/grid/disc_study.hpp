#pragma once
// The paper's accuracy study (Sec. 9.2, Eq. 17, Figs. 12-15): the disc of radius 1/4 centered
// at (1/2, 1/2), deformed by phi(x, y) = 2x / sqrt(pi) (cos(pi y / 2), sin(pi y / 2)), embedded
// in a lattice of n x n cells over the unit square. Cells overlapping the disc are interior; the
// boundary cells along the left half of the circle (quadrants II and III) are Dirichlet cells with
// the analytic displacement; the right half carries the analytic traction P N, applied as segment
// forces of a polygon distributed to the staggered variables (embedded_traction.hpp). The body
// force is -div P of the analytic field. Reports the max error of u at interior variables.
#include <vector>

#include "mgelastic/grid/problem.hpp"

namespace mgelastic::grid {

struct DiscStudyRow {
  int cells = 0;
  double max_error = 0;
  std::size_t unknowns = 0;
  int cycles = 0;
  double rate = 0;
};

struct DiscStudy {
  double poisson_ratio = 0;
  std::vector<DiscStudyRow> rows;
  double order = 0;  // log2 of the error ratio of the two finest resolutions
};

ElasticityProblem<2> make_disc_problem(int cells, double poisson_ratio);

// The analytic displacement u = phi(X) - X of Eq. 17.
Vec<2> disc_displacement(const Vec<2>& x);

DiscStudy run_disc_study(double poisson_ratio, const std::vector<int>& resolutions);

}  // namespace mgelastic::grid
