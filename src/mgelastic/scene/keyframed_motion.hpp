#pragma once
// Rigid motion of a constraint region through keyframes: x(t) = R(t) (X - pivot) + pivot + T(t).
// Between keys the translation is interpolated linearly and the rotation by quaternion slerp
// (shortest arc, constant angular speed); before the first and after the last key the nearest
// key's pose holds. No keys = the identity (a fixed region). Shared by both engines.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

namespace mgelastic::scene {

struct RigidKeyframe {
  double time = 0;
  Eigen::Vector3d translate = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
};

class KeyframedMotion {
 public:
  KeyframedMotion() = default;
  // Keys must have strictly increasing times (the scene loader checks and names the key).
  KeyframedMotion(const Eigen::Vector3d& pivot, std::vector<RigidKeyframe> keys);

  bool is_fixed() const { return m_keys.empty(); }
  const Eigen::Vector3d& pivot() const { return m_pivot; }
  // Position at `time` of the material point at rest position `rest`.
  Eigen::Vector3d position(const Eigen::Vector3d& rest, double time) const;
  Eigen::Vector3d displacement(const Eigen::Vector3d& rest, double time) const {
    return position(rest, time) - rest;
  }

 private:
  RigidKeyframe pose(double time) const;
  Eigen::Vector3d m_pivot = Eigen::Vector3d::Zero();
  std::vector<RigidKeyframe> m_keys;
};

}  // namespace mgelastic::scene
