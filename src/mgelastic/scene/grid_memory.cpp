#include "mgelastic/scene/grid_memory.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "mgelastic/core/error.hpp"
#include "mgelastic/grid/local_corrections.hpp"

namespace mgelastic::scene {
namespace {

constexpr double kGiB = 1024.0 * 1024.0 * 1024.0;

std::string gib(double bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f GiB", bytes / kGiB);
  return text;
}

std::string lattice_text(const Eigen::Vector3d& cells) {
  char text[96];
  std::snprintf(text, sizeof text, "%.0f x %.0f x %.0f = %.3g cells", cells[0], cells[1], cells[2],
                cells.prod());
  return text;
}

// The largest factors solver.local_corrections boxes can hold on a lattice of `points` (the
// body has at most that many cells).
double local_correction_bytes(const Scene& scene, double points) {
  if (scene.local_corrections <= 0) return 0;
  const double cells =
      std::min(points, std::min(static_cast<double>(grid::kLocalCorrectionMaxCells),
                                std::max(static_cast<double>(grid::kLocalCorrectionMinCells),
                                         grid::kLocalCorrectionBodyShare * points)));
  return scene.local_corrections * cells * 4.0 * kGridLocalCorrectionBytesPerUnknown;
}

}  // namespace

double estimated_grid_bytes(const Scene& scene, const Eigen::Vector3d& cells) {
  const double padded = (cells.array() + 2.0).prod();  // the level lattice's ghost ring
  if (scene.material_model == "corotated")
    return padded * kGridPeakBytesPerPointCorotated * kGridPeakMargin;
  const double plain = scene.precision == "single"  ? kGridPeakBytesPerPointSingle
                       : scene.precision == "float" ? kGridPeakBytesPerPointFloat
                                                    : kGridPeakBytesPerPointDouble;
  // Single precision iterates plain cycles (no double level for FGMRES).
  const bool krylov = scene.accelerate && scene.precision != "single";
  return padded * (plain + (krylov ? kGridFgmresBytesPerPoint : 0.0)) * kGridPeakMargin +
         local_correction_bytes(scene, padded);
}

void check_grid_size(const Scene& scene, const Eigen::Vector3d& cells,
                     std::uint64_t available_bytes, const std::string& memory_source) {
  const ErrorContext at{.file = scene.file,
                        .pointer = scene.cell_size > 0 ? "/grid/cell_size" : "/grid/resolution"};
  const std::string remedy =
      scene.cell_size > 0 ? "; increase the cell size" : "; lower the resolution";
  const double estimate = estimated_grid_bytes(scene, cells);
  if (available_bytes > 0 && estimate > static_cast<double>(available_bytes))
    throw Error("the grid would need about " + gib(estimate) + " of memory (lattice " +
                    lattice_text(cells) + "), more than the " +
                    gib(static_cast<double>(available_bytes)) + " available on this machine (" +
                    memory_source + ")" + remedy,
                at);
  // Level arrays index variables as field * size + k in 32 bits (level.hpp).
  const double indices = 4.0 * (cells.array() + 2.0).prod();
  if (!(indices < static_cast<double>(std::numeric_limits<std::uint32_t>::max())))
    throw Error("the lattice of the body's bounding box would have " + lattice_text(cells) +
                    ", beyond the solver's 32-bit variable indices (at most ~1.07e9 cells)" +
                    remedy,
                at);
}

}  // namespace mgelastic::scene
