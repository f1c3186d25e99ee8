#pragma once
// Shared fixtures for grid-engine tests: manufactured solutions and irregular cell patterns.
#include <cmath>
#include <random>

#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/problem.hpp"

namespace mgelastic::grid::test {

// The mixed 3D box (make_box_problem's boundary) at nu 0.48 with `cells` cells per side.
inline ElasticityProblem<3> mixed_box(int cells) {
  BoxSpec spec;
  spec.cells = cells;
  spec.poisson_ratio = 0.48;
  return make_box_problem<3>(spec);
}

// A beam of `cells` lattice cells (all real cells of the body, spacing 1 / cells[0]) clamped over
// its first three cell layers along x, with make_box_problem's material and loads at nu 0.3:
// plates and slender bars.
inline ElasticityProblem<3> clamped_beam(const IVec<3>& cells) {
  ElasticityProblem<3> beam = make_box_problem<3>({.cells = 8, .poisson_ratio = 0.3});
  beam.lattice = Lattice<3>(cells, 1.0 / cells[0]);
  beam.cells.assign(beam.lattice.size(), CellType::EXTERIOR);
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(beam.lattice.size()); ++k) {
    const IVec<3> s = beam.lattice.coords(k);
    if (beam.lattice.is_real(s))
      beam.cells[k] = s[0] <= 2 ? CellType::DIRICHLET : CellType::INTERIOR;
  }
  return beam;
}

// sqrt(sum (a - b)^2) / sqrt(sum a^2) over the displacement fields of two hierarchies' solutions.
template <typename A, typename B>
double relative_displacement_difference(const A& a, const B& b) {
  double difference = 0, norm = 0;
  for (int f = 0; f < 3; ++f)
    for (std::size_t k = 0; k < a.finest().size(); ++k) {
      difference += std::pow(a.solution(f, k) - b.solution(f, k), 2);
      norm += std::pow(a.solution(f, k), 2);
    }
  return std::sqrt(difference / norm);
}

// A smooth displacement made of one plane wave per component, u_i = A cos(k_i . x + phi_i),
// with its exact stress P = mu (grad u + grad u^T) + lambda (div u) I and div P.
template <int Dim>
struct PlaneWaveSolution {
  double amplitude = 1e-3;
  Material material;
  std::array<Vec<Dim>, Dim> k;
  Vec<Dim> phase;

  explicit PlaneWaveSolution(const Material& m) : material(m) {
    for (int i = 0; i < Dim; ++i) {
      for (int j = 0; j < Dim; ++j) k[i][j] = 1.0 + 0.7 * i + 0.45 * j * (i + 1);
      phase[i] = 0.3 + 0.5 * i;
    }
  }
  double theta(int i, const Vec<Dim>& x) const { return k[i].dot(x) + phase[i]; }
  Vec<Dim> displacement(const Vec<Dim>& x) const {
    Vec<Dim> u;
    for (int i = 0; i < Dim; ++i) u[i] = amplitude * std::cos(theta(i, x));
    return u;
  }
  double gradient(int i, int j, const Vec<Dim>& x) const {  // d u_i / d x_j
    return -amplitude * k[i][j] * std::sin(theta(i, x));
  }
  double stress(int i, int j, const Vec<Dim>& x) const {
    double div = 0;
    for (int m = 0; m < Dim; ++m) div += gradient(m, m, x);
    return material.mu() * (gradient(i, j, x) + gradient(j, i, x)) +
           (i == j ? material.lambda() * div : 0.0);
  }
  // Body force f = -div P.
  Vec<Dim> body_force(const Vec<Dim>& x) const {
    const double mu = material.mu(), lambda = material.lambda();
    Vec<Dim> f;
    for (int i = 0; i < Dim; ++i) {
      double div_p = -mu * amplitude * k[i].squaredNorm() * std::cos(theta(i, x));
      for (int m = 0; m < Dim; ++m) {
        const double c = -amplitude * k[m][m] * k[m][i] * std::cos(theta(m, x));
        div_p += mu * c + lambda * c;
      }
      f[i] = -div_p;
    }
    return f;
  }
};

// A unit box of n cells per axis whose cells satisfy `dirichlet(stored coords)` are Dirichlet.
template <int Dim, typename Predicate>
ElasticityProblem<Dim> unit_box(int n, const Material& material, Predicate dirichlet) {
  ElasticityProblem<Dim> problem;
  problem.lattice = Lattice<Dim>(IVec<Dim>::Constant(n), 1.0 / n);
  problem.material = material;
  problem.cells.assign(problem.lattice.size(), CellType::EXTERIOR);
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(problem.lattice.size()); ++k) {
    const IVec<Dim> s = problem.lattice.coords(k);
    if (!problem.lattice.is_real(s)) continue;
    problem.cells[k] = dirichlet(s) ? CellType::DIRICHLET : CellType::INTERIOR;
  }
  return problem;
}

