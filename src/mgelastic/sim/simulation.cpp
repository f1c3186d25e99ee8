#include "mgelastic/sim/simulation.hpp"

#include <cmath>

#include "mgelastic/core/cancellation.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/core/threads.hpp"
#include "mgelastic/sim/run_checkpoints.hpp"

namespace mgelastic::sim {

struct Simulation::State {
  scene::Scene scene;
  std::unique_ptr<GridStepper> grid;
  std::unique_ptr<TetStepper> tet;
  int frame = 0;
  double attempt_time = 0;
  FrameStats stats;
  // The start of the step in progress while cancellation is armed (Python steps under a scope):
  // kept between steps so that each capture reuses the last one's array storage.
  io::Checkpoint start;
};

Simulation::Simulation(scene::Scene scene) : m(new State{std::move(scene)}) {
  if (m->scene.engine == "tet") {
    m->tet = std::make_unique<TetStepper>(m->scene);
  } else {
    m->grid = std::make_unique<GridStepper>(m->scene);
  }
}

Simulation Simulation::resume(scene::Scene scene, const std::filesystem::path& path) {
  const io::Checkpoint c = read_resume_checkpoint(scene, path);
  Simulation simulation(std::move(scene));
  simulation.restore(c);
  return simulation;
}

Simulation::Simulation(Simulation&&) noexcept = default;
Simulation& Simulation::operator=(Simulation&&) noexcept = default;
Simulation::~Simulation() = default;

const scene::Scene& Simulation::scene() const {
  return m->scene;
}
int Simulation::frame() const {
  return m->frame;
}
int Simulation::frames() const {
  return m->scene.time.frames;
}
double Simulation::time() const {
  return m->grid ? m->grid->time() : m->tet->time();
}
const FrameStats& Simulation::stats() const {
  return m->stats;
}
double Simulation::attempt_time() const {
  return m->attempt_time;
}
const GridStepper* Simulation::grid() const {
  return m->grid.get();
}
const TetStepper* Simulation::tet() const {
  return m->tet.get();
}

const FrameStats& Simulation::step() {
  // A cancelled solve leaves the engine half-way through the frame: while cancellation is armed
  // the frame's start state is kept, as a checkpoint holds it, to return to.
  const bool armed = cancellation_armed();
  if (armed) {
    io::Checkpoint& start = m->start;
    start.spare = std::move(start.arrays);
    start.arrays.clear();
    start.time = time();
    if (m->grid) {
      m->grid->save_start(start);
    } else {
      m->tet->save(start, {});
    }
  }
  try {
    m->stats = m->grid ? m->grid->advance_frame(m->frame, m->attempt_time)
                       : m->tet->advance_frame(m->frame, m->attempt_time);
  } catch (const Cancelled&) {
    if (armed && m->grid) m->grid->return_to_start(m->start);
    if (armed && m->tet) m->tet->restore(m->start);
    throw;
  }
  ++m->frame;
  return m->stats;
}

void Simulation::advance_to(double time) {
  // Half a step of slack so that round-off in (k + 1) dt does not add a frame.
  const double slack = 0.5 * m->scene.time.dt / m->scene.time.substeps;
  while (this->time() < time - slack) step();
}

void Simulation::run(Observer& observer) {
  observer.started(*this);
  while (m->frame < frames()) {
    try {
      step();
    } catch (const Error& e) {
      throw observer.frame_failed(*this, e);
    }
    if (!observer.frame_done(*this, m->stats)) break;
  }
}

void Simulation::set_region_pose(std::size_t region, const Eigen::Vector3d& translate,
                                 const Eigen::Quaterniond& rotate) {
  if (m->grid) {
    m->grid->set_region_pose(region, translate, rotate);
  } else {
    m->tet->set_region_pose(region, translate, rotate);
  }
}

namespace {

// The load `index` of the scene's loads.<kind>, or Error naming it and what the scene has.
template <typename Load>
Load& scene_load(std::vector<Load>& loads, std::size_t index, const std::string& kind,
                 const scene::Scene& scene, bool finite) {
  const std::string pointer = "/loads/" + kind;
  if (index >= loads.size())
    throw Error("no load " + std::to_string(index) + " of this kind (the scene has " +
                    std::to_string(loads.size()) + ")",
                ErrorContext{.file = scene.file, .pointer = pointer});
  if (!finite)
    throw Error("the new value of load " + std::to_string(index) + " is not finite",
                ErrorContext{.file = scene.file, .pointer = pointer + "/" + std::to_string(index)});
  return loads[index];
}

}  // namespace

void Simulation::set_traction(std::size_t index, const Eigen::Vector3d& traction) {
  scene_load(m->scene.tractions, index, "tractions", m->scene, traction.allFinite()).traction =
      traction;
  loads_changed();
}

void Simulation::set_pressure(std::size_t index, double pressure) {
  scene_load(m->scene.pressures, index, "pressures", m->scene, std::isfinite(pressure)).pressure =
      pressure;
  loads_changed();
}

void Simulation::set_force(std::size_t index, const Eigen::Vector3d& force) {
  scene_load(m->scene.forces, index, "forces", m->scene, force.allFinite()).force = force;
  loads_changed();
}

void Simulation::loads_changed() {
  if (m->grid) {
    m->grid->loads_changed();
  } else {
    m->tet->loads_changed();
  }
}

io::SurfaceVertices Simulation::surface_vertices() const {
  return m->grid ? io::SurfaceVertices(m->grid->surface_vertices()) : m->tet->surface_vertices();
}

const io::SurfaceTriangles& Simulation::surface_triangles() const {
  return m->grid ? m->grid->rest_surface().triangles : m->tet->triangles();
}

io::Checkpoint Simulation::checkpoint(const std::vector<io::NamedArray>& attachments,
                                      std::vector<io::NamedArray> storage) const {
  io::Checkpoint c;
  c.spare = std::move(storage);
  c.engine = m->scene.engine;
  c.scene_fingerprint = scene_fingerprint(m->scene);
  c.threads = thread_count();
  c.frame = m->frame - 1;
  c.time = time();
  if (m->grid) {
    m->grid->save(c, attachments);
  } else {
    m->tet->save(c, attachments);
  }
  c.spare.clear();
  return c;
}

void Simulation::restore(const io::Checkpoint& c) {
  if (m->grid) {
    m->grid->restore(c);
  } else {
    m->tet->restore(c);
  }
  m->frame = c.frame + 1;
  m->stats = FrameStats{};
}

void Simulation::save(const std::filesystem::path& path) const {
  io::write_checkpoint(path, checkpoint());
}

}  // namespace mgelastic::sim
