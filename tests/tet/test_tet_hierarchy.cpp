// Coarse regular tet grids, barycentric prolongation and the Dirichlet rule (tet_hierarchy.hpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "mgelastic/core/error.hpp"
#include "mgelastic/tet/tet_hierarchy.hpp"
#include "tet/tet_test_support.hpp"

namespace mgelastic::tet {
namespace {

// Barycentric weights are round-off accurate: a few ulps of O(1) sums.
constexpr double kWeightRoundoff = 1e-12;

geometry::TetMesh jittered_bar(double h, unsigned seed) {
  geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.25, 0.25), h);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.2 * h, 0.2 * h);
  for (int v = 0; v < mesh.vertex_count(); ++v)
    for (int a = 0; a < 3; ++a) {
      const double x = mesh.vertices(v, a);
      const double extent = a == 0 ? 1.0 : 0.25;
      if (x > 1e-9 && x < extent - 1e-9) mesh.vertices(v, a) += jitter(rng);  // keep the box
    }
  return mesh;
}

TEST(TetHierarchy, LevelsDoubleCubeSizeAndStopAtTheCoarsestLimit) {
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.25, 0.25), 1.0 / 32);
  TetHierarchySettings settings;
  settings.max_coarsest_vertices = 100;
  const TetHierarchy hierarchy(mesh, {}, settings);
  ASSERT_GE(hierarchy.level_count(), 3);
  EXPECT_NEAR(hierarchy.cell_size(1), settings.first_cell_factor * mean_edge_length(mesh), 1e-12);
  for (int l = 2; l < hierarchy.level_count(); ++l)
    EXPECT_DOUBLE_EQ(hierarchy.cell_size(l), 2.0 * hierarchy.cell_size(l - 1));
  const int last = hierarchy.level_count() - 1;
  EXPECT_LE(hierarchy.vertex_count(last), 100);
  EXPECT_GT(hierarchy.vertex_count(last - 1), 100);
}

// Restriction by the stored transpose (parallel gather) and by the serial scatter both equal
// P^T r.
TEST(TetHierarchy, RestrictionGatherEqualsTheTransposedProlongation) {
  const geometry::TetMesh mesh = jittered_bar(1.0 / 24, 8);
  const TetHierarchy hierarchy(mesh, {}, {});
  Prolongation scatter = hierarchy.prolongation(0);
  ASSERT_FALSE(scatter.transpose_offsets.empty());
  scatter.transpose_offsets.clear();
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> uniform(-1, 1);
  Eigen::VectorXd r(3 * mesh.vertex_count()), gathered, scattered;
  for (int i = 0; i < r.size(); ++i) r[i] = uniform(rng);
  hierarchy.prolongation(0).restrict_to(r, gathered);
  scatter.restrict_to(r, scattered);
  const Eigen::VectorXd reference = hierarchy.prolongation(0).to_sparse().transpose() * r;
  EXPECT_LE((gathered - reference).norm(), 1e-13 * reference.norm());
  EXPECT_LE((scattered - reference).norm(), 1e-13 * reference.norm());
}

TEST(TetHierarchy, ProlongationIsAPartitionOfUnityReproducingLinearFields) {
  const geometry::TetMesh mesh = jittered_bar(1.0 / 24, 7);
  TetHierarchySettings settings;
  settings.max_coarsest_vertices = 50;
  const TetHierarchy hierarchy(mesh, {}, settings);
  ASSERT_GE(hierarchy.level_count(), 3);
  for (int l = 0; l + 1 < hierarchy.level_count(); ++l) {
    const Prolongation& p = hierarchy.prolongation(l);
    const Eigen::MatrixX3d& fine = hierarchy.positions(l);
    const Eigen::MatrixX3d& coarse = hierarchy.positions(l + 1);
    // Prolonging the coarse positions (a linear field) gives the fine positions.
    Eigen::VectorXd coarse_field(3 * coarse.rows()),
        fine_field = Eigen::VectorXd::Zero(3 * fine.rows());
    for (int v = 0; v < coarse.rows(); ++v)
      coarse_field.segment<3>(3 * v) = coarse.row(v).transpose();
    p.prolong_add(coarse_field, fine_field);
    for (int v = 0; v < p.fine_vertex_count(); ++v) {
      double sum = 0.0;
      for (int s = 0; s < 4; ++s) {
        sum += p.weights[v][s];
        // Covering grids: every vertex lies inside (or on) its coarse tetrahedron.
        EXPECT_GE(p.weights[v][s], -kWeightRoundoff) << "level " << l << " vertex " << v;
      }
      EXPECT_NEAR(sum, 1.0, kWeightRoundoff);
      EXPECT_LE((fine_field.segment<3>(3 * v) - fine.row(v).transpose()).norm(), kWeightRoundoff);
    }
  }
}

