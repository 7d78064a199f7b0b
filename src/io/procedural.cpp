#include "io/procedural.hpp"
#include "io/format.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <numeric>
#include <string>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "clraster/clraster.hpp"

namespace clraster::io {
namespace {

// ---- Argument checks ---------------------------------------------------------------------------

void require_count(const char* function, const char* name, int value, int minimum) {
  if (value < minimum) {
    throw InvalidArgument(std::string(function) + ": " + name + " must be at least " + std::to_string(minimum) +
                          ", got " + std::to_string(value));
  }
}

void require_positive(const char* function, const char* name, float value) {
  if (!(std::isfinite(value) && value > 0)) {
    throw InvalidArgument(std::string(function) + ": " + name + " must be a positive finite number, got " +
                          format_number(value));
  }
}

void require_finite(const char* function, const char* name, Vec3f value) {
  if (!(std::isfinite(value.x) && std::isfinite(value.y) && std::isfinite(value.z))) {
    throw InvalidArgument(std::string(function) + ": " + name + " must be finite, got (" + format_number(value.x) +
                          ", " + format_number(value.y) + ", " + format_number(value.z) + ")");
  }
}

// The Mesh invariants that merge and transform rely on.
void require_attributes_per_vertex(const std::string& what, const Mesh& mesh) {
  if (mesh.normals.size() != mesh.positions.size()) {
    throw InvalidArgument(what + " has " + std::to_string(mesh.normals.size()) + " normal values for " +
                          std::to_string(mesh.positions.size()) + " position values");
  }
  if (!mesh.texcoords.empty() && mesh.texcoords.size() != 2 * mesh.vertex_count()) {
    throw InvalidArgument(what + " has " + std::to_string(mesh.texcoords.size()) + " texture coordinate values for " +
                          std::to_string(mesh.vertex_count()) + " vertices");
  }
}

// Mesh indices are 32-bit, so a mesh holds at most 2^32 - 1 vertices.
void require_indexable(const char* function, std::uint64_t vertex_count) {
  constexpr std::uint64_t kMaxVertices = std::numeric_limits<std::uint32_t>::max();
  if (vertex_count > kMaxVertices) {
    throw InvalidArgument(std::string(function) + ": " + std::to_string(vertex_count) +
                          " vertices is more than 32-bit indices can address (" + std::to_string(kMaxVertices) + ")");
  }
}

// ---- Deterministic randomness ------------------------------------------------------------------

constexpr std::uint64_t kGoldenGamma = 0x9e3779b97f4a7c15ull;

// The output function of splitmix64 (Steele, Lea and Flood, 2014): a bijective mixer in which every
// input bit affects every output bit.
std::uint64_t mix64(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

// Top 53 bits of a hash as a double in [0, 1), exactly.
double unit_double(std::uint64_t hash) { return static_cast<double>(hash >> 11) * 0x1p-53; }

// The splitmix64 generator. Arithmetic is done in double and rounded to float once at the end:
// whether the compiler fuses a * b + c into one instruction (it may, depending on the target)
// then changes the last bits of a double, and almost never the float they round to.
class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}

  double unit() { return unit_double(mix64(state_ += kGoldenGamma)); }

  // Uniform in the box [lo, hi]. The coordinates are drawn in separate statements: the order in
  // which function arguments are evaluated differs between compilers.
  glm::vec3 point_in(glm::vec3 lo, glm::vec3 hi) {
    glm::vec3 point;
    for (int axis = 0; axis < 3; ++axis) {
      point[axis] = static_cast<float>(lo[axis] + (double{hi[axis]} - lo[axis]) * unit());
    }
    return point;
  }

  // Rejection sampling in the cube [-1, 1]^3: uniform over directions, with no trigonometry whose
  // last bits could differ between math libraries.
  glm::vec3 unit_vector() {
    for (;;) {
      glm::dvec3 v;
      for (int axis = 0; axis < 3; ++axis) v[axis] = 2 * unit() - 1;
      const double length_squared = glm::dot(v, v);
      if (length_squared > 1e-4 && length_squared <= 1) return glm::vec3(v / std::sqrt(length_squared));
    }
  }