// Turns interior cells that are not face-connected to a Dirichlet cell exterior, so the
// problem is well-posed (no floating pieces with rigid-motion null spaces).
template <int Dim>
void keep_supported_pieces(ElasticityProblem<Dim>& problem) {
  const auto& lat = problem.lattice;
  std::vector<std::uint8_t> reached(lat.size(), 0);
  std::vector<std::ptrdiff_t> stack;
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(lat.size()); ++k)
    if (problem.cells[k] == CellType::DIRICHLET) stack.push_back(k);
  while (!stack.empty()) {
    const std::ptrdiff_t k = stack.back();
    stack.pop_back();
    for (int a = 0; a < Dim; ++a) {
      for (std::ptrdiff_t nb : {k - lat.stride(a), k + lat.stride(a)}) {
        if (nb < 0 || nb >= static_cast<std::ptrdiff_t>(lat.size())) continue;
        if (reached[nb] || problem.cells[nb] != CellType::INTERIOR) continue;
        reached[nb] = 1;
        stack.push_back(nb);
      }
    }
  }
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(lat.size()); ++k)
    if (problem.cells[k] == CellType::INTERIOR && !reached[k])
      problem.cells[k] = CellType::EXTERIOR;
}

// Random irregular typing: blobs of interior cells, one-cell-thin bars and traction corners,
// with a Dirichlet patch; seeded for reproducibility.
template <int Dim>
ElasticityProblem<Dim> irregular_problem(int n, unsigned seed, const Material& material) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  ElasticityProblem<Dim> problem;
  problem.lattice = Lattice<Dim>(IVec<Dim>::Constant(n), 1.0 / n);
  problem.material = material;
  problem.cells.assign(problem.lattice.size(), CellType::EXTERIOR);
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(problem.lattice.size()); ++k) {
    const IVec<Dim> s = problem.lattice.coords(k);
    if (!problem.lattice.is_real(s)) continue;
    const bool thin_bar = s[1] == n / 2 && s[0] > n / 2;  // one cell thick
    const bool blob = uniform(rng) < 0.8 && s[0] < n - 1;
    if (blob || thin_bar) problem.cells[k] = CellType::INTERIOR;
    if (s[0] == 1 && s[1] < n / 2) problem.cells[k] = CellType::DIRICHLET;
  }
  keep_supported_pieces(problem);
  return problem;
}

// A problem on the unit box with n cells per axis whose real cells take the type
// type_of(storage coordinates, cell center) (the ghost ring stays exterior).
template <typename TypeOf>
ElasticityProblem<3> typed_unit_box(int n, const Material& material, const TypeOf& type_of) {
  ElasticityProblem<3> problem;
  problem.lattice = Lattice<3>(IVec<3>::Constant(n), 1.0 / n);
  problem.material = material;
  problem.cells.assign(problem.lattice.size(), CellType::EXTERIOR);
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(problem.lattice.size()); ++k) {
    const IVec<3> s = problem.lattice.coords(k);
    if (problem.lattice.is_real(s)) problem.cells[k] = type_of(s, problem.lattice.cell_center(k));
  }
  return problem;
}

// A ball (radius 0.45 of the unit box, n cells per axis) whose bottom cap (z < 0.2) is clamped,
// under gravity: an embedded body whose band has rows of every shape and no mechanisms.
inline ElasticityProblem<3> clamped_ball(int n) {
  auto problem = typed_unit_box(n, {1e5, 0.48}, [](const IVec<3>&, const Vec<3>& center) {
    if ((center - Vec<3>::Constant(0.5)).norm() >= 0.45) return CellType::EXTERIOR;
    return center[2] < 0.2 ? CellType::DIRICHLET : CellType::INTERIOR;
  });
  problem.body_force = [](const Vec<3>&) { return Vec<3>(0, 0, -1e4); };
  return problem;
}

// Two thin fingers (2 x 1 cells, one cell apart) standing on a slab clamped at its bottom, n
// cells per axis, under gravity and a force pulling them apart: the coarse levels merge the
// fingers, so their opposite bending is a slow mode of the V-cycle that sits at the fingers.
inline ElasticityProblem<3> two_fingers(int n) {
  auto problem = typed_unit_box(n, {1e5, 0.45}, [n](const IVec<3>& s, const Vec<3>&) {
    const bool slab = s[2] <= n / 4;
    const bool finger = s[2] <= n - 2 && s[1] >= n / 2 - 1 && s[1] <= n / 2 &&
                        (s[0] == n / 2 - 1 || s[0] == n / 2 + 1);
    if (s[2] <= 2) return CellType::DIRICHLET;
    return slab || finger ? CellType::INTERIOR : CellType::EXTERIOR;
  });
  problem.body_force = [](const Vec<3>& x) { return Vec<3>(1e3 * (x[0] - 0.5), 0, -1e3); };
  return problem;
}

}  // namespace mgelastic::grid::test
