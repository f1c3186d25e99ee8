#pragma once
// The parts of the Python module `mgelastic`, one per concept; mgelastic_module.cpp calls them
// in this order (errors first: the others raise them).
#include <pybind11/pybind11.h>

#include "mgelastic/core/error.hpp"

namespace mgelastic::python {

// mgelastic.Error (RuntimeError) for every library error, mgelastic.SceneError (Error and
// ValueError) for invalid scenes; a translator maps C++ mgelastic::Error to mgelastic.Error.
void bind_errors(pybind11::module_& m);
// Raises mgelastic.SceneError with the message of `error` (what the CLI prints after "error: ").
[[noreturn]] void raise_scene_error(const Error& error);

// mgelastic.Scene: load, from_dict, to_dict.
void bind_scene(pybind11::module_& m);

// mgelastic.Simulation, FrameStats, StepStats.
void bind_simulation(pybind11::module_& m);

}  // namespace mgelastic::python