 private:
  std::uint64_t state_;
};

// ---- Fractal value noise -----------------------------------------------------------------------

// Noise is computed in double for the reason given at Random.

// A value in [-1, 1) attached to the integer lattice point (x, z) of one noise layer.
double lattice_value(std::uint64_t layer, std::int64_t x, std::int64_t z) {
  const std::uint64_t hash = mix64(mix64(layer + static_cast<std::uint64_t>(x)) + static_cast<std::uint64_t>(z));
  return 2 * unit_double(hash) - 1;
}

// 6t^5 - 15t^4 + 10t^3: eases lattice interpolation so that heights have continuous slope and
// curvature, and the terrain shows no creases along lattice lines.
double smootherstep(double t) { return t * t * t * (t * (t * 6 - 15) + 10); }

double lerp(double a, double b, double t) { return a + (b - a) * t; }

double value_noise(std::uint64_t layer, double x, double z) {
  const double x0 = std::floor(x);
  const double z0 = std::floor(z);
  const auto ix = static_cast<std::int64_t>(x0);
  const auto iz = static_cast<std::int64_t>(z0);
  const double sx = smootherstep(x - x0);
  const double sz = smootherstep(z - z0);
  return lerp(lerp(lattice_value(layer, ix, iz), lattice_value(layer, ix + 1, iz), sx),
              lerp(lattice_value(layer, ix, iz + 1), lattice_value(layer, ix + 1, iz + 1), sx), sz);
}

// Five octaves of value noise, each at twice the frequency and half the amplitude of the one
// before, normalized to [-1, 1].
double fractal_noise(std::uint64_t seed, double x, double z) {
  constexpr int kOctaves = 5;
  double sum = 0;
  double total_amplitude = 0;
  double amplitude = 1;
  double frequency = 1;
  for (int octave = 0; octave < kOctaves; ++octave) {
    sum += amplitude * value_noise(mix64(seed) + octave, x * frequency, z * frequency);
    total_amplitude += amplitude;
    amplitude /= 2;
    frequency *= 2;
  }
  return sum / total_amplitude;
}

// ---- Mesh assembly -----------------------------------------------------------------------------

void add_vertex(Mesh& mesh, glm::vec3 position, glm::vec3 normal) {
  mesh.positions.insert(mesh.positions.end(), {position.x, position.y, position.z});
  mesh.normals.insert(mesh.normals.end(), {normal.x, normal.y, normal.z});
}

// Adds two triangles per cell of a grid of vertices stored row by row from `first`: vertex (i, j)
// is first + j * columns + i, i running along the grid's u direction and j along v. The triangles
// are counter-clockwise about cross(u, v). With wrap_u (wrap_v) the last column (row) of cells
// joins back to vertex column (row) 0, so that there are cells_u columns (cells_v rows) of
// vertices instead of one more.
void add_grid_triangles(Mesh& mesh, std::uint32_t first, int cells_u, int cells_v, bool wrap_u, bool wrap_v) {
  const std::uint64_t columns = wrap_u ? cells_u : cells_u + 1;
  const std::uint64_t rows = wrap_v ? cells_v : cells_v + 1;
  const auto vertex = [&](std::uint64_t i, std::uint64_t j) {
    return static_cast<std::uint32_t>(first + (j % rows) * columns + i % columns);
  };
  mesh.indices.reserve(mesh.indices.size() + std::size_t{6} * cells_u * cells_v);
  for (int j = 0; j < cells_v; ++j) {
    for (int i = 0; i < cells_u; ++i) {
      const std::uint32_t a = vertex(i, j), b = vertex(i + 1, j), c = vertex(i, j + 1), d = vertex(i + 1, j + 1);
      mesh.indices.insert(mesh.indices.end(), {a, b, c, b, d, c});
    }
  }
}

// Coordinate of grid line `index` of `cells` across [-size/2, size/2]; exact at both ends.
float grid_coordinate(int index, int cells, float size) {
  return static_cast<float>(-0.5 * size + static_cast<double>(size) * index / cells);
}

void reserve_vertices(Mesh& mesh, std::size_t count) {
  mesh.positions.reserve(3 * count);
  mesh.normals.reserve(3 * count);
}

}  // namespace

