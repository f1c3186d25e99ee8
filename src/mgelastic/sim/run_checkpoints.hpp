#pragma once
// Checkpoints of a run (Simulation::run with an OutputObserver, `mgelastic run`) (format:
// mgelastic/io/checkpoint.hpp). One file, OUTPUT_DIR/checkpoint.mgck, replaced atomically: every
// `output.checkpoint_every` frames, after the last frame, after the frame in progress when
// SIGINT/SIGTERM stop the run, and, when a frame diverges, with the state of the last good frame.
// `run --resume` reads it back, refuses it unless it was written by the same scene, engine and
// thread count, and the engine continues with the next frame; the .pvd series is part of the state,
// so it lists every frame.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

#include "mgelastic/core/error.hpp"
#include "mgelastic/io/checkpoint.hpp"
#include "mgelastic/io/vtk_writers.hpp"
#include "mgelastic/scene/scene.hpp"

namespace mgelastic::sim {

std::filesystem::path checkpoint_path(const std::filesystem::path& output_dir);

// FNV-1a of the validated scene document (defaults filled in) without the keys that do not
// change any frame's numbers: output.dir, output.checkpoint_every and time.frames (so a finished
// run can be extended by raising the frame count and resuming).
std::uint64_t scene_fingerprint(const scene::Scene& s);

// The series so far, stored in the checkpoint as the u8 array "series" (one line per entry:
// time as a hexadecimal float, part, file).
io::NamedArray series_array(const std::vector<io::SeriesEntry>& series);
std::vector<io::SeriesEntry> series_of(const io::Checkpoint& checkpoint);

// Reads a checkpoint to continue `s` from; throws Error (naming the file and the reason) when
// there is none, it is damaged, or another scene, engine or thread count wrote it.
io::Checkpoint read_resume_checkpoint(const scene::Scene& s, const std::filesystem::path& path);

class RunCheckpoints {
 public:
  // With `resume`, reads the directory's checkpoint and throws Error (naming the file and the
  // reason) when there is none, it is damaged, or another scene, engine or thread count wrote it.
  // Nothing is written here, so a refused resume leaves the directory as it was.
  RunCheckpoints(const scene::Scene& s, std::filesystem::path dir, bool resume);

  // The checkpoint to continue from (null without --resume), and the first frame to compute.
  const io::Checkpoint* resume_from() const { return m_resume ? &*m_resume : nullptr; }
  int first_frame() const { return m_resume ? m_resume->frame + 1 : 0; }

  // The frame completed with this state: it becomes the last good one, and is written when the
  // frame is due (every N frames, or the last frame) or `now` (interrupted).
  void completed(io::Checkpoint state, bool now);
  // The last good state's arrays, for the snapshot of the frame completed after it to reuse
  // (Simulation::checkpoint's storage); that state is gone then, so call it only with that
  // frame completed.
  std::vector<io::NamedArray> take_storage();
  // After a failed frame: writes the last good state unless it is on disk already. Returns its
  // frame index, -1 when no frame completed in this run or the one resumed from.
  int save_last_good();

 private:
  const scene::Scene* m_scene;
  std::filesystem::path m_path;
  std::optional<io::Checkpoint> m_resume;
  std::optional<io::Checkpoint> m_last_good;
  bool m_last_good_written = false;
};

// A frame failed with `e` (a diverged solve): saves the last good state and returns the error to
// throw, its reason extended by which frame failed, which frames are complete and which frame
// the checkpoint holds.
Error frame_failed(const Error& e, RunCheckpoints& checkpoints, int frame, double time);

}  // namespace mgelastic::sim