TEST(TetHierarchy, CoarseVertexIsConstrainedWhenItsSupportIsAllDirichlet) {
  const geometry::TetMesh mesh = jittered_bar(1.0 / 24, 11);
  std::vector<char> fixed(mesh.vertex_count(), 0);
  for (int v = 0; v < mesh.vertex_count(); ++v) fixed[v] = mesh.vertices(v, 0) < 0.15;
  TetHierarchySettings settings;
  settings.max_coarsest_vertices = 50;
  const TetHierarchy free_hierarchy(mesh, {}, settings);
  const TetHierarchy hierarchy(mesh, fixed, settings);
  ASSERT_EQ(hierarchy.level_count(), free_hierarchy.level_count());
  int constrained_coarse = 0;
  for (int l = 0; l + 1 < hierarchy.level_count(); ++l) {
    const Prolongation& p = hierarchy.prolongation(l);
    const Prolongation& unconstrained = free_hierarchy.prolongation(l);
    // Support of each coarse vertex among the free vertices of level l (weights without rule).
    std::vector<int> free_support(p.coarse_vertex_count, 0);
    for (int v = 0; v < p.fine_vertex_count(); ++v)
      for (int s = 0; s < 4; ++s) {
        if (hierarchy.constrained(l)[v] != 0) {
          EXPECT_EQ(p.weights[v][s], 0.0) << "Dirichlet row of P must be zero";
        } else {
          EXPECT_EQ(p.weights[v][s], unconstrained.weights[v][s]);
          if (unconstrained.weights[v][s] != 0.0) ++free_support[unconstrained.vertices[v][s]];
        }
      }
    for (int a = 0; a < p.coarse_vertex_count; ++a) {
      EXPECT_EQ(hierarchy.constrained(l + 1)[a] != 0, free_support[a] == 0) << "level " << l + 1;
      constrained_coarse += hierarchy.constrained(l + 1)[a] != 0;
    }
  }
  EXPECT_GT(constrained_coarse, 0);
}

// Two slabs separated by a gap narrower than a coarse cube: grid vertices in the gap see fine
// vertices of both slabs, and are split into one DOF per slab, so the coarse space does not tie
// the slabs together. Every coarse DOF's support lies in one slab; P stays a partition of unity.
TEST(TetHierarchy, CoarseVerticesStraddlingAGapAreSplitPerPart) {
  const double h = 0.25 / 4;
  const geometry::TetMesh slab = test::box_mesh(Eigen::Vector3d(1.0, 0.25, 0.25), h);
  geometry::TetMesh mesh;
  const double offset = 0.25 + 0.05;  // gap 0.05, coarse cube ~2.5 h = 0.16
  mesh.vertices.resize(2 * slab.vertex_count(), 3);
  mesh.vertices.topRows(slab.vertex_count()) = slab.vertices;
  mesh.vertices.bottomRows(slab.vertex_count()) = slab.vertices;
  mesh.vertices.bottomRows(slab.vertex_count()).col(1).array() += offset;
  mesh.tets.resize(2 * slab.tet_count(), 4);
  mesh.tets.topRows(slab.tet_count()) = slab.tets;
  mesh.tets.bottomRows(slab.tet_count()) = slab.tets.array() + slab.vertex_count();
  TetHierarchySettings settings;
  settings.max_coarsest_vertices = 100;
  const TetHierarchy hierarchy(mesh, {}, settings);
  ASSERT_GE(hierarchy.level_count(), 2);
  EXPECT_GT(hierarchy.vertex_count(1), hierarchy.grid_point_count(1));
  const Prolongation& p = hierarchy.prolongation(0);
  std::vector<int> side(p.coarse_vertex_count, -1);  // slab of the support, -1 = none yet
  for (int v = 0; v < p.fine_vertex_count(); ++v) {
    const int slab_of_v = v < slab.vertex_count() ? 0 : 1;
    double sum = 0.0;
    for (int s = 0; s < 4; ++s) {
      sum += p.weights[v][s];
      if (p.weights[v][s] == 0.0) continue;
      int& owner = side[p.vertices[v][s]];
      if (owner < 0) owner = slab_of_v;
      EXPECT_EQ(owner, slab_of_v) << "coarse DOF " << p.vertices[v][s] << " spans both slabs";
    }
    EXPECT_NEAR(sum, 1.0, kWeightRoundoff);
  }
}

