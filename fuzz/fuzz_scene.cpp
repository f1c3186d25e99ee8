// libFuzzer target: load_scene (JSON syntax, schema validation, typed scene) on arbitrary bytes.
// Any exception other than mgelastic::Error, a crash or a sanitizer report is a bug of the loader.
#include "fuzz_support.hpp"
#include "mgelastic/scene/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const mgelastic::fuzz::InputFile file("scene.json");
  try {
    mgelastic::scene::load_scene(file.write(mgelastic::fuzz::as_text(data, size)));
  } catch (const mgelastic::Error& error) {
    mgelastic::fuzz::rejected(error);
  }
  return 0;
}
