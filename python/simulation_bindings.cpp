// mgelastic.Simulation over sim::Simulation (sim/simulation.hpp): stepping with the GIL released,
// Ctrl-C between solver cycles, fields as live numpy views (field_buffers.hpp), checkpoints.
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <Eigen/Geometry>
#include <cstring>
#include <memory>
#include <optional>

#include "bindings.hpp"
#include "field_buffers.hpp"
#include "mgelastic/core/threads.hpp"
#include "mgelastic/sim/simulation.hpp"
#include "sigint_cancellation.hpp"

namespace py = pybind11;

namespace mgelastic::python {
namespace {

using ScenePtr = std::shared_ptr<scene::Scene>;

// The Python object: the library simulation, its thread count (set before every solve, since the
// OpenMP setting is process-wide) and the live field buffers.
class PySimulation {
 public:
  PySimulation(sim::Simulation s, int threads) : m_sim(std::move(s)), m_threads(threads) {}

  static std::unique_ptr<PySimulation> create(const ScenePtr& scene, int threads) {
    require(threads >= 0, "threads",
            "must be >= 0 (0 = all cores), got " + std::to_string(threads));
    set_thread_count(threads);
    std::optional<sim::Simulation> s;
    try {
      py::gil_scoped_release release;
      s.emplace(*scene);
    } catch (const Error& e) {
      if (e.context().pointer.empty()) throw;
      raise_scene_error(e);  // a setting of the scene the engine refuses
    }
    return std::make_unique<PySimulation>(std::move(*s), threads);
  }

  static std::unique_ptr<PySimulation> resume(const ScenePtr& scene,
                                              const std::filesystem::path& path, int threads) {
    require(threads >= 0, "threads",
            "must be >= 0 (0 = all cores), got " + std::to_string(threads));
    set_thread_count(threads);
    py::gil_scoped_release release;
    return std::make_unique<PySimulation>(sim::Simulation::resume(*scene, path), threads);
  }

  sim::Simulation& sim() { return m_sim; }

  // One frame with the GIL released; then the live fields are refilled. Ctrl-C stops the solve
  // at its next cycle (sigint_cancellation.hpp): the simulation stays at the last completed
  // frame and Python's SIGINT handler runs (KeyboardInterrupt). A Ctrl-C after the last cycle
  // completes the frame first.
  sim::FrameStats step() {
    bool completed = false, interrupted = false;
    {
      SigintCancellation sigint;
      {
        py::gil_scoped_release release;
        set_thread_count(m_threads);
        try {
          m_sim.step();
          completed = true;
        } catch (const Cancelled&) {
          // Back at the last completed frame (Simulation::step under the guard's scope).
        }
      }
      interrupted = sigint.interrupted();
    }
    if (completed) m_fields.refresh();
    if (interrupted) SigintCancellation::deliver();
    return m_sim.stats();
  }

  // A SIGINT outside step()'s guard (the callback's Python code) is recorded by Python's handler;
  // between frames it raises KeyboardInterrupt here.
  static void check_signals() {
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
  }

  void run(std::optional<int> frames,
           const std::function<py::object(PySimulation&, const sim::FrameStats&)>& callback) {
    const int last = frames ? m_sim.frame() + *frames : m_sim.frames();
    while (m_sim.frame() < last) {
      const sim::FrameStats stats = step();
      check_signals();
      if (callback) {
        py::object r = callback(*this, stats);
        if (r.ptr() == Py_False) break;
      }
    }
  }

  void advance_to(double time) {
    // As sim::Simulation::advance_to: half a step of slack so that round-off does not add a frame.
    const auto& t = m_sim.scene().time;
    const double slack = 0.5 * t.dt / t.substeps;
    while (m_sim.time() < time - slack) {
      step();
      check_signals();
    }
  }

