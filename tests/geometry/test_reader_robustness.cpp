// Regressions from fuzzing the readers (fuzz/, docs/reliability.md): corrupt counts, extreme
// integers and degenerate headers must end in mgelastic::Error (or a correct mesh), never in a
// huge allocation, an endless loop, integer overflow or another exception type. Each test is an
// input that once broke a reader; the asan preset runs them with the sanitizers.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>

#include "mgelastic/core/error.hpp"
#include "mgelastic/geometry/surface_mesh_readers.hpp"
#include "mgelastic/geometry/tet_mesh_readers.hpp"
#include "support/error_of.hpp"
#include "support/temp_dir.hpp"

namespace mgelastic::geometry {
namespace {

using test::TempDir;

using test::error_of;

template <class T>
void put(std::string& s, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  s.append(bytes, sizeof(T));
}

const std::string kLongMax = "9223372036854775807";
const std::string kLongMin = "-9223372036854775808";

// Two tets sharing a face, as MEDIT vertices / tetrahedra sections.
const std::string kMeditVertices = "Vertices\n5\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n1 1 1 0\n";
const std::string kMeditTets = "Tetrahedra\n2\n1 2 3 4 7\n2 3 4 5 8\n";

// Found by fuzz_medit: the skipped entries were counted as count * width, which overflowed.
TEST(ReaderRobustness, MeditHugeSkippedSectionCountIsAnError) {
  TempDir dir;
  const auto path = dir.write(
      "m.mesh", "Dimension 3\n" + kMeditVertices + "Triangles\n4444444444444444441\n1 2 3 0\n");
  EXPECT_NE(error_of([&] { read_medit(path); }).find("cannot hold 4444444444444444441 Triangles"),
            std::string::npos);
}

TEST(ReaderRobustness, MeditHugeVertexCountIsAnErrorNotAnAllocation) {
  TempDir dir;
  const auto path = dir.write("m.mesh", "Vertices\n" + kLongMax + "\n0 0 0 0\n");
  EXPECT_NE(error_of([&] { read_medit(path); }).find("cannot hold"), std::string::npos);
}

TEST(ReaderRobustness, MeditSmallestLongIndexIsOutOfRange) {
  TempDir dir;
  const auto path =
      dir.write("m.mesh", kMeditVertices + "Tetrahedra\n1\n" + kLongMin + " 2 3 4 0\nEnd\n");
  EXPECT_NE(error_of([&] { read_medit(path); }).find("vertex index " + kLongMin + " out of range"),
            std::string::npos);
}

TEST(ReaderRobustness, MeditStillReadsTheTwoTets) {
  TempDir dir;
  const auto path = dir.write("m.mesh", kMeditVertices + "Edges\n1\n1 2 0\n" + kMeditTets);
  const TetMesh mesh = read_medit(path);
  EXPECT_EQ(mesh.vertex_count(), 5);
  EXPECT_EQ(mesh.tet_count(), 2);
}

const std::string kTetgenNodes = "5 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n4 1 1 1\n";

TEST(ReaderRobustness, TetgenHugeCountsAreErrors) {
  TempDir dir;
  dir.write("a.ele", "1 4 0\n0 0 1 2 3\n");
  dir.write("a.node", kLongMax + " 3 0 0\n0 0 0 0\n");
  EXPECT_NE(error_of([&] { read_tetgen(dir.path() / "a"); }).find("cannot hold"),
            std::string::npos);
  // 4 + attributes + markers overflowed before the count was checked.
  dir.write("a.node", "1 3 " + kLongMax + " 1\n0 0 0 0\n");
  EXPECT_NE(error_of([&] { read_tetgen(dir.path() / "a"); }).find("attributes per node"),
            std::string::npos);
  dir.write("a.node", kTetgenNodes);
  dir.write("a.ele", "1 4 " + kLongMax + "\n0 0 1 2 3\n");
  EXPECT_NE(error_of([&] { read_tetgen(dir.path() / "a"); }).find("attributes per tetrahedron"),
            std::string::npos);
}

TEST(ReaderRobustness, TetgenSmallestLongIndexIsOutOfRange) {
  TempDir dir;
  dir.write("a.node", "5 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n");  // 1-based
  dir.write("a.ele", "1 4 0\n1 " + kLongMin + " 2 3 4\n");
  EXPECT_NE(error_of([&] { read_tetgen(dir.path() / "a"); }).find("out of range"),
            std::string::npos);
}

const std::string kGmsh22Nodes =
    "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"
    "5 1 1 1\n$EndNodes\n";

TEST(ReaderRobustness, GmshAsciiHugeTagCountIsAnError) {
  TempDir dir;
  const auto path = dir.write(
      "m.msh", kGmsh22Nodes + "$Elements\n1\n1 4 " + kLongMax + " 1 2 3 4\n$EndElements\n");
  EXPECT_NE(error_of([&] { read_gmsh(path); }).find("invalid tag count"), std::string::npos);
}

TEST(ReaderRobustness, GmshBinaryHugeTagCountIsAnError) {
  TempDir dir;
  std::string s = "$MeshFormat\n2.2 1 8\n";
  put<int>(s, 1);
  s += "\n$EndMeshFormat\n$Nodes\n1\n";
  put<int>(s, 1);
  for (double c : {0.0, 0.0, 0.0}) put<double>(s, c);
  s += "\n$EndNodes\n$Elements\n1\n";
  for (int value : {4, 1, 2147483647}) put<int>(s, value);  // one tet with 2^31 - 1 tags
  const auto path = dir.write("m.msh", s);
  EXPECT_NE(error_of([&] { read_gmsh(path); }).find("element tags"), std::string::npos);
}

TEST(ReaderRobustness, GmshHugeNodeBlockIsAnErrorNotAnAllocation) {
  TempDir dir;
  const auto ascii =
      dir.write("a.msh", "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 " + kLongMax + " 1 " +
                             kLongMax + "\n3 1 0 " + kLongMax + "\n1\n0 0 0\n$EndNodes\n");
  EXPECT_NE(error_of([&] { read_gmsh(ascii); }).find("cannot hold"), std::string::npos);
  std::string s = "$MeshFormat\n4.1 1 8\n";
  put<int>(s, 1);
  s += "\n$EndMeshFormat\n$Nodes\n";
  for (std::uint64_t value : {1ull, 1ull << 40, 1ull, 1ull << 40}) put<std::uint64_t>(s, value);
  for (int value : {3, 1, 0}) put<int>(s, value);
  put<std::uint64_t>(s, 1ull << 40);  // a trillion nodes announced, none present
  const auto binary = dir.write("b.msh", s);
  EXPECT_NE(error_of([&] { read_gmsh(binary); }).find("cannot hold"), std::string::npos);
}

const std::string kPlyTet = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";

std::string ply_header(const std::string& extra_face_property = "",
                       const std::string& extra_elements = "") {
  return "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
         "property float z\nelement face 4\nproperty list uchar int vertex_indices\n" +
         extra_face_property + extra_elements + "end_header\n";
}

// A skipped float list was converted to long item by item: 1e300 overflowed (undefined).
TEST(ReaderRobustness, PlySkippedFloatListWithHugeValuesIsRead) {
  TempDir dir;
  const auto path =
      dir.write("m.ply", ply_header("property list uchar double weights\n") +
                             "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1 1 1e300\n3 0 1 3 0\n"
                             "3 0 3 2 2 -1e300 nan\n3 1 2 3 0\n");
  const TriangleMesh mesh = read_ply(path);
  EXPECT_EQ(mesh.vertices.rows(), 4);
  EXPECT_EQ(mesh.triangles.rows(), 4);
}

// ASCII indices went through double: 2^63 - 1 rounded to 2^63, which overflowed long.
TEST(ReaderRobustness, PlyLargestLongIndexIsOutOfRange) {
  TempDir dir;
  const auto path =
      dir.write("m.ply", ply_header() + "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 " + kLongMax + "\n");
  EXPECT_NE(error_of([&] { read_ply(path); }).find("out of range"), std::string::npos);
}

// An element without properties holds no data: a count of 10^18 must not loop 10^18 times.
TEST(ReaderRobustness, PlyEmptyElementWithHugeCountIsSkipped) {
  TempDir dir;
  const auto path =
      dir.write("m.ply", ply_header("", "element nothing 1000000000000000000\n") + kPlyTet);
  EXPECT_EQ(read_ply(path).triangles.rows(), 4);
}

// 2 * vertex count overflowed when the reserve hint was computed.
TEST(ReaderRobustness, PlyHugeVertexCountIsAnError) {
  TempDir dir;
  const auto path = dir.write("m.ply", "ply\nformat binary_little_endian 1.0\nelement vertex " +
                                           kLongMax + "\nproperty float x\nproperty float y\n" +
                                           "property float z\nend_header\nabc");
  EXPECT_NE(error_of([&] { read_ply(path); }).find("truncated"), std::string::npos);
}

TEST(ReaderRobustness, OffHugeCountsAreAnErrorNotAnAllocation) {
  TempDir dir;
  const auto path = dir.write("m.off", "OFF\n" + kLongMax + " " + kLongMax + " 0\n0 0 0\n");
  EXPECT_NE(error_of([&] { read_off(path); }).find("unexpected end of file"), std::string::npos);
}

}  // namespace
}  // namespace mgelastic::geometry
