#pragma once
// Dynamic corotated linear FEM on tetrahedra (Georgii & Westermann 2008, Sec. 2, Eq. 2):
//   M a + C v + K~ x = f_ext + f^0,   K~ = sum Q K Q^T,  f^0 = sum Q K X,  C = alpha M + beta K~,
// i.e. M a + C v + Q K (Q^T x - X) = f_ext with the rotations Q frozen during a step.
// Every step: (1) rotations from the current positions, (2) assembly of K~ into the BRC matrix,
// (3) one linear solve, (4) state update. f_ext is gravity on the lumped masses.
//
// Integrators (h = time step):
//  IMPLICIT_EULER  unknown v+:  (M + h C + h^2 K~) v+ = M v + h (f_ext + f_el(x)),  x+ = x + h v+
//  NEWMARK         average acceleration (beta = 1/4, gamma = 1/2), unknown a+:
//                  x^ = x + h v + h^2/4 a,  v^ = v + h/2 a,
//                  (M + h/2 C + h^2/4 K~) a+ = f_ext + f_el(x^) - C v^,
//                  x+ = x^ + h^2/4 a+,  v+ = v^ + h/2 a+    (no numerical damping)
// where f_el(x) = -sum Q K (Q^T x - X). Dirichlet vertices follow a prescribed motion (default:
// fixed at rest); the step's unknown is fixed on them so that they reach the prescribed position
// at t + h exactly. Vertices referenced by no element are treated as fixed.
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <vector>

#include "mgelastic/geometry/tet_mesh.hpp"
#include "mgelastic/tet/block_jacobi_pcg.hpp"
#include "mgelastic/tet/corotated_assembly.hpp"
#include "mgelastic/tet/rotation_field.hpp"
#include "mgelastic/tet/tet_body.hpp"
#include "mgelastic/tet/tet_multigrid.hpp"

namespace mgelastic::tet {

enum class Integrator { IMPLICIT_EULER, NEWMARK };
enum class LinearSolver {
  PCG,       // block-Jacobi preconditioned CG on the BRC matrix
  CHOLESKY,  // sparse Cholesky (CHOLMOD), for small static problems and cross-checks
  // Geometric multigrid (tet_multigrid.hpp, paper Sec. 4.3): the hierarchy is built on the first
  // solve (and again after set_dirichlet); every solve copies the step matrix into level 0 and
  // rebuilds the Galerkin coarse operators (stream product) before solving.
  MULTIGRID,  // V-cycles from the previous step's unknown: `vcycles` of them, or (vcycles = 0)
              // until pcg.tolerance, at most pcg.max_iterations cycles
  MG_PCG      // CG preconditioned by one V-cycle, to pcg.tolerance / pcg.max_iterations
};

struct CorotatedSolverSettings {
  double time_step = 1.0 / 60.0;  // s
  Integrator integrator = Integrator::IMPLICIT_EULER;
  RotationMethod rotation_method = RotationMethod::ENERGY_MINIMIZATION;
  NewtonSettings newton;
  double rayleigh_alpha = 0.0;                        // mass-proportional damping, 1/s
  double rayleigh_beta = 0.0;                         // stiffness-proportional damping, s
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();  // m/s^2
  LinearSolver linear_solver = LinearSolver::PCG;
  PcgSettings pcg;
  TetMultigridSettings multigrid;  // MULTIGRID and MG_PCG
  int vcycles = 0;                 // MULTIGRID: fixed V-cycles per step, 0 = to pcg.tolerance
};

// Prescribed position of Dirichlet vertex `vertex` (rest position `rest`) at time `time`.
using DirichletMotion =
    std::function<Eigen::Vector3d(int vertex, const Eigen::Vector3d& rest, double time)>;

struct StepStats {
  double rotate_seconds = 0.0;
  double assemble_seconds = 0.0;
  double solve_seconds = 0.0;
  // MULTIGRID / MG_PCG: level-0 copy, Galerkin coarse operators and coarsest factorization
  // (not included in solve_seconds).
  double galerkin_seconds = 0.0;
  double total_seconds = 0.0;
  RotationStats rotation;
  // CHOLESKY: iterations 0 and the achieved relative residual; MULTIGRID: iterations = V-cycles
  // (with a fixed `vcycles` count: converged = true, the residual is what the cycles reached).
  PcgResult solve;
  int static_iterations = 0;      // solve_static only: rotation/solve rounds used
  bool static_converged = false;  // solve_static only: the update fell below the tolerance
};

// Everything a later step or static solve depends on besides the set-up (checkpoint/resume):
// positions, velocities and accelerations (3N each), the rotations (Newton warm starts), clock.
struct CorotatedState {
  Eigen::VectorXd positions, velocities, accelerations;
  std::vector<Eigen::Quaterniond> rotations;
  bool have_acceleration = false;
  double time = 0.0;
  long steps = 0;
};

class CorotatedSolver {
 public:
  // Throws Error for invalid settings, materials or mesh.
  CorotatedSolver(const geometry::TetMesh& mesh, const ElementMaterials& materials,
                  const CorotatedSolverSettings& settings);
  ~CorotatedSolver();
  CorotatedSolver(const CorotatedSolver&) = delete;
  CorotatedSolver& operator=(const CorotatedSolver&) = delete;

