#include "mgelastic/tet/energy_rotation.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>

namespace mgelastic::tet {

namespace {

using Vector5d = Eigen::Matrix<double, 5, 1>;
using Matrix5d = Eigen::Matrix<double, 5, 5>;

Eigen::Vector4d to_vector(const Eigen::Quaterniond& q) {
  return {q.w(), q.x(), q.y(), q.z()};
}
Eigen::Quaterniond to_quaternion(const Eigen::Vector4d& v) {
  return Eigen::Quaterniond(v[0], v[1], v[2], v[3]);
}

// Orthonormal basis of the tangent space of the unit sphere at q: q * i, q * j, q * k.
Eigen::Matrix<double, 4, 3> tangent_basis(const Eigen::Vector4d& q) {
  Eigen::Matrix<double, 4, 3> u;
  u << -q[1], -q[2], -q[3],  //
      q[0], -q[3], q[2],     //
      q[3], q[0], -q[1],     //
      -q[2], q[1], q[0];
  return u;
}

// Second-order test on the sphere: q is a minimizer iff mu I - N (mu = q^T N q) is positive
// semidefinite on the tangent space, i.e. q belongs to the largest eigenvalue of N.
bool is_minimizer(const Eigen::Vector4d& q, const Eigen::Matrix4d& n, double scale) {
  const Eigen::Matrix<double, 4, 3> u = tangent_basis(q);
  const Eigen::Matrix3d g = u.transpose() * (q.dot(n * q) * Eigen::Matrix4d::Identity() - n) * u;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
  eigen.computeDirect(g, Eigen::EigenvaluesOnly);
  return eigen.eigenvalues().minCoeff() >= -1e-9 * scale;
}

// The answer of the eigen-decomposition: the top eigenvector of N, or inside a (nearly)
// degenerate top eigenspace the warm start's projection onto it, so flat or collinear elements
// do not jump between equally good rotations from step to step.
Eigen::Vector4d top_eigenvector(const Eigen::Matrix4d& n, const Eigen::Vector4d& warm,
                                double scale) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eigen(n);
  const Eigen::Vector4d values = eigen.eigenvalues();  // ascending
  Eigen::Vector4d projected = Eigen::Vector4d::Zero();
  for (int k = 3; k >= 0 && values[3] - values[k] <= 1e-10 * scale; --k) {
    const Eigen::Vector4d v = eigen.eigenvectors().col(k);
    projected += v.dot(warm) * v;
  }
  Eigen::Vector4d q = projected.norm() > 1e-6 ? projected : eigen.eigenvectors().col(3);
  q.normalize();
  return q.dot(warm) < 0.0 ? -q : q;
}

struct NewtonState {
  Eigen::Vector4d q;
  double lambda;
};

Vector5d lagrangian_gradient(const NewtonState& s, const Eigen::Matrix4d& n, double t) {
  Vector5d g;
  g.head<4>() = 4.0 * t * s.q.squaredNorm() * s.q - 4.0 * n * s.q + 2.0 * s.lambda * s.q;
  g[4] = s.q.squaredNorm() - 1.0;
  return g;
}

Matrix5d lagrangian_hessian(const NewtonState& s, const Eigen::Matrix4d& n, double t) {
  Matrix5d h;
  h.topLeftCorner<4, 4>() =
      4.0 * t * (s.q.squaredNorm() * Eigen::Matrix4d::Identity() + 2.0 * s.q * s.q.transpose()) -
      4.0 * n + 2.0 * s.lambda * Eigen::Matrix4d::Identity();
  h.topRightCorner<4, 1>() = 2.0 * s.q;
  h.bottomLeftCorner<1, 4>() = 2.0 * s.q.transpose();
  h(4, 4) = 0.0;
  return h;
}

// Runs the Newton iteration; returns false when it cannot be trusted (singular, non-finite,
// not converged within the cap).
bool newton(NewtonState& s, const Eigen::Matrix4d& n, double t, double scale,
            const NewtonSettings& settings, int& iterations) {
  for (iterations = 0; iterations < settings.max_iterations; ++iterations) {
    const Vector5d g = lagrangian_gradient(s, n, t);
    if (!g.allFinite()) return false;
    if (g.head<4>().norm() <= settings.tolerance * scale) return true;
    const Eigen::FullPivLU<Matrix5d> lu(lagrangian_hessian(s, n, t));
    if (!lu.isInvertible()) return false;
    Vector5d step = -lu.solve(g);
    if (!step.allFinite()) return false;
    // Limit the step so a nearly singular KKT matrix cannot throw q across the sphere.
    const double length = step.head<4>().norm();
    if (length > settings.max_step) step *= settings.max_step / length;
    s.q += step.head<4>();
    s.lambda += step[4];
    // Renormalize: the returned quaternion is unit by construction, not only at convergence.
    const double norm = s.q.norm();
    if (!(norm > 1e-12) || !std::isfinite(norm)) return false;
    s.q /= norm;
  }
  return lagrangian_gradient(s, n, t).head<4>().norm() <= settings.tolerance * scale;
}

// Fast path: Newton on the unit sphere in the tangent coordinates of tangent_basis. On |q| = 1,
// E = T + tr S - 2 q^T N q, so the minimizer maximizes q^T N q; with U = tangent_basis(q),
// mu = q^T N q, g = U^T N q and H = mu I - U^T N U (minus half the Riemannian Hessian), the
// Newton step is U H^{-1} g, followed by renormalization. This is the Lagrangian Newton of
// Eqs. 5-8 restricted to the constraint surface (lambda eliminated): the same iterates' limit
// with a 3x3 factorization instead of a 5x5 pivoted LU, and H > 0 is exactly the second-order
// test of is_minimizer. Returns false (the full path decides) when H is not positive definite
// (far from the minimizer, or a degenerate top eigenspace) or the cap is reached.
//
// Cost (once per element and step, so written out in scalars): the columns of [q U] are the
// quaternion products q*1, q*i, q*j, q*k, and q^T N(B) q = tr(M(q) B) with M(q r) = M(q) M(r), so
// [q U]^T N(B) [q U] = N(B M(q)): mu, g and H are sums of entries of B' = B M(q) (one 3x3
// product per iteration instead of 4x4 products), and H is factored by a closed-form LDL^T.
// The iteration stops without a further evaluation after a step shorter than
// settings.converged_step: Newton converges (here cubically, as Rayleigh quotient iteration) so
// the next gradient would be far below the tolerance.
bool sphere_newton(const Eigen::Matrix3d& b, double scale, const NewtonSettings& settings,
                   Eigen::Vector4d& q_vector, int& iterations) {
  double w = q_vector[0], x = q_vector[1], y = q_vector[2], z = q_vector[3];
  const double tolerance2 = settings.tolerance * settings.tolerance * scale * scale;
  const double max_step2 = settings.max_step * settings.max_step;
  const double converged2 = settings.converged_step * settings.converged_step;
  for (iterations = 0;; ++iterations) {
    const Eigen::Matrix3d r = Eigen::Quaterniond(w, x, y, z).toRotationMatrix();
    const Eigen::Matrix3d bp = b * r;
    const double g0 = bp(1, 2) - bp(2, 1), g1 = bp(2, 0) - bp(0, 2), g2 = bp(0, 1) - bp(1, 0);
    const double h00 = 2.0 * (bp(1, 1) + bp(2, 2)), h11 = 2.0 * (bp(0, 0) + bp(2, 2)),
                 h22 = 2.0 * (bp(0, 0) + bp(1, 1));
    const double h01 = -(bp(0, 1) + bp(1, 0)), h02 = -(bp(0, 2) + bp(2, 0)),
                 h12 = -(bp(1, 2) + bp(2, 1));
    // LDL^T; H > 0 iff every pivot is positive (also false for NaN).
    if (!(h00 > 0.0)) return false;
    const double inv_d0 = 1.0 / h00;
    const double l10 = h01 * inv_d0, l20 = h02 * inv_d0;
    const double d1 = h11 - l10 * h01;
    if (!(d1 > 0.0)) return false;
    const double inv_d1 = 1.0 / d1;
    const double l21 = (h12 - l20 * h01) * inv_d1;
    const double d2 = h22 - l20 * h02 - l21 * l21 * d1;
    if (!(d2 > 0.0)) return false;
    // |dE/dq| on the sphere is 4 |U^T N q| (the criterion of newton()).
    if (16.0 * (g0 * g0 + g1 * g1 + g2 * g2) <= tolerance2) break;
    if (iterations >= settings.max_iterations) return false;
    const double y1 = g1 - l10 * g0, y2 = g2 - l20 * g0 - l21 * y1;
    double s2 = y2 / d2;
    double s1 = y1 * inv_d1 - l21 * s2;
    double s0 = g0 * inv_d0 - l10 * s1 - l20 * s2;
    const double length2 = s0 * s0 + s1 * s1 + s2 * s2;
    if (!std::isfinite(length2)) return false;
    if (length2 > max_step2) {
      const double shrink = settings.max_step / std::sqrt(length2);
      s0 *= shrink, s1 *= shrink, s2 *= shrink;
    }
    // q + U s = q * (1, s), then back onto the sphere.
    const double nw = w - x * s0 - y * s1 - z * s2, nx = x + w * s0 + y * s2 - z * s1,
                 ny = y + w * s1 + z * s0 - x * s2, nz = z + w * s2 + x * s1 - y * s0;
    const double inverse = 1.0 / std::sqrt(nw * nw + nx * nx + ny * ny + nz * nz);
    w = nw * inverse, x = nx * inverse, y = ny * inverse, z = nz * inverse;
    if (length2 <= converged2) {
      ++iterations;
      break;
    }
  }
  q_vector = Eigen::Vector4d(w, x, y, z);
  return true;
}

// The (q, lambda) Newton of Eqs. 5-8 from the warm start; the eigen-decomposition when it fails.
RotationFit lagrangian_newton_or_eigen(const Eigen::Matrix4d& n, double t, double scale,
                                       const Eigen::Vector4d& warm, const NewtonSettings& settings,
                                       Eigen::Quaterniond& q) {
  RotationFit fit;
  NewtonState s{warm, 2.0 * (warm.dot(n * warm) - t)};
  const bool converged = newton(s, n, t, scale, settings, fit.iterations);
  if (converged && is_minimizer(s.q, n, scale)) {
    q = to_quaternion(s.q.dot(warm) < 0.0 ? Eigen::Vector4d(-s.q) : s.q);
    return fit;
  }
  fit.fallback = true;
  q = to_quaternion(top_eigenvector(n, warm, scale));
  return fit;
}

}  // namespace

