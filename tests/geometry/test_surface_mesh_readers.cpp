#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <limits>
#include <sstream>

#include "geometry/surface_mesh_test_support.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/geometry/surface_mesh_readers.hpp"
#include "mgelastic/io/surface_mesh_writers.hpp"
#include "support/error_of.hpp"

namespace mgelastic::geometry {
namespace {

using test::make_box_mesh;
using test::make_icosphere;
using test::SurfaceTempDir;

using test::error_of;

// A mesh off the origin with non-terminating binary fractions, so round-trips test all digits.
TriangleMesh sample_mesh() {
  return make_icosphere(2, 0.7310585786300049, Eigen::Vector3d(0.1, -1.0 / 3.0, 2.0 / 7.0));
}

void expect_identical(const TriangleMesh& a, const TriangleMesh& b) {
  ASSERT_EQ(a.vertices.rows(), b.vertices.rows());
  ASSERT_EQ(a.triangles.rows(), b.triangles.rows());
  EXPECT_TRUE(a.vertices == b.vertices);  // bit-exact: max_digits10 / binary doubles
  EXPECT_TRUE(a.triangles == b.triangles);
}

template <class T>
void put_big_endian(std::string& out, T value) {
  char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if constexpr (std::endian::native == std::endian::little)
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(bytes[i], bytes[sizeof(T) - 1 - i]);
  out.append(bytes, sizeof(T));
}

TEST(SurfaceMeshReaders, ObjRoundTripIsExact) {
  SurfaceTempDir dir;
  const TriangleMesh mesh = sample_mesh();
  io::write_obj(dir.path() / "sphere.obj", mesh.vertices, mesh.triangles);
  expect_identical(read_surface_mesh(dir.path() / "sphere.obj"), mesh);
}

TEST(SurfaceMeshReaders, PlyAsciiAndBinaryRoundTripsAreExact) {
  SurfaceTempDir dir;
  const TriangleMesh mesh = sample_mesh();
  io::write_ply(dir.path() / "ascii.ply", mesh.vertices, mesh.triangles, false);
  io::write_ply(dir.path() / "binary.ply", mesh.vertices, mesh.triangles, true);
  expect_identical(read_surface_mesh(dir.path() / "ascii.ply"), mesh);
  expect_identical(read_surface_mesh(dir.path() / "binary.ply"), mesh);
}

// Binary STL stores corners by value in float32: welding must restore the shared vertices, so the
// mesh comes back closed, with the same triangles up to float rounding.
TEST(SurfaceMeshReaders, BinaryStlRoundTripWeldsCorners) {
  SurfaceTempDir dir;
  const TriangleMesh mesh = sample_mesh();
  io::write_stl_binary(dir.path() / "sphere.stl", mesh.vertices, mesh.triangles);
  const TriangleMesh read = read_surface_mesh(dir.path() / "sphere.stl");
  EXPECT_EQ(read.vertex_count(), mesh.vertex_count());
  ASSERT_EQ(read.triangle_count(), mesh.triangle_count());
  for (Eigen::Index t = 0; t < mesh.triangle_count(); ++t)
    for (int k = 0; k < 3; ++k)
      EXPECT_LT((read.vertices.row(read.triangles(t, k)) - mesh.vertices.row(mesh.triangles(t, k)))
                    .norm(),
                test::kFloat32Rounding);
  EXPECT_TRUE(mesh_facts(read).closed);
}

// ASCII STL beginning with "solid", several solids, upper-case-free keywords: a tetrahedron.
TEST(SurfaceMeshReaders, AsciiStlIsReadAndWelded) {
  SurfaceTempDir dir;
  const char* corners[4][3] = {{"0 0 0", "0 1 0", "1 0 0"},
                               {"0 0 0", "1 0 0", "0 0 1"},
                               {"0 0 0", "0 0 1", "0 1 0"},
                               {"1 0 0", "0 1 0", "0 0 1"}};
  std::ostringstream text;
  text << "solid tet\n";
  for (const auto& facet : corners) {
    text << "  facet normal 0 0 0\n    outer loop\n";
    for (const char* corner : facet) text << "      vertex " << corner << "\n";
    text << "    endloop\n  endfacet\n";
  }
  text << "endsolid tet\n";
  const TriangleMesh mesh = read_surface_mesh(dir.write("tet.STL", text.str()));
  EXPECT_EQ(mesh.vertex_count(), 4);
  EXPECT_EQ(mesh.triangle_count(), 4);
  const MeshFacts facts = mesh_facts(mesh);
  EXPECT_TRUE(facts.closed && facts.manifold && facts.consistently_oriented);
  EXPECT_NEAR(facts.signed_volume, 1.0 / 6.0, 1e-15);
}

// OFF with quads (fan-triangulated), comments, and the counts on the header line.
TEST(SurfaceMeshReaders, OffQuadsAreTriangulated) {
  SurfaceTempDir dir;
  const std::string text =
      "OFF 8 6 12\n# unit cube\n"
      "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
      "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 2 3 7 6\n4 1 2 6 5\n4 0 4 7 3 255 0 0\n";
  const TriangleMesh mesh = read_surface_mesh(dir.write("cube.off", text));
  EXPECT_EQ(mesh.triangle_count(), 12);
  const MeshFacts facts = mesh_facts(mesh);
  EXPECT_TRUE(facts.closed && facts.manifold && facts.consistently_oriented);
  EXPECT_NEAR(facts.signed_volume, 1.0, 1e-15);
}

// v/vt/vn corners, negative indices, a quad, ignored statements and comments.
TEST(SurfaceMeshReaders, ObjCornerFormsAndRelativeIndices) {
  SurfaceTempDir dir;
  const std::string text =
      "# comment\nmtllib cube.mtl\no cube\ng side\ns off\nusemtl red\n"
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 -1\n"
      "f 1/1/1 4/1/1 3/1/1 2/1/1\n"  // a quad
      "f -4//1 -3//1 -1//1\n"        // relative: vertices 1, 2, 4
      "f 1/1 2/1 3/1 # trailing comment\n";
  const TriangleMesh mesh = read_surface_mesh(dir.write("quad.Obj", text));
  ASSERT_EQ(mesh.triangle_count(), 4);
  EXPECT_EQ(mesh.triangles.row(0), Eigen::RowVector3i(0, 3, 2));
  EXPECT_EQ(mesh.triangles.row(1), Eigen::RowVector3i(0, 2, 1));
  EXPECT_EQ(mesh.triangles.row(2), Eigen::RowVector3i(0, 1, 3));
  EXPECT_EQ(mesh.triangles.row(3), Eigen::RowVector3i(0, 1, 2));
}

// Properties other than x, y, z and vertex_indices are skipped by type, in both byte orders.
TEST(SurfaceMeshReaders, PlySkipsOtherPropertiesAndElements) {
  SurfaceTempDir dir;
  const std::string header =
      "ply\nformat %s 1.0\ncomment test\nelement vertex 4\nproperty uchar red\n"
      "property float x\nproperty float y\nproperty double z\nproperty list uchar int extra\n"
      "element face 2\nproperty list uint uint vertex_indices\nproperty short flags\n"
      "element edge 1\nproperty int v1\nproperty int v2\nend_header\n";
  const auto with_format = [&](const std::string& format) {
    std::string h = header;
    return h.replace(h.find("%s"), 2, format);
  };
  const std::string ascii = with_format("ascii") +
                            "7 0 0 0 2 5 6\n7 1 0 0 0\n7 0 1 0 1 9\n7 0 0 1 0\n"
                            "3 0 2 1 -4\n3 0 1 3 12\n0 1\n";
  std::string binary = with_format("binary_big_endian");
  const float xy[4][2] = {{0, 0}, {1, 0}, {0, 1}, {0, 0}};
  const double z[4] = {0, 0, 0, 1};
  for (int v = 0; v < 4; ++v) {
    put_big_endian<std::uint8_t>(binary, 7);
    put_big_endian(binary, xy[v][0]);
    put_big_endian(binary, xy[v][1]);
    put_big_endian(binary, z[v]);
    put_big_endian<std::uint8_t>(binary, 1);
    put_big_endian<std::int32_t>(binary, -1);
  }
  for (const auto& face : {std::array<std::uint32_t, 3>{0, 2, 1}, {0, 1, 3}}) {
    put_big_endian<std::uint32_t>(binary, 3);
    for (const std::uint32_t i : face) put_big_endian(binary, i);
    put_big_endian<std::int16_t>(binary, 3);
  }
  put_big_endian<std::int32_t>(binary, 0);
  put_big_endian<std::int32_t>(binary, 1);
  for (const auto& file : {dir.write("a.ply", ascii), dir.write("b.PLY", binary)}) {
    const TriangleMesh mesh = read_surface_mesh(file);
    ASSERT_EQ(mesh.vertex_count(), 4) << file;
    EXPECT_EQ(mesh.vertices.row(3), Eigen::RowVector3d(0, 0, 1)) << file;
    ASSERT_EQ(mesh.triangle_count(), 2) << file;
    EXPECT_EQ(mesh.triangles.row(1), Eigen::RowVector3i(0, 1, 3)) << file;
  }
}

TEST(SurfaceMeshReaders, UnknownExtensionNamesFileAndFormats) {
  const std::string message = error_of([] { read_surface_mesh("model.xyz"); });
  EXPECT_NE(message.find("model.xyz"), std::string::npos) << message;
  EXPECT_NE(message.find(".obj, .stl, .ply, .off"), std::string::npos) << message;
}

TEST(SurfaceMeshReaders, MissingFileIsNamed) {
  const std::string message = error_of([] { read_surface_mesh("/nonexistent/bunny.obj"); });
  EXPECT_NE(message.find("/nonexistent/bunny.obj"), std::string::npos) << message;
  EXPECT_NE(message.find("cannot open"), std::string::npos) << message;
}

// Each malformed text file reports "file:line:" and what is wrong.
TEST(SurfaceMeshReaders, MalformedTextNamesFileAndLine) {
  SurfaceTempDir dir;
  const std::string tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
  const std::vector<std::array<std::string, 4>> cases = {
      // file name, content, expected "file:line", expected words
      {"number.obj", "v 0 0 0\nv 1 0 0\nv 0 1.5x 0\nf 1 2 3\n", "number.obj:3:", "1.5x"},
      {"range.obj", tri + "f 1 2 3\nf 1 2 9\n", "range.obj:5:", "face 1: vertex index 9"},
      {"relative.obj", tri + "f -1 -2 -7\n", "relative.obj:4:", "face 0"},
      {"nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", "nan.obj:2:", "NaN"},
      {"inf.off", "OFF\n3 1 0\n0 0 0\n1 inf 0\n0 1 0\n3 0 1 2\n", "inf.off:4:", "infinite"},
      {"empty.obj", tri, "empty.obj", "no triangles"},
      {"range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
       "range.off:6:", "face 0: vertex index 3 out of range"},
      {"short.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
       "short.off:7:", "after 1 of 2 faces"},
      {"long.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n",
       "long.off:7:", "do not match"},
      {"size.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n", "size.off:6:", "announces 4"},
      {"count.ply",
       "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
       "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
       "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 2\n",
       "count.ply:14:", "do not match"},
      {"word.stl", "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvortex 1 0 0\n",
       "word.stl:5:", "vortex"},
  };
  for (const auto& [name, content, where, what] : cases) {
    const auto file = dir.write(name, content);
    const std::string message = error_of([&] { read_surface_mesh(file); });
    EXPECT_NE(message.find(where), std::string::npos) << name << ": " << message;
    EXPECT_NE(message.find(what), std::string::npos) << name << ": " << message;
  }
}

// Truncated binary data reports the file and the byte offset where data ran out.
TEST(SurfaceMeshReaders, TruncatedBinaryNamesFileAndByteOffset) {
  SurfaceTempDir dir;
  const TriangleMesh mesh = make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 2);
  io::write_ply(dir.path() / "full.ply", mesh.vertices, mesh.triangles, true);
  io::write_stl_binary(dir.path() / "full.stl", mesh.vertices, mesh.triangles);
  for (const std::string ext : {".ply", ".stl"}) {
    std::ifstream in(dir.path() / ("full" + ext), std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const auto file = dir.write("cut" + ext, bytes.substr(0, bytes.size() - 7));
    const std::string message = error_of([&] { read_surface_mesh(file); });
    EXPECT_NE(message.find(file.string()), std::string::npos) << message;
    EXPECT_NE(message.find("byte"), std::string::npos) << message;
    EXPECT_NE(message.find("truncated"), std::string::npos) << message;
  }
}

// The writers refuse an index that would make an unreadable file.
TEST(SurfaceMeshWriters, OutOfRangeIndexIsRefused) {
  SurfaceTempDir dir;
  TriangleMesh mesh = make_box_mesh(Eigen::Vector3d::Zero(), Eigen::Vector3d::Ones(), 1);
  mesh.triangles(5, 1) = 99;
  const std::string message =
      error_of([&] { io::write_obj(dir.path() / "bad.obj", mesh.vertices, mesh.triangles); });
  EXPECT_NE(message.find("triangle 5"), std::string::npos) << message;
  EXPECT_FALSE(std::filesystem::exists(dir.path() / "bad.obj"));
}

}  // namespace
}  // namespace mgelastic::geometry
