// libFuzzer target: read_ply on arbitrary bytes. Any exception other than mgelastic::Error, a
// crash or a sanitizer report is a bug of the reader.
#include "fuzz_support.hpp"
#include "mgelastic/geometry/surface_mesh_readers.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const mgelastic::fuzz::InputFile file("input.ply");
  try {
    mgelastic::geometry::read_ply(file.write(mgelastic::fuzz::as_text(data, size)));
  } catch (const mgelastic::Error& error) {
    mgelastic::fuzz::rejected(error);
  }
  return 0;
}