Mesh make_sphere(int slices, int stacks, float radius, Vec3f center) {
  require_count("make_sphere", "slices", slices, 3);
  require_count("make_sphere", "stacks", stacks, 2);
  require_positive("make_sphere", "radius", radius);
  require_finite("make_sphere", "center", center);
  const std::uint64_t ring_vertices = static_cast<std::uint64_t>(stacks - 1) * slices;
  require_indexable("make_sphere", ring_vertices + 2);

  Mesh mesh;
  reserve_vertices(mesh, ring_vertices + 2);
  const glm::vec3 origin(center.x, center.y, center.z);
  const auto add_point = [&](glm::dvec3 direction) {
    add_vertex(mesh, glm::vec3(glm::dvec3(origin) + double{radius} * direction), glm::vec3(direction));
  };
  // Polar angle theta from +y, azimuth phi from +x towards +z: with phi along the grid's u and
  // theta along its v, cross(u, v) points outwards.
  add_point({0, 1, 0});
  for (int stack = 1; stack < stacks; ++stack) {
    const double theta = std::numbers::pi * stack / stacks;
    for (int slice = 0; slice < slices; ++slice) {
      const double phi = 2 * std::numbers::pi * slice / slices;
      add_point({std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)});
    }
  }
  add_point({0, -1, 0});

  const std::uint32_t north = 0;
  const std::uint32_t first_ring = 1;
  const auto last_ring = static_cast<std::uint32_t>(1 + (stacks - 2) * static_cast<std::uint64_t>(slices));
  const auto south = static_cast<std::uint32_t>(mesh.vertex_count() - 1);
  mesh.indices.reserve(std::size_t{6} * slices * (stacks - 1));
  for (std::uint32_t slice = 0; slice < static_cast<std::uint32_t>(slices); ++slice) {
    const std::uint32_t next = (slice + 1) % slices;
    mesh.indices.insert(mesh.indices.end(), {north, first_ring + next, first_ring + slice});
  }
  add_grid_triangles(mesh, first_ring, slices, stacks - 2, /*wrap_u=*/true, /*wrap_v=*/false);
  for (std::uint32_t slice = 0; slice < static_cast<std::uint32_t>(slices); ++slice) {
    const std::uint32_t next = (slice + 1) % slices;
    mesh.indices.insert(mesh.indices.end(), {last_ring + slice, last_ring + next, south});
  }
  return mesh;
}

Mesh make_torus(int rings, int sides, float ring_radius, float tube_radius) {
  require_count("make_torus", "rings", rings, 3);
  require_count("make_torus", "sides", sides, 3);
  require_positive("make_torus", "ring_radius", ring_radius);
  require_positive("make_torus", "tube_radius", tube_radius);
  const std::uint64_t vertex_count = static_cast<std::uint64_t>(rings) * sides;
  require_indexable("make_torus", vertex_count);

  Mesh mesh;
  reserve_vertices(mesh, vertex_count);
  // phi goes around the y axis, theta around the tube; with theta along the grid's u and phi
  // along its v, cross(u, v) points out of the tube.
  for (int ring = 0; ring < rings; ++ring) {
    const double phi = 2 * std::numbers::pi * ring / rings;
    for (int side = 0; side < sides; ++side) {
      const double theta = 2 * std::numbers::pi * side / sides;
      const glm::dvec3 normal(std::cos(theta) * std::cos(phi), std::sin(theta), std::cos(theta) * std::sin(phi));
      const glm::dvec3 tube_center(ring_radius * std::cos(phi), 0, ring_radius * std::sin(phi));
      add_vertex(mesh, glm::vec3(tube_center + double{tube_radius} * normal), glm::vec3(normal));
    }
  }
  add_grid_triangles(mesh, 0, sides, rings, /*wrap_u=*/true, /*wrap_v=*/true);
  return mesh;
}

