#pragma once
// Size limits of a grid scene, checked before anything of the lattice's size is allocated: the
// lattice of the body's bounding box (geometry::voxel_lattice) must fit the level arrays' 32-bit
// global indices ((Dim + 1) * padded cells < 2^32, level.hpp) and the estimated memory must fit
// the memory available on this machine (core/system_memory.hpp).
//
// Estimate per lattice cell (the level arrays are dense over the box): the solver's working set,
// kGridBytesPerUnknown per unknown (93 at 128^3 from `mgelastic bench vcycle`, 70 at 256^3; the
// band rows make it larger on small or thin lattices) times Dim + 1 unknowns, times the peak
// resident memory over the working set (1.25 at 256^3: 5.0 GiB / 4.1 GB), plus the
// voxelization's byte-per-cell arrays (occupancy, its dilated copy, a region mask, cell types).
#include <cstdint>

#include <Eigen/Core>

#include "mgelastic/scene/scene.hpp"

namespace mgelastic::scene {

inline constexpr double kGridBytesPerUnknown = 93.0;
inline constexpr double kGridPeakOverWorkingSet = 1.25;
inline constexpr double kVoxelizationBytesPerCell = 4.0;

// Estimated peak memory of a grid scene whose voxel lattice has `cells` per axis, bytes.
double estimated_grid_bytes(const Eigen::Vector3d& cells);

// Throws Error (pointer /grid/resolution, or /grid/cell_size when the scene sets it) when the
// lattice exceeds the index range or the estimate exceeds `available_bytes` (0 = unknown: only
// the index range is checked); `memory_source` names where that number came from.
void check_grid_size(const Scene& scene, const Eigen::Vector3d& cells,
                     std::uint64_t available_bytes, const std::string& memory_source);

}  // namespace mgelastic::scene
