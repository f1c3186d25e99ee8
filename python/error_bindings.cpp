#include <pybind11/pybind11.h>

#include "bindings.hpp"

namespace py = pybind11;

namespace mgelastic::python {
namespace {

// Set once at import; the module keeps the classes alive.
PyObject* g_error = nullptr;
PyObject* g_scene_error = nullptr;

}  // namespace

void bind_errors(py::module_& m) {
  static py::exception<Error> error(m, "Error", PyExc_RuntimeError);
  error.doc() = "An error of the library: its message is what `mgelastic` (the CLI) prints.";
  g_error = error.ptr();
  // SceneError is both an mgelastic.Error and a ValueError (a bad document is a bad value).
  py::tuple bases = py::make_tuple(error, py::handle(PyExc_ValueError));
  PyObject* scene_error =
      PyErr_NewExceptionWithDoc("mgelastic.SceneError",
                                "An invalid scene: the message names the file and the JSON "
                                "pointer of the offending value.",
                                bases.ptr(), nullptr);
  if (!scene_error) throw py::error_already_set();
  m.add_object("SceneError", py::reinterpret_borrow<py::object>(scene_error));
  g_scene_error = scene_error;
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Error& e) {
      PyErr_SetString(g_error, e.what());
    }
  });
}

void raise_scene_error(const Error& error) {
  PyErr_SetString(g_scene_error, error.what());
  throw py::error_already_set();
}

}  // namespace mgelastic::python
