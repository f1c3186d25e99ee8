#include "info_command.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <limits>

#include "mgelastic/geometry/surface_mesh_readers.hpp"
#include "mgelastic/geometry/tet_mesh_readers.hpp"
#include "mgelastic/geometry/triangle_mesh.hpp"

namespace mgelastic::app {
namespace {

const char* yes_no(bool b) {
  return b ? "yes" : "no";
}

void print_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi) {
  const Eigen::Vector3d size = hi - lo;
  std::printf("bounding box   [%g, %g, %g] - [%g, %g, %g]  (size %g x %g x %g)\n", lo.x(), lo.y(),
              lo.z(), hi.x(), hi.y(), hi.z(), size.x(), size.y(), size.z());
}

void surface_info(const std::filesystem::path& path) {
  const geometry::TriangleMesh mesh = geometry::read_surface_mesh(path);
  const geometry::MeshFacts f = geometry::mesh_facts(mesh);
  std::printf("surface mesh   %s\nvertices       %td\ntriangles      %td\n", path.c_str(),
              f.vertex_count, f.triangle_count);
  print_box(f.bounding_box.min(), f.bounding_box.max());
  std::printf(
      "closed         %s (%td boundary edges)\nmanifold       %s (%td non-manifold edges)\n"
      "oriented       %s (%td inconsistent edges)\ncomponents     %d\n"
      "degenerate     %td triangles\nvolume         %g%s\n",
      yes_no(f.closed), f.boundary_edges, yes_no(f.manifold), f.non_manifold_edges,
      yes_no(f.consistently_oriented), f.inconsistent_edges, f.components, f.degenerate_triangles,
      f.signed_volume,
      f.closed ? (f.signed_volume < 0 ? " (negative: inside-out)" : "")
               : " (not closed: approximate)");
}

void tet_info(const std::filesystem::path& path) {
  const geometry::TetMesh mesh = geometry::read_tet_mesh(path);
  double total = 0, smallest = std::numeric_limits<double>::infinity(), largest = 0;
  for (int t = 0; t < mesh.tet_count(); ++t) {
    const auto c = mesh.corners(t);
    const double v = geometry::signed_volume6(c.col(0), c.col(1), c.col(2), c.col(3)) / 6;
    total += v;
    smallest = std::min(smallest, v);
    largest = std::max(largest, v);
  }
  std::printf("tet mesh       %s\nvertices       %d\ntetrahedra     %d\n", path.c_str(),
              mesh.vertex_count(), mesh.tet_count());
  print_box(mesh.vertices.colwise().minCoeff(), mesh.vertices.colwise().maxCoeff());
  std::printf("volume         %g (tet volumes %g - %g)\n", total, smallest, largest);
}

void info(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (ext == ".node" || ext == ".ele" || ext == ".msh" || ext == ".mesh")
    tet_info(path);
  else
    surface_info(path);
}

}  // namespace

void register_info_command(CLI::App& app) {
  static std::string path;
  CLI::App* cmd = app.add_subcommand("info", "Print facts about a surface or tetrahedral mesh");
  cmd->add_option("file", path, "Mesh file (.obj .stl .ply .off .node/.ele .msh .mesh)")
      ->required();
  cmd->callback([] { info(path); });
}

}  // namespace mgelastic::app
