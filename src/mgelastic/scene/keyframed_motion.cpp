#include "mgelastic/scene/keyframed_motion.hpp"

#include <algorithm>

namespace mgelastic::scene {

KeyframedMotion::KeyframedMotion(const Eigen::Vector3d& pivot, std::vector<RigidKeyframe> keys)
    : m_pivot(pivot), m_keys(std::move(keys)) {}

RigidKeyframe KeyframedMotion::pose(double time) const {
  if (time <= m_keys.front().time) return m_keys.front();
  if (time >= m_keys.back().time) return m_keys.back();
  const auto next = std::upper_bound(m_keys.begin(), m_keys.end(), time,
                                     [](double t, const RigidKeyframe& k) { return t < k.time; });
  const RigidKeyframe& a = *(next - 1);
  const RigidKeyframe& b = *next;
  const double s = (time - a.time) / (b.time - a.time);
  return {time, (1 - s) * a.translate + s * b.translate, a.rotation.slerp(s, b.rotation)};
}

Eigen::Vector3d KeyframedMotion::position(const Eigen::Vector3d& rest, double time) const {
  if (m_keys.empty()) return rest;
  const RigidKeyframe p = pose(time);
  return p.rotation * (rest - m_pivot) + m_pivot + p.translate;
}

}  // namespace mgelastic::scene