// A tuning fork: two prongs one fine cube apart, joined only by the base at x < 0.125. Every
// level-1 cube between the prongs overlaps both; per-cube components give each prong its own
// copies of the cube's corners, so along the prongs no coarse DOF weighs both (the coarse space
// can move the tips against each other). Near the base they share DOFs. No coarse DOF of any
// level is left without weight (copies no fine vertex weighs are dropped).
TEST(TetHierarchy, ProngsInsideOneCoarseCubeGetSeparateCoarseDofs) {
  const double h = 1.0 / 32;
  const auto fork = [&](const Eigen::Vector3d& p) {
    const bool base = p[0] < 0.125;
    const bool prong = p[1] < 4 * h || p[1] > 5 * h;
    return base || prong;
  };
  const geometry::TetMesh mesh =
      geometry::regular_tet_grid(
          fork, Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 9 * h, 4 * h)), h)
          .mesh;
  TetHierarchySettings settings;
  settings.max_coarsest_vertices = 50;
  const TetHierarchy hierarchy(mesh, {}, settings);
  ASSERT_GE(hierarchy.level_count(), 3);
  EXPECT_GT(hierarchy.vertex_count(1), hierarchy.grid_point_count(1));
  const Prolongation& p = hierarchy.prolongation(0);
  std::vector<int> prong(p.coarse_vertex_count, -1);  // prong weighing the DOF beyond the base
  for (int v = 0; v < p.fine_vertex_count(); ++v) {
    if (mesh.vertices(v, 0) < 0.25) continue;
    const int side = mesh.vertices(v, 1) < 4.5 * h ? 0 : 1;
    for (int s = 0; s < 4; ++s) {
      if (p.weights[v][s] == 0.0) continue;
      int& owner = prong[p.vertices[v][s]];
      if (owner < 0) owner = side;
      EXPECT_EQ(owner, side) << "coarse DOF " << p.vertices[v][s] << " weighs both prongs";
    }
  }
  for (int l = 0; l + 1 < hierarchy.level_count(); ++l) {
    const Prolongation& pl = hierarchy.prolongation(l);
    std::vector<char> weighed(pl.coarse_vertex_count, 0);
    for (int v = 0; v < pl.fine_vertex_count(); ++v)
      for (int s = 0; s < 4; ++s)
        if (pl.weights[v][s] != 0.0) weighed[pl.vertices[v][s]] = 1;
    EXPECT_EQ(std::count(weighed.begin(), weighed.end(), 0), 0) << "level " << l + 1;
  }
}

TEST(TetHierarchy, RejectsAConstraintVectorOfTheWrongSize) {
  const geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.25, 0.25), 0.125);
  EXPECT_THROW(TetHierarchy(mesh, std::vector<char>(3, 0)), Error);
}

}  // namespace
}  // namespace mgelastic::tet
