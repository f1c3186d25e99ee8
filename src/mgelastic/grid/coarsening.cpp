#include "mgelastic/grid/coarsening.hpp"

#include <cstdint>

#include "mgelastic/geometry/rigid_blocks.hpp"

namespace mgelastic::grid {

template <int Dim>
Lattice<Dim> coarsen(const Lattice<Dim>& fine) {
  IVec<Dim> n;
  for (int a = 0; a < Dim; ++a) n[a] = (fine.cells[a] + 1) / 2;
  return Lattice<Dim>(n, 2.0 * fine.h, fine.origin);
}

template <int Dim>
std::vector<CellType> coarsen_cells(const Lattice<Dim>& fine, const std::vector<CellType>& cells,
                                    CoarseDirichletRule rule) {
  const Lattice<Dim> coarse = coarsen(fine);
  std::vector<CellType> result(coarse.size(), CellType::EXTERIOR);
  // The type that wins over the other non-exterior one.
  const CellType dominant =
      rule == CoarseDirichletRule::ANY_CHILD ? CellType::DIRICHLET : CellType::INTERIOR;
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(fine.size()); ++k) {
    const IVec<Dim> s = fine.coords(k);
    if (!fine.is_real(s) || cells[k] == CellType::EXTERIOR) continue;
    IVec<Dim> cs;
    for (int a = 0; a < Dim; ++a) cs[a] = (s[a] - 1) / 2 + 1;
    CellType& parent = result[coarse.index(cs)];
    if (cells[k] == dominant || parent == CellType::EXTERIOR) parent = cells[k];
  }
  return result;
}

template <int Dim>
std::vector<std::uint8_t> finest_dirichlet_wall_layers(const Lattice<Dim>& finest,
                                                       const std::vector<CellType>& finest_cells,
                                                       const Lattice<Dim>& coarse,
                                                       const std::vector<CellType>& coarse_cells,
                                                       int factor, bool misaligned) {
  constexpr int faces = 2 * Dim;
  std::vector<std::uint8_t> walls(coarse.size() * faces, 0);
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(coarse.size()); ++k) {
    const IVec<Dim> cs = coarse.coords(k);
    if (!coarse.is_real(cs) || coarse_cells[k] != CellType::DIRICHLET) continue;
    for (int a = 0; a < Dim; ++a) {
      for (int side = 0; side < 2; ++side) {
        // Finest layers of the cell along a, from the face inward: the first one that holds a
        // Dirichlet cell must be all Dirichlet, and it is the finest wall.
        for (int layer = 0; layer < (misaligned ? factor : 1); ++layer) {
          IVec<Dim> lo, hi;
          for (int b = 0; b < Dim; ++b) {
            lo[b] = (cs[b] - 1) * factor + 1;
            hi[b] = cs[b] * factor;
          }
          lo[a] = hi[a] = side == 0 ? lo[a] + layer : hi[a] - layer;
          bool all = true, some = false;
          IVec<Dim> s = lo;
          while (true) {
            const CellType cell =
                finest.is_real(s) ? finest_cells[finest.index(s)] : CellType::EXTERIOR;
            all = all && cell == CellType::DIRICHLET;
            some = some || cell == CellType::DIRICHLET;
            int b = 0;
            for (; b < Dim && ++s[b] > hi[b]; ++b) s[b] = lo[b];
            if (b == Dim) break;
          }
          if (all && some) walls[k * faces + 2 * a + side] = static_cast<std::uint8_t>(layer + 1);
          if (some) break;
        }
      }
    }
  }
  return walls;
}

template <int Dim>
int repair_coarse_cells(const Lattice<Dim>& lattice, std::vector<CellType>& cells) {
  // Occupancy of the real cells (no ghost ring), x fastest.
  const geometry::CellCoords<Dim> dims = lattice.cells;
  std::vector<std::uint8_t> occupied(static_cast<std::size_t>(dims.prod()), 0);
  const auto stored = [&](std::size_t q) {
    IVec<Dim> s;
    for (int a = 0; a < Dim; ++a) {
      s[a] = static_cast<int>(q % static_cast<std::size_t>(dims[a])) + 1;
      q /= static_cast<std::size_t>(dims[a]);
    }
    return lattice.index(s);
  };
  for (std::size_t q = 0; q < occupied.size(); ++q)
    occupied[q] = cells[stored(q)] != CellType::EXTERIOR;
  int added = geometry::thicken_to_full_blocks<Dim>(dims, occupied);
  added += geometry::connect_full_blocks<Dim>(dims, occupied);
  if (added == 0) return 0;
  for (std::size_t q = 0; q < occupied.size(); ++q) {
    CellType& cell = cells[stored(q)];
    if (occupied[q] && cell == CellType::EXTERIOR) cell = CellType::INTERIOR;
  }
  return added;
}

template std::vector<std::uint8_t> finest_dirichlet_wall_layers<2>(const Lattice<2>&,
                                                                   const std::vector<CellType>&,
                                                                   const Lattice<2>&,
                                                                   const std::vector<CellType>&,
                                                                   int, bool);
template std::vector<std::uint8_t> finest_dirichlet_wall_layers<3>(const Lattice<3>&,
                                                                   const std::vector<CellType>&,
                                                                   const Lattice<3>&,
                                                                   const std::vector<CellType>&,
                                                                   int, bool);
template int repair_coarse_cells<2>(const Lattice<2>&, std::vector<CellType>&);
template int repair_coarse_cells<3>(const Lattice<3>&, std::vector<CellType>&);
template Lattice<2> coarsen<2>(const Lattice<2>&);
template Lattice<3> coarsen<3>(const Lattice<3>&);
template std::vector<CellType> coarsen_cells<2>(const Lattice<2>&, const std::vector<CellType>&,
                                                CoarseDirichletRule);
template std::vector<CellType> coarsen_cells<3>(const Lattice<3>&, const std::vector<CellType>&,
                                                CoarseDirichletRule);

}  // namespace mgelastic::grid
