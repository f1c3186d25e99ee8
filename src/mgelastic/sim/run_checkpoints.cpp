#include "mgelastic/sim/run_checkpoints.hpp"

#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

#include "mgelastic/core/error.hpp"
#include "mgelastic/core/threads.hpp"

namespace mgelastic::sim {

namespace {

std::string hex(std::uint64_t value) {
  char buffer[24];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(value));
  return buffer;
}

}  // namespace

std::filesystem::path checkpoint_path(const std::filesystem::path& output_dir) {
  return output_dir / "checkpoint.mgck";
}

std::uint64_t scene_fingerprint(const scene::Scene& s) {
  nlohmann::json document = s.document;
  if (document.contains("output")) {
    document["output"].erase("dir");
    document["output"].erase("checkpoint_every");
  }
  if (document.contains("time")) document["time"].erase("frames");
  // dump() sorts object keys, so equal documents give equal text.
  return io::fnv1a64(s.engine + "\n" + document.dump());
}

io::NamedArray series_array(const std::vector<io::SeriesEntry>& series) {
  std::string text;
  for (const io::SeriesEntry& e : series) {
    char time[64];
    std::snprintf(time, sizeof time, "%a", e.time);  // exact round trip through strtod
    text += std::string(time) + "\t" + std::to_string(e.part) + "\t" + e.file + "\n";
  }
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(text.data());
  io::Checkpoint holder;
  holder.add<std::uint8_t>("series", std::span(bytes, text.size()));
  return std::move(holder.arrays.front());
}

std::vector<io::SeriesEntry> series_of(const io::Checkpoint& checkpoint) {
  const std::vector<std::uint8_t> bytes = checkpoint.get<std::uint8_t>("series");
  std::istringstream lines(std::string(bytes.begin(), bytes.end()));
  std::vector<io::SeriesEntry> series;
  std::string line;
  while (std::getline(lines, line)) {
    const auto first = line.find('\t'), second = line.find('\t', first + 1);
    if (second == std::string::npos)
      throw Error("corrupted checkpoint: bad series entry '" + line + "'",
                  ErrorContext{.file = checkpoint.source});
    series.push_back({std::strtod(line.substr(0, first).c_str(), nullptr), line.substr(second + 1),
                      std::atoi(line.c_str() + first + 1)});
  }
  return series;
}

io::Checkpoint read_resume_checkpoint(const scene::Scene& s, const std::filesystem::path& path) {
  const std::uint64_t fingerprint = scene_fingerprint(s);
  const int threads = thread_count();
  const ErrorContext where{.file = path.string()};
  if (!std::filesystem::exists(path))
    throw Error("--resume: no checkpoint here (run without --resume to start from frame 0)", where);
  io::Checkpoint c = io::read_checkpoint(path);
  if (c.engine != s.engine)
    throw Error("--resume: the checkpoint was written by the " + c.engine +
                    " engine, this scene uses the " + s.engine + " engine",
                where);
  if (c.scene_fingerprint != fingerprint)
    throw Error("--resume: the checkpoint belongs to a different scene (scene fingerprint " +
                    hex(c.scene_fingerprint) + ", this scene " + hex(fingerprint) +
                    "); only output.dir, output.checkpoint_every and time.frames may change "
                    "between a run and its resume",
                where);
  if (c.threads != threads)
    throw Error("--resume: the checkpoint was written with " + std::to_string(c.threads) +
                    " threads, this run has " + std::to_string(threads) +
                    "; frames are bit-identical only with the same count (pass --threads " +
                    std::to_string(c.threads) + ")",
                where);
  if (c.frame < 0)
    throw Error("--resume: corrupted checkpoint: frame index " + std::to_string(c.frame), where);
  return c;
}

RunCheckpoints::RunCheckpoints(const scene::Scene& s, std::filesystem::path dir, bool resume)
    : m_scene(&s), m_path(checkpoint_path(dir)) {
  if (resume) m_resume = read_resume_checkpoint(s, m_path);
}

void RunCheckpoints::completed(io::Checkpoint state, bool now) {
  const int every = m_scene->checkpoint_every;
  const bool due =
      (every > 0 && (state.frame + 1) % every == 0) || state.frame + 1 >= m_scene->time.frames;
  m_last_good = std::move(state);
  m_last_good_written = false;
  if (due || now) {
    io::write_checkpoint(m_path, *m_last_good);
    m_last_good_written = true;
  }
}

std::vector<io::NamedArray> RunCheckpoints::take_storage() {
  if (!m_last_good) return {};
  std::vector<io::NamedArray> arrays = std::move(m_last_good->arrays);
  m_last_good.reset();
  return arrays;
}

int RunCheckpoints::save_last_good() {
  if (!m_last_good) return m_resume ? m_resume->frame : -1;  // the resumed-from file is on disk
  if (!m_last_good_written) io::write_checkpoint(m_path, *m_last_good);
  m_last_good_written = true;
  return m_last_good->frame;
}

Error frame_failed(const Error& e, RunCheckpoints& checkpoints, int frame, double time) {
  const int good = checkpoints.save_last_good();
  char where[96];
  std::snprintf(where, sizeof where, "; the run stopped in frame %d (t = %.6g s): ", frame, time);
  std::string reason = e.reason() + where;
  if (good >= 0) {
    reason += "the files of frames 0-" + std::to_string(frame - 1) +
              " are complete and checkpoint.mgck holds frame " + std::to_string(good);
  } else {
    reason += "no frame was completed";
  }
  return Error(reason, e.context());
}

}  // namespace mgelastic::sim
