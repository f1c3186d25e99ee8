#pragma once
// The local corrections of a hierarchy's finest level (local_correction.hpp) and when to place
// them (MultigridOptions::local_corrections): the cycles report their ratios; after
// kLocalCorrectionWatch cycles (since the start or the last placement) whose last two ratios
// exceed kLocalCorrectionRatio, the caller places boxes around the cubes holding most of the
// residual (slow_mode_boxes). A box that overlaps boxes placed before replaces them by their
// union; a box holds at most kLocalCorrectionBodyShare of the body cells (within
// [kLocalCorrectionMinCells, kLocalCorrectionMaxCells]).
//
// A placement is on trial until kLocalCorrectionWatch cycles later: it passes if the ratio has
// fallen below kLocalCorrectionGain times the ratio that triggered it. After a failed trial one
// more placement may grow the boxes (a first box may hold only part of the mode); if it fails
// too, the boxes before the first failure return and no more are placed (the slow mode is not
// local). Every correction applies before each cycle.
#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "mgelastic/grid/level.hpp"
#include "mgelastic/grid/local_correction.hpp"
#include "mgelastic/grid/material.hpp"

namespace mgelastic::grid {

inline constexpr int kLocalCorrectionWatch = 4;
inline constexpr double kLocalCorrectionRatio = 0.4;
inline constexpr double kLocalCorrectionGain = 0.85;
// Residual cubes of the lattice's longest side / kLocalCorrectionCubesPerSide cells (2 to 8),
// and boxes that margin around them: a slow mode's extent follows the body's features.
inline constexpr int kLocalCorrectionCubesPerSide = 32;
inline constexpr double kLocalCorrectionMinShare = 0.01;  // of the squared residual, per cube
inline constexpr double kLocalCorrectionCover = 0.9;      // cubes taken until they hold this
// A mode that needs more cells is not local: its factorization would outweigh the cycles it
// saves (~60k unknowns factor in ~1 s).
inline constexpr double kLocalCorrectionBodyShare = 1.0 / 64;
inline constexpr std::size_t kLocalCorrectionMinCells = 4096;
inline constexpr std::size_t kLocalCorrectionMaxCells = 16384;

template <int Dim, typename Scalar>
class LocalCorrections {
 public:
  // At most `limit` boxes (0: none), built with the problem's material and inertia.
  LocalCorrections(int limit, const Material& material, double inertia);

  // After `cycles` more cycles whose last ratios are `ratio` and `previous`: settles a
  // placement's trial and says whether to place boxes now.
  bool due(int cycles, double ratio, double previous);
  // Cells per side of the residual cubes (and of the boxes' margin) on `fine`.
  int cube(const Level<Dim, Scalar>& fine) const;
  // Builds corrections of `fine` for `boxes` (slow_mode_boxes) and puts the placement on trial.
  void place(const Level<Dim, Scalar>& fine, const std::vector<std::array<IVec<Dim>, 2>>& boxes);
  // Every correction, in placement order.
  void apply(Level<Dim, Scalar>& fine);

  int size() const { return static_cast<int>(m_local.size()); }
  const LocalCorrection<Dim, Scalar>& operator[](int i) const { return *m_local[i]; }
  std::size_t bytes() const;

  // The boxes and the placement state, so that a checkpointed run resumes bit for bit (boxes
  // are rebuilt from their coordinates, which gives the same factors): counters and boxes as
  // integers, the ratio of the last placement. restore throws Error on a malformed state.
  struct State {
    std::vector<std::int64_t> integers;
    double ratio_at_placement = 0;
  };
  State state() const;
  void restore(const Level<Dim, Scalar>& fine, const State& state);

 private:
  using List = std::vector<std::shared_ptr<LocalCorrection<Dim, Scalar>>>;
  int m_limit = 0;
  Material m_material;
  double m_inertia = 0;
  List m_local, m_local_before, m_local_fallback;
  int m_cycles_since_placement = 0;
  double m_ratio_at_placement = 0;
  bool m_placement_on_trial = false, m_trial_failed = false, m_placement_stopped = false;
};

}  // namespace mgelastic::grid
