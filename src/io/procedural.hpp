// Procedural meshes for the demo, the tests and the benchmarks, and the two operations that build
// scenes out of them (merge, transform).
//
// Every generator is deterministic: random choices come from a seeded splitmix64 stream mapped to
// floats by hand (the std:: distributions are implementation-defined), and arithmetic is done in
// double and rounded to float once, so that fused multiply-adds do not show either. A seed gives
// the same bytes on every compiler, standard library and target. Triangles are counter-clockwise seen from the side
// their normals point to. Invalid arguments (counts below the minimum, non-finite or non-positive
// sizes, meshes beyond 2^32 vertices) throw clraster::InvalidArgument.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/mat4x4.hpp>

#include "io/mesh.hpp"

namespace clraster::io {

// A UV sphere: `slices` (>= 3) meridians, `stacks` (>= 2) bands from pole to pole, one vertex at
// each pole. 2 * slices * (stacks - 1) triangles with exact radial normals.
Mesh make_sphere(int slices, int stacks, float radius, Vec3f center = {});

// A torus around the y axis, centred at the origin: `rings` (>= 3) segments around the axis,
// `sides` (>= 3) around the tube. 2 * rings * sides triangles with exact normals.
Mesh make_torus(int rings, int sides, float ring_radius, float tube_radius);

// A (p, q) torus knot: a tube of radius tube_radius around the closed curve that winds p times
// around the y axis and q times around the circle of radius ring_radius in the xz plane, at
// winding_radius from it. p, q >= 1 and coprime (so that the curve is one knot, (2, 3) the
// trefoil); ring_radius > winding_radius > 0. `segments` (>= 3) rings along the curve, `sides`
// (>= 3) vertices around each: 2 * segments * sides triangles, smooth and closed, with exact
// normals (outward from the curve, perpendicular to it). A tube thicker than the curve's radius of
// curvature, or than half the distance between its strands, intersects itself.
Mesh make_torus_knot(int p, int q, int segments, int sides, float ring_radius, float winding_radius, float tube_radius);

// The axis-aligned box [min, max] (min < max on each axis): 6 faces of 4 vertices with the face
// normal, 12 triangles.
Mesh make_box(Vec3f min, Vec3f max);

// A rolling landscape over x in [-size_x/2, size_x/2], z in [-size_z/2, size_z/2]:
// a grid of cells_x * cells_z quads (two triangles each; 708 x 708 cells is about 1M triangles)
// with heights y within [-height, height] from fractal value noise, counter-clockwise seen from
// +y. The landscape depends on the seed, not on the resolution: more cells sample the same hills
// more finely. Normals come from central differences of the grid heights.
Mesh make_terrain(int cells_x, int cells_z, float size_x, float size_z, float height, std::uint64_t seed);

// The rectangle x in [-size_x/2, size_x/2], y in [-size_y/2, size_y/2] at z = 0, facing +z, as a
// grid of cells_x * cells_y quads of two triangles that share their edges. With cells smaller than
// a pixel it is a field of sub-pixel triangles that a rasterizer must cover without gaps or double
// hits at the shared edges and vertices.
Mesh make_plane(int cells_x, int cells_y, float size_x, float size_y);

// `count` separate triangles of random sizes scattered in the box [box_min, box_max]: each has a
// centre uniform in the box and corners at random offsets of up to max_size * u^3 per axis (u
// uniform in [0, 1), so most triangles are small and a few are large), clamped into the box. Every
// vertex has its own random unit normal. For stress tests; not a surface.
Mesh make_random_triangles(int count, std::uint64_t seed, Vec3f box_min, Vec3f box_max, float max_size);

// All meshes in one, in order: vertices appended, indices offset to match. When some of the
// meshes have texture coordinates, the vertices of the others get (0, 0).
Mesh merge(const std::vector<Mesh>& meshes);

// Applies the affine `matrix` in place: positions by the matrix, normals by its inverse transpose,
// renormalized (zero normals stay zero); texture coordinates stay as they are. A mirroring matrix
// (negative determinant) also reverses
// each triangle's winding, so that faces seen from their normal's side stay counter-clockwise.
void transform(Mesh& mesh, const glm::mat4& matrix);

}  // namespace clraster::io