Mesh make_torus_knot(int p, int q, int segments, int sides, float ring_radius, float winding_radius,
                     float tube_radius) {
  require_count("make_torus_knot", "p", p, 1);
  require_count("make_torus_knot", "q", q, 1);
  if (std::gcd(p, q) != 1) {
    throw InvalidArgument("make_torus_knot: p and q must be coprime, got " + std::to_string(p) + " and " +
                          std::to_string(q));
  }
  require_count("make_torus_knot", "segments", segments, 3);
  require_count("make_torus_knot", "sides", sides, 3);
  require_positive("make_torus_knot", "winding_radius", winding_radius);
  require_positive("make_torus_knot", "tube_radius", tube_radius);
  if (!(std::isfinite(ring_radius) && ring_radius > winding_radius)) {
    throw InvalidArgument("make_torus_knot: ring_radius must be a finite number above winding_radius (" +
                          format_number(winding_radius) + "), got " + format_number(ring_radius));
  }
  const std::uint64_t vertex_count = static_cast<std::uint64_t>(segments) * sides;
  require_indexable("make_torus_knot", vertex_count);

  Mesh mesh;
  reserve_vertices(mesh, vertex_count);
  const double big = ring_radius, small = winding_radius;
  for (int segment = 0; segment < segments; ++segment) {
    // The curve at t: azimuth u = p t around the y axis, angle v = q t around the ring.
    const double t = 2 * std::numbers::pi * segment / segments;
    const double u = p * t, v = q * t;
    const double rho = big + small * std::cos(v);  // distance from the y axis, > 0
    const double rho_dt = -small * q * std::sin(v);
    const glm::dvec3 radial(std::cos(u), 0, std::sin(u));
    const glm::dvec3 azimuthal(-std::sin(u), 0, std::cos(u));
    const glm::dvec3 curve = rho * radial + glm::dvec3(0, small * std::sin(v), 0);
    const glm::dvec3 tangent =
        glm::normalize(rho_dt * radial + rho * p * azimuthal + glm::dvec3(0, small * q * std::cos(v), 0));
    // The tube's frame: the radial direction made perpendicular to the tangent. The tangent always
    // has an azimuthal component (rho * p > 0), so it is never radial and the frame never
    // degenerates, unlike a Frenet frame where the curvature vanishes; it is periodic in t, so the
    // tube closes without a seam.
    const glm::dvec3 across = glm::normalize(radial - glm::dot(radial, tangent) * tangent);
    const glm::dvec3 binormal = glm::cross(tangent, across);
    for (int side = 0; side < sides; ++side) {
      const double theta = 2 * std::numbers::pi * side / sides;
      const glm::dvec3 normal = std::cos(theta) * across + std::sin(theta) * binormal;
      add_vertex(mesh, glm::vec3(curve + double{tube_radius} * normal), glm::vec3(normal));
    }
  }
  // theta along the grid's u and t along its v: cross(u, v) is cross(d/dtheta, tangent), outward.
  add_grid_triangles(mesh, 0, sides, segments, /*wrap_u=*/true, /*wrap_v=*/true);
  return mesh;
}

Mesh make_box(Vec3f min, Vec3f max) {
  require_finite("make_box", "min", min);
  require_finite("make_box", "max", max);
  if (!(min.x < max.x && min.y < max.y && min.z < max.z)) {
    throw InvalidArgument("make_box: min must be below max on every axis, got min (" + format_number(min.x) + ", " +
                          format_number(min.y) + ", " + format_number(min.z) + ") and max (" +
                          format_number(max.x) + ", " + format_number(max.y) + ", " + format_number(max.z) + ")");
  }
  // Each face as its outward normal and two in-plane axes with cross(u, v) == normal.
  struct Face {
    glm::vec3 normal, u, v;
  };
  static constexpr Face kFaces[6] = {
      {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},  {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
      {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}},  {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
      {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}},
  };
  const glm::vec3 lo(min.x, min.y, min.z), hi(max.x, max.y, max.z);

  Mesh mesh;
  reserve_vertices(mesh, 24);
  for (std::uint32_t face = 0; face < 6; ++face) {
    const Face& f = kFaces[face];
    for (float v : {-1.0f, 1.0f}) {
      for (float u : {-1.0f, 1.0f}) {
        // Pick each coordinate from min or max, rather than computing it, so corners are exact.
        const glm::vec3 corner = f.normal + u * f.u + v * f.v;
        add_vertex(mesh, glm::mix(lo, hi, glm::greaterThan(corner, glm::vec3(0))), f.normal);
      }
    }
    add_grid_triangles(mesh, 4 * face, 1, 1, /*wrap_u=*/false, /*wrap_v=*/false);
  }
  return mesh;
}