  // Field `name` as a live view (shapes and units: docs/python.md).
  py::array field(const std::string& name, py::handle self) {
    using Layout = FieldBuffers::Layout;
    const sim::Simulation& s = m_sim;
    if (const sim::GridStepper* g = s.grid()) {
      const Eigen::Vector3i n = g->cells();
      const py::ssize_t nx = n[0], ny = n[1];
      const auto nodal = [=] {
        const std::size_t nodes = std::size_t(n[0] + 1) * (n[1] + 1) * (n[2] + 1);
        return Layout{'d',
                      {n[0] + 1, n[1] + 1, n[2] + 1, 3},
                      {24, 24 * (nx + 1), 24 * (nx + 1) * (ny + 1), 8},
                      nodes * 24};
      };
      const auto cellular = [=](std::size_t size) {
        return [=] {
          const std::size_t cells = std::size_t(n[0]) * n[1] * n[2];
          return Layout{size == 1 ? 'B' : 'd',
                        {n[0], n[1], n[2]},
                        {py::ssize_t(size), py::ssize_t(size) * nx, py::ssize_t(size) * nx * ny},
                        cells * size};
        };
      };
      if (name == "displacement")
        return m_fields.view(
            name, nodal,
            [g](std::byte* out) {
              const auto& v = g->displacement().values;
              std::memcpy(out, v.data(), v.size() * sizeof(double));
            },
            self);
      if (name == "velocity")
        return m_fields.view(
            name, nodal,
            [g](std::byte* out) {
              const auto& v = g->velocity();
              std::memcpy(out, v.data(), v.size() * sizeof(double));
            },
            self);
      if (name == "pressure")
        return m_fields.view(
            name, cellular(8),
            [g](std::byte* out) {
              const auto& v = g->pressure();
              std::memcpy(out, v.data(), v.size() * sizeof(double));
            },
            self);
      if (name == "von_mises")
        return m_fields.view(
            name, cellular(8),
            [g](std::byte* out) {
              const auto& v = g->von_mises();
              std::memcpy(out, v.data(), v.size() * sizeof(double));
            },
            self);
      if (name == "cell_types")
        return m_fields.view(
            name, cellular(1),
            [g](std::byte* out) {
              const auto& v = g->cell_types();
              std::memcpy(out, v.data(), v.size());
            },
            self);
      if (name == "positions")
        throw Error("the grid engine has no mesh vertices: use displacement() (nodal)",
                    ErrorContext{.pointer = "positions"});
    } else {
      const sim::TetStepper* t = s.tet();
      const py::ssize_t vertices = t->setup().mesh.vertex_count();
      const auto per_vertex = [=] {
        return Layout{'d', {vertices, 3}, {24, 8}, std::size_t(vertices) * 24};
      };
      if (name == "displacement")
        return m_fields.view(
            name, per_vertex,
            [t](std::byte* out) {
              const Eigen::VectorXd& x = t->positions();
              const Eigen::MatrixX3d& rest = t->setup().mesh.vertices;
              auto* u = reinterpret_cast<double*>(out);
              for (Eigen::Index v = 0; v < rest.rows(); ++v)
                for (int c = 0; c < 3; ++c) u[3 * v + c] = x[3 * v + c] - rest(v, c);
            },
            self);
      if (name == "positions" || name == "velocity")
        return m_fields.view(
            name, per_vertex,
            [t, name](std::byte* out) {
              const Eigen::VectorXd& x = name == "positions" ? t->positions() : t->velocities();
              std::memcpy(out, x.data(), x.size() * sizeof(double));
            },
            self);
      if (name == "von_mises") {
        const py::ssize_t tets = t->setup().mesh.tet_count();
        return m_fields.view(
            name,
            [=] {
              return Layout{'d', {tets}, {8}, std::size_t(tets) * 8};
            },
            [t](std::byte* out) {
              const Eigen::MatrixXd v = t->von_mises();
              std::memcpy(out, v.data(), v.size() * sizeof(double));
            },
            self);
      }
      if (name == "pressure" || name == "cell_types")
        throw Error(
            "the tet engine has no " + name + " field (displacement-only elements, no lattice)",
            ErrorContext{.pointer = name});
    }
    throw Error("no field " + name);
  }

