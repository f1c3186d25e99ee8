#pragma once
// Surface loads of a scene (loads.pressures, loads.forces) as per-triangle forces on a triangle
// surface: the grid engine's embedded rest surface, the tet engine's boundary faces.
//
// Selection: a triangle is loaded when its centroid lies in the load's region and, when the load
// gives a `normal` n (non-zero), its outward unit normal N satisfies N . n >= cos(tolerance), so
// "the face x = 1" is a box around that face with normal [1, 0, 0]: side faces inside the box are
// left out.
// Pressure p (Pa) acts along the inward normal: force -p A N per triangle of area A. The normal is
// that of the rest (reference) surface, and the force is constant during a run: co-rotated and
// large-deformation runs do not follow the deformed normal (a dead load).
// Total force F (N): triangle t gets F A_t / sum A over the selected triangles, so the selected
// surface carries exactly F.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "mgelastic/geometry/triangle_mesh.hpp"
#include "mgelastic/scene/scene.hpp"

namespace mgelastic::scene {

// Indices of the triangles of `surface` selected by `selection`.
// Degenerate (zero-area) triangles are never selected. Throws Error naming `pointer`/region when
// the region holds no triangle ("the region contains no <surface_name>"), `pointer`/normal when
// none of those has the requested normal.
std::vector<int> select_surface(const geometry::TriangleMesh& surface,
                                const Scene::SurfaceSelection& selection, const Scene& scene,
                                const std::string& pointer, const std::string& surface_name);

// One triangle's share of a surface load, applied at its centroid.
struct TriangleForce {
  int triangle = 0;
  Eigen::Vector3d centroid, force, normal;  // normal: outward unit normal of the triangle
};

// Per-triangle forces of every loads.tractions, loads.pressures and loads.forces entry of the
// scene on the given surface, in that order. Throws Error naming the entry's JSON pointer when
// its region selects no triangle (see select_surface).
std::vector<TriangleForce> surface_load_forces(const Scene& scene,
                                               const geometry::TriangleMesh& surface,
                                               const std::string& surface_name);

}  // namespace mgelastic::scene
