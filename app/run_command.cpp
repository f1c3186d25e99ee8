#include "run_command.hpp"

#include <cstdio>
#include <filesystem>

#include "interruption.hpp"
#include "mgelastic/core/cancellation.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/core/threads.hpp"
#include "mgelastic/core/timer.hpp"
#include "mgelastic/scene/scene.hpp"
#include "mgelastic/sim/run_checkpoints.hpp"
#include "mgelastic/sim/simulation.hpp"
#include "run_printer.hpp"

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
  sim::RunCheckpoints checkpoints(s, dir, resume);
  if (checkpoints.first_frame() >= s.time.frames) {
    std::printf(
        "nothing to resume: %s already holds the last frame %d (raise time.frames to "
        "continue)\n",
        sim::checkpoint_path(dir).string().c_str(), s.time.frames - 1);
    return;
  }
  const InterruptionGuard guard;
  // The guard's Ctrl-C stops the solve in progress. The run ends there, with the checkpoint of the
  // last completed frame, so the simulation need not keep its frame's start state.
  const CancellationScope cancellable(/*return_to_start=*/false);
  try {
    Timer timer;
    sim::Simulation simulation(s);
    print_setup(simulation, timer.seconds());
    if (const io::Checkpoint* from = checkpoints.resume_from()) {
      simulation.restore(*from);
      std::printf("resumed from %s: frame %d (t = %.6g s) done\n", from->source.c_str(),
                  from->frame, from->time);
    }
    RunPrinter printer(s, dir, checkpoints);
    try {
      simulation.run(printer);
    } catch (const Cancelled&) {
      printer.cancelled(simulation, checkpoints);
    }
    printer.print_summary(simulation, dir);
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
