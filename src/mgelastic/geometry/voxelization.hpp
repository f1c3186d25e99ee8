#pragma once
// Voxelization of a solid (Sec. 5.1): a cell is occupied when it OVERLAPS the body. With the
// signed distance d (a lower bound of the true distance for CSG): the cell overlaps when
// d(center) <= 0; it cannot overlap when d(center) > half the cell diagonal; in between, it
// overlaps when d <= 0 at one of 4^3 sample points strictly inside the cell (cells that only
// touch the body along a face, edge or corner do not overlap it).
// Optional padding dilates the occupied set by whole layers (26-neighborhood, Sec. 9.2), and a
// margin of empty cells surrounds everything. Repairs for the staggered discretization
// (rigid_blocks.hpp): diagonal contacts bridged, every cell in a full 2x2x2 block, the blocks of
// each piece chained rigidly (no hinges), then, after padding, features thinner than
// min_thickness cells thickened.
#include <cstdint>
#include <vector>

#include "mgelastic/geometry/shape.hpp"

namespace mgelastic::geometry {

struct VoxelGrid {
  Point origin = Point::Zero();  // min corner of cell (0, 0, 0)
  double cell_size = 1;
  Eigen::Vector3i dims = Eigen::Vector3i::Zero();
  std::vector<std::uint8_t> occupied;  // x fastest
  int bridged_cells = 0;               // cells added by bridge_diagonal_contacts
  int thickened_cells = 0;             // cells added by thicken_thin_features
  int connected_cells = 0;             // cells added by connect_thick_blocks
  std::size_t cell_count() const {
    return static_cast<std::size_t>(dims[0]) * static_cast<std::size_t>(dims[1]) *
           static_cast<std::size_t>(dims[2]);
  }
  std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(k) * static_cast<std::size_t>(dims[1]) +
            static_cast<std::size_t>(j)) *
               static_cast<std::size_t>(dims[0]) +
           static_cast<std::size_t>(i);
  }
  Point cell_center(int i, int j, int k) const {
    return origin + cell_size * (Eigen::Vector3d(i, j, k).array() + 0.5).matrix();
  }
};

struct VoxelizeOptions {
  double cell_size = 0;  // used when > 0
  int resolution = 64;   // otherwise: cells along the longest bounding-box axis
  int padding = 0;
  int margin = 1;
  // After padding, every occupied cell is made part of a full block of min_thickness^3 cells
  // (thin features thickened; no-op on bodies at least that thick). 3 makes the first coarse
  // level free of one-cell sheets and hinges: a thin feature two cells thick coarsens into a
  // sheet one coarse cell thick whose coarse correction is far off (docs/embedded-geometry.md).
  int min_thickness = 3;
};

// The lattice voxelize() lays over `box`: cell size, origin and cells per axis (margin and
// padding included), in double because the counts are checked against limits before any cast.
struct VoxelLattice {
  double cell_size = 0;
  Point origin = Point::Zero();
  Eigen::Vector3d cells = Eigen::Vector3d::Zero();
};
VoxelLattice voxel_lattice(const BoundingBox& box, const VoxelizeOptions& options);

VoxelGrid voxelize(const Shape& body, const VoxelizeOptions& options);

// Staggered unknowns couple cells through shared faces only, so parts of a thin body that touch
// along an edge or a corner alone would move independently (and float, making the system
// singular). This occupies, for every such contact, the cells of one face path between the two
// cells, until the occupied set is face-connected wherever it was 26-connected. Returns the number
// of cells added. voxelize() calls it before padding.
int bridge_diagonal_contacts(VoxelGrid& grid);

// A part one cell thick carries no shear across it on the staggered lattice (its shear stresses
// all sit on traction-free edges), so parts attached through it rotate freely. This makes every
// occupied cell part of a fully occupied 2x2x2 block, filling the block that already holds the
// most occupied cells (geometry/rigid_blocks.hpp). Returns the number of cells added. voxelize()
// calls it after bridging.
int thicken_thin_features(VoxelGrid& grid);

// Hinges: two thick parts joined through a single cell face or a strip one cell wide rotate
// freely about it (the shear stresses on the edges along the hinge are traction-free). A fully
// occupied 2x2x2 block moves rigidly when unstrained, and so does every union of full blocks
// chained by shared 2x2x1 halves. This fills, in each face-connected piece, the fewest cells
// (Dijkstra over block positions) that chain all its full blocks into one such union. Returns
// the number of cells added. voxelize() calls it after thickening.
int connect_thick_blocks(VoxelGrid& grid);

// Cells of `grid` that overlap `region` (same rule as voxelize).
std::vector<std::uint8_t> overlapping_cells(const VoxelGrid& grid, const Shape& region);

}  // namespace mgelastic::geometry
