// libFuzzer target: read_gmsh on arbitrary bytes. Any exception other than mgelastic::Error, a
// crash or a sanitizer report is a bug of the reader.
#include "fuzz_support.hpp"
#include "mgelastic/geometry/tet_mesh_readers.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const mgelastic::fuzz::InputFile file("input.msh");
  try {
    mgelastic::geometry::read_gmsh(file.write(mgelastic::fuzz::as_text(data, size)));
  } catch (const mgelastic::Error& error) {
    mgelastic::fuzz::rejected(error);
  }
  return 0;
}
