#pragma once
// Names of the per-frame output files shared by the engines' runs: `stem_NNNN.ext`.
#include <algorithm>
#include <cstdio>
#include <string>

#include "mgelastic/io/vtk_array_encoder.hpp"
#include "mgelastic/scene/scene.hpp"

namespace mgelastic::app {

inline bool wants(const scene::Scene& s, const std::string& format) {
  return std::find(s.formats.begin(), s.formats.end(), format) != s.formats.end();
}

// The scene's `output.vtk_encoding`.
inline io::VtkEncoding vtk_encoding(const scene::Scene& s) {
  return s.vtk_encoding == "ascii" ? io::VtkEncoding::ASCII : io::VtkEncoding::BINARY;
}

inline std::string frame_name(const std::string& stem, int frame, const std::string& extension) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "_%04d.", frame);
  return stem + buffer + extension;
}

}  // namespace mgelastic::app
