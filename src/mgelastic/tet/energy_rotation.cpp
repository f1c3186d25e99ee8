#include "mgelastic/tet/energy_rotation.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
#include <cmath>
#include <cstring>
#include <limits>

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

namespace {

// Four doubles / four 64-bit masks (all bits set = true) as compiler vector types: arithmetic and
// comparisons are lane-wise, `mask ? a : b` selects per lane (GCC and Clang), so the batch below
// is vector code without intrinsics.
using Lanes = double __attribute__((vector_size(8 * kRotationLanes)));
using Mask = long long __attribute__((vector_size(8 * kRotationLanes)));

Lanes load(const RotationLanes& a) {
  Lanes v;
  std::memcpy(&v, a.data(), sizeof v);
  return v;
}
Lanes broadcast(double value) {
  return Lanes{} + value;
}
Lanes square_root(Lanes v) {
  for (int l = 0; l < kRotationLanes; ++l) v[l] = std::sqrt(v[l]);
  return v;
}
bool any(Mask m) {
  bool set = false;
  for (int l = 0; l < kRotationLanes; ++l) set |= m[l] != 0;
  return set;
}

struct BatchState {
  Lanes w, x, y, z, tolerance2;
  Mask active, failed;
  Lanes iterations;
};

// One iteration of sphere_newton on all lanes, without branches: flags combine with & and |,
// values are computed on every lane and selected (NaN fails every comparison, as in
// sphere_newton). Lanes that are not active keep their iterate.
void sphere_newton_lanes(const std::array<Lanes, 9>& b, const NewtonSettings& settings, bool at_cap,
                         BatchState& st) {
  const Lanes w = st.w, x = st.x, y = st.y, z = st.z;
  // R(q) as Eigen's toRotationMatrix, then B' = B R(q).
  const Lanes tx = 2.0 * x, ty = 2.0 * y, tz = 2.0 * z;
  const Lanes twx = tx * w, twy = ty * w, twz = tz * w, txx = tx * x, txy = ty * x, txz = tz * x,
              tyy = ty * y, tyz = tz * y, tzz = tz * z;
  const Lanes r[9] = {1.0 - (tyy + tzz), txy - twz, txz + twy, txy + twz,        1.0 - (txx + tzz),
                      tyz - twx,         txz - twy, tyz + twx, 1.0 - (txx + tyy)};
  Lanes bp[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      bp[3 * i + j] = b[3 * i] * r[j] + b[3 * i + 1] * r[3 + j] + b[3 * i + 2] * r[6 + j];
  const Lanes g0 = bp[5] - bp[7], g1 = bp[6] - bp[2], g2 = bp[1] - bp[3];
  const Lanes h00 = 2.0 * (bp[4] + bp[8]), h11 = 2.0 * (bp[0] + bp[8]), h22 = 2.0 * (bp[0] + bp[4]);
  const Lanes h01 = -(bp[1] + bp[3]), h02 = -(bp[2] + bp[6]), h12 = -(bp[5] + bp[7]);
  const Lanes inv_d0 = 1.0 / h00;
  const Lanes l10 = h01 * inv_d0, l20 = h02 * inv_d0;
  const Lanes d1 = h11 - l10 * h01;
  const Lanes inv_d1 = 1.0 / d1;
  const Lanes l21 = (h12 - l20 * h01) * inv_d1;
  const Lanes d2 = h22 - l20 * h02 - l21 * l21 * d1;
  const Mask definite = (h00 > 0.0) & (d1 > 0.0) & (d2 > 0.0);
  const Mask gradient_small = 16.0 * (g0 * g0 + g1 * g1 + g2 * g2) <= st.tolerance2;
  const Mask cap = at_cap ? Mask{} - 1 : Mask{};
  Mask steps = st.active & definite & ~gradient_small;
  st.failed |= (st.active & ~definite) | (steps & cap);
  steps &= ~cap;
  const Lanes y1 = g1 - l10 * g0, y2 = g2 - l20 * g0 - l21 * y1;
  Lanes s2 = y2 / d2;
  Lanes s1 = y1 * inv_d1 - l21 * s2;
  Lanes s0 = g0 * inv_d0 - l10 * s1 - l20 * s2;
  const Lanes length2 = s0 * s0 + s1 * s1 + s2 * s2;
  const Mask finite = length2 <= std::numeric_limits<double>::max();
  st.failed |= steps & ~finite;
  steps &= finite;
  const Lanes shrink = length2 > settings.max_step * settings.max_step
                           ? settings.max_step / square_root(length2)
                           : broadcast(1.0);
  s0 *= shrink, s1 *= shrink, s2 *= shrink;
  // q + U s = q * (1, s), then back onto the sphere.
  const Lanes nw = w - x * s0 - y * s1 - z * s2, nx = x + w * s0 + y * s2 - z * s1,
              ny = y + w * s1 + z * s0 - x * s2, nz = z + w * s2 + x * s1 - y * s0;
  const Lanes inverse = 1.0 / square_root(nw * nw + nx * nx + ny * ny + nz * nz);
  st.w = steps ? nw * inverse : w;
  st.x = steps ? nx * inverse : x;
  st.y = steps ? ny * inverse : y;
  st.z = steps ? nz * inverse : z;
  st.iterations += steps ? broadcast(1.0) : broadcast(0.0);
  st.active = steps & ~(length2 <= settings.converged_step * settings.converged_step);
}

// Lanes prepare_fit would accept as they are (finite warm start of norm > 0.5, normalized here;
// finite positive scale) are active; the others go to the scalar function.
void prepare_batch(const RotationFitBatch& batch, const std::array<Lanes, 9>& b,
                   const NewtonSettings& settings, BatchState& st) {
  Lanes b2{};
  for (int k = 0; k < 9; ++k) b2 += b[k] * b[k];
  const Lanes t = load(batch.deformed_moment);
  const Lanes scale = 4.0 * ((t < 0.0 ? -t : t) + 2.0 * square_root(b2));
  const Lanes w = load(batch.q[0]), x = load(batch.q[1]), y = load(batch.q[2]),
              z = load(batch.q[3]);
  const Lanes norm = square_root(w * w + x * x + y * y + z * z);
  const double huge = std::numeric_limits<double>::max();
  const Mask regular = (norm > 0.5) & (norm <= huge) & (scale > 1e-300) & (scale <= huge);
  st.w = w / norm, st.x = x / norm, st.y = y / norm, st.z = z / norm;
  st.tolerance2 = settings.tolerance * settings.tolerance * scale * scale;
  st.active = regular;
  st.failed = ~regular;
  st.iterations = broadcast(0.0);
}

}  // namespace

void minimize_rotation_energy(RotationFitBatch& batch, const NewtonSettings& settings) {
  std::array<Lanes, 9> b;
  for (int k = 0; k < 9; ++k) b[k] = load(batch.moment[k]);
  BatchState st;
  prepare_batch(batch, b, settings, st);
  for (int iteration = 0; any(st.active); ++iteration)
    sphere_newton_lanes(b, settings, iteration >= settings.max_iterations, st);
  for (int l = 0; l < kRotationLanes; ++l) {
    Eigen::Quaterniond q(batch.q[0][l], batch.q[1][l], batch.q[2][l], batch.q[3][l]);
    const Eigen::Vector4d fast(st.w[l], st.x[l], st.y[l], st.z[l]);
    if (st.failed[l] == 0 && fast.allFinite()) {
      // The sign nearest the warm start, as the scalar path.
      const bool flip = fast.dot(to_vector(q)) < 0.0;
      q = to_quaternion(flip ? Eigen::Vector4d(-fast) : fast);
      batch.fits[l] = {static_cast<int>(st.iterations[l]), false};
    } else {
      Eigen::Matrix3d moment;
      for (int k = 0; k < 9; ++k) moment(k / 3, k % 3) = batch.moment[k][l];
      batch.fits[l] = minimize_rotation_energy(moment, batch.deformed_moment[l], q, settings);
    }
    batch.q[0][l] = q.w(), batch.q[1][l] = q.x(), batch.q[2][l] = q.y(), batch.q[3][l] = q.z();
  }
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
