#include "mgelastic/scene/schema.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "mgelastic/core/error.hpp"

namespace mgelastic::scene {
namespace {

Field number(std::string name, std::string description, std::string unit, nlohmann::json fallback,
             std::optional<double> minimum = {}, bool exclusive_minimum = false,
             std::optional<double> maximum = {}, bool exclusive_maximum = false) {
  Field f{std::move(name), FieldType::NUMBER, std::move(description), std::move(unit),
          std::move(fallback)};
  f.minimum = minimum;
  f.exclusive_minimum = exclusive_minimum;
  f.maximum = maximum;
  f.exclusive_maximum = exclusive_maximum;
  return f;
}

Field integer(std::string name, std::string description, nlohmann::json fallback, int minimum) {
  Field f{std::move(name), FieldType::INTEGER, std::move(description), "", std::move(fallback)};
  f.minimum = minimum;
  return f;
}

Field integer(std::string name, std::string description, nlohmann::json fallback, int minimum,
              int maximum) {
  Field f = integer(std::move(name), std::move(description), std::move(fallback), minimum);
  f.maximum = maximum;
  return f;
}

Field choice(std::string name, std::string description, std::string fallback,
             std::vector<std::string> choices) {
  Field f{std::move(name), FieldType::STRING, std::move(description), "", std::move(fallback)};
  f.choices = std::move(choices);
  return f;
}

Field object(std::string name, std::string description, std::vector<Field> members) {
  Field f{std::move(name), FieldType::OBJECT, std::move(description), "", nlohmann::json::object()};
  f.children = std::move(members);
  return f;
}

Field array(std::string name, std::string description, Field element) {
  Field f{std::move(name), FieldType::ARRAY, std::move(description), "", nlohmann::json::array()};
  f.children = {std::move(element)};
  return f;
}

Field shape(std::string name, std::string description, bool required) {
  Field f{std::move(name), FieldType::SHAPE, std::move(description)};
  f.required = required;
  return f;
}

Field vector3(std::string name, std::string description, std::string unit,
              nlohmann::json fallback) {
  return Field{std::move(name), FieldType::VECTOR3, std::move(description), std::move(unit),
               std::move(fallback)};
}

Field build_schema() {
  Field engine = choice("engine", "Simulation engine: the staggered-grid multigrid or the tet FEM",
                        "grid", {"grid", "tet"});
  Field geometry = shape("geometry", "The elastic body (see Shapes below)", true);
  Field grid = object(
      "grid", "Embedding lattice of the grid engine (Sec. 5.1)",
      {number("cell_size", "Cell edge length; 0 = derive from `resolution`", "m", 0.0, 0.0),
       integer("resolution",
               "Cells along the longest axis of the body's bounding box. A scene whose lattice "
               "would exceed the solver's 32-bit indices (~1e9 cells) or the memory available "
               "(estimated at ~470 bytes per lattice cell, plus up to ~260 MB per "
               "`solver.local_corrections` box) is refused before it allocates",
               64, 4),
       integer("padding", "Extra layers of cells around the body (Sec. 9.2)", 0, 0)});
  Field material_region = object(
      "", "A part of the body with its own material (tet engine)",
      {shape("region", "Tetrahedra whose centroid lies in this shape take this material", true),
       number("youngs_modulus", "Young's modulus E", "Pa", 1e5, 0.0, true),
       number("poisson_ratio", "Poisson ratio nu", "", 0.45, 0.0, false, 0.5, true),
       number("density", "Mass density", "kg/m^3", 1000.0, 0.0, true)});
  Field material = object(
      "material", "Isotropic linear material",
      {number("youngs_modulus", "Young's modulus E", "Pa", 1e5, 0.0, true),
       number("poisson_ratio", "Poisson ratio nu", "", 0.45, 0.0, false, 0.5, true),
       number("density", "Mass density (gravity load)", "kg/m^3", 1000.0, 0.0, true),
       choice("model",
              "Grid engine constitutive model: linear elasticity, or co-rotational linear "
              "elasticity (Sec. 7: stresses in the frame of each cell's rotation, invariant under "
              "large rotations; double precision, rotations refreshed every "
              "`time.rotation_update_every` cycles). The tet engine is always co-rotated",
              "linear", {"linear", "corotated"}),
       array("regions",
             "Heterogeneous bodies (tet engine): later regions override earlier ones and the "
             "material above",
             material_region)});
  Field keyframe = object(
      "", "Rigid pose of the region at a time: x -> R (x - pivot) + pivot + translate",
      {[] {
         Field f =
             number("time", "Key time (strictly increasing along the list)", "s", nullptr, 0.0);
         f.required = true;
         return f;
       }(),
       vector3("translate", "Translation", "m", nlohmann::json::array({0, 0, 0})),
       vector3("rotate_axis", "Rotation axis", "", nlohmann::json::array({0, 0, 1})),
       number("rotate_degrees", "Rotation angle about the axis through `pivot`", "deg", 0.0)});
  Field constraint = object(
      "", "A Dirichlet region",
      {shape("region",
             "Cells (grid engine) or vertices (tet engine) inside this shape are constrained",
             true),
       choice("motion",
              "fixed: held at rest; keyframed: rigid motion through `keyframes` (translation "
              "interpolated linearly, rotation by slerp, held constant outside the key range)",
              "fixed", {"fixed", "keyframed"}),
       vector3("pivot", "Center of the keyframed rotations", "m", nlohmann::json::array({0, 0, 0})),
       array("keyframes", "Poses of a keyframed region (at least one)", keyframe)});
  // Every surface load selects its triangles the same way (surface_selection.hpp).
  const auto surface_load = [](std::string description, Field value) {
    return object(
        "", std::move(description),
        {shape("region",
               "Surface triangles (grid engine: of the embedded surface; tet engine: boundary "
               "faces) whose centroid lies in this shape are loaded",
               true),
         vector3("normal",
                 "Only triangles whose outward normal lies within `normal_tolerance_degrees` of "
                 "this direction (e.g. [1, 0, 0] for the face x = max); [0, 0, 0] = any",
                 "", nlohmann::json::array({0, 0, 0})),
         number("normal_tolerance_degrees", "Cone half-angle of the `normal` selection", "deg",
                30.0, 0.0, false, 180.0),
         std::move(value)});
  };
  Field traction = surface_load(
      "A traction on the part of the body's surface inside a region (Sec. 9.2)",
      vector3("traction", "Force per area on the surface", "Pa", nlohmann::json::array({0, 0, 0})));
  Field pressure = surface_load(
      "A pressure on the selected surface, along its inward normal. The normal is the rest "
      "surface's: co-rotated and large-deformation runs keep the load's direction (dead load)",
      [] {
        Field f = number("pressure", "Pressure (negative: suction)", "Pa", nullptr);
        f.required = true;
        return f;
      }());
  Field force = surface_load(
      "A total force spread over the selected surface in proportion to area (a dead load)", [] {
        Field f = vector3("force", "Total force on the selected surface", "N", nullptr);
        f.required = true;
        return f;
      }());
  Field loads = object("loads", "External loads",
                       {vector3("gravity", "Gravitational acceleration", "m/s^2",
                                nlohmann::json::array({0, -9.81, 0})),
                        array("tractions", "Surface tractions", traction),
                        array("pressures", "Surface pressures", pressure),
                        array("forces", "Total forces on surfaces", force)});
  Field solver = object(
      "solver", "Multigrid solver",
      {number("tolerance",
              "Relative residual to reach. Below the round-off floor of the solution's precision "
              "(the residual of x's own rounding, growing with the resolution: ~1e-10 for a "
              "slender bar at 256 cells in double) a solve stops as stalled, not at the cycle "
              "limit (fixed time.vcycles_per_step run every cycle)",
              "", 1e-6, 0.0, true, 1.0, true),
       integer("max_vcycles", "Cycle limit", 50, 1),
       choice("precision",
              "Arithmetic of the grid engine's solve. float: float cycles on a double solution "
              "(mixed precision, residuals far below float round-off); single: float cycles "
              "and a float solution (the paper's setting, ~40 % less solver memory; linear "
              "quasistatic scenes without acceleration only, and the relative residual stalls "
              "at float round-off, about 6e-8 (L/h)^2, where the solve stops and reports it); "
              "double: double throughout",
              "float", {"float", "single", "double"}),
       choice("cycle", "V (Algorithm 1) or W cycles", "V", {"V", "W"}),
       Field{"accelerate", FieldType::BOOLEAN,
             "Use each cycle as the preconditioner of flexible GMRES(10) instead of iterating "
             "cycles alone (robust for slender embedded bodies); precision single has no "
             "Krylov acceleration: it iterates cycles alone and refuses an explicit true",
             "", true},
       integer("boundary_sweeps", "Band Gauss-Seidel sweeps per pass; 0 = paper default for nu", 0,
               0),
       choice("corotated_smoother",
              "Smoother of material.model corotated: box (Vanka) Gauss-Seidel over every cell, or "
              "distributive (Sec. 7: distributive interior, Gauss-Seidel on the band's Schur "
              "complement)",
              "box", {"box", "distributive"}),
       choice("smoother_order",
              "Order of the boundary band's Gauss-Seidel sweeps: block_local (each colored "
              "block takes all sweeps of a pass while its rows are in cache; a quarter less of the "
              "band's time at 128^3, same rates), band_wide (sweep after sweep over the whole "
              "band, the paper's order) or auto (block_local in 3D, band_wide in 2D)",
              "auto", {"auto", "block_local", "band_wide"}),
       integer("band_layers",
               "Extra cell layers of the boundary band (0 = the paper's narrow band; 1 speeds up "
               "embedded bodies whose constraints cut them at shallow angles)",
               1, 0, 4),
       integer("local_corrections",
               "Exact box solves that plain V-cycles place where a slow mode's residual sits (a "
               "thin limb the coarse levels merge), at most this many, each up to ~170 MB of "
               "factors (16k body cells); kept only where they speed up the cycles (0 = none)",
               4, 0, 16)});
  Field time = object(
      "time", "Frames and time stepping",
      {number("dt", "Frame duration", "s", 1.0 / 30.0, 0.0, true),
       integer("frames", "Frames to simulate (a quasistatic run solves one equilibrium per frame)",
               1, 1),
       integer("substeps", "Time steps per frame (dynamic runs)", 1, 1),
       Field{"quasistatic", FieldType::BOOLEAN,
             "Solve static equilibrium at each frame time (true) or integrate dynamics (false)", "",
             true},
       choice("integrator",
              "Time integrator of dynamic runs (the grid engine integrates with implicit_euler "
              "only)",
              "implicit_euler", {"implicit_euler", "newmark"}),
       number("damping",
              "Stiffness-proportional (Rayleigh) damping coefficient (gamma of the grid engine's "
              "backward Euler, Sec. 8)",
              "s", 0.0, 0.0),
       number("mass_damping", "Mass-proportional (Rayleigh) damping coefficient", "1/s", 0.0, 0.0),
       integer("vcycles_per_step",
               "Grid engine, dynamic runs: V-cycles per time step, warm-started from the previous "
               "step (Sec. 8); 0 = cycle to `solver.tolerance` (at most `solver.max_vcycles`)",
               1, 0),
       integer("rotation_update_every",
               "Grid engine, `material.model: corotated`: V-cycles between refreshes of the cell "
               "rotations (quasistatic and dynamic runs; the paper uses 5, 1 converges faster "
               "far from equilibrium)",
               5, 1)});
  Field initial = object("initial", "Initial state of dynamic runs",
                         {vector3("velocity", "Uniform initial velocity of the body (grid engine)",
                                  "m/s", nlohmann::json::array({0, 0, 0}))});
  Field tet = object(
      "tet", "Tetrahedral engine (Georgii & Westermann 2008)",
      {choice("rotation",
              "Element rotations: energy minimization (quaternion Newton), polar decomposition, "
              "or polar decomposition smoothed over the 1-ring",
              "energy", {"energy", "polar", "smoothed_polar"}),
       integer("resolution",
               "Cubes along the longest axis when the tet mesh is generated from the geometry "
               "(cubes split into 6 tetrahedra); ignored when `geometry.mesh` is a tet mesh",
               16, 1),
       choice("linear_solver",
              "Step solver: block-Jacobi PCG, sparse Cholesky, multigrid V-cycles (Galerkin "
              "hierarchy of regular tet grids, Sec. 4.3) or CG preconditioned by one V-cycle",
              "pcg", {"pcg", "cholesky", "multigrid", "mg_pcg"}),
       number("tolerance", "Relative residual of the PCG / MG-PCG / V-cycle step solve", "", 1e-6,
              0.0, true, 1.0, true),
       integer("max_iterations", "PCG / MG-PCG iteration (or V-cycle) limit per step", 2000, 1),
       integer("vcycles",
               "multigrid: fixed number of V-cycles per step (the paper's setting); 0 = cycle "
               "until `tolerance`",
               0, 0),
       choice("smoother",
              "multigrid / mg_pcg smoothing: one forward block Gauss-Seidel sweep before and one "
              "backward after the coarse correction (the paper), or a symmetric pair (forward + "
              "backward) on each side: slower per cycle, better rate (armadillo 0.43 -> 0.21)",
              "gauss_seidel", {"gauss_seidel", "symmetric_gauss_seidel"}),
       object("feature_patches",
              "multigrid / mg_pcg: block solves on patches at thin features of the finest level "
              "(ear and claw tips) after each forward and before each backward smoothing sweep",
              {integer("max_valence",
                       "A patch around every free vertex in at most this many tetrahedra; 0 = "
                       "no patches (7 brings the tetgen armadillo to <= 0.3 per symmetric "
                       "V-cycle)",
                       0, 0),
               integer("max_size", "Vertices per patch (the seed and its nearest neighbours)", 12,
                       1, 64),
               integer("adaptive_rounds",
                       "At most this many rounds of adaptive patches at the first step: power "
                       "iterations of the V-cycle find where its error concentrates and patches "
                       "grow there, until the cycle contracts by <= 0.1; 0 = off (10 with "
                       "max_valence 7 and symmetric sweeps makes the tetgen armadillo and bunny "
                       "size-independent)",
                       0, 0, 100)})});
  Field surface = object(
      "surface",
      "Deformed embedded surface: the body's input surface carried by the lattice (grid engine, "
      "Sec. 9.3) or by the tets of a generated tet mesh (tet engine, barycentric; a tet-mesh file "
      "shows its own boundary faces)",
      {choice("interpolation", "How surface points follow the lattice (grid engine)", "tricubic",
              {"trilinear", "tricubic"}),
       number("spacing",
              "Marching-cubes spacing for primitive/CSG bodies, as a fraction of the cell size "
              "(grid engine) or cube edge (tet engine)",
              "", 0.5, 0.0, true, 4.0)});
  Field formats = choice("", "Output format", "vtk", {"vtk", "obj", "ply"});
  Field probe = object("", "A named point sampled after every frame (probes.csv)",
                       {[] {
                          Field f{"name", FieldType::STRING,
                                  "Column prefix in probes.csv (unique; letters, digits, _ - .)",
                                  "", nullptr};
                          f.required = true;
                          return f;
                        }(),
                        [] {
                          Field f = vector3("point",
                                            "Rest position inside the body: displacement "
                                            "(trilinear in the lattice / barycentric in its tet), "
                                            "von Mises stress and pressure (of its cell / tet)",
                                            "m", nullptr);
                          f.required = true;
                          return f;
                        }()});
  Field output = object("output", "Results",
                        {Field{"dir", FieldType::STRING,
                               "Output directory, relative to the working directory", "", "out"},
                         [&] {
                           Field f =
                               array("formats",
                                     "vtk: grid fields (.vti) or tet mesh (.vtu) and the deformed "
                                     "surface (.vtp) in a .pvd series; obj/ply: deformed surface",
                                     formats);
                           f.default_value = nlohmann::json::array({"vtk", "obj"});
                           return f;
                         }(),
                         choice("vtk_encoding",
                                "Data arrays of the VTK files: binary (zlib-compressed, appended) "
                                "or ascii (text, larger and slower)",
                                "binary", {"binary", "ascii"}),
                         integer("checkpoint_every",
                                 "Write a checkpoint (checkpoint.mgck, for `run --resume`) every "
                                 "this many frames, after the last frame and when a run is "
                                 "interrupted or diverges; 0: only in those cases",
                                 10, 0),
                         array("probes",
                               "Points sampled after every frame; probes.csv holds them and the "
                               "reaction force and moment of every constraint",
                               probe),
                         surface});
  Field root = object(
      "", "A mgelastic scene",
      {engine, geometry, grid, material, array("constraints", "Dirichlet regions", constraint),
       loads, time, initial, solver, tet, output});
  return root;
}

std::string format_number(double v) {
  std::ostringstream s;
  s.precision(12);
  s << v;
  return s.str();
}

[[noreturn]] void fail(const std::string& file, const std::string& pointer,
                       const std::string& why) {
  throw Error(why, ErrorContext{.file = file, .pointer = pointer.empty() ? "/" : pointer});
}

void check_number(const Field& f, const nlohmann::json& v, const std::string& file,
                  const std::string& pointer) {
  if (!v.is_number()) fail(file, pointer, "expected a number, got " + std::string(v.type_name()));
  const double x = v.get<double>();
  if (!std::isfinite(x)) fail(file, pointer, "must be finite");
  if (f.type == FieldType::INTEGER && (!v.is_number_integer()))
    fail(file, pointer, "expected an integer, got " + format_number(x));
  auto bound = [&](bool ok, const std::string& what) {
    if (!ok) fail(file, pointer, "must be " + what + " (got " + format_number(x) + ")");
  };
  // Integers are read into int: larger ones would wrap around.
  constexpr int largest = std::numeric_limits<int>::max();
  if (f.type == FieldType::INTEGER) bound(x <= largest, "<= " + std::to_string(largest));
  if (f.minimum)
    bound(f.exclusive_minimum ? x > *f.minimum : x >= *f.minimum,
          (f.exclusive_minimum ? "> " : ">= ") + format_number(*f.minimum));
  if (f.maximum)
    bound(f.exclusive_maximum ? x < *f.maximum : x <= *f.maximum,
          (f.exclusive_maximum ? "< " : "<= ") + format_number(*f.maximum));
}

void check_vector3(const nlohmann::json& v, const std::string& file, const std::string& pointer) {
  if (!v.is_array() || v.size() != 3) fail(file, pointer, "expected an array of 3 numbers");
  for (std::size_t i = 0; i < 3; ++i)
    if (!v[i].is_number() || !std::isfinite(v[i].get<double>()))
      fail(file, pointer + "/" + std::to_string(i), "expected a finite number");
}

nlohmann::json validate(const Field& f, const nlohmann::json& v, const std::string& file,
                        const std::string& pointer);
nlohmann::json validate_object(const Field& f, const nlohmann::json& v, const std::string& file,
                               const std::string& pointer);
nlohmann::json fill_shape_defaults(const nlohmann::json& v, const std::string& file,
                                   const std::string& pointer);

// Shape kinds: primitives (objects with these members), a mesh file, or CSG lists.
const std::vector<Field>& primitive_kinds() {
  static const std::vector<Field> kinds = [] {
    const nlohmann::json origin = nlohmann::json::array({0, 0, 0});
    const nlohmann::json up = nlohmann::json::array({0, 1, 0});
    auto required_vec = [](std::string name, std::string description) {
      Field f = vector3(std::move(name), std::move(description), "m", nullptr);
      f.required = true;
      return f;
    };
    auto length = [](std::string name, std::string description) {
      Field f = number(std::move(name), std::move(description), "m", nullptr, 0.0, true);
      f.required = true;
      return f;
    };
    return std::vector<Field>{
        object("box", "Axis-aligned box",
               {vector3("center", "Center", "m", origin), required_vec("size", "Edge lengths")}),
        object("sphere", "Sphere",
               {vector3("center", "Center", "m", origin), length("radius", "Radius")}),
        object("cylinder", "Capped cylinder between two end-cap centers",
               {required_vec("a", "First end-cap center"),
                required_vec("b", "Second end-cap center"), length("radius", "Radius")}),
        object("capsule", "Segment a-b swept by a sphere",
               {required_vec("a", "Segment start"), required_vec("b", "Segment end"),
                length("radius", "Radius")}),
        object(
            "torus", "Torus",
            {vector3("center", "Center", "m", origin), vector3("axis", "Axis of symmetry", "", up),
             length("major_radius", "Distance of the tube center from the axis"),
             length("minor_radius", "Tube radius")}),
    };
  }();
  return kinds;
}

const Field& transform_field() {
  static const Field f = object(
      "transform", "Optional rigid transform and uniform scale, applied scale-rotate-translate",
      {vector3("translate", "Translation", "m", nlohmann::json::array({0, 0, 0})),
       vector3("rotate_axis", "Rotation axis", "", nlohmann::json::array({0, 0, 1})),
       number("rotate_degrees", "Rotation angle about the axis", "deg", 0.0),
       number("scale", "Uniform scale factor", "", 1.0, 0.0, true)});
  return f;
}

// CSG lists nest shapes; every later pass over a shape recurses too, so the depth is bounded
// (a hand-written scene never comes near; a generated or corrupt one must not overflow the stack).
constexpr int kMaxShapeDepth = 64;

void check_shape(const nlohmann::json& v, const std::string& file, const std::string& pointer,
                 int depth = 0) {
  static const std::vector<std::string> lists{"union", "difference", "intersection"};
  if (depth > kMaxShapeDepth)
    fail(file, pointer,
         "shapes nested deeper than " + std::to_string(kMaxShapeDepth) + " CSG levels");
  if (!v.is_object())
    fail(file, pointer, "expected a shape object, e.g. {\"sphere\": {\"radius\": 1}}");
  std::vector<std::string> kinds;
  for (const auto& [key, value] : v.items())
    if (key != "transform") kinds.push_back(key);
  if (kinds.size() != 1)
    fail(file, pointer,
         "a shape has exactly one of box, sphere, cylinder, capsule, torus, mesh, "
         "union, difference, intersection (plus an optional transform)");
  const std::string& kind = kinds.front();
  const std::string at = pointer + "/" + kind;
  if (v.contains("transform"))
    validate_object(transform_field(), v["transform"], file, pointer + "/transform");
  if (kind == "mesh") {
    if (!v[kind].is_string()) fail(file, at, "expected a mesh file path (relative to the scene)");
    return;
  }
  if (std::find(lists.begin(), lists.end(), kind) != lists.end()) {
    const std::size_t least = kind == "union" ? 1 : 2;
    if (!v[kind].is_array() || v[kind].size() < least)
      fail(file, at, "expected an array of at least " + std::to_string(least) + " shapes");
    for (std::size_t i = 0; i < v[kind].size(); ++i)
      check_shape(v[kind][i], file, at + "/" + std::to_string(i), depth + 1);
    return;
  }
  for (const Field& primitive : primitive_kinds()) {
    if (primitive.name != kind) continue;
    validate_object(primitive, v[kind], file, at);
    return;
  }
  fail(file, at, "unknown shape kind '" + kind + "'");
}

nlohmann::json validate_object(const Field& f, const nlohmann::json& v, const std::string& file,
                               const std::string& pointer) {
  if (!v.is_object()) fail(file, pointer, "expected an object, got " + std::string(v.type_name()));
  nlohmann::json result = nlohmann::json::object();
  for (const auto& [key, value] : v.items()) {
    bool known = false;
    for (const Field& c : f.children) known = known || c.name == key;
    if (!known) {
      std::string expected;
      for (const Field& c : f.children) expected += (expected.empty() ? "" : ", ") + c.name;
      fail(file, pointer + "/" + key, "unknown key (expected one of: " + expected + ")");
    }
  }
  for (const Field& c : f.children) {
    const std::string child = pointer + "/" + c.name;
    if (v.contains(c.name)) {
      result[c.name] = validate(c, v[c.name], file, child);
    } else if (c.required) {
      fail(file, child, "missing required key");
    } else {
      result[c.name] = validate(c, c.default_value, file, child);
    }
  }
  return result;
}

nlohmann::json validate(const Field& f, const nlohmann::json& v, const std::string& file,
                        const std::string& pointer) {
  switch (f.type) {
    case FieldType::NUMBER:
    case FieldType::INTEGER:
      check_number(f, v, file, pointer);
      return v;
    case FieldType::BOOLEAN:
      if (!v.is_boolean()) fail(file, pointer, "expected true or false");
      return v;
    case FieldType::STRING:
      if (!v.is_string())
        fail(file, pointer, "expected a string, got " + std::string(v.type_name()));
      if (!f.choices.empty() &&
          std::find(f.choices.begin(), f.choices.end(), v.get<std::string>()) == f.choices.end()) {
        std::string allowed;
        for (const auto& c : f.choices) allowed += (allowed.empty() ? "" : ", ") + c;
        fail(file, pointer, "must be one of " + allowed + " (got '" + v.get<std::string>() + "')");
      }
      return v;
    case FieldType::VECTOR3:
      check_vector3(v, file, pointer);
      return v;
    case FieldType::SHAPE:
      check_shape(v, file, pointer);
      return fill_shape_defaults(v, file, pointer);
    case FieldType::OBJECT:
      return validate_object(f, v, file, pointer);
    case FieldType::ARRAY: {
      if (!v.is_array())
        fail(file, pointer, "expected an array, got " + std::string(v.type_name()));
      nlohmann::json result = nlohmann::json::array();
      for (std::size_t i = 0; i < v.size(); ++i)
        result.push_back(validate(f.children[0], v[i], file, pointer + "/" + std::to_string(i)));
      return result;
    }
  }
  return v;
}

// Copies a validated shape with the defaults of its primitive members filled in.
nlohmann::json fill_shape_defaults(const nlohmann::json& v, const std::string& file,
                                   const std::string& pointer) {
  nlohmann::json result = v;
  if (v.contains("transform"))
    result["transform"] =
        validate_object(transform_field(), v["transform"], file, pointer + "/transform");
  for (const auto& [kind, value] : v.items()) {
    if (kind == "transform") continue;
    for (const Field& primitive : primitive_kinds())
      if (primitive.name == kind)
        result[kind] = validate_object(primitive, value, file, pointer + "/" + kind);
    if (value.is_array())
      for (std::size_t i = 0; i < value.size(); ++i)
        result[kind][i] =
            fill_shape_defaults(value[i], file, pointer + "/" + kind + "/" + std::to_string(i));
  }
  return result;
}

std::string type_name(const Field& f) {
  switch (f.type) {
    case FieldType::NUMBER:
      return "number";
    case FieldType::INTEGER:
      return "integer";
    case FieldType::STRING:
      return f.choices.empty() ? "string" : "one of `" + [&] {
        std::string s;
        for (const auto& c : f.choices) s += (s.empty() ? "" : "`, `") + c;
        return s;
      }() + "`";
    case FieldType::BOOLEAN:
      return "boolean";
    case FieldType::VECTOR3:
      return "[x, y, z]";
    case FieldType::OBJECT:
      return "object";
    case FieldType::ARRAY:
      return "array";
    case FieldType::SHAPE:
      return "shape";
  }
  return "";
}

std::string range_text(const Field& f) {
  std::string r;
  if (f.minimum) r += (f.exclusive_minimum ? "> " : ">= ") + format_number(*f.minimum);
  if (f.maximum)
    r += (r.empty() ? "" : ", ") + std::string(f.exclusive_maximum ? "< " : "<= ") +
         format_number(*f.maximum);
  return r;
}

void markdown_rows(const Field& f, const std::string& prefix, std::ostringstream& out) {
  for (const Field& c : f.children) {
    const std::string key = prefix.empty() ? c.name : prefix + "." + c.name;
    out << "| `" << (key.empty() ? "[]" : key) << "` | " << type_name(c) << " | " << c.unit << " | "
        << range_text(c) << " | ";
    if (c.required) {
      out << "required";
    } else if (!c.default_value.is_null() && c.type != FieldType::OBJECT) {
      out << '`' << c.default_value.dump() << '`';
    }
    out << " | " << c.description << " |\n";
    if (c.type == FieldType::OBJECT) markdown_rows(c, key, out);
    if (c.type == FieldType::ARRAY && !c.children.empty() &&
        c.children[0].type == FieldType::OBJECT)
      markdown_rows(c.children[0], key + "[]", out);
  }
}

}  // namespace

std::string scene_format_markdown() {
  std::ostringstream out;
  out << "# Scene format\n\n"
         "<!-- Generated by `mgelastic scene-format` from src/mgelastic/scene/schema.cpp; a test "
         "checks that this page matches. -->\n\n"
         "A scene is a JSON object. Unknown keys and wrong types are errors reported as "
         "`scene.json: /json/pointer: reason` before any work starts; missing keys take the "
         "defaults below. Units are SI.\n\n"
         "| key | type | unit | range | default | description |\n|---|---|---|---|---|---|\n";
  markdown_rows(scene_schema(), "", out);
  out << "\n## Shapes\n\nA shape is an object with exactly one of the keys below, plus an "
         "optional `transform`. `mesh` is a path to a closed triangle mesh (OBJ, STL, PLY, OFF) "
         "relative to the scene file; `union`, `intersection` take a list of shapes, "
         "`difference` subtracts the second and later shapes from the first.\n\n"
         "| key | type | unit | range | default | description |\n|---|---|---|---|---|---|\n";
  for (const Field& kind : primitive_kinds()) {
    out << "| `" << kind.name << "` | object | | | | " << kind.description << " |\n";
    markdown_rows(kind, kind.name, out);
  }
  out << "| `transform` | object | | | | " << transform_field().description << " |\n";
  markdown_rows(transform_field(), "transform", out);
  return out.str();
}

const Field& scene_schema() {
  static const Field schema = build_schema();
  return schema;
}

nlohmann::json validate_scene(const nlohmann::json& document, const std::string& file) {
  return validate(scene_schema(), document, file, "");
}

}  // namespace mgelastic::scene
