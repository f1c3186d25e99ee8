#include "mgelastic/sim/output_observer.hpp"

#include <algorithm>
#include <cstdio>

#include "mgelastic/core/timer.hpp"
#include "mgelastic/geometry/tet_mesh_vtu.hpp"
#include "mgelastic/io/surface_mesh_writers.hpp"
#include "mgelastic/sim/probes.hpp"
#include "mgelastic/sim/simulation.hpp"

namespace mgelastic::sim {
namespace {

bool wants(const scene::Scene& s, const std::string& format) {
  return std::find(s.formats.begin(), s.formats.end(), format) != s.formats.end();
}

bool wants_surface(const scene::Scene& s) {
  return wants(s, "vtk") || wants(s, "obj") || wants(s, "ply");
}

// The scene's `output.vtk_encoding`.
io::VtkEncoding vtk_encoding(const scene::Scene& s) {
  return s.vtk_encoding == "ascii" ? io::VtkEncoding::ASCII : io::VtkEncoding::BINARY;
}

// `stem_NNNN.ext`.
std::string frame_name(const std::string& stem, int frame, const std::string& extension) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "_%04d.", frame);
  return stem + buffer + extension;
}

io::ImageData grid_image(const GridStepper& grid) {
  io::ImageData image;
  image.cells = grid.cells();
  image.spacing = grid.spacing();
  image.origin = grid.origin();
  // Fields of a single-precision solve are stored as Float32: half the bytes to write.
  const auto real = grid.single_precision() ? io::VtkScalar::FLOAT32 : io::VtkScalar::FLOAT64;
  // The solver's fields are borrowed, not copied (hundreds of MB at 256^3); the image is written
  // at once, while `grid` holds them.
  image.point_data.push_back({"displacement", 3, {}, real, grid.displacement().values});
  const auto& types = grid.cell_types();
  image.cell_data = {
      {"cell_type", 1, std::vector<double>(types.begin(), types.end()), io::VtkScalar::UINT8},
      {"pressure", 1, {}, real, grid.pressure()},
      {"von_mises", 1, {}, real, grid.von_mises()}};
  return image;
}

// The surface files of both engines; `rest` gives the .vtp's displacement field.
void write_surface(const scene::Scene& s, const std::filesystem::path& dir, int frame, double time,
                   const io::SurfaceVertices& deformed, const io::SurfaceVertices& rest,
                   const io::SurfaceTriangles& triangles, std::vector<io::SeriesEntry>& entries) {
  if (wants(s, "vtk")) {
    const std::string name = frame_name("surface", frame, "vtp");
    io::DataArray displacement{"displacement", 3, {}};
    const io::SurfaceVertices d = deformed - rest;
    displacement.values.assign(d.data(), d.data() + d.size());
    io::write_vtp(dir / name, deformed, triangles, {displacement}, vtk_encoding(s));
    entries.push_back({time, name, 1});
  }
  if (wants(s, "obj"))
    io::write_obj(dir / frame_name("surface", frame, "obj"), deformed, triangles);
  if (wants(s, "ply"))
    io::write_ply(dir / frame_name("surface", frame, "ply"), deformed, triangles, true);
}

}  // namespace

std::vector<io::SeriesEntry> write_frame(const Simulation& simulation,
                                         const std::filesystem::path& dir, int frame, double time) {
  const scene::Scene& s = simulation.scene();
  std::vector<io::SeriesEntry> entries;
  if (const GridStepper* grid = simulation.grid()) {
    if (wants(s, "vtk")) {
      const std::string name = frame_name("grid", frame, "vti");
      io::write_vti(dir / name, grid_image(*grid), vtk_encoding(s));
      entries.push_back({time, name, 0});
    }
    // The deformed surface is interpolated only when a format writes it (it costs as much as a
    // V-cycle on large surfaces).
    if (wants_surface(s))
      write_surface(s, dir, frame, time, grid->surface_vertices(), grid->rest_surface().vertices,
                    grid->rest_surface().triangles, entries);
    return entries;
  }
  const TetStepper& tet = *simulation.tet();
  if (wants(s, "vtk")) {
    const Eigen::MatrixX3d positions = tet.solver().positions_matrix();
    const Eigen::MatrixX3d displacement = positions - tet.setup().mesh.vertices;
    geometry::TetMesh deformed = tet.setup().mesh;
    deformed.vertices = positions;
    const std::string name = frame_name("tet", frame, "vtu");
    const geometry::VtuField point_fields[] = {{"displacement", displacement}};
    const geometry::VtuField cell_fields[] = {{"von_mises", tet.von_mises()}};
    geometry::write_vtu(dir / name, deformed, point_fields, cell_fields, vtk_encoding(s));
    entries.push_back({time, name, 0});
  }
  if (wants_surface(s))
    write_surface(s, dir, frame, time, tet.surface_vertices(), tet.rest_surface(), tet.triangles(),
                  entries);
  return entries;
}

OutputObserver::OutputObserver(const scene::Scene& scene, std::filesystem::path dir,
                               RunCheckpoints& checkpoints)
    : m_scene(&scene), m_dir(std::move(dir)), m_checkpoints(&checkpoints) {
  if (const io::Checkpoint* resume = checkpoints.resume_from()) m_series = series_of(*resume);
}

void OutputObserver::started(const Simulation& simulation) {
  check_probes(simulation);  // before any file is written or any frame is computed
  std::error_code ec;
  std::filesystem::create_directories(m_dir, ec);
  if (ec)
    throw Error("cannot create the output directory: " + ec.message(),
                ErrorContext{.file = m_dir.string()});
  if (m_checkpoints->resume_from())
    m_probes.keep_rows_before(m_dir / "probes.csv", simulation.frame());
}

bool OutputObserver::frame_done(const Simulation& simulation, const FrameStats& stats) {
  Timer timer;
  for (const auto& e : write_frame(simulation, m_dir, stats.frame, stats.time))
    m_series.push_back(e);
  if (!m_series.empty()) io::write_pvd(m_dir / "simulation.pvd", m_series);
  if (!m_scene->probes.empty() || !m_scene->constraints.empty()) {
    m_probes.add(simulation, stats.frame, stats.time);
    m_probes.write(m_dir / "probes.csv");
  }
  const bool stop = stop_requested && stop_requested();
  m_checkpoints->completed(
      simulation.checkpoint({series_array(m_series)}, m_checkpoints->take_storage()), stop);
  // The state's snapshot and checkpoint count as output (a 256-cell lattice's snapshot took
  // seconds before its fields were stored as non-zero runs, and the time line did not show it).
  m_last_output_seconds = timer.seconds();
  m_output_seconds += m_last_output_seconds;
  return !stop;
}

Error OutputObserver::frame_failed(const Simulation& simulation, const Error& error) {
  return sim::frame_failed(error, *m_checkpoints, simulation.frame(), simulation.attempt_time());
}

}  // namespace mgelastic::sim
