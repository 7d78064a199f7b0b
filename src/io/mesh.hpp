// Host-side triangle meshes, as the front ends (CLI, tests, benchmarks) build or load them before
// uploading them into clraster::VertexBuffer / clraster::IndexBuffer.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace clraster::io {

struct Vec3f {
  float x = 0, y = 0, z = 0;
};

// An indexed triangle list with one normal per vertex, and texture coordinates when it has them.
struct Mesh {
  std::vector<float> positions;       // x, y, z per vertex
  std::vector<float> normals;         // x, y, z per vertex; same length as positions
  // u, v per vertex, or none at all. v runs up the image, as in OpenGL and as assimp gives every
  // format (it turns glTF's v around): v = 0 is the image's bottom row, so an image file whose
  // first row is its top (PNG, JPEG) is loaded with Texture::load(..., flip_vertically = true).
  std::vector<float> texcoords;
  std::vector<std::uint32_t> indices; // three per triangle

  std::size_t vertex_count() const { return positions.size() / 3; }
  std::size_t triangle_count() const { return indices.size() / 3; }
};

// The smallest sphere found around the finite vertices (a bounding sphere, not necessarily minimal).
struct BoundingSphere {
  Vec3f center;
  float radius = 0;
};

// The sphere centred on the axis-aligned box of the finite vertices (those with three finite
// coordinates) that just reaches the farthest of them. Radius 0 for a single point; centre 0 and
// radius 0 when no vertex is finite.
inline BoundingSphere bounding_sphere(const Mesh& mesh) {
  const auto finite_vertex = [&](std::size_t v) {
    return std::isfinite(mesh.positions[3 * v]) && std::isfinite(mesh.positions[3 * v + 1]) &&
           std::isfinite(mesh.positions[3 * v + 2]);
  };
  float lo[3] = {HUGE_VALF, HUGE_VALF, HUGE_VALF};
  float hi[3] = {-HUGE_VALF, -HUGE_VALF, -HUGE_VALF};
  bool any_finite = false;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    if (!finite_vertex(v)) continue;
    any_finite = true;
    for (int axis = 0; axis < 3; ++axis) {
      lo[axis] = std::min(lo[axis], mesh.positions[3 * v + axis]);
      hi[axis] = std::max(hi[axis], mesh.positions[3 * v + axis]);
    }
  }
  if (!any_finite) return {};

  // The midpoint in double, as (lo + hi) / 2 in float can overflow.
  const float center[3] = {static_cast<float>((double{lo[0]} + hi[0]) / 2),
                           static_cast<float>((double{lo[1]} + hi[1]) / 2),
                           static_cast<float>((double{lo[2]} + hi[2]) / 2)};
  double radius_squared = 0;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    if (!finite_vertex(v)) continue;
    double distance_squared = 0;
    for (int axis = 0; axis < 3; ++axis) {
      const double d = double{mesh.positions[3 * v + axis]} - center[axis];
      distance_squared += d * d;
    }
    radius_squared = std::max(radius_squared, distance_squared);
  }
  // Rounded up to a float, so that the farthest vertex is inside the sphere, not just outside it.
  const double exact_radius = std::sqrt(radius_squared);
  float radius = static_cast<float>(exact_radius);
  if (radius < exact_radius) radius = std::nextafter(radius, HUGE_VALF);
  return {{center[0], center[1], center[2]}, radius};
}

}  // namespace clraster::io
