#include "mgelastic/grid/disc_study.hpp"

#include <cmath>
#include <numbers>

#include "mgelastic/grid/convergence_rate.hpp"
#include "mgelastic/grid/embedded_traction.hpp"
#include "mgelastic/grid/multigrid.hpp"

namespace mgelastic::grid {
namespace {

constexpr double kRadius = 0.25;
const Vec<2> kCenter(0.5, 0.5);
const double kScale = 2.0 / std::sqrt(std::numbers::pi);
constexpr double kWave = std::numbers::pi / 2.0;

// Gradient of phi (Eq. 17).
Eigen::Matrix2d phi_gradient(const Vec<2>& x) {
  const double c = std::cos(kWave * x[1]), s = std::sin(kWave * x[1]);
  Eigen::Matrix2d f;
  f << kScale * c, -kScale * x[0] * kWave * s, kScale * s, kScale * x[0] * kWave * c;
  return f;
}

// Linear stress of u = phi - X: P = mu (grad u + grad u^T) + lambda tr(grad u) I.
Eigen::Matrix2d stress(const Vec<2>& x, const Material& m) {
  const Eigen::Matrix2d grad_u = phi_gradient(x) - Eigen::Matrix2d::Identity();
  return m.mu() * (grad_u + grad_u.transpose()) +
         m.lambda() * grad_u.trace() * Eigen::Matrix2d::Identity();
}

// div P = mu Lap phi + (mu + lambda) grad div phi.
Vec<2> stress_divergence(const Vec<2>& x, const Material& m) {
  const double c = std::cos(kWave * x[1]), s = std::sin(kWave * x[1]);
  const Vec<2> laplacian(-kScale * x[0] * kWave * kWave * c, -kScale * x[0] * kWave * kWave * s);
  const Vec<2> grad_div(kScale * kWave * c, -kScale * kWave * s * (1.0 + kWave * x[0]));
  return m.mu() * laplacian + (m.mu() + m.lambda()) * grad_div;
}

double cell_near_distance(const Vec<2>& lo, double h) {
  const Vec<2> nearest = kCenter.cwiseMax(lo).cwiseMin(lo + Vec<2>::Constant(h));
  return (nearest - kCenter).norm();
}

double cell_far_distance(const Vec<2>& lo, double h) {
  double far = 0;
  for (double dx : {0.0, h})
    for (double dy : {0.0, h}) far = std::max(far, (lo + Vec<2>(dx, dy) - kCenter).norm());
  return far;
}

std::vector<SurfaceForce<2>> traction_forces(int cells, const Material& material) {
  const int segments = 8 * cells;  // the polygon resolves the circle well below the cell size
  std::vector<SurfaceForce<2>> forces;
  auto point = [](double theta) {
    return Vec<2>(kCenter + kRadius * Vec<2>(std::cos(theta), std::sin(theta)));
  };
  for (int k = 0; k < segments; ++k) {
    const double t0 = -std::numbers::pi / 2 + std::numbers::pi * k / segments;
    const double t1 = -std::numbers::pi / 2 + std::numbers::pi * (k + 1) / segments;
    const Vec<2> a = point(t0), b = point(t1), mid = 0.5 * (a + b);
    const Vec<2> normal = (mid - kCenter).normalized();
    const Vec<2> force = (b - a).norm() * (stress(mid, material) * normal);
    forces.push_back({a, 0.5 * force, normal});
    forces.push_back({b, 0.5 * force, normal});
  }
  return forces;
}

}  // namespace

Vec<2> disc_displacement(const Vec<2>& x) {
  return Vec<2>(kScale * x[0] * std::cos(kWave * x[1]), kScale * x[0] * std::sin(kWave * x[1])) - x;
}

ElasticityProblem<2> make_disc_problem(int cells, double poisson_ratio) {
  ElasticityProblem<2> problem;
  problem.lattice = Lattice<2>(IVec<2>::Constant(cells), 1.0 / cells);
  problem.material = {1.0, poisson_ratio};
  problem.cells.assign(problem.lattice.size(), CellType::EXTERIOR);
  const double h = problem.lattice.h;
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(problem.lattice.size()); ++k) {
    const IVec<2> s = problem.lattice.coords(k);
    if (!problem.lattice.is_real(s)) continue;
    const Vec<2> lo = problem.lattice.cell_center(k) - Vec<2>::Constant(0.5 * h);
    const bool overlaps = cell_near_distance(lo, h) < kRadius;
    const bool cut_or_outside = cell_far_distance(lo, h) > kRadius;
    const bool left_half = problem.lattice.cell_center(k)[0] < kCenter[0];
    // Dirichlet: the cells the left half of the circle cuts, and a band outside them, so no
    // interior cell on that side borders an exterior (traction) cell.
    const bool dirichlet =
        left_half && cut_or_outside && cell_near_distance(lo, h) < kRadius + 2 * h;
    if (dirichlet) {
      problem.cells[k] = CellType::DIRICHLET;
    } else if (overlaps) {
      problem.cells[k] = CellType::INTERIOR;
    }
  }
  const Material material = problem.material;
  problem.body_force = [material](const Vec<2>& x) {
    return Vec<2>(-stress_divergence(x, material));
  };
  problem.dirichlet_displacement = disc_displacement;
  apply_surface_forces(problem, traction_forces(cells, material));
  return problem;
}

DiscStudy run_disc_study(double poisson_ratio, const std::vector<int>& resolutions) {
  DiscStudy study;
  study.poisson_ratio = poisson_ratio;
  for (int cells : resolutions) {
    Multigrid<2, double> mg(make_disc_problem(cells, poisson_ratio));
    const SolveReport report = mg.solve(1e-10, 100);
    const auto& level = mg.finest();
    DiscStudyRow row{cells, 0.0, mg.unknowns(), report.cycles(),
                     convergence_rate(report.residuals)};
    for (int i = 0; i < 2; ++i)
      for (std::size_t k = 0; k < level.size(); ++k)
        if (level.kind(i, k) == VarKind::INTERIOR)
          row.max_error = std::max(
              row.max_error,
              std::abs(mg.solution(i, k) - disc_displacement(level.lattice.face_center(i, k))[i]));
    study.rows.push_back(row);
  }
  if (study.rows.size() >= 2) {
    const auto& a = study.rows[study.rows.size() - 2];
    const auto& b = study.rows.back();
    study.order = std::log(a.max_error / b.max_error) / std::log(double(b.cells) / a.cells);
  }
  return study;
}

}  // namespace mgelastic::grid
