#pragma once
// Composite coarsening: one coarse cube, one set of coarse DOFs per connected piece of the body in
// it (the treatment of disconnected material in a coarse cell of embedded/composite-grid
// multigrid, cf. Zhu et al. 2010's per-cell components). Two thin features inside one coarse
// cube (claw tips, fingertips) that meet only outside it get separate copies of the cube's
// corners, so the coarse space can move them independently.
//
// Input (level l -> level l+1): the level's "cells" (level 0: the tetrahedra; coarser: the
// composite cubes of level l), each with its level-l DOFs and the level-(l+1) cubes it overlaps.
// 1. Components: incidences (cell, cube) of one cube are joined when their cells share a DOF.
// 2. Copies: each component gets its own copy of its cube's 8 corners; copies of the same grid
//    point are merged when their components meet at a common DOF (the body is connected there).
// 3. P: DOF v takes the barycentric weights of the Kuhn tetrahedron (Freudenthal split: the
//    cube's six tets around its main diagonal, conforming across cubes) of its cube containing
//    it, on the copies of v's component there. Copies no row weighs are dropped.
// R = P^T; P is still barycentric within every (copied) coarse tet, so it reproduces linear
// fields on every connected piece.
#include <Eigen/Core>
#include <functional>
#include <vector>

#include "mgelastic/tet/tet_hierarchy.hpp"

namespace mgelastic::tet {

// Cells of level l: DOFs and overlapped level-(l+1) cubes (integer cube indices), both CSR.
struct LevelCells {
  std::vector<int> dof_offsets{0}, dofs;
  std::vector<int> cube_offsets{0};
  std::vector<Eigen::Vector3i> cubes;
  int cell_count() const { return static_cast<int>(dof_offsets.size()) - 1; }
};

struct CompositeLevel {
  Prolongation prolongation;            // level l+1 -> level l
  std::vector<Eigen::Vector3i> points;  // grid point (level-(l+1) index) of each coarse DOF
  LevelCells cells;  // the components as cells of level l+1 (cubes left empty for the caller)
  std::vector<Eigen::Vector3i> cell_cubes;  // level-(l+1) cube of each of those cells
};

// local(v, cube): v's coordinates in the cube, in cube units ([0,1]^3 inside; clamped).
// home(v): the cube v is assigned to when it lies in several (used when one of v's cells
// overlaps it; otherwise the cube nearest to v among those of v's cells).
using LocalCoordinates = std::function<Eigen::Vector3d(int, const Eigen::Vector3i&)>;
using HomeCube = std::function<Eigen::Vector3i(int)>;

CompositeLevel composite_coarsening(const LevelCells& cells, int dof_count,
                                    const std::vector<char>& constrained,
                                    const LocalCoordinates& local, const HomeCube& home);

}  // namespace mgelastic::tet
