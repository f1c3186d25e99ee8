#pragma once
// A synthetic grid-engine frame for the VTK write benchmark (`mgelastic bench vtk`): n^3 cells
// with the arrays sim/output_observer.cpp writes for a single-precision solve.
#include "mgelastic/io/vtk_writers.hpp"

namespace mgelastic::io {

// Displacement (3 components, (n + 1)^3 nodes), cell_type (UInt8), pressure and von Mises (n^3
// cells), Float32; smooth fields with an empty slab (a displaced solid, not noise: what the
// compressor meets in a simulation).
ImageData synthetic_lattice_frame(int n);

}  // namespace mgelastic::io