  // Replaces the Dirichlet set; an empty `motion` keeps the vertices at their rest positions.
  void set_dirichlet(std::vector<int> vertices, DirichletMotion motion = {});
  // Constant external forces on the vertices (3N, N; e.g. surface tractions lumped to the
  // vertices of the loaded boundary faces), added to gravity.
  void set_surface_forces(Eigen::VectorXd forces);
  // Advances by one time step; throws Error (naming the phase) on NaN or divergence.
  const StepStats& step();
  // Static equilibrium K~(x) (x - ...) = f_ext at the current time by repeated rotation update and
  // linear solve, until the update is below `tolerance` times the largest displacement. From the
  // second round on the update is halved (at most 10 times) until the residual force on the free
  // vertices decreases, which keeps the frozen-rotation iteration from cycling under large
  // rotations. The returned phase times and PCG iterations are summed over the rounds (line
  // search included); the residual is the last round's.
  const StepStats& solve_static(int max_iterations = 20, double tolerance = 1e-10);

  // f_el(x) + f_ext per vertex (3N, N) with the rotations of the last update: zero on the free
  // vertices at static equilibrium; minus it on a Dirichlet vertex is the force its constraint
  // applies (tet/constraint_reactions.hpp).
  Eigen::VectorXd unbalanced_forces() const;

  double time() const { return m_time; }
  // Sets the clock that the Dirichlet motion is evaluated at (a quasistatic sequence solves
  // equilibria at given frame times); positions and velocities are left as they are.
  void set_time(double time);
  long step_count() const { return m_steps; }
  const Eigen::VectorXd& positions() const { return m_x; }  // 3N, vertex-major
  const Eigen::VectorXd& velocities() const { return m_v; }
  Eigen::MatrixX3d positions_matrix() const;  // N x 3
  void set_state(const Eigen::VectorXd& positions, const Eigen::VectorXd& velocities);
  CorotatedState state() const;
  // Continues exactly where state() was taken; throws Error on sizes or non-finite values.
  void restore(const CorotatedState& state);
  const StepStats& last_stats() const { return m_stats; }

  double kinetic_energy() const;
  // Corotated strain energy with the rotations of the last update.
  double elastic_energy() const;
  // -sum m g . (x - X): zero at rest.
  double gravity_energy() const;

  const TetBody& body() const { return m_body; }
  const RotationField& rotations() const { return m_rotations; }
  const BlockRowMatrix<double>& stiffness() const { return m_assembler.stiffness(); }
  const CorotatedSolverSettings& settings() const { return m_settings; }
  // The multigrid of MULTIGRID / MG_PCG (nullptr before the first solve or for other solvers).
  const TetMultigrid* multigrid() const { return m_multigrid.get(); }
  TetMultigrid* multigrid() { return m_multigrid.get(); }  // benchmarks: naive Galerkin timing

 private:
  struct Cholesky;
  void update_operator(StepStats& stats);
  Eigen::VectorXd gravity_forces() const;
  // |f_el(x) + f_ext| over the free vertices, with the rotations updated to x.
  double free_residual_norm(const Eigen::VectorXd& x, StepStats& stats);
  Eigen::VectorXd prescribed_positions(double time) const;
  void solve_multigrid(const Eigen::VectorXd& b, Eigen::VectorXd& unknown, StepStats& stats);
  void solve(double mass_scale, double stiffness_scale, const Eigen::VectorXd& known,
             Eigen::VectorXd& b, Eigen::VectorXd& unknown, StepStats& stats);
  void step_implicit_euler(StepStats& stats);
  void step_newmark(StepStats& stats);

  CorotatedSolverSettings m_settings;
  TetBody m_body;
  RotationField m_rotations;
  CorotatedAssembler m_assembler;
  std::vector<char> m_constrained;
  std::vector<int> m_dirichlet;
  DirichletMotion m_motion;
  Eigen::VectorXd m_x, m_v, m_a;
  Eigen::VectorXd m_surface_forces;
  bool m_have_acceleration = false;
  double m_time = 0.0;
  long m_steps = 0;
  StepStats m_stats;
  std::unique_ptr<Cholesky> m_cholesky;
  std::unique_ptr<TetMultigrid> m_multigrid;
};

}  // namespace mgelastic::tet