  py::tuple surface(py::handle self) {
    const py::ssize_t v = m_sim.surface_vertices().rows();
    py::array vertices = m_fields.view(
        "surface",
        [v] {
          return FieldBuffers::Layout{'d', {v, 3}, {24, 8}, std::size_t(v) * 24};
        },
        [this](std::byte* out) {
          const io::SurfaceVertices x = m_sim.surface_vertices();
          std::memcpy(out, x.data(), x.size() * sizeof(double));
        },
        self);
    const io::SurfaceTriangles& tri = m_sim.surface_triangles();
    static_assert(sizeof(int) == 4);
    py::array triangles = read_only_view(
        FieldBuffers::Layout{'i', {tri.rows(), 3}, {12, 4}, std::size_t(tri.size()) * 4},
        tri.data(), self);
    return py::make_tuple(vertices, triangles);
  }

  void set_region_pose(std::size_t region, const Eigen::Vector3d& translate,
                       const py::object& rotate) {
    Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
    if (!rotate.is_none()) {
      const auto r = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(rotate);
      if (r && r.ndim() == 2 && r.shape(0) == 3 && r.shape(1) == 3) {
        const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> m(r.data());
        const Eigen::Matrix3d rm = m;
        require((rm.transpose() * rm - Eigen::Matrix3d::Identity()).norm() < 1e-6 &&
                    rm.determinant() > 0,
                "rotate", "is not a rotation matrix");
        q = Eigen::Quaterniond(rm);
      } else if (r && r.ndim() == 1 && r.shape(0) == 4) {
        q = Eigen::Quaterniond(r.data()[0], r.data()[1], r.data()[2], r.data()[3]);
        require(q.norm() > 0, "rotate", "is a zero quaternion");
        q.normalize();
      } else {
        PyErr_Clear();
        throw Error("must be a 3x3 rotation matrix or a quaternion (w, x, y, z)",
                    ErrorContext{.pointer = "rotate"});
      }
    }
    m_sim.set_region_pose(region, translate, q);
  }

 private:
  sim::Simulation m_sim;
  int m_threads;
  FieldBuffers m_fields;
};

// A 3-vector argument `name`, or Error naming it and the shape it got.
Eigen::Vector3d vector3(const py::object& value, const char* name) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
  if (!a || a.ndim() != 1 || a.shape(0) != 3) {
    PyErr_Clear();
    throw Error("must be 3 numbers (x, y, z), got " + std::string(py::str(py::repr(value))),
                ErrorContext{.pointer = name});
  }
  return Eigen::Vector3d(a.data()[0], a.data()[1], a.data()[2]);
}

Eigen::Matrix3d rotation(const Eigen::Vector3d& axis, double degrees) {
  require(axis.norm() > 0, "axis", "must not be zero");
  return Eigen::AngleAxisd(degrees * EIGEN_PI / 180.0, axis.normalized()).toRotationMatrix();
}

}  // namespace

