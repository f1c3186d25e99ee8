#pragma once
// The zero level set of a shape's signed distance as a closed triangle mesh: the embedded surface
// that Sec. 9.3 carries along with the lattice's displacement.
//
// Sampling: d[i, j, k] = signed_distance(o + s (i, j, k)) for 0 <= i < n_x etc., x fastest, on a
// lattice of spacing s centered on the box and reaching at least one sample beyond it on every
// side. The outermost layer of samples counts as outside (d := max(d, 0)), so the surface is
// closed even where a caller's box clips the shape: the clipped part is capped there. Samples
// farther than 2 s from the surface are not queried one by one: a block of 8 x 8 samples of a
// slab whose center is far enough takes the bound the 1-Lipschitz distance gives from the
// center's value (its sign is theirs); no cube with such a corner is crossed by the surface,
// so the mesh is the one the full sampling gives (CSG min/max bounds are 1-Lipschitz too).
//
// Extraction: marching tetrahedra on the cube lattice. Each cube is split into the six Kuhn
// tetrahedra around its (0,0,0)-(1,1,1) diagonal, so every cube face is split along the diagonal
// from its min to its max corner from both sides and the tetrahedra form one conforming mesh.
// A sample is inside when d < 0. In each tetrahedron the zero set of the linear interpolant of d
// is a triangle (one corner apart from the other three) or a quad cut into two triangles (two and
// two). Neighboring tetrahedra share whole faces and, on them, the same crossing segment, so the
// pieces meet edge to edge: no case table, hence no ambiguous faces to resolve. The result is a
// closed, oriented 2-manifold (the level set of a piecewise linear function at a regular value).
//
// Vertices: one per lattice edge whose ends lie on opposite sides, shared by every triangle that
// uses that edge, at x_a + t (x_b - x_a) with t = d_a / (d_a - d_b) clamped to [1e-6, 1 - 1e-6].
// An exact zero sample would put the vertices of several edges at one point and create zero-area
// triangles; the clamp moves vertices by at most 1e-6 s and keeps every triangle non-degenerate,
// so there is nothing to drop (dropping degenerate triangles would open holes in the mesh).
// Where the surface is smooth, vertices lie within O(s^2) of it (about 3 s^2 / (8 r) for radius
// of curvature r) and the enclosed volume converges with order 2. Sharp edges are not kept:
// those not along a Kuhn diagonal are chamfered within one cell.
#include <optional>

#include "mgelastic/geometry/shape.hpp"
#include "mgelastic/geometry/triangle_mesh.hpp"

namespace mgelastic::geometry {

// Returns vertices (V x 3, world coordinates) and triangles (T x 3 vertex rows, counterclockwise
// seen from outside). Throws Error when spacing <= 0, the box is empty or not finite, the lattice
// would exceed 2^31 samples, or the signed distance is not finite at a sample it queries (every
// sample within 2 s of the surface and one per block of 8 x 8 samples elsewhere). `box` defaults to
// shape.bounding_box().
TriangleMesh extract_surface(const Shape& shape, double spacing,
                             const std::optional<BoundingBox>& box = std::nullopt);

}  // namespace mgelastic::geometry
