// Tetrahedral mesh readers: every format on a small two-tet file written by the test (Gmsh in
// all four variants), and malformed files that must name the line or element.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>

#include "mgelastic/core/error.hpp"
#include "mgelastic/geometry/tet_mesh_readers.hpp"
#include "tet/tet_test_support.hpp"

namespace mgelastic::geometry {
namespace {

using test::TempDir;

// Two positively oriented tets sharing the face (1, 2, 3) (zero-based vertex ids).
const double kPoints[5][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
const int kTets[2][4] = {{0, 1, 2, 3}, {1, 2, 3, 4}};

void expect_two_tets(const TetMesh& mesh) {
  ASSERT_EQ(mesh.vertex_count(), 5);
  ASSERT_EQ(mesh.tet_count(), 2);
  for (int v = 0; v < 5; ++v)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(mesh.vertices(v, k), kPoints[v][k]);
  for (int t = 0; t < 2; ++t)
    for (int a = 0; a < 4; ++a) EXPECT_EQ(mesh.tets(t, a), kTets[t][a]);
}

// Runs `read` and returns the Error it must throw.
template <class Read>
Error expect_error(Read read) {
  try {
    read();
  } catch (const Error& error) {
    return error;
  }
  ADD_FAILURE() << "no mgelastic::Error thrown";
  return Error("none");
}

// ---- text fixtures ----

std::string tetgen_node(int base) {
  std::string s = "# comment line\n5 3 0 0\n";
  for (int v = 0; v < 5; ++v)
    s += std::to_string(v + base) + " " + std::to_string(kPoints[v][0]) + " " +
         std::to_string(kPoints[v][1]) + " " + std::to_string(kPoints[v][2]) + "\n";
  return s;
}

std::string tetgen_ele(int base, int count = 2, bool extra_line = false) {
  std::string s = std::to_string(count) + " 4 0\n";
  for (int t = 0; t < 2; ++t) {
    if (t >= count && !extra_line) break;
    s += std::to_string(t + base);
    for (int a = 0; a < 4; ++a) s += " " + std::to_string(kTets[t][a] + base);
    s += "\n";
  }
  return s;
}

std::string gmsh22_ascii() {
  return "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n3 7 \"body\"\n"
         "$EndPhysicalNames\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 1 1 1\n$EndNodes\n"
         "$Elements\n3\n1 2 2 7 1 1 2 3\n2 4 2 7 1 1 2 3 4\n3 4 2 8 1 2 3 4 5\n$EndElements\n";
}

std::string gmsh41_ascii() {
  return "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 0 0 1\n1 0 0 0 1 1 1 0 0\n"
         "$EndEntities\n$Nodes\n1 5 1 5\n3 1 0 5\n1\n2\n3\n4\n5\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
         "1 1 1\n$EndNodes\n$Elements\n2 3 1 3\n2 1 2 1\n1 1 2 3\n3 1 4 2\n2 1 2 3 4\n"
         "3 2 3 4 5\n$EndElements\n";
}

std::string medit() {
  return "MeshVersionFormatted 1\nDimension 3\n# a comment\nVertices\n5\n0 0 0 0\n1 0 0 0\n"
         "0 1 0 0\n0 0 1 0\n1 1 1 0\nTriangles\n1\n1 2 3 0\nTetrahedra\n2\n1 2 3 4 7\n"
         "2 3 4 5 8\nEnd\n";
}

// ---- binary fixtures ----

template <class T>
void put(std::string& s, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  s.append(bytes, sizeof(T));
}

std::string gmsh22_binary() {
  std::string s = "$MeshFormat\n2.2 1 8\n";
  put<int>(s, 1);
  s += "\n$EndMeshFormat\n$Nodes\n5\n";
  for (int v = 0; v < 5; ++v) {
    put<int>(s, v + 1);
    for (double c : kPoints[v]) put<double>(s, c);
  }
  s += "\n$EndNodes\n$Elements\n3\n";
  for (int value : {2, 1, 2, 1, 7, 1, 1, 2, 3}) put<int>(s, value);  // one triangle block
  for (int value : {4, 2, 2}) put<int>(s, value);                    // two tets, two tags
  for (int t = 0; t < 2; ++t) {
    for (int value : {t + 2, 7 + t, 1}) put<int>(s, value);
    for (int a = 0; a < 4; ++a) put<int>(s, kTets[t][a] + 1);
  }
  s += "\n$EndElements\n";
  return s;
}

std::string gmsh41_binary() {
  std::string s = "$MeshFormat\n4.1 1 8\n";
  put<int>(s, 1);
  s += "\n$EndMeshFormat\n$Nodes\n";
  for (std::uint64_t value : {1, 5, 1, 5}) put<std::uint64_t>(s, value);
  for (int value : {3, 1, 0}) put<int>(s, value);
  put<std::uint64_t>(s, 5);
  for (std::uint64_t tag = 1; tag <= 5; ++tag) put<std::uint64_t>(s, tag);
  for (const auto& p : kPoints)
    for (double c : p) put<double>(s, c);
  s += "\n$EndNodes\n$Elements\n";
  for (std::uint64_t value : {2, 3, 1, 3}) put<std::uint64_t>(s, value);
  for (int value : {2, 1, 2}) put<int>(s, value);
  for (std::uint64_t value : {1, 1, 1, 2, 3}) put<std::uint64_t>(s, value);
  for (int value : {3, 1, 4}) put<int>(s, value);
  put<std::uint64_t>(s, 2);
  for (int t = 0; t < 2; ++t) {
    put<std::uint64_t>(s, t + 2);
    for (int a = 0; a < 4; ++a) put<std::uint64_t>(s, kTets[t][a] + 1);
  }
  s += "\n$EndElements\n";
  return s;
}

// ---- well-formed files ----

TEST(TetMeshReaders, TetGenZeroBased) {
  TempDir dir;
  dir.write("m.node", tetgen_node(0));
  dir.write("m.ele", tetgen_ele(0));
  expect_two_tets(read_tet_mesh(dir.path() / "m.node"));
}

TEST(TetMeshReaders, TetGenOneBasedByBaseName) {
  TempDir dir;
  dir.write("m.node", tetgen_node(1));
  dir.write("m.ele", tetgen_ele(1));
  expect_two_tets(read_tetgen(dir.path() / "m"));
}

TEST(TetMeshReaders, GmshAscii22KeepsTetsAndPhysicalTags) {
  TempDir dir;
  const TetMesh mesh = read_tet_mesh(dir.write("m.msh", gmsh22_ascii()));
  expect_two_tets(mesh);
  EXPECT_EQ(mesh.element_tags(0), 7);
  EXPECT_EQ(mesh.element_tags(1), 8);
}

TEST(TetMeshReaders, GmshAscii41SkipsEntitiesAndTriangles) {
  TempDir dir;
  expect_two_tets(read_tet_mesh(dir.write("m.msh", gmsh41_ascii())));
}

TEST(TetMeshReaders, GmshBinary22) {
  TempDir dir;
  const TetMesh mesh = read_tet_mesh(dir.write("m.msh", gmsh22_binary()));
  expect_two_tets(mesh);
  EXPECT_EQ(mesh.element_tags(1), 8);
}

TEST(TetMeshReaders, GmshBinary41) {
  TempDir dir;
  expect_two_tets(read_tet_mesh(dir.write("m.msh", gmsh41_binary())));
}

TEST(TetMeshReaders, MeditKeepsReferencesAsTags) {
  TempDir dir;
  const TetMesh mesh = read_tet_mesh(dir.write("m.mesh", medit()));
  expect_two_tets(mesh);
  EXPECT_EQ(mesh.element_tags(0), 7);
}

// ---- malformed files ----

TEST(TetMeshReaders, TruncatedNodeFileNamesLine) {
  TempDir dir;
  std::string node = tetgen_node(0);
  node.resize(node.find("3 0.0"));  // drop vertices 3 and 4
  dir.write("m.node", node);
  dir.write("m.ele", tetgen_ele(0));
  const Error error = expect_error([&] { read_tet_mesh(dir.path() / "m.node"); });
  EXPECT_NE(std::string(error.what()).find("truncated"), std::string::npos) << error.what();
  EXPECT_NE(std::string(error.what()).find("m.node"), std::string::npos) << error.what();
  EXPECT_GT(error.context().line, 0);
}

TEST(TetMeshReaders, WrongElementCountNamesLine) {
  TempDir dir;
  dir.write("m.node", tetgen_node(0));
  dir.write("m.ele", tetgen_ele(0, 1, true));  // header says 1, file holds 2
  const Error error = expect_error([&] { read_tet_mesh(dir.path() / "m.ele"); });
  EXPECT_EQ(error.context().line, 3) << error.what();
  EXPECT_NE(std::string(error.what()).find("count"), std::string::npos) << error.what();
}

TEST(TetMeshReaders, BadVertexIndexNamesLine) {
  TempDir dir;
  dir.write("m.node", tetgen_node(0));
  dir.write("m.ele", "2 4 0\n0 0 1 2 3\n1 1 2 3 9\n");
  const Error error = expect_error([&] { read_tet_mesh(dir.path() / "m.ele"); });
  EXPECT_EQ(error.context().line, 3) << error.what();
  EXPECT_NE(std::string(error.what()).find("out of range"), std::string::npos) << error.what();
}

TEST(TetMeshReaders, InvertedTetRejectedInStrictModeNamingElementAndLine) {
  TempDir dir;
  dir.write("m.node", tetgen_node(0));
  dir.write("m.ele", "2 4 0\n0 0 1 2 3\n1 1 3 2 4\n");  // second tet has two vertices swapped
  const TetMeshReadOptions strict{.inverted = InvertedTets::REJECT};
  const Error error = expect_error([&] { read_tet_mesh(dir.path() / "m.ele", strict); });
  EXPECT_EQ(error.context().pointer, "element 1");
  EXPECT_EQ(error.context().line, 3);
  EXPECT_NE(std::string(error.what()).find("inverted"), std::string::npos) << error.what();
}

TEST(TetMeshReaders, InvertedTetFixedByDefault) {
  TempDir dir;
  dir.write("m.node", tetgen_node(0));
  dir.write("m.ele", "2 4 0\n0 0 1 2 3\n1 1 3 2 4\n");
  const TetMesh mesh = read_tet_mesh(dir.path() / "m.ele");
  const Eigen::Matrix<double, 3, 4> c = mesh.corners(1);
  EXPECT_GT(signed_volume6(c.col(0), c.col(1), c.col(2), c.col(3)), 0.0);
}

TEST(TetMeshReaders, ZeroVolumeTetRejectedNamingElement) {
  TempDir dir;
  dir.write("m.mesh",
            "MeshVersionFormatted 1\nDimension 3\nVertices\n5\n0 0 0 0\n1 0 0 0\n0 1 0 0\n"
            "0 0 1 0\n1 1 0 0\nTetrahedra\n2\n1 2 3 4 0\n1 2 3 5 0\nEnd\n");
  const Error error = expect_error([&] { read_tet_mesh(dir.path() / "m.mesh"); });
  EXPECT_EQ(error.context().pointer, "element 1");
  EXPECT_EQ(error.context().line, 13);
  EXPECT_NE(std::string(error.what()).find("zero-volume"), std::string::npos) << error.what();
}

TEST(TetMeshReaders, GmshAsciiTruncatedInElementsNamesLine) {
  TempDir dir;
  std::string text = gmsh22_ascii();
  text.resize(text.find("3 4 2 8"));
  const Error error = expect_error([&] { read_tet_mesh(dir.write("m.msh", text)); });
  EXPECT_GT(error.context().line, 0) << error.what();
  EXPECT_NE(std::string(error.what()).find("truncated"), std::string::npos) << error.what();
}

TEST(TetMeshReaders, GmshWrongNodeCountNamesLine) {
  TempDir dir;
  std::string text = gmsh22_ascii();
  text.replace(text.find("$Nodes\n5"), 8, "$Nodes\n6");
  const Error error = expect_error([&] { read_tet_mesh(dir.write("m.msh", text)); });
  EXPECT_EQ(error.context().line, 15) << error.what();  // the $EndNodes line
}

TEST(TetMeshReaders, GmshUndefinedNodeNamesLine) {
  TempDir dir;
  std::string text = gmsh41_ascii();
  text.replace(text.find("3 2 3 4 5"), 9, "3 2 3 4 9");
  const Error error = expect_error([&] { read_tet_mesh(dir.write("m.msh", text)); });
  EXPECT_EQ(error.context().line, 28) << error.what();
  EXPECT_NE(std::string(error.what()).find("undefined node 9"), std::string::npos);
}

TEST(TetMeshReaders, GmshBinaryTruncatedNamesByteOffset) {
  TempDir dir;
  std::string data = gmsh41_binary();
  data.resize(data.size() - 40);
  const Error error = expect_error([&] { read_tet_mesh(dir.write("m.msh", data)); });
  EXPECT_NE(std::string(error.what()).find("truncated"), std::string::npos) << error.what();
  EXPECT_NE(error.context().pointer.find("byte"), std::string::npos) << error.what();
}

TEST(TetMeshReaders, MeditBadIndexNamesLine) {
  TempDir dir;
  std::string text = medit();
  text.replace(text.find("2 3 4 5 8"), 9, "2 3 4 0 8");
  const Error error = expect_error([&] { read_tet_mesh(dir.write("m.mesh", text)); });
  EXPECT_EQ(error.context().line, 17) << error.what();
}

TEST(TetMeshReaders, MissingFileAndUnknownExtensionAreErrors) {
  TempDir dir;
  EXPECT_THROW(read_tet_mesh(dir.path() / "absent.msh"), Error);
  EXPECT_THROW(read_tet_mesh(dir.write("m.xyz", "")), Error);
}

}  // namespace
}  // namespace mgelastic::geometry
