#pragma once
// From a scene to the tet engine's problem (Georgii & Westermann 2008, Sec. 2): a tetrahedral
// mesh, per-element materials, the Dirichlet vertices with their prescribed motion, and the
// solver settings.
//
// Mesh: a `geometry` that is {"mesh": file} with a tet-mesh extension (.msh, .mesh, .node, .ele)
// is read as it is (its `transform`, if any, applied to the vertices); any other geometry
// (primitives, CSG, a closed surface mesh) is meshed by a regular tet grid: cubes of edge
// longest bounding-box extent / tet.resolution whose centers are inside, six Kuhn tetrahedra per
// cube. The grid is centered on the bounding box so the mesh is as symmetric as the body.
// Constraints: every vertex whose rest position is inside a constraint region is a Dirichlet
// vertex and follows that region's rigid keyframed motion (the first region listed wins where
// regions overlap).
// Surface: the frames show the body's input surface embedded in the tets (tet/embedded_surface.hpp)
// when the mesh is generated from it: the triangles a surface-mesh geometry brings, the
// marching-cubes render surface (render_surface.hpp, spacing output.surface.spacing * cube edge)
// of primitives and CSG. A mesh read from a tet-mesh file shows its own boundary faces.
// Settings: one solver step is time.dt / time.substeps; time.mass_damping and time.damping are
// the Rayleigh coefficients alpha (of M) and beta (of K~).
#include <string>
#include <vector>

#include "mgelastic/geometry/tet_mesh.hpp"
#include "mgelastic/scene/scene.hpp"
#include "mgelastic/tet/corotated_solver.hpp"
#include "mgelastic/tet/element_materials.hpp"
#include "mgelastic/tet/embedded_surface.hpp"

namespace mgelastic::scene {

struct TetSetup {
  geometry::TetMesh mesh;
  tet::ElementMaterials materials;
  std::vector<int> dirichlet_vertices;  // sorted, each once
  // Per mesh vertex: index into Scene::constraints of the region that holds it, or -1 (free).
  std::vector<int> vertex_constraint;
  // Per constraint: centroid of its vertices' rest positions (the moment point of its reaction).
  std::vector<Eigen::Vector3d> constraint_centroids;
  tet::DirichletMotion motion;  // position(rest, time) of the vertex's region
  tet::CorotatedSolverSettings settings;
  // Surface loads (tractions, pressures, total forces; surface_selection.hpp) lumped to vertices
  // (3N, N): a third of each selected boundary face's force to each corner; empty when there are
  // none.
  Eigen::VectorXd surface_forces;
  tet::EmbeddedSurface surface;  // what the frames show as the deformed surface
  // Seconds to build the input surface (marching cubes or reading the file) and to embed it.
  double surface_seconds = 0.0, embed_seconds = 0.0;
  double cell_size = 0.0;   // edge of the generating grid's cubes; 0 for a mesh read from a file
  std::string mesh_source;  // the tet-mesh file, or "regular tet grid"
  // True when some region moves (keyframed), i.e. frames differ even for a quasistatic run.
  bool animated = false;
};

// Extensions read as tetrahedral meshes (geometry::read_tet_mesh); case-insensitive.
bool is_tet_mesh_file(const std::filesystem::path& path);

// Throws Error as `file: /json/pointer: reason`: unreadable or invalid tet-mesh files (the reason
// carries the mesh reader's own message), a region that selects no vertex, a traction region
// holding no boundary face, a quasistatic scene without constraints.
TetSetup build_tet_setup(const Scene& scene);

// TetSetup::surface_forces of the scene's loads on `mesh` (also when a Simulation's loads change
// between steps); empty when the scene has no surface loads.
Eigen::VectorXd tet_surface_forces(const Scene& scene, const geometry::TetMesh& mesh);

}  // namespace mgelastic::scene