Mesh make_terrain(int cells_x, int cells_z, float size_x, float size_z, float height, std::uint64_t seed) {
  require_count("make_terrain", "cells_x", cells_x, 1);
  require_count("make_terrain", "cells_z", cells_z, 1);
  require_positive("make_terrain", "size_x", size_x);
  require_positive("make_terrain", "size_z", size_z);
  if (!std::isfinite(height)) {
    throw InvalidArgument("make_terrain: height must be finite, got " + format_number(height));
  }
  const int columns = cells_x + 1;
  const int rows = cells_z + 1;
  require_indexable("make_terrain", static_cast<std::uint64_t>(columns) * rows);

  // Rows run from +z to -z: the grid's u is +x and v is -z, so cross(u, v) is +y and the triangles
  // are counter-clockwise seen from above.
  std::vector<float> xs(columns), zs(rows);
  for (int i = 0; i < columns; ++i) xs[i] = grid_coordinate(i, cells_x, size_x);
  for (int j = 0; j < rows; ++j) zs[j] = -grid_coordinate(j, cells_z, size_z);

  // About four hills across the longer side, whatever the resolution.
  const double feature_size = std::max(size_x, size_z) / 4.0;
  std::vector<float> heights(static_cast<std::size_t>(columns) * rows);
  const auto height_at = [&](int i, int j) -> float& { return heights[static_cast<std::size_t>(j) * columns + i]; };
  for (int j = 0; j < rows; ++j) {
    for (int i = 0; i < columns; ++i) {
      height_at(i, j) = static_cast<float>(height * fractal_noise(seed, xs[i] / feature_size, zs[j] / feature_size));
    }
  }

  Mesh mesh;
  reserve_vertices(mesh, heights.size());
  for (int j = 0; j < rows; ++j) {
    for (int i = 0; i < columns; ++i) {
      // Central differences inside, one-sided at the border. The surface y = h(x, z) has the
      // normal (-dh/dx, 1, -dh/dz).
      const int i0 = std::max(i - 1, 0), i1 = std::min(i + 1, cells_x);
      const int j0 = std::max(j - 1, 0), j1 = std::min(j + 1, cells_z);
      const float slope_x = (height_at(i1, j) - height_at(i0, j)) / (xs[i1] - xs[i0]);
      const float slope_z = (height_at(i, j1) - height_at(i, j0)) / (zs[j1] - zs[j0]);
      add_vertex(mesh, {xs[i], height_at(i, j), zs[j]}, glm::vec3(glm::normalize(glm::dvec3(-slope_x, 1, -slope_z))));
    }
  }
  add_grid_triangles(mesh, 0, cells_x, cells_z, /*wrap_u=*/false, /*wrap_v=*/false);
  return mesh;
}

Mesh make_plane(int cells_x, int cells_y, float size_x, float size_y) {
  require_count("make_plane", "cells_x", cells_x, 1);
  require_count("make_plane", "cells_y", cells_y, 1);
  require_positive("make_plane", "size_x", size_x);
  require_positive("make_plane", "size_y", size_y);
  const std::uint64_t vertex_count = static_cast<std::uint64_t>(cells_x + 1) * (cells_y + 1);
  require_indexable("make_plane", vertex_count);

  Mesh mesh;
  reserve_vertices(mesh, vertex_count);
  for (int j = 0; j <= cells_y; ++j) {
    for (int i = 0; i <= cells_x; ++i) {
      add_vertex(mesh, {grid_coordinate(i, cells_x, size_x), grid_coordinate(j, cells_y, size_y), 0}, {0, 0, 1});
    }
  }
  add_grid_triangles(mesh, 0, cells_x, cells_y, /*wrap_u=*/false, /*wrap_v=*/false);
  return mesh;
}

