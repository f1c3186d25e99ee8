#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "mgelastic/core/error.hpp"
#include "mgelastic/scene/scene.hpp"
#include "mgelastic/scene/schema.hpp"
#include "scene/scene_test_support.hpp"

namespace mgelastic::scene {
namespace {

nlohmann::json minimal() {
  return nlohmann::json::parse(R"({"geometry": {"sphere": {"radius": 0.5}}})");
}

using test::parse_error_of;

TEST(Scene, MinimalSceneGetsDocumentedDefaults) {
  const Scene s = parse_scene(minimal(), "scene.json", ".");
  EXPECT_EQ(s.engine, "grid");
  EXPECT_EQ(s.resolution, 64);
  EXPECT_DOUBLE_EQ(s.poisson_ratio, 0.45);
  EXPECT_DOUBLE_EQ(s.gravity.y(), -9.81);
  EXPECT_EQ(s.precision, "float");
  EXPECT_EQ(s.formats, (std::vector<std::string>{"vtk", "obj"}));
  EXPECT_DOUBLE_EQ(s.geometry["sphere"]["center"][0].get<double>(), 0.0);  // primitive default
}

TEST(Scene, UnknownKeyIsNamedByPointer) {
  auto d = minimal();
  d["grid"] = {{"cellsize", 0.1}};
  EXPECT_EQ(
      parse_error_of(d),
      "scene.json: /grid/cellsize: unknown key (expected one of: cell_size, resolution, padding)");
}

TEST(Scene, WrongTypeIsNamedByPointer) {
  auto d = minimal();
  d["material"] = {{"youngs_modulus", "soft"}};
  EXPECT_EQ(parse_error_of(d),
            "scene.json: /material/youngs_modulus: expected a number, got string");
}

TEST(Scene, OutOfRangeValueIsNamedWithTheValue) {
  auto d = minimal();
  d["material"] = {{"poisson_ratio", 0.5}};
  EXPECT_EQ(parse_error_of(d), "scene.json: /material/poisson_ratio: must be < 0.5 (got 0.5)");
}

TEST(Scene, MissingGeometryIsReported) {
  EXPECT_EQ(parse_error_of(nlohmann::json::object()),
            "scene.json: /geometry: missing required key");
}

TEST(Scene, ShapeErrorsPointIntoTheShapeTree) {
  auto d = minimal();
  d["constraints"] = nlohmann::json::parse(
      R"([{"region": {"union": [{"box": {"size": [1, 1, 1]}}, {"sphere": {"radius": -1}}]}}])");
  EXPECT_EQ(parse_error_of(d),
            "scene.json: /constraints/0/region/union/1/sphere/radius: must be > 0 (got -1)");
  d["geometry"] = nlohmann::json::parse(R"({"sphere": {"radius": 1}, "box": {"size": [1, 1, 1]}})");
  EXPECT_NE(parse_error_of(d).find("/geometry: a shape has exactly one of"), std::string::npos);
}

TEST(Scene, InvalidJsonNamesTheLine) {
  const auto path = std::filesystem::temp_directory_path() / "mgelastic_bad_scene.json";
  std::ofstream(path) << "{\n  \"geometry\": {\"sphere\": {\"radius\": 1}},\n  \"grid\": {,}\n}\n";
  try {
    load_scene(path);
    FAIL() << "expected an error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find(path.string() + ":3: invalid JSON"), std::string::npos)
        << e.what();
  }
  std::filesystem::remove(path);
}

TEST(Scene, MissingFileIsReported) {
  EXPECT_THROW(load_scene("/nonexistent/scene.json"), Error);
}

// docs/scene-format.md is generated from the schema; regenerate with
// `mgelastic scene-format > docs/scene-format.md` when the schema changes.
TEST(Scene, FormatPageMatchesTheSchema) {
  std::ifstream in(std::filesystem::path(MGELASTIC_SOURCE_DIR) / "docs" / "scene-format.md");
  ASSERT_TRUE(in) << "docs/scene-format.md is missing";
  std::stringstream page;
  page << in.rdbuf();
  EXPECT_EQ(page.str(), scene_format_markdown());
}

// solver.precision "single" has no double solution level: what needs one is refused at load,
// naming the field and the reason.
nlohmann::json single_precision(const nlohmann::json& solver = nlohmann::json::object()) {
  auto d = minimal();
  d["solver"] = solver;
  d["solver"]["precision"] = "single";
  return d;
}

TEST(Scene, SinglePrecisionLinearQuasistaticIsAccepted) {
  const Scene s = parse_scene(single_precision(), "scene.json", ".");
  EXPECT_EQ(s.precision, "single");
  EXPECT_TRUE(s.accelerate);  // the default; single precision iterates cycles alone
}

TEST(Scene, SinglePrecisionRefusesTheCorotatedModel) {
  auto d = single_precision();
  d["material"] = {{"model", "corotated"}};
  const std::string error = parse_error_of(d);
  EXPECT_EQ(error.rfind("scene.json: /solver/precision: ", 0), 0u) << error;
  EXPECT_NE(error.find("linear model only"), std::string::npos) << error;
}

TEST(Scene, SinglePrecisionRefusesDynamics) {
  auto d = single_precision();
  d["time"] = {{"quasistatic", false}};
  const std::string error = parse_error_of(d);
  EXPECT_EQ(error.rfind("scene.json: /solver/precision: ", 0), 0u) << error;
  EXPECT_NE(error.find("quasistatic scenes only"), std::string::npos) << error;
}

TEST(Scene, SinglePrecisionRefusesAnExplicitAcceleration) {
  const std::string error = parse_error_of(single_precision({{"accelerate", true}}));
  EXPECT_EQ(error.rfind("scene.json: /solver/precision: ", 0), 0u) << error;
  EXPECT_NE(error.find("accelerate"), std::string::npos) << error;
  EXPECT_EQ(parse_error_of(single_precision({{"accelerate", false}})), "");
}

// The tet engine has no multigrid precision to restrict.
TEST(Scene, SinglePrecisionChecksOnlyTheGridEngine) {
  auto d = single_precision();
  d["engine"] = "tet";
  d["time"] = {{"quasistatic", false}};
  EXPECT_EQ(parse_error_of(d), "");
}

}  // namespace
}  // namespace mgelastic::scene