void bind_simulation(py::module_& m) {
  py::class_<sim::StepStats>(m, "StepStats", "Statistics of one solve (time step or equilibrium).")
      .def_readonly("cycles", &sim::StepStats::cycles,
                    "grid: multigrid cycles; tet: linear solver iterations")
      .def_readonly("relative_residual", &sim::StepStats::relative_residual)
      .def_readonly("quasi_linear_reduction", &sim::StepStats::quasi_linear_reduction)
      .def_readonly("quasi_linear_residual", &sim::StepStats::quasi_linear_residual)
      .def_readonly("converged", &sim::StepStats::converged)
      .def_readonly("stalled", &sim::StepStats::stalled,
                    "grid: stopped short of the tolerance where round-off stalled the residual "
                    "(float round-off in single precision, else the round-off floor of x in "
                    "double)")
      .def_readonly("seconds", &sim::StepStats::seconds);
  py::class_<sim::FrameStats>(m, "FrameStats", "Solver statistics of one frame.")
      .def_readonly("frame", &sim::FrameStats::frame, "index (-1 before the first frame)")
      .def_readonly("time", &sim::FrameStats::time, "s; the frame shows the state at this time")
      .def_readonly("steps", &sim::FrameStats::steps)
      .def_readonly("cycles", &sim::FrameStats::cycles, "summed over the steps")
      .def_readonly("worst_residual", &sim::FrameStats::worst_residual)
      .def_readonly("converged", &sim::FrameStats::converged)
      .def_readonly("solve_seconds", &sim::FrameStats::solve_seconds)
      .def_readonly("rotate_seconds", &sim::FrameStats::rotate_seconds)
      .def_readonly("assemble_seconds", &sim::FrameStats::assemble_seconds)
      .def_readonly("step_stats", &sim::FrameStats::step_stats)
      .def("__repr__", [](const sim::FrameStats& s) {
        return "<FrameStats frame=" + std::to_string(s.frame) + " time=" + std::to_string(s.time) +
               " cycles=" + std::to_string(s.cycles) +
               " worst_residual=" + std::to_string(s.worst_residual) + ">";
      });

  m.def("rotation", &rotation, py::arg("axis"), py::arg("degrees"),
        "The 3x3 matrix of a rotation by `degrees` about `axis` (for set_region_pose).");

  using Callback = std::function<py::object(PySimulation&, const sim::FrameStats&)>;
  py::class_<PySimulation>(m, "Simulation",
                           "A simulation of one scene, frames in, fields out (either engine).\n\n"
                           "Frame k (0-based) shows the state at time (k + 1) dt. Field arrays "
                           "are read-only live views: they show the current frame after every "
                           "step (copy() one to keep it).")
      .def(py::init(&PySimulation::create), py::arg("scene"), py::arg("threads") = 0,
           "Builds the engine the scene names; `threads` = 0 uses every core (results are "
           "bit-identical for a given thread count).")
      .def_static("resume", &PySimulation::resume, py::arg("scene"), py::arg("path"),
                  py::arg("threads") = 0,
                  "A simulation of `scene` continuing from checkpoint `path` (Simulation.save or "
                  "`mgelastic run` of the same scene and thread count).")
      .def("step", &PySimulation::step,
           "Computes the next frame (GIL released); its stats. Ctrl-C raises KeyboardInterrupt "
           "at the next solver cycle; the simulation stays at the last completed frame, as if "
           "the step had not run.")
      .def("advance_to", &PySimulation::advance_to, py::arg("time"),
           "Steps until time >= `time` (s); Ctrl-C raises KeyboardInterrupt at the next solver "
           "cycle, leaving the simulation at the last completed frame.")
      .def(
          "run", &PySimulation::run, py::arg("frames") = py::none(),
          py::arg("callback") = Callback{},
          "Steps `frames` more frames (default: to the scene's last frame), calling "
          "callback(sim, stats) after each; a callback returning False stops the run. "
          "Ctrl-C raises KeyboardInterrupt at the next solver cycle, leaving the simulation at the "
          "last completed frame.")
      .def(
          "save", [](PySimulation& s, const std::filesystem::path& p) { s.sim().save(p); },
          py::arg("path"), "Writes a checkpoint of the last completed frame.")
      .def(
          "set_region_pose",
          [](PySimulation& s, std::size_t region, const Eigen::Vector3d& translate,
             const py::object& rotate) { s.set_region_pose(region, translate, rotate); },
          py::arg("region"), py::arg("translate") = Eigen::Vector3d::Zero().eval(),
          py::arg("rotate") = py::none(),
          "Constraint region `region` (index in the scene's constraints) holds the rigid pose "
          "x = R (X - pivot) + pivot + translate from the next step on, replacing its keyframes; "
          "`rotate` is a 3x3 matrix (mgelastic.rotation) or a quaternion (w, x, y, z).")
      .def(
          "set_traction",
          [](PySimulation& s, std::size_t index, const py::object& traction) {
            s.sim().set_traction(index, vector3(traction, "traction"));
          },
          py::arg("index"), py::arg("traction"),
          "Load `index` of the scene's loads.tractions applies `traction` (3 numbers, Pa) from "
          "the next step on, on the same surface. Grid engine: the new load replaces the old "
          "one in the solver hierarchy (no rebuild).")
      .def(
          "set_pressure",
          [](PySimulation& s, std::size_t index, double pressure) {
            s.sim().set_pressure(index, pressure);
          },
          py::arg("index"), py::arg("pressure"),
          "Load `index` of the scene's loads.pressures applies `pressure` (Pa, along the inward "
          "rest normal) from the next step on.")
      .def(
          "set_force",
          [](PySimulation& s, std::size_t index, const py::object& force) {
            s.sim().set_force(index, vector3(force, "force"));
          },
          py::arg("index"), py::arg("force"),
          "Load `index` of the scene's loads.forces applies the total force `force` (3 numbers, "
          "N, spread over its surface by area) from the next step on.")
      .def(
          "displacement",
          [](py::object self) { return self.cast<PySimulation&>().field("displacement", self); },
          "grid: nodal, (nx+1, ny+1, nz+1, 3); tet: per vertex, (N, 3); m")
      .def(
          "velocity",
          [](py::object self) { return self.cast<PySimulation&>().field("velocity", self); },
          "as displacement, m/s (zero for quasistatic grid runs)")
      .def(
          "pressure",
          [](py::object self) { return self.cast<PySimulation&>().field("pressure", self); },
          "grid only: per lattice cell, (nx, ny, nz), Pa (0 outside interior cells)")
      .def(
          "von_mises",
          [](py::object self) { return self.cast<PySimulation&>().field("von_mises", self); },
          "von Mises stress, Pa: grid per lattice cell (nx, ny, nz); tet per tet (T,)")
      .def(
          "cell_types",
          [](py::object self) { return self.cast<PySimulation&>().field("cell_types", self); },
          "grid only: per lattice cell, (nx, ny, nz) uint8 (0 exterior, 1 interior, 2 Dirichlet)")
      .def(
          "positions",
          [](py::object self) { return self.cast<PySimulation&>().field("positions", self); },
          "tet only: deformed vertex positions, (N, 3), m")
      .def(
          "surface", [](py::object self) { return self.cast<PySimulation&>().surface(self); },
          "(vertices (V, 3) float64 m, triangles (T, 3) int32): the deformed render surface")
      .def_property_readonly(
          "stats", [](PySimulation& s) { return s.sim().stats(); },
          "FrameStats of the last completed frame")
      .def_property_readonly(
          "frame", [](PySimulation& s) { return s.sim().frame(); },
          "frames completed = index of the next frame")
      .def_property_readonly(
          "frames", [](PySimulation& s) { return s.sim().frames(); }, "the scene's time.frames")
      .def_property_readonly(
          "time", [](PySimulation& s) { return s.sim().time(); },
          "s, of the last completed frame; 0 before the first")
      .def_property_readonly("engine",
                             [](PySimulation& s) { return s.sim().is_grid() ? "grid" : "tet"; })
      .def_property_readonly(
          "scene", [](PySimulation& s) { return std::make_shared<scene::Scene>(s.sim().scene()); })
      .def_property_readonly(
          "cells",
          [](PySimulation& s) {
            require(s.sim().is_grid(), "cells", "the tet engine has no lattice");
            const Eigen::Vector3i n = s.sim().grid()->cells();
            return py::make_tuple(n[0], n[1], n[2]);
          },
          "grid: lattice cells per axis (nx, ny, nz)")
      .def_property_readonly(
          "spacing",
          [](PySimulation& s) {
            require(s.sim().is_grid(), "spacing", "the tet engine has no lattice");
            return s.sim().grid()->spacing();
          },
          "grid: cell size, m")
      .def_property_readonly(
          "origin",
          [](PySimulation& s) {
            require(s.sim().is_grid(), "origin", "the tet engine has no lattice");
            return Eigen::Vector3d(s.sim().grid()->origin());
          },
          "grid: the lattice's min corner (node (0, 0, 0)), m");
}

}  // namespace mgelastic::python
