#pragma once
// Geometric multigrid for the tet engine's step systems (Georgii & Westermann 2008, Sec. 4.3 and
// 5: one Gauss-Seidel step for pre- and post-smoothing in a V-cycle).
//
// System (level 0): A_0 = m (M (x) I3) + k K~ on the free vertices, identity rows/columns on the
// constrained ones (the same matrix as StepSystem, block_jacobi_pcg.hpp), stored as a BRC matrix
// with K~'s pattern. Coarse levels (tet_hierarchy.hpp): A_{l+1} = P_l^T A_l P_l (galerkin_product),
// plus the identity on the diagonal blocks of constrained coarse vertices (whose rows are zero).
// The coarsest level is factorized by CHOLMOD (supernodal LLT; the symbolic analysis once).
//
// V-cycle on level l (cycle()):  pre-smooth (forward block Gauss-Seidel), residual, restrict
// (R = P^T), recurse from a zero guess, prolong and add, post-smooth (backward block Gauss-Seidel)
// ; exact solve on the coarsest level. With forward pre- and backward post-smoothing the cycle
// from a zero guess is a symmetric positive definite operator, so it serves as a preconditioner
// for CG (solve_pcg). Options (TetMultigridSettings): more sweeps; symmetric sweeps (each
// smoothing step a forward + backward pair, also symmetric); SOR relaxation.
//
// Vectors are 3N (vertex-major). The solver keeps per-level work vectors: one instance must not
// be used by several threads at once.
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "mgelastic/geometry/tet_mesh.hpp"
#include "mgelastic/tet/block_jacobi_pcg.hpp"
#include "mgelastic/tet/brc_matrix.hpp"
#include "mgelastic/tet/cluster_smoother.hpp"
#include "mgelastic/tet/feature_patches.hpp"
#include "mgelastic/tet/galerkin_product.hpp"
#include "mgelastic/tet/patch_seeds.hpp"
#include "mgelastic/tet/tet_hierarchy.hpp"

namespace mgelastic::tet {

enum class GalerkinMethod { STREAM, NAIVE };

struct TetMultigridSettings {
  TetHierarchySettings hierarchy;
  GalerkinMethod galerkin = GalerkinMethod::STREAM;
  int pre_smoothing = 1;   // forward block Gauss-Seidel sweeps
  int post_smoothing = 1;  // backward block Gauss-Seidel sweeps
  // Each smoothing step is a forward + backward pair instead of a single sweep (twice the work;
  // armadillo rate 0.43 -> 0.21 for cycle(), 0.33 in the symmetric form, docs/tet-engine.md).
  bool symmetric_sweeps = false;
  // Over-relaxation of the block Gauss-Seidel update (1 = plain Gauss-Seidel, SOR otherwise):
  // `relaxation` for single sweeps, `symmetric_relaxation` with symmetric_sweeps (SSOR). 1.2 took
  // the symmetric rate 0.39 -> 0.36 (bar 8), 0.38 -> 0.34 (bunny), 0.51 -> 0.46 (tetgen armadillo
  // 67k) at no cost; single sweeps get slower with w > 1 (docs/tet-engine.md, Convergence).
  double relaxation = 1.0;
  double symmetric_relaxation = 1.2;
  // Smoother: multicolour cluster block Gauss-Seidel (parallel; strongly coupled vertices solved
  // together, cluster_smoother.hpp), or the serial point-block sweep in vertex order
  // (`lexicographic`, the earlier smoother, kept for comparison).
  ClusterSmootherSettings smoother;
  bool lexicographic = false;
  // Block solves on patches at thin features of the fine level after each forward sweep and
  // before each backward one (feature_patches.hpp; off by default). Max valence 7, 12 vertices:
  // tetgen armadillo 18k / 28k / 67k symmetric 0.29 / 0.43 / 0.55 -> 0.07 / 0.09 / 0.24, at ~2x
  // the symmetric V-cycle's CPU time (docs/tet-engine.md, Convergence).
  FeaturePatchSettings patches;
  // More feature patches where the cycle's own slow error concentrates, found at the first
  // update() (patch_seeds.hpp; off by default). With 10 rounds on top of the valence-7 patches:
  // tetgen armadillo 0.07 / 0.09 / 0.08, bunny 0.10 / 0.08 / 0.10 (size-independent), at 2.8-4
  // s setup CPU on the finest meshes (docs/tet-engine.md, Convergence).
  AdaptivePatchSettings adaptive_patches;
};

// Residual norms of one traced V-cycle per level (cycle_traced): after restriction (entry), after
// pre-smoothing, after the coarse correction, after post-smoothing. The coarsest level's entry
// only (it is solved exactly).
struct LevelResiduals {
  double entry = 0.0, pre_smoothed = 0.0, corrected = 0.0, post_smoothed = 0.0;
};

struct MultigridResult {
  int cycles = 0;
  double relative_residual = 0.0;  // |b - A x| / |b|
  bool converged = false;
};

// Seconds of the last update(), per phase.
struct MultigridUpdateTimes {
  double fine_seconds = 0.0;      // A_0 from K~ and M
  double galerkin_seconds = 0.0;  // all coarse operators
  double factor_seconds = 0.0;    // coarsest Cholesky and smoother diagonals
};

class TetMultigrid {
 public:
  // `stiffness_pattern` gives the pattern of K~ (values ignored), e.g. CorotatedAssembler's.
  // `constrained[v]` != 0 marks a Dirichlet vertex. Builds the hierarchy, the coarse patterns and
  // (for STREAM) the streams; throws Error on size mismatches.
  TetMultigrid(const geometry::TetMesh& mesh, const std::vector<char>& constrained,
               const BlockRowMatrix<double>& stiffness_pattern,
               const TetMultigridSettings& settings = {});
  ~TetMultigrid();
  TetMultigrid(const TetMultigrid&) = delete;
  TetMultigrid& operator=(const TetMultigrid&) = delete;
  TetMultigrid(TetMultigrid&&) noexcept;
  TetMultigrid& operator=(TetMultigrid&&) noexcept;

