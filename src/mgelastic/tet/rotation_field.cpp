#include "mgelastic/tet/rotation_field.hpp"
#include "mgelastic/tet/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "mgelastic/core/error.hpp"

namespace mgelastic::tet {

RotationField::RotationField(const TetBody& body, RotationMethod method, NewtonSettings newton)
    : m_body(&body), m_method(method), m_newton(newton) {
  m_volumes.resize(body.element_count());
  for (int e = 0; e < body.element_count(); ++e) m_volumes[e] = body.volume(e);
  if (method == RotationMethod::POLAR_SMOOTHED)
    m_ring = element_one_ring(body.tets(), body.vertex_count());
  if (method == RotationMethod::ENERGY_MINIMIZATION) {
    m_weighted_rest_offsets.resize(body.element_count());
    for (int e = 0; e < body.element_count(); ++e) {
      const TetCorners rest = body.corners(e, body.rest_positions());
      m_weighted_rest_offsets[e] =
          std::abs(m_volumes[e]) / 20.0 * (rest.colwise() - rest.rowwise().mean());
    }
  }
  reset();
}

void RotationField::reset() {
  m_rotations.assign(m_body->element_count(), Eigen::Matrix3d::Identity());
  m_quaternions.assign(m_body->element_count(), Eigen::Quaterniond::Identity());
}

void RotationField::set_quaternions(const std::vector<Eigen::Quaterniond>& quaternions) {
  if (quaternions.size() != m_quaternions.size())
    throw Error("need one rotation per element (" + std::to_string(m_quaternions.size()) +
                    "), got " + std::to_string(quaternions.size()),
                ErrorContext{std::string(), -1, "rotations"});
  for (std::size_t e = 0; e < quaternions.size(); ++e)
    if (!quaternions[e].coeffs().allFinite() || std::abs(quaternions[e].norm() - 1.0) > 1e-6)
      throw Error("not a unit quaternion",
                  ErrorContext{std::string(), -1, "rotation of element " + std::to_string(e)});
  m_quaternions = quaternions;
  for (std::size_t e = 0; e < quaternions.size(); ++e)
    m_rotations[e] = m_quaternions[e].toRotationMatrix();
}

RotationStats RotationField::update(const Eigen::VectorXd& positions) {
  if (positions.size() != 3 * m_body->vertex_count())
    throw Error("position vector has the wrong size", ErrorContext{std::string(), -1, "positions"});
  if (!positions.allFinite()) {
    for (int e = 0; e < m_body->element_count(); ++e)
      if (!m_body->corners(e, positions).allFinite())
        throw Error("non-finite vertex position (simulation diverged?)",
                    ErrorContext{std::string(), -1, "element " + std::to_string(e)});
  }
  RotationStats stats;
  if (m_method == RotationMethod::ENERGY_MINIMIZATION) {
    update_energy_minimization(positions, stats);
  } else {
    update_polar(positions, stats);
  }
  return stats;
}

template <class Load>
RotationStats RotationField::fit_in_batches(const Load& load,
                                            std::vector<Eigen::Quaterniond>& out) {
  const int count = m_body->element_count();
  const int batches = (count + kRotationLanes - 1) / kRotationLanes;
  const bool final_rotations = &out == &m_quaternions;  // else smoothing follows
  long total_iterations = 0;
  int max_iterations = 0;
  int fallbacks = 0;
#pragma omp parallel for schedule(static) if (count >= kMinParallelElements) reduction(+ : total_iterations, fallbacks) \
    reduction(max : max_iterations)
  for (int batch = 0; batch < batches; ++batch) {
    const int first = batch * kRotationLanes;
    const int lanes = std::min(kRotationLanes, count - first);
    RotationFitBatch fit;
    // The last batch repeats its last element in the unused lanes (results dropped).
    for (int l = 0; l < kRotationLanes; ++l) {
      const int e = first + std::min(l, lanes - 1);
      load(e, fit, l);
      // Warm start from the previous update, as the paper's q (the conjugate of Q).
      const Eigen::Quaterniond& q = m_quaternions[e];
      fit.q[0][l] = q.w(), fit.q[1][l] = -q.x(), fit.q[2][l] = -q.y(), fit.q[3][l] = -q.z();
    }
    minimize_rotation_energy(fit, m_newton);
    for (int l = 0; l < lanes; ++l) {
      const int e = first + l;
      out[e] = Eigen::Quaterniond(fit.q[0][l], -fit.q[1][l], -fit.q[2][l], -fit.q[3][l]);
      if (final_rotations) m_rotations[e] = out[e].toRotationMatrix();
      total_iterations += fit.fits[l].iterations;
      max_iterations = std::max(max_iterations, fit.fits[l].iterations);
      fallbacks += fit.fits[l].fallback ? 1 : 0;
    }
  }
  RotationStats stats;
  stats.max_newton_iterations = max_iterations;
  stats.mean_newton_iterations = count > 0 ? static_cast<double>(total_iterations) / count : 0.0;
  stats.fallbacks = fallbacks;
  return stats;
}

void RotationField::update_energy_minimization(const Eigen::VectorXd& positions,
                                               RotationStats& stats) {
  // B = D R^T and T = V/20 |D|^2 from the deformed centroid offsets D (see the header).
  stats = fit_in_batches(
      [&](int e, RotationFitBatch& fit, int lane) {
        const TetCorners x = m_body->corners(e, positions);
        const Eigen::Matrix<double, 3, 4> offsets = x.colwise() - 0.25 * x.rowwise().sum();
        const Eigen::Matrix3d b = offsets * m_weighted_rest_offsets[e].transpose();
        for (int k = 0; k < 9; ++k) fit.moment[k][lane] = b(k / 3, k % 3);
        fit.deformed_moment[lane] = std::abs(m_volumes[e]) / 20.0 * offsets.squaredNorm();
      },
      m_quaternions);
}

void RotationField::update_polar(const Eigen::VectorXd& positions, RotationStats& stats) {
  // The polar rotation R of F maximizes tr(R^T F) over rotations: the energy-minimization fit
  // with B = F (S = I), whose q is R^T as there. T only sets the convergence scale.
  const bool smooth = m_method == RotationMethod::POLAR_SMOOTHED;
  std::vector<Eigen::Quaterniond>& raw = smooth ? m_scratch : m_quaternions;
  raw.resize(m_quaternions.size());
  stats = fit_in_batches(
      [&](int e, RotationFitBatch& fit, int lane) {
        const Eigen::Matrix3d f =
            deformation_gradient(m_body->corners(e, positions), m_body->rest_edge_inverse(e));
        for (int k = 0; k < 9; ++k) fit.moment[k][lane] = f(k / 3, k % 3);
        fit.deformed_moment[lane] = f.squaredNorm();
      },
      raw);
  if (!smooth) return;
  smooth_rotations(m_ring, m_volumes, m_scratch, m_quaternions);
  const int count = m_body->element_count();
#pragma omp parallel for schedule(static) if (count >= kMinParallelElements)
  for (int e = 0; e < count; ++e) m_rotations[e] = m_quaternions[e].toRotationMatrix();
}

}  // namespace mgelastic::tet
