#pragma once
// Names of the per-frame output files shared by the engines' runs: `stem_NNNN.ext`.
#include <algorithm>
#include <cstdio>
#include <string>

#include "mgelastic/scene/scene.hpp"

namespace mgelastic::app {

inline bool wants(const scene::Scene& s, const std::string& format) {
  return std::find(s.formats.begin(), s.formats.end(), format) != s.formats.end();
}

inline std::string frame_name(const std::string& stem, int frame, const std::string& extension) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "_%04d.", frame);
  return stem + buffer + extension;
}

}  // namespace mgelastic::app
