#pragma once
// The body's rest surface, carried by the lattice for output (Sec. 9.3) and for surface
// tractions (Sec. 9.2): a body given as a triangle mesh keeps its own triangles (transformed
// like the shape, turned outward if it was inside-out); primitives and CSG get the zero level set
// of their signed distance, extracted at `spacing` (a fraction of the cell size).
#include "mgelastic/geometry/shape.hpp"
#include "mgelastic/geometry/triangle_mesh.hpp"
#include "mgelastic/scene/scene.hpp"

namespace mgelastic::scene {

geometry::TriangleMesh rest_surface(const Scene& scene, const geometry::Shape& body,
                                    double cell_size);

}  // namespace mgelastic::scene
