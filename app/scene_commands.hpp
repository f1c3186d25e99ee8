#pragma once
// Scene-file commands: `mgelastic scene-format` prints the generated format reference,
// `mgelastic check SCENE` validates a scene and prints it with defaults filled in.
#include <CLI/CLI.hpp>

namespace mgelastic::app {

void register_scene_commands(CLI::App& app);

}  // namespace mgelastic::app
