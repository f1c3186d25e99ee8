// The Python module `mgelastic`: scenes in, frames and numpy fields out (docs/python.md).
#include "bindings.hpp"
#include "mgelastic/core/heap_policy.hpp"

PYBIND11_MODULE(mgelastic, m) {
  m.doc() =
      "mgelastic: multigrid elastic solids (grid and tet engines).\n\n"
      "    scene = mgelastic.Scene.load('examples/scenes/cantilever_bar.json')\n"
      "    sim = mgelastic.Simulation(scene, threads=2)\n"
      "    sim.run()\n"
      "    u = sim.displacement()  # grid: (nx+1, ny+1, nz+1, 3) m, a live view\n";
  m.attr("__version__") = MGELASTIC_VERSION;
  mgelastic::restore_heap_release();  // hypre's dependencies switched it off (heap_policy.hpp)
  mgelastic::python::bind_errors(m);
  mgelastic::python::bind_scene(m);
  mgelastic::python::bind_simulation(m);
}
