#include "mgelastic/scene/tet_setup.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <memory>
#include <numbers>
#include <sstream>

#include "mgelastic/core/error.hpp"
#include "mgelastic/core/timer.hpp"
#include "mgelastic/geometry/tet_mesh_boundary.hpp"
#include "mgelastic/geometry/tet_mesh_grid.hpp"
#include "mgelastic/geometry/tet_mesh_readers.hpp"
#include "mgelastic/scene/build_shape.hpp"
#include "mgelastic/scene/render_surface.hpp"
#include "mgelastic/scene/surface_selection.hpp"

namespace mgelastic::scene {
namespace {

Eigen::Vector3d transform_vec3(const nlohmann::json& v) {
  return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
}

std::string format_length(double value) {
  std::ostringstream s;
  s.precision(6);
  s << value;
  return s.str();
}

[[noreturn]] void fail(const Scene& scene, const std::string& pointer, const std::string& why) {
  throw Error(why, ErrorContext{.file = scene.file, .pointer = pointer});
}

// Same map as geometry::make_transformed: x -> translate + R(axis, degrees) (scale x). A proper
// rotation and a positive scale keep every tetrahedron positively oriented.
void apply_transform(const nlohmann::json& t, geometry::TetMesh& mesh) {
  const Eigen::Vector3d axis = transform_vec3(t["rotate_axis"]);
  const double degrees = t["rotate_degrees"];
  const Eigen::Matrix3d rotation =
      degrees != 0.0 && axis.norm() > 0.0
          ? Eigen::AngleAxisd(degrees * std::numbers::pi / 180.0, axis.normalized())
                .toRotationMatrix()
          : Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d linear = rotation * t["scale"].get<double>();
  const Eigen::RowVector3d translate = transform_vec3(t["translate"]).transpose();
  mesh.vertices = (mesh.vertices * linear.transpose()).rowwise() + translate;
}

geometry::TetMesh read_scene_tet_mesh(const Scene& scene, TetSetup& setup) {
  const std::filesystem::path path = scene.directory / scene.geometry["mesh"].get<std::string>();
  geometry::TetMesh mesh;
  try {
    mesh = geometry::read_tet_mesh(path);
  } catch (const Error& e) {
    // The reader names the mesh file and line; the prefix says which scene key asked for it.
    fail(scene, "/geometry/mesh", e.what());
  }
  if (scene.geometry.contains("transform")) apply_transform(scene.geometry["transform"], mesh);
  setup.mesh_source = path.string();
  return mesh;
}

// The stair-stepped boundary of the generated tets is a poor picture of a smooth body, so the
// frames show the surface the mesh was generated from, carried by the tets.
void embed_input_surface(const Scene& scene, const geometry::Shape& body,
                         const geometry::TetMesh& mesh, TetSetup& setup) {
  Timer timer;
  const geometry::TriangleMesh surface = rest_surface(scene, body, setup.cell_size);
  setup.surface_seconds = timer.seconds();
  timer.restart();
  setup.surface = tet::embed_surface(mesh, surface);
  setup.embed_seconds = timer.seconds();
}

geometry::TetMesh generate_tet_mesh(const Scene& scene, TetSetup& setup) {
  const geometry::ShapePtr body =
      build_shape(scene.geometry, scene.directory, scene.file, "/geometry");
  const geometry::BoundingBox box = body->bounding_box();
  if (box.isEmpty() || !box.min().allFinite() || !box.max().allFinite())
    fail(scene, "/geometry", "the body's bounding box is empty or not finite");
  const double h = box.sizes().maxCoeff() / scene.tet.resolution;
  // Grow the box to whole cubes around its center (the generator would add the excess on the
  // max side only), so a symmetric body gets a symmetric mesh. The slack matches the generator's.
  Eigen::Vector3d half;
  for (int a = 0; a < 3; ++a)
    half[a] = 0.5 * h * std::max(1.0, std::ceil(box.sizes()[a] / h - 1e-9));
  const Eigen::AlignedBox3d grid_box(box.center() - half, box.center() + half);
  geometry::TetMesh mesh;
  try {
    mesh = geometry::regular_tet_grid([&](const Eigen::Vector3d& p) { return body->contains(p); },
                                      grid_box, h, geometry::CubeSelection::CENTER)
               .mesh;
  } catch (const Error& e) {
    fail(scene, "/tet/resolution",
         std::string(e.reason()) + " (regular tet grid with cubes of edge " + format_length(h) +
             " m)");
  }
  setup.cell_size = h;
  setup.mesh_source = "regular tet grid";
  embed_input_surface(scene, *body, mesh, setup);
  return mesh;
}

tet::CorotatedSolverSettings solver_settings(const Scene& scene) {
  tet::CorotatedSolverSettings s;
  s.time_step = scene.time.dt / scene.time.substeps;
  s.integrator = scene.time.integrator == "newmark" ? tet::Integrator::NEWMARK
                                                    : tet::Integrator::IMPLICIT_EULER;
  if (scene.tet.rotation == "polar") {
    s.rotation_method = tet::RotationMethod::POLAR;
  } else if (scene.tet.rotation == "smoothed_polar") {
    s.rotation_method = tet::RotationMethod::POLAR_SMOOTHED;
  } else {
    s.rotation_method = tet::RotationMethod::ENERGY_MINIMIZATION;
  }
  s.rayleigh_alpha = scene.time.mass_damping;
  s.rayleigh_beta = scene.time.damping;
  s.gravity = scene.gravity;
  s.linear_solver = tet::LinearSolver::PCG;
  if (scene.tet.linear_solver == "cholesky") s.linear_solver = tet::LinearSolver::CHOLESKY;
  if (scene.tet.linear_solver == "multigrid") s.linear_solver = tet::LinearSolver::MULTIGRID;
  if (scene.tet.linear_solver == "mg_pcg") s.linear_solver = tet::LinearSolver::MG_PCG;
  s.vcycles = scene.tet.vcycles;
  s.multigrid.symmetric_sweeps = scene.tet.smoother == "symmetric_gauss_seidel";
  s.multigrid.patches = {scene.tet.feature_patches.max_valence, scene.tet.feature_patches.max_size};
  s.multigrid.adaptive_patches.rounds = scene.tet.feature_patches.adaptive_rounds;
  s.pcg.tolerance = scene.tet.tolerance;
  s.pcg.max_iterations = scene.tet.max_iterations;
  return s;
}

}  // namespace

bool is_tet_mesh_file(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".msh" || extension == ".mesh" || extension == ".node" || extension == ".ele";
}

namespace {

// Heterogeneous bodies: each material region overrides the tetrahedra whose centroid it holds.
void assign_region_materials(const Scene& scene, const geometry::TetMesh& mesh,
                             tet::ElementMaterials& materials) {
  for (std::size_t r = 0; r < scene.material_regions.size(); ++r) {
    const auto& m = scene.material_regions[r];
    const std::string at = "/material/regions/" + std::to_string(r) + "/region";
    const geometry::ShapePtr region = build_shape(m.region, scene.directory, scene.file, at);
    int selected = 0;
    for (int t = 0; t < mesh.tet_count(); ++t) {
      if (!region->contains(mesh.corners(t).rowwise().mean())) continue;
      materials.youngs_modulus[t] = m.youngs_modulus;
      materials.poisson_ratio[t] = m.poisson_ratio;
      materials.density[t] = m.density;
      ++selected;
    }
    if (selected == 0) fail(scene, at, "the region contains no tetrahedron of the body");
  }
}

}  // namespace

// Surface loads lumped to the vertices of the tet mesh's boundary faces: a third of each face's
// force to each corner.
Eigen::VectorXd tet_surface_forces(const Scene& scene, const geometry::TetMesh& mesh) {
  if (scene.tractions.empty() && scene.pressures.empty() && scene.forces.empty()) return {};
  const geometry::TetMeshBoundary boundary = geometry::tet_mesh_boundary(mesh);
  geometry::TriangleMesh faces;
  faces.triangles = boundary.triangles;
  faces.vertices.resize(static_cast<Eigen::Index>(boundary.mesh_vertex.size()), 3);
  for (std::size_t v = 0; v < boundary.mesh_vertex.size(); ++v)
    faces.vertices.row(static_cast<Eigen::Index>(v)) = mesh.vertices.row(boundary.mesh_vertex[v]);
  Eigen::VectorXd forces = Eigen::VectorXd::Zero(3 * mesh.vertex_count());
  for (const TriangleForce& f : surface_load_forces(scene, faces, "boundary face of the body"))
    for (int k = 0; k < 3; ++k)
      forces.segment<3>(3 * boundary.mesh_vertex[boundary.triangles(f.triangle, k)]) +=
          f.force / 3.0;
  return forces;
}

TetSetup build_tet_setup(const Scene& scene) {
  if (scene.time.quasistatic && scene.constraints.empty())
    fail(scene, "/constraints",
         "a quasistatic tet run needs at least one constraint (a free body has no equilibrium)");
  TetSetup setup;
  const bool tet_file = scene.geometry.contains("mesh") &&
                        is_tet_mesh_file(scene.geometry["mesh"].get<std::string>());
  setup.mesh = tet_file ? read_scene_tet_mesh(scene, setup) : generate_tet_mesh(scene, setup);
  const geometry::TetMesh& mesh = setup.mesh;
  if (tet_file) setup.surface = tet::boundary_as_embedded(mesh, geometry::tet_mesh_boundary(mesh));
  setup.materials = tet::ElementMaterials::uniform(
      mesh.tet_count(), {scene.youngs_modulus, scene.poisson_ratio, scene.density});
  assign_region_materials(scene, mesh, setup.materials);
  setup.surface_forces = tet_surface_forces(scene, mesh);

  // Dirichlet vertices: rest positions inside a region; the first region listed claims a vertex.
  setup.vertex_constraint.assign(mesh.vertex_count(), -1);
  std::vector<KeyframedMotion> motions;
  for (std::size_t c = 0; c < scene.constraints.size(); ++c) {
    const std::string at = "/constraints/" + std::to_string(c) + "/region";
    const geometry::ShapePtr region =
        build_shape(scene.constraints[c].region, scene.directory, scene.file, at);
    int selected = 0;
    for (int v = 0; v < mesh.vertex_count(); ++v) {
      if (!region->contains(mesh.vertices.row(v).transpose())) continue;
      ++selected;
      if (setup.vertex_constraint[v] < 0) setup.vertex_constraint[v] = static_cast<int>(c);
    }
    if (selected == 0)
      fail(scene, at,
           "the region contains no vertex of the tet mesh (" + std::to_string(mesh.vertex_count()) +
               " vertices" +
               (setup.cell_size > 0 ? ", cube edge " + format_length(setup.cell_size) + " m"
                                    : std::string()) +
               ")");
    motions.push_back(scene.constraints[c].motion);
    setup.animated = setup.animated || !scene.constraints[c].motion.is_fixed();
  }
  for (int v = 0; v < mesh.vertex_count(); ++v)
    if (setup.vertex_constraint[v] >= 0) setup.dirichlet_vertices.push_back(v);
  {
    std::vector<int> count(scene.constraints.size(), 0);
    setup.constraint_centroids.assign(scene.constraints.size(), Eigen::Vector3d::Zero());
    for (int v = 0; v < mesh.vertex_count(); ++v) {
      const int c = setup.vertex_constraint[v];
      if (c < 0) continue;
      setup.constraint_centroids[c] += mesh.vertices.row(v).transpose();
      ++count[c];
    }
    for (std::size_t c = 0; c < count.size(); ++c)
      if (count[c] > 0) setup.constraint_centroids[c] /= count[c];
  }

  // The callback owns what it reads, so it stays valid wherever the setup is moved or copied.
  const auto owner = std::make_shared<const std::vector<int>>(setup.vertex_constraint);
  const auto owned_motions = std::make_shared<const std::vector<KeyframedMotion>>(motions);
  setup.motion = [owner, owned_motions](int vertex, const Eigen::Vector3d& rest, double time) {
    const int c = (*owner)[vertex];
    return c < 0 ? rest : (*owned_motions)[c].position(rest, time);
  };
  setup.settings = solver_settings(scene);
  return setup;
}

}  // namespace mgelastic::scene