Mesh make_random_triangles(int count, std::uint64_t seed, Vec3f box_min, Vec3f box_max, float max_size) {
  require_count("make_random_triangles", "count", count, 0);
  require_finite("make_random_triangles", "box_min", box_min);
  require_finite("make_random_triangles", "box_max", box_max);
  if (!(box_min.x <= box_max.x && box_min.y <= box_max.y && box_min.z <= box_max.z)) {
    throw InvalidArgument("make_random_triangles: box_min must not exceed box_max on any axis");
  }
  if (!(std::isfinite(max_size) && max_size >= 0)) {
    throw InvalidArgument("make_random_triangles: max_size must be a finite number >= 0, got " +
                          format_number(max_size));
  }
  require_indexable("make_random_triangles", 3 * static_cast<std::uint64_t>(count));

  const glm::vec3 lo(box_min.x, box_min.y, box_min.z), hi(box_max.x, box_max.y, box_max.z);
  Random random(seed);
  Mesh mesh;
  reserve_vertices(mesh, 3 * static_cast<std::size_t>(count));
  mesh.indices.reserve(3 * static_cast<std::size_t>(count));
  for (int triangle = 0; triangle < count; ++triangle) {
    const glm::vec3 center = random.point_in(lo, hi);
    const double u = random.unit();
    const auto size = static_cast<float>(max_size * u * u * u);
    for (int corner = 0; corner < 3; ++corner) {
      const glm::vec3 offset = random.point_in(glm::vec3(-size), glm::vec3(size));
      const glm::vec3 normal = random.unit_vector();
      mesh.indices.push_back(static_cast<std::uint32_t>(mesh.vertex_count()));
      add_vertex(mesh, glm::clamp(center + offset, lo, hi), normal);
    }
  }
  return mesh;
}

Mesh merge(const std::vector<Mesh>& meshes) {
  std::uint64_t vertex_count = 0;
  std::size_t index_count = 0;
  bool any_texcoords = false;
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    require_attributes_per_vertex("merge: mesh " + std::to_string(m), meshes[m]);
    vertex_count += meshes[m].vertex_count();
    index_count += meshes[m].indices.size();
    any_texcoords |= !meshes[m].texcoords.empty();
  }
  require_indexable("merge", vertex_count);

  Mesh merged;
  reserve_vertices(merged, vertex_count);
  if (any_texcoords) merged.texcoords.reserve(2 * vertex_count);
  merged.indices.reserve(index_count);
  for (const Mesh& mesh : meshes) {
    const auto offset = static_cast<std::uint32_t>(merged.vertex_count());
    merged.positions.insert(merged.positions.end(), mesh.positions.begin(), mesh.positions.end());
    merged.normals.insert(merged.normals.end(), mesh.normals.begin(), mesh.normals.end());
    if (mesh.texcoords.empty()) {
      if (any_texcoords) merged.texcoords.resize(merged.texcoords.size() + 2 * mesh.vertex_count(), 0.0f);
    } else {
      merged.texcoords.insert(merged.texcoords.end(), mesh.texcoords.begin(), mesh.texcoords.end());
    }
    for (std::uint32_t index : mesh.indices) merged.indices.push_back(index + offset);
  }
  return merged;
}

void transform(Mesh& mesh, const glm::mat4& matrix) {
  require_attributes_per_vertex("transform: the mesh", mesh);
  // In double: the cofactors of a large scale (1e20) overflow floats and would make normals NaN.
  const glm::dmat3 linear(matrix);
  const double determinant = glm::determinant(linear);
  // The cofactor matrix is the inverse transpose times the determinant, and unlike the inverse it
  // exists for singular matrices too. Taking it times the determinant's sign keeps normals on the
  // side they were on.
  glm::dmat3 normal_matrix(glm::cross(linear[1], linear[2]), glm::cross(linear[2], linear[0]),
                           glm::cross(linear[0], linear[1]));
  if (determinant < 0) normal_matrix = -normal_matrix;

  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    float* position = &mesh.positions[3 * v];
    const glm::vec4 moved = matrix * glm::vec4(position[0], position[1], position[2], 1);
    position[0] = moved.x, position[1] = moved.y, position[2] = moved.z;

    float* normal = &mesh.normals[3 * v];
    const glm::dvec3 turned = normal_matrix * glm::dvec3(normal[0], normal[1], normal[2]);
    const double length = glm::length(turned);
    const glm::vec3 unit = length > 0 ? glm::vec3(turned / length) : glm::vec3(0);
    normal[0] = unit.x, normal[1] = unit.y, normal[2] = unit.z;
  }
  if (determinant < 0) {
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) std::swap(mesh.indices[3 * t + 1], mesh.indices[3 * t + 2]);
  }
}

}  // namespace clraster::io
