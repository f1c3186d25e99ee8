#pragma once
// A validated scene: typed values for the engines, with the geometry kept as its validated JSON
// shape description (built into geometry::Shape objects by build_shape).
#include <Eigen/Core>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "mgelastic/scene/keyframed_motion.hpp"

namespace mgelastic::scene {

struct Scene {
  std::string file;                 // how errors name the scene
  std::filesystem::path directory;  // mesh paths are relative to it
  nlohmann::json document;          // the validated document, defaults filled in

  std::string engine;
  nlohmann::json geometry;
  double cell_size = 0;
  int resolution = 64;
  int padding = 0;
  double youngs_modulus = 1e5, poisson_ratio = 0.45, density = 1000;
  std::string material_model = "linear";  // grid engine: "linear" or "corotated"
  struct MaterialRegion {
    nlohmann::json region;
    double youngs_modulus = 1e5, poisson_ratio = 0.45, density = 1000;
  };
  std::vector<MaterialRegion> material_regions;
  struct Constraint {
    nlohmann::json region;
    std::string motion_kind;  // "fixed" or "keyframed"
    KeyframedMotion motion;
  };
  std::vector<Constraint> constraints;
  Eigen::Vector3d gravity = Eigen::Vector3d(0, -9.81, 0);
  // Part of the body's surface a surface load acts on (surface_selection.hpp): centroid inside
  // `region` and, for a non-zero `normal`, outward normal within `tolerance_degrees` of it.
  struct SurfaceSelection {
    nlohmann::json region;
    Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // zero: any direction
    double tolerance_degrees = 30.0;
  };
  struct Traction {
    SurfaceSelection surface;
    Eigen::Vector3d traction;  // Pa
  };
  std::vector<Traction> tractions;
  struct Pressure {
    SurfaceSelection surface;
    double pressure = 0.0;  // Pa, along the inward (rest) normal
  };
  std::vector<Pressure> pressures;
  struct TotalForce {
    SurfaceSelection surface;
    Eigen::Vector3d force;  // N, spread over the selected surface by area
  };
  std::vector<TotalForce> forces;
  struct Time {
    double dt = 1.0 / 30.0;
    int frames = 1, substeps = 1;
    bool quasistatic = true;
    std::string integrator = "implicit_euler";
    double damping = 0, mass_damping = 0;
    int vcycles_per_step = 1;       // grid engine dynamics; 0 = cycle to `tolerance`
    int rotation_update_every = 5;  // grid engine, corotated model
  } time;
  Eigen::Vector3d initial_velocity = Eigen::Vector3d::Zero();
  struct Tet {
    std::string rotation = "energy";
    int resolution = 16;
    std::string linear_solver = "pcg";
    double tolerance = 1e-6;
    int max_iterations = 2000;
    int vcycles = 0;  // multigrid: V-cycles per step, 0 = to the tolerance
    std::string smoother = "gauss_seidel";
    struct FeaturePatches {
      int max_valence = 0;  // 0 = none
      int max_size = 12;
      int adaptive_rounds = 0;  // 0 = none
    } feature_patches;
  } tet;
  std::string surface_interpolation = "tricubic";
  double surface_spacing = 0.5;  // marching-cubes spacing / cell size
  double tolerance = 1e-6;
  int max_vcycles = 50;
  std::string precision = "float", cycle = "V";
  int boundary_sweeps = 0;
  std::string corotated_smoother = "box";
  int band_layers = 1;
  int local_corrections = 4;
  std::string smoother_order = "auto";
  bool accelerate = true;
  std::string output_dir = "out";
  std::vector<std::string> formats;
  std::string vtk_encoding = "binary";  // or "ascii"
  int checkpoint_every = 10;  // frames; 0 = only at the end, on interruption and on divergence
  struct Probe {
    std::string name;
    Eigen::Vector3d point;  // m, rest position
  };
  std::vector<Probe> probes;  // sampled after every frame (sim/probes.hpp)
};

// Reads, validates and types a scene file; errors name the file and line (JSON syntax) or the
// JSON pointer (schema).
Scene load_scene(const std::filesystem::path& path);

// Same for an in-memory document; `file` names it in errors.
Scene parse_scene(const nlohmann::json& document, const std::string& file,
                  const std::filesystem::path& directory);

}  // namespace mgelastic::scene
