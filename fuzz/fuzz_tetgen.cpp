// libFuzzer target: read_tetgen on arbitrary bytes. TetGen meshes are two files, so an input is
// the .node file, a line "--- ele ---", and the .ele file (no separator: an empty .ele file).
// Any exception other than mgelastic::Error, a crash or a sanitizer report is a bug of the reader.
#include <algorithm>

#include "fuzz_support.hpp"
#include "mgelastic/geometry/tet_mesh_readers.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const mgelastic::fuzz::InputFile node("input.node");
  static const mgelastic::fuzz::InputFile ele("input.ele");
  constexpr std::string_view separator = "\n--- ele ---\n";
  const std::string_view input = mgelastic::fuzz::as_text(data, size);
  const std::size_t split = std::min(input.find(separator), input.size());
  node.write(input.substr(0, split));
  ele.write(input.substr(std::min(split + separator.size(), input.size())));
  try {
    mgelastic::geometry::read_tetgen(node.path());
  } catch (const mgelastic::Error& error) {
    mgelastic::fuzz::rejected(error);
  }
  return 0;
}
