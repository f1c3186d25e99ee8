#pragma once
// probes.csv of `mgelastic run`: one row per frame with the scene's probes (sim/probes.hpp) and
// the reaction of every constraint (sim/constraint_reactions.hpp):
//   frame,time,<probe>.ux,<probe>.uy,<probe>.uz,<probe>.von_mises,<probe>.pressure,...,
//   reaction<c>.fx,.fy,.fz,.mx,.my,.mz,...          (m, Pa, N, N m; 9 significant digits)
// The file is rewritten atomically after each frame, so it always holds whole frames; a resumed
// run keeps the rows of the frames before the one it resumes at.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "mgelastic/core/reaction.hpp"
#include "mgelastic/sim/probes.hpp"

namespace mgelastic::sim {

class Simulation;

class ProbeTable {
 public:
  // Samples the simulation's current state as frame `frame` at `time` and appends the row.
  void add(const Simulation& simulation, int frame, double time);
  // Rows of an existing file for frames < `frame` (a resumed run); nothing if it does not exist.
  void keep_rows_before(const std::filesystem::path& path, int frame);
  void write(const std::filesystem::path& path) const;

  bool empty() const { return m_rows.empty(); }
  const std::vector<ProbeSample>& last_samples() const { return m_samples; }
  // Of the last row; std::nullopt where the engine has none (co-rotated grid).
  const std::optional<std::vector<Reaction>>& last_reactions() const { return m_reactions; }

 private:
  std::string m_header;
  std::vector<std::string> m_rows;  // "frame,..." lines
  std::vector<ProbeSample> m_samples;
  std::optional<std::vector<Reaction>> m_reactions;
};

}  // namespace mgelastic::sim