Eigen::Matrix4d rotation_energy_matrix(const Eigen::Matrix3d& b) {
  Eigen::Matrix4d n;
  n(0, 0) = b(0, 0) + b(1, 1) + b(2, 2);
  n(1, 1) = b(0, 0) - b(1, 1) - b(2, 2);
  n(2, 2) = -b(0, 0) + b(1, 1) - b(2, 2);
  n(3, 3) = -b(0, 0) - b(1, 1) + b(2, 2);
  n(0, 1) = n(1, 0) = b(1, 2) - b(2, 1);
  n(0, 2) = n(2, 0) = b(2, 0) - b(0, 2);
  n(0, 3) = n(3, 0) = b(0, 1) - b(1, 0);
  n(1, 2) = n(2, 1) = b(0, 1) + b(1, 0);
  n(1, 3) = n(3, 1) = b(0, 2) + b(2, 0);
  n(2, 3) = n(3, 2) = b(1, 2) + b(2, 1);
  return n;
}

double rotation_energy(const Eigen::Vector4d& q, const Eigen::Matrix4d& n, double t,
                       double rest_trace) {
  const double q2 = q.squaredNorm();
  return q2 * q2 * t - 2.0 * q.dot(n * q) + rest_trace;
}

namespace {

// The convergence scale 4 (|T| + |N|) (|N|_F = 2 |B|_F for Horn's matrix) and the normalized
// warm start; false for an element collapsed to a point (it carries no rotation information: q
// keeps the previous rotation).
bool prepare_fit(const Eigen::Matrix3d& moment, double t, Eigen::Quaterniond& q, double& scale,
                 Eigen::Vector4d& warm) {
  scale = 4.0 * (std::abs(t) + 2.0 * moment.norm());
  warm = to_vector(q);
  if (!warm.allFinite() || !(warm.norm() > 0.5)) warm = Eigen::Vector4d::UnitX();
  warm.normalize();
  if (scale > 1e-300 && std::isfinite(scale)) return true;
  q = to_quaternion(warm);
  return false;
}

}  // namespace

RotationFit minimize_rotation_energy(const Eigen::Matrix3d& moment, double t, Eigen::Quaterniond& q,
                                     const NewtonSettings& settings) {
  double scale = 0.0;
  Eigen::Vector4d warm;
  if (!prepare_fit(moment, t, q, scale, warm)) return {0, true};
  Eigen::Vector4d fast = warm;
  int iterations = 0;
  if (sphere_newton(moment, scale, settings, fast, iterations) && fast.allFinite()) {
    q = to_quaternion(fast.dot(warm) < 0.0 ? Eigen::Vector4d(-fast) : fast);
    return {iterations, false};
  }
  return lagrangian_newton_or_eigen(rotation_energy_matrix(moment), t, scale, warm, settings, q);
}

RotationFit minimize_rotation_energy_reference(const Eigen::Matrix3d& moment, double t,
                                               Eigen::Quaterniond& q,
                                               const NewtonSettings& settings) {
  double scale = 0.0;
  Eigen::Vector4d warm;
  if (!prepare_fit(moment, t, q, scale, warm)) return {0, true};
  return lagrangian_newton_or_eigen(rotation_energy_matrix(moment), t, scale, warm, settings, q);
}

}  // namespace mgelastic::tet