  // A_0 <- m M + k K~ (constrained), then every coarse operator and the coarsest factorization.
  void update(const BlockRowMatrix<double>& stiffness, const Eigen::VectorXd& vertex_mass,
              double mass_scale, double stiffness_scale);
  // Recomputes the coarse operators from the current A_0 with the given method (benchmarks).
  void update_coarse(GalerkinMethod method);
  const MultigridUpdateTimes& update_times() const { return m_times; }

  // One V-cycle on A_0 x = b, improving x in place.
  void cycle(const Eigen::VectorXd& b, Eigen::VectorXd& x) const;
  // z <- one V-cycle on A_0 z = r from the given z, in the symmetric form (with symmetric_sweeps:
  // forward + backward on both sides; cycle() mirrors the post-smoothing instead, a better but
  // non-symmetric stand-alone cycle). The preconditioner of solve_pcg (from z = 0).
  void precondition(const Eigen::VectorXd& r, Eigen::VectorXd& z) const;
  // The same cycle, recording per-level residual norms (diagnostics; costs extra products).
  std::vector<LevelResiduals> cycle_traced(const Eigen::VectorXd& b, Eigen::VectorXd& x) const;
  // V-cycles until |b - A_0 x| <= tolerance |b| or max_cycles.
  MultigridResult solve(const Eigen::VectorXd& b, Eigen::VectorXd& x, double tolerance,
                        int max_cycles) const;
  // CG on A_0 preconditioned by one V-cycle from zero. Throws Error on non-finite values or
  // non-positive curvature.
  PcgResult solve_pcg(const Eigen::VectorXd& b, Eigen::VectorXd& x,
                      const PcgSettings& settings) const;
  // r = b - A_0 x.
  void residual(const Eigen::VectorXd& b, const Eigen::VectorXd& x, Eigen::VectorXd& r) const;

  const TetHierarchy& hierarchy() const { return m_hierarchy; }
  int level_count() const { return m_hierarchy.level_count(); }
  const BlockRowMatrix<double>& level_matrix(int level) const { return m_levels[level].matrix; }
  // Stream of the product that makes level + 1 (nullptr for NAIVE).
  const GalerkinStream* stream(int level) const { return m_levels[level].stream.get(); }
  std::size_t stream_memory_bytes() const;
  // The smoother of a level (not the coarsest); partitioned at the first update().
  const ClusterSmoother& smoother(int level) const { return m_levels[level].smoother; }
  const FeaturePatches& patches() const { return m_patches; }
  // Per adaptive-patch round: the power iteration's contraction before that round's patches
  // (the last one at or below the target ends the seeding).
  const std::vector<double>& adaptive_contractions() const { return m_adaptive_contractions; }

 private:
  struct Level {
    BlockRowMatrix<double> matrix;
    std::unique_ptr<GalerkinStream> stream;  // product to the next level
    std::vector<Eigen::Matrix3d> inverse_diagonal;
    ClusterSmoother smoother;
    bool partitioned = false;
    mutable Eigen::VectorXd b, x, r;
  };
  struct Coarsest;
  void smooth(int level, const Eigen::VectorXd& b, Eigen::VectorXd& x, bool forward) const;
  void lexicographic_sweep(int level, const Eigen::VectorXd& b, Eigen::VectorXd& x, bool forward,
                           double w) const;
  void cycle_level(int level, std::vector<LevelResiduals>* trace, bool symmetric_cycle) const;
  void sweeps(int level, int count, bool forward, bool symmetric_cycle) const;
  void finish_coarse_update();
  void seed_adaptive_patches();

  TetMultigridSettings m_settings;
  TetHierarchy m_hierarchy;
  std::vector<Level> m_levels;
  std::unique_ptr<Coarsest> m_coarsest;
  FeaturePatches m_patches;  // fine level only
  bool m_patches_seeded = false;
  std::vector<double> m_adaptive_contractions;
  MultigridUpdateTimes m_times;
};

}  // namespace mgelastic::tet