#include "mgelastic/scene/build_shape.hpp"
#include "mgelastic/scene/grid_setup.hpp"

namespace mgelastic::scene {
namespace {

Scene grid_bar_scene() {
  return parse_scene(nlohmann::json::parse(R"({
    "geometry": {"difference": [{"box": {"size": [1, 0.25, 0.25]}},
                                {"cylinder": {"a": [0, -1, 0], "b": [0, 1, 0], "radius": 0.12}}]},
    "grid": {"resolution": 32},
    "constraints": [{"region": {"box": {"center": [-0.5, 0, 0], "size": [0.1, 1, 1]}}}]
  })"),
                     "bar.json", ".");
}

TEST(GridSetup, VoxelizesTheBodyAndMarksConstraintCells) {
  const GridSetup setup = build_grid_setup(grid_bar_scene());
  EXPECT_GT(setup.interior_cells, 32u * 8 * 8 / 2);
  EXPECT_GT(setup.dirichlet_cells, 0u);
  // The drilled hole at the center is exterior: the cell at the bar's center is not interior.
  const auto& p = setup.problem;
  const grid::Vec<3> center(0.01, 0.01, 0.01);
  const grid::IVec<3> s =
      ((center - p.lattice.origin) / p.lattice.h).cast<int>() + grid::IVec<3>::Ones();
  EXPECT_EQ(p.cells[p.lattice.index(s)], grid::CellType::EXTERIOR);
  EXPECT_NEAR(p.body_force(center).y(), -9.81 * 1000, 1e-9);
}

TEST(GridSetup, RegionSelectingNothingIsAnError) {
  Scene s = grid_bar_scene();
  s.constraints[0].region =
      nlohmann::json::parse(R"({"sphere": {"center": [5, 5, 5], "radius": 0.1}})");
  try {
    build_grid_setup(s);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()),
              "bar.json: /constraints/0/region: the region selects no cell of the body at this "
              "resolution");
  }
}

TEST(BuildShape, GeometryParameterErrorsNameTheScenePointer) {
  const auto spec =
      nlohmann::json::parse(R"({"cylinder": {"a": [0, 0, 0], "b": [0, 0, 0], "radius": 1}})");
  try {
    build_shape(spec, ".", "s.json", "/geometry");
    FAIL();
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("s.json: /geometry/cylinder/b - a"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace mgelastic::scene
