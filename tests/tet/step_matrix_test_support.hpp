#pragma once
// Step matrices for the smoother tests: M + h^2 K of a mesh at rest, h = 1/60 s, stiff enough
// (E = 1e7, rho = 1000) that h^2 K dominates M, as in the multigrid's step systems.
#include "mgelastic/geometry/tet_mesh.hpp"
#include "mgelastic/tet/brc_matrix.hpp"
#include "mgelastic/tet/corotated_assembly.hpp"

namespace mgelastic::test {

inline tet::BlockRowMatrix<double> stiff_step_matrix(const geometry::TetMesh& mesh) {
  using namespace tet;
  const TetBody body(mesh, ElementMaterials::uniform(mesh.tet_count(), {1e7, 0.3, 1000.0}));
  RotationField rotations(body, RotationMethod::ENERGY_MINIMIZATION);
  CorotatedAssembler assembler(body);
  rotations.update(body.rest_positions() * 1.0);
  assembler.assemble(rotations);
  BlockRowMatrix<double> a = assembler.stiffness();
  for (int k = 0; k < a.block_count(); ++k) a.block(k) *= 1.0 / 3600.0;
  for (int i = 0; i < a.block_rows(); ++i)
    a.block(a.diagonal_index(i)).diagonal().array() += body.vertex_mass()[i];
  return a;
}

}  // namespace mgelastic::test
