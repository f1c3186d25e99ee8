#include "run_command.hpp"

#include <cstdio>
#include <filesystem>

#include "grid_run.hpp"
#include "interruption.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/core/threads.hpp"
#include "mgelastic/scene/scene.hpp"
#include "run_checkpoints.hpp"
#include "tet_run.hpp"

namespace mgelastic::app {
namespace {

struct RunOptions {
  std::string scene;
  std::string output;
  int threads = 0;
  bool resume = false;
};

}  // namespace

void run_scene(const scene::Scene& s, const std::filesystem::path& output, bool resume) {
  const std::filesystem::path dir = output.empty() ? std::filesystem::path(s.output_dir) : output;
  // A refused resume throws here, before anything is written.
  RunCheckpoints checkpoints(s, dir, resume);
  if (checkpoints.first_frame() >= s.time.frames) {
    std::printf(
        "nothing to resume: %s already holds the last frame %d (raise time.frames to "
        "continue)\n",
        checkpoint_path(dir).string().c_str(), s.time.frames - 1);
    return;
  }
  const InterruptionGuard guard;
  try {
    if (s.engine == "tet") {
      run_tet_scene(s, dir, checkpoints);
    } else {
      run_grid_scene(s, dir, checkpoints);
    }
  } catch (const Error& e) {
    // Engine errors about the set-up (e.g. an unsupported body) name no file: it is the scene's.
    if (!e.context().file.empty()) throw;
    ErrorContext context = e.context();
    context.file = s.file;
    throw Error(e.reason(), context);
  }
}

namespace {

void run(const RunOptions& o) {
  require(o.threads >= 0, "--threads",
          "must be >= 0 (0 = all cores), got " + std::to_string(o.threads));
  set_thread_count(o.threads);
  run_scene(scene::load_scene(o.scene), o.output, o.resume);
}

}  // namespace

void register_run_command(CLI::App& app) {
  static RunOptions options;
  CLI::App* cmd = app.add_subcommand(
      "run", "Simulate a scene: frames of the grid or tet engine, written as VTK/OBJ/PLY");
  cmd->add_option("scene", options.scene, "Scene file (JSON)")->required();
  cmd->add_option("--output", options.output, "Output directory (default: the scene's output.dir)");
  cmd->add_option("--threads", options.threads, "Worker threads (default: all cores)");
  cmd->add_flag("--resume", options.resume,
                "Continue from the output directory's checkpoint.mgck (same scene and threads)");
  cmd->callback([] { run(options); });
}

}  // namespace mgelastic::app
