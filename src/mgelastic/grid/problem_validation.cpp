#include "mgelastic/grid/problem_validation.hpp"

#include <cmath>
#include <string>

#include "mgelastic/core/error.hpp"

namespace mgelastic::grid {
namespace {

template <int Dim>
bool touches_dirichlet(const ElasticityProblem<Dim>& problem, std::ptrdiff_t k) {
  const auto& lat = problem.lattice;
  const IVec<Dim> s = lat.coords(k);
  bool found = false;
  IVec<Dim> t;
  auto recurse = [&](auto&& self, int a) -> void {
    if (found) return;
    if (a == Dim) {
      found = problem.cells[lat.index(t)] == CellType::DIRICHLET;
      return;
    }
    for (int d = -1; d <= 1; ++d) {
      t[a] = s[a] + d;
      self(self, a + 1);
    }
  };
  recurse(recurse, 0);
  return found;
}

// Flood fill over face-connected interior cells; returns the number of pieces without a
// Dirichlet cell in their neighborhood and the total number of pieces.
template <int Dim>
std::pair<int, int> count_unsupported_pieces(const ElasticityProblem<Dim>& problem) {
  const auto& lat = problem.lattice;
  std::vector<std::uint8_t> seen(lat.size(), 0);
  std::vector<std::ptrdiff_t> stack;
  int unsupported = 0, pieces = 0;
  for (std::ptrdiff_t start = 0; start < static_cast<std::ptrdiff_t>(lat.size()); ++start) {
    if (seen[start] || problem.cells[start] != CellType::INTERIOR) continue;
    ++pieces;
    bool supported = false;
    stack.push_back(start);
    seen[start] = 1;
    while (!stack.empty()) {
      const std::ptrdiff_t k = stack.back();
      stack.pop_back();
      supported = supported || touches_dirichlet(problem, k);
      for (int a = 0; a < Dim; ++a) {
        for (std::ptrdiff_t nb : {k - lat.stride(a), k + lat.stride(a)}) {
          if (seen[nb] || problem.cells[nb] != CellType::INTERIOR) continue;
          seen[nb] = 1;
          stack.push_back(nb);
        }
      }
    }
    if (!supported) ++unsupported;
  }
  return {unsupported, pieces};
}

template <int Dim>
void validate_lattice(const ElasticityProblem<Dim>& problem) {
  const auto& lat = problem.lattice;
  for (int a = 0; a < Dim; ++a) {
    if (lat.cells[a] < 4)
      throw Error("needs at least 4 cells along every axis for one coarsening (axis " +
                      std::to_string(a) + " has " + std::to_string(lat.cells[a]) + ")",
                  {.pointer = "grid.cells"});
  }
  if (!(lat.h > 0.0))
    throw Error("cell size must be positive (got " + std::to_string(lat.h) + ")",
                {.pointer = "grid.cell_size"});
  if (problem.cells.size() != lat.size())
    throw Error("cell type array has " + std::to_string(problem.cells.size()) +
                    " entries, the padded lattice " + std::to_string(lat.size()),
                {.pointer = "grid.cells"});
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(lat.size()); ++k) {
    if (!lat.is_real(lat.coords(k)) && problem.cells[k] != CellType::EXTERIOR)
      throw Error("the ghost ring around the lattice must stay exterior",
                  {.pointer = "grid.cells"});
  }
}

}  // namespace

template <int Dim>
void validate(const ElasticityProblem<Dim>& problem) {
  validate(problem.material);
  validate_lattice(problem);
  const auto [unsupported, pieces] = count_unsupported_pieces(problem);
  if (pieces == 0)
    throw Error("the domain has no interior cell: nothing to simulate", {.pointer = "grid.cells"});
  if (!(std::isfinite(problem.inertia) && problem.inertia >= 0.0))
    throw Error(
        "the inertia term c must be finite and >= 0 (got " + std::to_string(problem.inertia) + ")",
        {.pointer = "time"});
  // Inertia (dynamics, c > 0) makes a free-floating piece well-posed.
  if (unsupported > 0 && problem.inertia == 0.0)
    throw Error(std::to_string(unsupported) + " of " + std::to_string(pieces) +
                    " connected piece(s) of the body touch no Dirichlet cell; a traction-only "
                    "body is singular in statics (add a constraint region)",
                {.pointer = "constraints"});
}

template void validate<2>(const ElasticityProblem<2>&);
template void validate<3>(const ElasticityProblem<3>&);

}  // namespace mgelastic::grid
