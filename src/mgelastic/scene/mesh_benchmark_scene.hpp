#pragma once
// The embedded-body benchmark scene (the paper's armadillo run, Fig. 22) that
// `mgelastic bench vcycle --mesh` and the kernel benchmarks (bench/grid) share: the surface mesh
// `file` voxelized at `resolution` cells along its longest axis with one padding layer, its
// lowest 5 % of height fixed, under gravity (density 1000).
#include <string>

#include <nlohmann/json.hpp>

namespace mgelastic::scene {

// The scene document (parse_scene reads it); throws Error when the mesh cannot be read.
nlohmann::json mesh_benchmark_scene(const std::string& file, int resolution, double youngs_modulus,
                                    double poisson_ratio);

}  // namespace mgelastic::scene
