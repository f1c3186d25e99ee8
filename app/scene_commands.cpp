#include "scene_commands.hpp"

#include <iostream>

#include "mgelastic/scene/scene.hpp"
#include "mgelastic/scene/schema.hpp"

namespace mgelastic::app {

void register_scene_commands(CLI::App& app) {
  app.add_subcommand("scene-format", "Print the scene file reference (Markdown)")->callback([] {
    std::cout << scene::scene_format_markdown();
  });
  static std::string path;
  CLI::App* check = app.add_subcommand("check", "Validate a scene file and print it with defaults");
  check->add_option("scene", path, "Scene file (JSON)")->required();
  check->callback([] { std::cout << scene::load_scene(path).document.dump(2) << "\n"; });
}

}  // namespace mgelastic::app
