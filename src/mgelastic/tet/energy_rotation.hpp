#pragma once
// Element rotation by energy minimization (Georgii & Westermann 2008, Sec. 3, Eqs. 3-8).
//
// The rotation Q (rest -> deformed) of an element minimizes
//   E(q) = int_T |q (x - c) q^* - (X - c0)|^2 dX + lambda (q.q - 1),
// where q is the unit quaternion of Q^T (the paper's convention), x(X) the deformed position, and
// c, c0 the deformed and rest centroids. For a linear tetrahedron x - c = F (X - c0), so with the
// rest second moment S = int r r^T (r = X - c0) the integrals are exact polynomials in q:
//   int |q r' q^*|^2 = |q|^4 T,  T = tr(F S F^T)          (rotation of r' = F r scales by |q|^2)
//   int r . (q r' q^*) = q^T N q,  N = N(B), B = F S       (4x4 symmetric, Horn's matrix)
//   E(q) = |q|^4 T - 2 q^T N q + tr(S) + lambda (q.q - 1).
// Gradient and Hessian (Eqs. 5-8):
//   dE/dq = 4 T |q|^2 q - 4 N q + 2 lambda q,   dE/dlambda = q.q - 1,
//   d2E/dq2 = 4 T (|q|^2 I + 2 q q^T) - 4 N + 2 lambda I,   d2E/dq dlambda = 2 q.
// Newton on (q, lambda) from the previous step's quaternion; lambda starts at the value that makes
// the warm start stationary along q, 2 (q^T N q - T). On the unit sphere stationary points are the
// eigenvectors of N and the minimizer is the one of the largest eigenvalue.
//
// Speed: the iteration runs first on the constraint surface itself (q kept unit, lambda
// eliminated: a closed-form 3x3 LDL^T per step in the sphere's tangent coordinates, whose positive
// definiteness is the second-order minimizer test); the (q, lambda) Newton below runs only when
// that fast path fails (indefinite tangent Hessian, iteration cap).
//
// Robustness: steps are length-limited and q is renormalized after each, so a non-unit quaternion
// is never returned; if Newton fails (singular KKT matrix, non-finite values, iteration cap, or a
// stationary point that is not the minimum, e.g. for inverted or flat elements) the result comes
// from the eigen-decomposition of N, preferring the warm start inside a degenerate top eigenspace.
// An element collapsed to a point (N = 0, T = 0) keeps its previous rotation.
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>

namespace mgelastic::tet {

struct NewtonSettings {
  int max_iterations = 12;
  // Stop when |grad E| <= tolerance * (4 T + 4 |N|), i.e. relative to the energy's scale.
  double tolerance = 1e-13;
  // Largest quaternion change per Newton step (a unit quaternion has norm 1).
  double max_step = 0.5;
  // Fast path: a step shorter than this ends the iteration without another evaluation (the
  // next gradient would be ~ step^3 relative, far below `tolerance`).
  double converged_step = 1e-6;
};

struct RotationFit {
  int iterations = 0;
  bool fallback = false;  // the eigen-decomposition answered instead of Newton
};

// Horn's matrix: q^T N(B) q = tr(M(q) B) for the (non-normalized) rotation matrix M(q) of q.
// Quaternions are (w, x, y, z) 4-vectors here.
Eigen::Matrix4d rotation_energy_matrix(const Eigen::Matrix3d& moment);

// E(q) without the multiplier term (for tests and brute-force comparisons).
double rotation_energy(const Eigen::Vector4d& q, const Eigen::Matrix4d& n, double deformed_moment,
                       double rest_moment_trace);

// Minimizes E over unit quaternions. `moment` is B = F S, `deformed_moment` is T = tr(F S F^T).
// `q` holds the warm start on entry (the paper's q, rotating deformed into rest) and the result
// on exit, always unit length and finite when the inputs are finite.
RotationFit minimize_rotation_energy(const Eigen::Matrix3d& moment, double deformed_moment,
                                     Eigen::Quaterniond& q, const NewtonSettings& settings = {});

// Batches: kRotationLanes fits at once, one element per lane, structure of arrays (`moment[3 i +
// j][lane]` = B(i, j), `q[c][lane]` = component c of (w, x, y, z)). The sphere Newton of the fast
// path runs branch-free over the lanes, so the four dependency chains (divisions, square roots)
// overlap and the lane loops compile to vector code; each lane stops when the scalar path would.
// A lane whose inputs are not regular (non-finite or tiny warm start, collapsed element) or where
// the fast path fails is finished by minimize_rotation_energy itself: results equal the scalar
// function's to round-off (test EnergyRotation.BatchEqualsTheScalarFit).
inline constexpr int kRotationLanes = 4;
using RotationLanes = std::array<double, kRotationLanes>;

struct RotationFitBatch {
  alignas(32) std::array<RotationLanes, 9> moment{};
  alignas(32) RotationLanes deformed_moment{};
  alignas(32) std::array<RotationLanes, 4> q{};  // warm start on entry, result on exit
  std::array<RotationFit, kRotationLanes> fits{};
};

void minimize_rotation_energy(RotationFitBatch& batch, const NewtonSettings& settings = {});

// The same minimizer by the (q, lambda) Newton of Eqs. 5-8 alone (no sphere fast path; the
// eigen-decomposition when it fails): the reference the fast path is tested against.
RotationFit minimize_rotation_energy_reference(const Eigen::Matrix3d& moment,
                                               double deformed_moment, Eigen::Quaterniond& q,
                                               const NewtonSettings& settings = {});

}  // namespace mgelastic::tet
