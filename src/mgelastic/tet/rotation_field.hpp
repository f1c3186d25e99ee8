#pragma once
// Per-element rotations Q_e (rest -> deformed frame) of the corotated formulation, extracted from
// the current positions by one of three methods (the paper's Sec. 3 and its Sec. 5 comparisons):
//   ENERGY_MINIMIZATION  Newton on the unit quaternion with Lagrange multiplier (energy_rotation),
//                        warm-started from the previous update;
//   POLAR                polar decomposition of F = R U: R maximizes tr(R^T F), which is the
//                        energy-minimization fit with B = F, so it runs the same warm-started
//                        quaternion Newton (polar_rotation's SVD is the reference, equal to
//                        round-off: test EnergyRotation.PolarFieldEqualsTheSvdPolar);
//   POLAR_SMOOTHED       POLAR followed by one volume-weighted quaternion average over the
//                        1-ring of elements (rotation_smoothing).
// Elements are independent, so the update is one parallel loop over elements.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "mgelastic/tet/energy_rotation.hpp"
#include "mgelastic/tet/rotation_smoothing.hpp"
#include "mgelastic/tet/tet_body.hpp"

namespace mgelastic::tet {

enum class RotationMethod { ENERGY_MINIMIZATION, POLAR, POLAR_SMOOTHED };

struct RotationStats {
  int max_newton_iterations = 0;
  double mean_newton_iterations = 0.0;
  int fallbacks = 0;  // elements where the eigen-decomposition answered instead of Newton
};

class RotationField {
 public:
  RotationField(const TetBody& body, RotationMethod method, NewtonSettings newton = {});

  // Recomputes all rotations from a 3N position vector. Throws Error naming the first element
  // with non-finite corner positions.
  RotationStats update(const Eigen::VectorXd& positions);
  // Back to identity rotations (and cold Newton starts).
  void reset();
  // Restores rotations saved from quaternions() (a checkpoint; the Newton warm starts of
  // ENERGY_MINIMIZATION); throws Error unless there is one unit quaternion per element.
  void set_quaternions(const std::vector<Eigen::Quaterniond>& quaternions);

  RotationMethod method() const { return m_method; }
  int size() const { return static_cast<int>(m_rotations.size()); }
  const Eigen::Matrix3d& rotation(int e) const { return m_rotations[e]; }
  // Unit quaternions of the rotations Q_e.
  const std::vector<Eigen::Quaterniond>& quaternions() const { return m_quaternions; }

 private:
  void update_energy_minimization(const Eigen::VectorXd& positions, RotationStats& stats);
  void update_polar(const Eigen::VectorXd& positions, RotationStats& stats);
  // Batched fits of all elements (energy_rotation), warm-started from quaternions(): load(e,
  // batch, lane) fills B and T of element e; out[e] receives Q_e (and rotation(e) when out is
  // quaternions()).
  template <class Load>
  RotationStats fit_in_batches(const Load& load, std::vector<Eigen::Quaterniond>& out);

  const TetBody* m_body;
  RotationMethod m_method;
  NewtonSettings m_newton;
  std::vector<Eigen::Matrix3d> m_rotations;
  std::vector<Eigen::Quaterniond> m_quaternions;
  std::vector<Eigen::Quaterniond> m_scratch;
  std::vector<double> m_volumes;
  // Energy minimization: rest corner offsets from the centroid times V/20, so that with the
  // deformed offsets D (3x4) B = F S = D R^T and T = tr(F S F^T) = V/20 |D|^2 (S = V/20 r r^T
  // is a linear tet's exact second moment): no F, no S per step.
  std::vector<Eigen::Matrix<double, 3, 4>> m_weighted_rest_offsets;
  ElementOneRing m_ring;  // built only for POLAR_SMOOTHED
};

}  // namespace mgelastic::tet
