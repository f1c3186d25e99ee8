#include <gtest/gtest.h>
#include <omp.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include "io/vtk_xml_reader.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/io/atomic_file.hpp"
#include "mgelastic/io/vtk_compressed_blocks.hpp"
#include "mgelastic/io/vtk_writers.hpp"
#include "support/temp_dir.hpp"

namespace mgelastic::io {
namespace {

using test::read_vtk;

std::vector<double> random_values(std::size_t count, unsigned seed) {
  std::mt19937 generator(seed);
  std::normal_distribution<double> normal;
  std::vector<double> values(count);
  for (double& v : values) v = normal(generator);
  return values;
}

// A lattice frame as the grid engine writes it, with every stored type.
ImageData lattice(int n) {
  ImageData image;
  image.cells = Eigen::Vector3i(n, n + 1, n + 2);
  image.spacing = 0.125;
  image.origin = Eigen::Vector3d(-1, 0.5, 2);
  const std::size_t points = std::size_t(n + 1) * (n + 2) * (n + 3);
  const std::size_t cells = std::size_t(n) * (n + 1) * (n + 2);
  image.point_data.push_back({"displacement", 3, random_values(3 * points, 1)});
  std::vector<double> type(cells);
  for (std::size_t c = 0; c < cells; ++c) type[c] = double(c % 3);
  image.cell_data.push_back({"cell_type", 1, type, VtkScalar::UINT8});
  image.cell_data.push_back({"pressure", 1, random_values(cells, 2)});
  image.cell_data.push_back({"von_mises", 1, random_values(cells, 3), VtkScalar::FLOAT32});
  image.cell_data.push_back({"label", 1, type, VtkScalar::INT32});
  return image;
}

// A frame whose arrays span several blocks each (Float64, and Float32 converted block by block).
ImageData multi_block_lattice() {
  ImageData image = lattice(40);
  DataArray single = image.point_data[0];
  single.name = "displacement32";
  single.type = VtkScalar::FLOAT32;
  image.point_data.push_back(std::move(single));
  return image;
}

// What the file must hold: the values converted to the stored type.
std::vector<double> stored(const DataArray& a) {
  std::vector<double> result;
  for (double v : a.values) result.push_back(a.type == VtkScalar::FLOAT32 ? float(v) : v);
  return result;
}

void expect_arrays(const test::VtkFile& file, const std::vector<DataArray>& arrays) {
  static const char* names[] = {"Float64", "Float32", "Int32", "UInt8"};
  for (const DataArray& a : arrays) {
    ASSERT_TRUE(file.arrays.count(a.name)) << a.name;
    EXPECT_EQ(file.arrays.at(a.name).type, names[int(a.type)]) << a.name;
    EXPECT_EQ(file.arrays.at(a.name).values, stored(a)) << a.name;
  }
}

std::vector<double> flat(const Eigen::MatrixXd& m) {
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> rows = m;
  return {rows.data(), rows.data() + rows.size()};
}

std::string bytes_of(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

TEST(VtkWriters, BinaryImageDataReadsBackExactly) {
  test::TempDir dir;
  const ImageData image = lattice(3);
  write_vti(dir.path() / "frame.vti", image);
  const test::VtkFile file = read_vtk(dir.path() / "frame.vti");
  EXPECT_NE(file.xml.find("header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\""),
            std::string::npos);
  EXPECT_NE(file.xml.find("WholeExtent=\"0 3 0 4 0 5\""), std::string::npos);
  expect_arrays(file, image.point_data);
  expect_arrays(file, image.cell_data);
  for (const auto& [name, array] : file.arrays) EXPECT_EQ(array.format, "appended") << name;
}

TEST(VtkWriters, BinaryPolyDataReadsBackExactly) {
  test::TempDir dir;
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> vertices(4, 3);
  vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.1, 0.2, 1.0 / 3.0;
  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> triangles(2, 3);
  triangles << 0, 1, 2, 0, 3, 1;
  const DataArray displacement{"displacement", 3, random_values(12, 4)};
  write_vtp(dir.path() / "surface.vtp", vertices, triangles, {displacement});
  const test::VtkFile file = read_vtk(dir.path() / "surface.vtp");
  expect_arrays(file, {displacement});
  EXPECT_EQ(file.arrays.at("Points").values,
            std::vector<double>(vertices.data(), vertices.data() + vertices.size()));
  EXPECT_EQ(file.arrays.at("connectivity").values, (std::vector<double>{0, 1, 2, 0, 3, 1}));
  EXPECT_EQ(file.arrays.at("offsets").values, (std::vector<double>{3, 6}));
}

TEST(VtkWriters, BinaryUnstructuredGridReadsBackExactly) {
  test::TempDir dir;
  const Eigen::MatrixX3d vertices = Eigen::MatrixX3d::Random(5, 3);
  Eigen::MatrixX4i tets(2, 4);
  tets << 0, 1, 2, 3, 1, 2, 3, 4;
  const DataArray displacement{"displacement", 3, random_values(15, 5)};
  const DataArray stress{"von_mises", 1, {1.5, 2.5}};
  const DataArray tag{"tag", 1, {7, -2}, VtkScalar::INT32};
  write_vtu(dir.path() / "tets.vtu", vertices, tets, {displacement}, {stress, tag});
  const test::VtkFile file = read_vtk(dir.path() / "tets.vtu");
  expect_arrays(file, {displacement, stress, tag});
  EXPECT_EQ(file.arrays.at("Points").values, flat(vertices));
  EXPECT_EQ(file.arrays.at("connectivity").values, flat(tets.cast<double>()));
  EXPECT_EQ(file.arrays.at("offsets").values, (std::vector<double>{4, 8}));
  EXPECT_EQ(file.arrays.at("types").values, (std::vector<double>{10, 10}));  // VTK_TETRA
}

// ASCII stays selectable and exact (shortest round-trip text), and the file is plain XML.
TEST(VtkWriters, AsciiFilesReadBackExactly) {
  test::TempDir dir;
  const ImageData image = lattice(2);
  write_vti(dir.path() / "frame.vti", image, VtkEncoding::ASCII);
  const test::VtkFile file = read_vtk(dir.path() / "frame.vti");
  EXPECT_TRUE(file.raw.empty());
  EXPECT_EQ(file.xml.find("compressor"), std::string::npos);
  expect_arrays(file, image.point_data);
  expect_arrays(file, image.cell_data);
  for (const auto& [name, array] : file.arrays) EXPECT_EQ(array.format, "ascii") << name;
}

// Arrays larger than a block are split into several; the last block may be partial or full.
TEST(VtkCompressedBlocks, SeveralBlocksWithPartialOrFullLastBlock) {
  for (const std::size_t count : {1000, 1024, 1}) {
    const std::vector<double> values = random_values(count, 6);
    std::string out = "prefix";
    append_compressed_blocks(out, std::as_bytes(std::span(values)), 1024);
    std::uint64_t header[3];
    std::memcpy(header, out.data() + 6, sizeof header);
    EXPECT_EQ(header[0], (8 * count + 1023) / 1024) << count;
    EXPECT_EQ(header[1], 1024u);
    EXPECT_EQ(header[2], 8 * count % 1024) << count;
    EXPECT_EQ(test::decode("Float64", test::inflate_appended(out, 6)), values) << count;
  }
}

// Writes `image` as .vti and expects every array back exactly.
void expect_vti_round_trip(const ImageData& image) {
  test::TempDir dir;
  write_vti(dir.path() / "frame.vti", image);
  const test::VtkFile file = read_vtk(dir.path() / "frame.vti");
  expect_arrays(file, image.point_data);
  expect_arrays(file, image.cell_data);
}

TEST(VtkWriters, ArrayLargerThanTheDefaultBlockReadsBack) {
  const ImageData image = lattice(40);  // 3 x 41 x 42 x 43 doubles: 1.7 MB, 7 blocks
  ASSERT_GT(image.point_data[0].values.size() * 8, 4 * kVtkBlockBytes);
  expect_vti_round_trip(image);
}

TEST(VtkWriters, EmptyArraysHaveNoBlocks) {
  test::TempDir dir;
  const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> vertices(0, 3);
  const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> triangles(0, 3);
  write_vtp(dir.path() / "empty.vtp", vertices, triangles, {{"displacement", 3, {}}});
  const test::VtkFile file = read_vtk(dir.path() / "empty.vtp");
  ASSERT_EQ(file.arrays.size(), 4u);
  for (const auto& [name, array] : file.arrays) EXPECT_TRUE(array.values.empty()) << name;
  std::uint64_t header[3];
  std::memcpy(header, file.raw.data(), sizeof header);
  EXPECT_EQ(header[0], 0u);
  EXPECT_EQ(header[2], 0u);
}

// Blocks are compressed in parallel: the file must not depend on the number of threads.
TEST(VtkWriters, BytesDoNotDependOnTheThreadCount) {
  test::TempDir dir;
  const ImageData image = multi_block_lattice();
  const int threads = omp_get_max_threads();
  omp_set_num_threads(1);
  write_vti(dir.path() / "one.vti", image);
  omp_set_num_threads(2);
  write_vti(dir.path() / "two.vti", image);
  omp_set_num_threads(threads);
  EXPECT_EQ(bytes_of(dir.path() / "one.vti"), bytes_of(dir.path() / "two.vti"));
}

TEST(VtkWriters, ArraysSpanningSeveralBlocksReadBackExactly) {
  const ImageData image = multi_block_lattice();
  ASSERT_GT(image.point_data[1].values.size() * sizeof(float), 3 * kVtkBlockBytes);
  expect_vti_round_trip(image);
}

// A borrowed field (a solver's array written without a copy) gives the same file as an owned one.
TEST(VtkWriters, BorrowedArraysWriteTheSameBytes) {
  test::TempDir dir;
  const ImageData owned = lattice(4);
  ImageData borrowed = owned;
  for (auto* arrays : {&borrowed.point_data, &borrowed.cell_data})
    for (std::size_t i = 0; i < arrays->size(); ++i) {
      DataArray& a = (*arrays)[i];
      a.values.clear();
      a.borrowed = (arrays == &borrowed.point_data ? owned.point_data : owned.cell_data)[i].values;
    }
  write_vti(dir.path() / "owned.vti", owned);
  write_vti(dir.path() / "borrowed.vti", borrowed);
  EXPECT_EQ(bytes_of(dir.path() / "owned.vti"), bytes_of(dir.path() / "borrowed.vti"));
}

// The Python interpreter that imports VTK (Debian python3-vtk9), or empty.
std::string python_with_vtk() {
  for (const std::string python : {"/usr/bin/python3", "python3"})
    if (std::system((python + " -c 'import vtk' >/dev/null 2>&1").c_str()) == 0) return python;
  return {};
}

// An array dumped by tests/io/read_with_vtk.py: little-endian Float64 values.
std::vector<double> dumped(const std::filesystem::path& path) {
  const std::string bytes = bytes_of(path);
  std::vector<double> values(bytes.size() / sizeof(double));
  if (!values.empty()) std::memcpy(values.data(), bytes.data(), values.size() * sizeof(double));
  return values;
}

// VTK's own XML readers (what ParaView uses) read all three kinds of file, binary and ASCII, to
// the same values. Skipped when VTK's Python module is not installed.
TEST(VtkWriters, VtkReadersReadTheFilesBack) {
  const std::string python = python_with_vtk();
  if (python.empty()) GTEST_SKIP() << "no Python module vtk (Debian python3-vtk9)";
  test::TempDir dir;
  const ImageData image = multi_block_lattice();
  write_vti(dir.path() / "frame.vti", image);
  write_vti(dir.path() / "ascii.vti", lattice(2), VtkEncoding::ASCII);
  Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> vertices(4, 3);
  vertices << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.1, 0.2, 1.0 / 3.0;
  Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor> triangles(2, 3);
  triangles << 0, 1, 2, 0, 3, 1;
  const DataArray surface_displacement{"displacement", 3, random_values(12, 4), VtkScalar::FLOAT32};
  write_vtp(dir.path() / "surface.vtp", vertices, triangles, {surface_displacement});
  const Eigen::MatrixX3d tet_vertices = Eigen::MatrixX3d::Random(5, 3);
  Eigen::MatrixX4i tets(2, 4);
  tets << 0, 1, 2, 3, 1, 2, 3, 4;
  const DataArray stress{"von_mises", 1, {1.5, 2.5}};
  write_vtu(dir.path() / "tets.vtu", tet_vertices, tets, {}, {stress});
  const std::string command =
      python + " " MGELASTIC_SOURCE_DIR "/tests/io/read_with_vtk.py " + dir.path().string() + " " +
      (dir.path() / "frame.vti").string() + " " + (dir.path() / "ascii.vti").string() + " " +
      (dir.path() / "surface.vtp").string() + " " + (dir.path() / "tets.vtu").string();
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const auto array = [&](const std::string& name) { return dumped(dir.path() / (name + ".f64")); };
  for (const auto* arrays : {&image.point_data, &image.cell_data})
    for (const DataArray& a : *arrays) EXPECT_EQ(array("frame.vti." + a.name), stored(a)) << a.name;
  const ImageData small = lattice(2);
  for (const auto* arrays : {&small.point_data, &small.cell_data})
    for (const DataArray& a : *arrays) EXPECT_EQ(array("ascii.vti." + a.name), stored(a)) << a.name;
  EXPECT_EQ(array("surface.vtp.displacement"), stored(surface_displacement));
  EXPECT_EQ(array("surface.vtp.Points"),
            std::vector<double>(vertices.data(), vertices.data() + vertices.size()));
  EXPECT_EQ(array("surface.vtp.connectivity"), (std::vector<double>{0, 1, 2, 0, 3, 1}));
  EXPECT_EQ(array("surface.vtp.offsets"), (std::vector<double>{0, 3, 6}));  // VTK adds the 0
  EXPECT_EQ(array("tets.vtu.von_mises"), stress.values);
  EXPECT_EQ(array("tets.vtu.Points"), flat(tet_vertices));
  EXPECT_EQ(array("tets.vtu.connectivity"), flat(tets.cast<double>()));
  EXPECT_EQ(array("tets.vtu.types"), (std::vector<double>{10, 10}));
}

// The Python helper of the CLI tests (tests/app/vtk_xml.py) reads both encodings, and the series
// file parses as XML.
TEST(VtkWriters, PythonHelperReadsBothEncodings) {
  test::TempDir dir;
  ImageData image;
  image.cells = Eigen::Vector3i(2, 1, 1);
  image.spacing = 0.5;
  image.point_data.push_back({"displacement", 3, std::vector<double>(12 * 3, 0.25)});
  image.cell_data.push_back({"pressure", 1, {1.0, 2.0}});
  write_vti(dir.path() / "binary.vti", image);
  write_vti(dir.path() / "ascii.vti", image, VtkEncoding::ASCII);
  write_pvd(dir.path() / "series.pvd", {{0.0, "binary.vti", 0}});
  const std::string script =
      "import sys, xml.etree.ElementTree as E\n"
      "sys.path.insert(0, sys.argv[1])\n"
      "import vtk_xml\n"
      "for f in sys.argv[2:4]:\n"
      "    root, arrays = vtk_xml.read(f)\n"
      "    assert arrays == {'displacement': [0.25] * 36, 'pressure': [1.0, 2.0]}, arrays\n"
      "s = E.parse(sys.argv[4]).getroot()\n"
      "assert [d.get('file') for d in s.iter('DataSet')] == ['binary.vti']\n";
  const auto check = dir.write("check.py", script);
  const std::string command =
      "python3 " + check.string() + " " + MGELASTIC_SOURCE_DIR "/tests/app " +
      (dir.path() / "binary.vti").string() + " " + (dir.path() / "ascii.vti").string() + " " +
      (dir.path() / "series.pvd").string();
  EXPECT_EQ(std::system(command.c_str()), 0);
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "binary.vti.tmp"));
}

TEST(VtkWriters, WrongArraySizeIsAnErrorAndLeavesNoFile) {
  test::TempDir dir;
  const auto path = dir.path() / "bad.vti";
  ImageData image;
  image.cells = Eigen::Vector3i(1, 1, 1);
  image.cell_data.push_back({"pressure", 1, {1.0, 2.0}});
  EXPECT_THROW(write_vti(path, image), Error);
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));
}

TEST(AtomicFile, ExistingFileSurvivesAFailedWrite) {
  test::TempDir dir;
  const auto path = dir.path() / "keep.txt";
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
