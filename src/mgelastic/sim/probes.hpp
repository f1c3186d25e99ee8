#pragma once
// The scene's probes (output.probes) sampled in the current state of a Simulation:
//   grid: displacement trilinear in the nodal field; von Mises stress and pressure of the
//         lattice cell that holds the point (cell-constant fields);
//   tet:  displacement barycentric in the rest tet that holds the point; von Mises stress and
//         pressure (-trace(sigma) / 3) of that tet.
// A probe outside the body is an error naming its JSON pointer (checked by check_probes before
// the first frame, so a run does not fail after hours).
#include <vector>

#include <Eigen/Core>

namespace mgelastic::sim {

class Simulation;

struct ProbeSample {
  Eigen::Vector3d displacement = Eigen::Vector3d::Zero();  // m
  double von_mises = 0;                                    // Pa
  double pressure = 0;                                     // Pa
};

// One sample per scene probe, in scene order.
std::vector<ProbeSample> sample_probes(const Simulation& simulation);

// Throws Error (pointer /output/probes/i/point) for the first probe outside the body.
void check_probes(const Simulation& simulation);

}  // namespace mgelastic::sim
