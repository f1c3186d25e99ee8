// The traction faces of a quasistatic problem carry their half cell's body force
// (grid/half_cell_body_force.hpp): P_ii(center) = sigma + sign (h / 2) f_i.
#include <gtest/gtest.h>

#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/half_cell_body_force.hpp"

namespace mgelastic::grid {
namespace {

ElasticityProblem<3> box(double inertia = 0.0) {
  BoxSpec spec;
  spec.cells = 8;  // mixed box: body force 1e3 N/m^3 along -y, free faces but the slab x < 1
  ElasticityProblem<3> problem = make_box_problem<3>(spec);
  problem.inertia = inertia;
  return problem;
}

// Center of the face of storage cell s at its lower side along axis i.
Vec<3> face(const ElasticityProblem<3>& p, int i, const IVec<3>& s) {
  return p.lattice.face_center(i, p.lattice.index(s));
}

TEST(HalfCellBodyForce, UpperFacesGainAndLowerFacesLoseHalfACellOfForce) {
  ElasticityProblem<3> problem = box();
  const double f = problem.body_force(Vec<3>::Zero())[1];
  ASSERT_LT(f, 0.0);
  add_half_cell_body_force(problem);
  const double half = 0.5 * problem.lattice.h * f;
  const int n = problem.lattice.cells[1];
  // The top face y = n (between storage cells n and n + 1) has the body below it.
  EXPECT_DOUBLE_EQ(problem.boundary_stress(1, 1, face(problem, 1, {4, n + 1, 4})), half);
  // The bottom face y = 0 has it above.
  EXPECT_DOUBLE_EQ(problem.boundary_stress(1, 1, face(problem, 1, {4, 1, 4})), -half);
  // x faces carry f_x = 0; shear stresses are unchanged.
  EXPECT_DOUBLE_EQ(problem.boundary_stress(0, 0, face(problem, 0, {n + 1, 4, 4})), 0.0);
  EXPECT_DOUBLE_EQ(problem.boundary_stress(0, 1, face(problem, 1, {4, n + 1, 4})), 0.0);
  // A face inside the body is no traction face.
  EXPECT_DOUBLE_EQ(problem.boundary_stress(1, 1, face(problem, 1, {4, 4, 4})), 0.0);
  // Nor is a cell center, where a one-cell-thin cell's condition is sampled: the top cell's
  // center would otherwise round to the face above it.
  const Vec<3> top_cell = problem.lattice.cell_center(problem.lattice.index({4, n, 4}));
  EXPECT_DOUBLE_EQ(problem.boundary_stress(1, 1, top_cell), 0.0);
}

TEST(HalfCellBodyForce, DynamicsKeepThePlainCondition) {
  ElasticityProblem<3> problem = box(1.0);
  add_half_cell_body_force(problem);
  const int n = problem.lattice.cells[1];
  const Vec<3> top = face(problem, 1, {4, n + 1, 4});
  EXPECT_DOUBLE_EQ(problem.boundary_stress ? problem.boundary_stress(1, 1, top) : 0.0, 0.0);
}

}  // namespace
}  // namespace mgelastic::grid
