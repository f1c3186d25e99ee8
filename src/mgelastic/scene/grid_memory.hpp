#pragma once
// Size limits of a grid scene, checked before anything of the lattice's size is allocated: the
// lattice of the body's bounding box (geometry::voxel_lattice) must fit the level arrays' 32-bit
// global indices ((Dim + 1) * padded cells < 2^32, level.hpp) and the estimated memory must fit
// the memory available on this machine (core/system_memory.hpp).
//
// Estimate per point of the padded lattice (the level arrays are dense over the box): the peak
// resident memory of `mgelastic run` on a box, measured per precision, plus FGMRES's Krylov
// vectors where the run is accelerated, times a margin. The peak is several times the solver's
// working set (Multigrid::bytes(), 50 / 25 / 43 bytes per unknown at 128^3 in float / single /
// double): the problem and voxelization arrays, the hierarchy build's temporaries and the Krylov
// vectors come on top. Measured 2026-12-04 (`/usr/bin/time -v mgelastic run`, 1 thread, a 1 m
// cube at grid.resolution 128, 132^3 padded points, 2 V-cycles, obj output): single 865 MB,
// float 974 MB (1486 with accelerate), double 934 MB (1366 with accelerate). Per point the peak
// falls with size (at 192 without output: single 315 instead of 385, float accelerated 633
// instead of 662) and grows on small lattices whose coarsest level is large (96: double
// accelerated 770 instead of 608, 3 levels), where the margin still covers it (805).
// The co-rotated model holds far more (its rotated rows and box-smoother blocks): a 96^3 cube
// had reached 8.6 GB (8600 bytes per point) when it was stopped in its first frame, a 32^3
// one 1.1 GB (24000 per point, 2 levels, a large coarsest factor); 8600 is a lower bound
// there, kept for lattices large enough to be refused.
#include <cstdint>

#include <Eigen/Core>

#include "mgelastic/scene/scene.hpp"

namespace mgelastic::scene {

// Peak bytes per padded lattice point of a plain-cycle run by solver.precision, measured as above.
inline constexpr double kGridPeakBytesPerPointSingle = 385.0;
inline constexpr double kGridPeakBytesPerPointFloat = 434.0;
inline constexpr double kGridPeakBytesPerPointDouble = 416.0;
inline constexpr double kGridPeakBytesPerPointCorotated = 8600.0;
// What solver.accelerate (FGMRES(10)'s vectors, krylov_workspace.hpp) adds once a restart is
// full: the 1 m cube at 128 in float with 12 accelerated cycles, 1 thread, peaked at 1582 MB
// against 599 MB with plain cycles (2026-12-07, 132^3 points; with the earlier double basis
// 1920 MB; the first estimate, 228, came from a 2-cycle run whose restart held 3 vectors).
inline constexpr double kGridFgmresBytesPerPoint = 430.0;
// solver.local_corrections: each box (grid/local_corrections.hpp) holds at most
// kLocalCorrectionMaxCells body cells and at most kLocalCorrectionBodyShare of the body, and its
// sparse Cholesky factor dominates its memory: ~2 KB per unknown for the armadillo's two boxes
// at 256 cells (158 MB for 25k + 55k unknowns), 2990 bytes for the largest box, a solid block
// of 16128 cells (57k unknowns, 171 MB; test GridMemory.LargestLocalCorrectionBoxFitsItsEstimate,
// 2026-12-07). Bound: 4 KB per unknown at (Dim + 1) unknowns per cell.
inline constexpr double kGridLocalCorrectionBytesPerUnknown = 4000.0;
// Embedded bodies' band rows, other thread counts and allocator slack.
inline constexpr double kGridPeakMargin = 1.25;

// Estimated peak memory of the grid scene `scene` whose voxel lattice has `cells` per axis,
// bytes (its material.model, solver.precision, solver.accelerate and solver.local_corrections:
// every box placed at its largest).
double estimated_grid_bytes(const Scene& scene, const Eigen::Vector3d& cells);

// Throws Error (pointer /grid/resolution, or /grid/cell_size when the scene sets it) when the
// lattice exceeds the index range or the estimate exceeds `available_bytes` (0 = unknown: only
// the index range is checked); `memory_source` names where that number came from.
void check_grid_size(const Scene& scene, const Eigen::Vector3d& cells,
                     std::uint64_t available_bytes, const std::string& memory_source);

}  // namespace mgelastic::scene
