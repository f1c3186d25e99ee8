#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "mgelastic/core/error.hpp"
#include "mgelastic/io/atomic_file.hpp"
#include "mgelastic/io/vtk_writers.hpp"

namespace mgelastic::io {
namespace {

std::filesystem::path temp_dir() {
  auto dir = std::filesystem::temp_directory_path() / "mgelastic_io_test";
  std::filesystem::create_directories(dir);
  return dir;
}

// The files parse as XML and carry their arrays (checked with Python's xml module, which the
// test command installs with python3).
TEST(VtkWriters, ImageDataAndSeriesParseWithTheirFields) {
  const auto dir = temp_dir();
  ImageData image;
  image.cells = Eigen::Vector3i(2, 1, 1);
  image.spacing = 0.5;
  image.point_data.push_back({"displacement", 3, std::vector<double>(12 * 3, 0.25)});
  image.cell_data.push_back({"pressure", 1, {1.0, 2.0}});
  write_vti(dir / "frame_0000.vti", image);
  write_pvd(dir / "series.pvd", {{0.0, "frame_0000.vti", 0}});
  const std::string script =
      "import xml.etree.ElementTree as E, sys\n"
      "r = E.parse(sys.argv[1]).getroot()\n"
      "names = [a.get('Name') for a in r.iter('DataArray')]\n"
      "vals = [len(a.text.split()) for a in r.iter('DataArray')]\n"
      "assert names == ['displacement', 'pressure'] and vals == [36, 2], (names, vals)\n"
      "s = E.parse(sys.argv[2]).getroot()\n"
      "assert [d.get('file') for d in s.iter('DataSet')] == ['frame_0000.vti']\n";
  std::ofstream(dir / "check.py") << script;
  const std::string command = "python3 " + (dir / "check.py").string() + " " +
                              (dir / "frame_0000.vti").string() + " " +
                              (dir / "series.pvd").string();
  EXPECT_EQ(std::system(command.c_str()), 0);
  EXPECT_FALSE(std::filesystem::exists(dir / "frame_0000.vti.tmp"));
}

TEST(VtkWriters, WrongArraySizeIsAnErrorAndLeavesNoFile) {
  const auto path = temp_dir() / "bad.vti";
  std::filesystem::remove(path);
  ImageData image;
  image.cells = Eigen::Vector3i(1, 1, 1);
  image.cell_data.push_back({"pressure", 1, {1.0, 2.0}});
  EXPECT_THROW(write_vti(path, image), Error);
  EXPECT_FALSE(std::filesystem::exists(path));
}

TEST(AtomicFile, ExistingFileSurvivesAFailedWrite) {
  const auto path = temp_dir() / "keep.txt";
  write_file_atomically(path, [](std::ostream& out) { out << "first"; });
  EXPECT_THROW(write_file_atomically(path, [](std::ostream&) { throw Error("interrupted"); }),
               Error);
  std::ifstream in(path);
  std::string text;
  in >> text;
  EXPECT_EQ(text, "first");
}

}  // namespace
}  // namespace mgelastic::io
