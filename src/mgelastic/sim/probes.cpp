#include "mgelastic/sim/probes.hpp"

#include <cmath>
#include <limits>
#include <optional>
#include <string>

#include "mgelastic/core/error.hpp"
#include "mgelastic/sim/simulation.hpp"

namespace mgelastic::sim {
namespace {

Error outside_body(const Simulation& simulation, std::size_t probe) {
  return Error("probe \"" + simulation.scene().probes[probe].name + "\" lies outside the body",
               ErrorContext{.file = simulation.scene().file,
                            .pointer = "/output/probes/" + std::to_string(probe) + "/point"});
}

// Flat index (x fastest) of the body cell holding `point`, if any.
std::optional<std::size_t> grid_cell(const GridStepper& grid, const Eigen::Vector3d& point) {
  const Eigen::Vector3i n = grid.cells();
  const Eigen::Vector3d t = (point - grid.origin()) / grid.spacing();
  Eigen::Vector3i c;
  for (int a = 0; a < 3; ++a) {
    if (!(t[a] >= 0.0 && t[a] <= n[a])) return std::nullopt;
    c[a] = std::min(static_cast<int>(std::floor(t[a])), n[a] - 1);
  }
  const std::size_t k =
      static_cast<std::size_t>(c[0]) +
      static_cast<std::size_t>(n[0]) * (c[1] + static_cast<std::size_t>(n[1]) * c[2]);
  if (grid.cell_types()[k] == static_cast<std::uint8_t>(grid::CellType::EXTERIOR))
    return std::nullopt;
  return k;
}

struct TetHit {
  int element = -1;
  Eigen::Vector4d weights = Eigen::Vector4d::Zero();  // barycentric
};

// The rest tet holding `point` (tolerance 1e-9 in barycentric weight: points on shared faces
// belong to the first tet found).
std::optional<TetHit> tet_element(const TetStepper& tet, const Eigen::Vector3d& point) {
  const tet::TetBody& body = tet.solver().body();
  const Eigen::VectorXd& rest = body.rest_positions();
  for (int e = 0; e < body.element_count(); ++e) {
    const Eigen::Vector3d x0 = rest.segment<3>(3 * body.tets()(e, 0));
    const Eigen::Vector3d w = body.rest_edge_inverse(e) * (point - x0);
    const double w0 = 1.0 - w.sum();
    if (w.minCoeff() >= -1e-9 && w0 >= -1e-9)
      return TetHit{e, Eigen::Vector4d(w0, w[0], w[1], w[2])};
  }
  return std::nullopt;
}

ProbeSample sample_grid(const GridStepper& grid, std::size_t cell, const Eigen::Vector3d& point) {
  ProbeSample sample;
  sample.displacement = grid.displacement().sample(point);
  sample.von_mises = grid.von_mises()[cell];
  sample.pressure = grid.pressure()[cell];
  return sample;
}

ProbeSample sample_tet(const TetStepper& tet, const TetHit& hit) {
  const tet::TetBody& body = tet.solver().body();
  const Eigen::VectorXd& rest = body.rest_positions();
  const Eigen::VectorXd& now = tet.positions();
  ProbeSample sample;
  for (int c = 0; c < 4; ++c) {
    const int v = body.tets()(hit.element, c);
    sample.displacement += hit.weights[c] * (now.segment<3>(3 * v) - rest.segment<3>(3 * v));
  }
  sample.von_mises = tet.von_mises_of(hit.element);
  sample.pressure = tet.pressure(hit.element);
  return sample;
}

}  // namespace

std::vector<ProbeSample> sample_probes(const Simulation& simulation) {
  const auto& probes = simulation.scene().probes;
  std::vector<ProbeSample> samples;
  samples.reserve(probes.size());
  for (std::size_t i = 0; i < probes.size(); ++i) {
    const Eigen::Vector3d& point = probes[i].point;
    if (const GridStepper* grid = simulation.grid()) {
      const auto cell = grid_cell(*grid, point);
      if (!cell) throw outside_body(simulation, i);
      samples.push_back(sample_grid(*grid, *cell, point));
    } else {
      const auto hit = tet_element(*simulation.tet(), point);
      if (!hit) throw outside_body(simulation, i);
      samples.push_back(sample_tet(*simulation.tet(), *hit));
    }
  }
  return samples;
}

void check_probes(const Simulation& simulation) {
  const auto& probes = simulation.scene().probes;
  for (std::size_t i = 0; i < probes.size(); ++i) {
    const bool inside = simulation.grid()
                            ? grid_cell(*simulation.grid(), probes[i].point).has_value()
                            : tet_element(*simulation.tet(), probes[i].point).has_value();
    if (!inside) throw outside_body(simulation, i);
  }
}

}  // namespace mgelastic::sim
