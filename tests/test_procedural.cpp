// Procedural meshes: counts, orientation, normals, determinism, and the merge and transform
// operations.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>
#include <numbers>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>
#include <string>
#include <utility>
#include <vector>

#include "clraster/clraster.hpp"
#include "support/mesh_inspection.hpp"
#include "io/procedural.hpp"

namespace clraster::io {
namespace {

using test::corner;
using test::face_cross;
using test::normal;
using test::position;



glm::dvec3 centroid(const Mesh& mesh, std::size_t triangle) {
  return (corner(mesh, triangle, 0) + corner(mesh, triangle, 1) + corner(mesh, triangle, 2)) / 3.0;
}

void expect_well_formed(const Mesh& mesh) {
  ASSERT_EQ(mesh.positions.size() % 3, 0u);
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  ASSERT_EQ(mesh.indices.size() % 3, 0u);
  for (std::uint32_t index : mesh.indices) ASSERT_LT(index, mesh.vertex_count());
  for (float value : mesh.positions) ASSERT_TRUE(std::isfinite(value));
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
    ASSERT_NEAR(glm::length(normal(mesh, v)), 1.0f, 1e-5f) << "vertex " << v;
  }
}

// Every triangle is counter-clockwise seen from the side its vertex normals point to.
void expect_winding_follows_normals(const Mesh& mesh) {
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const glm::dvec3 cross = face_cross(mesh, t);
    ASSERT_GT(glm::length(cross), 0) << "triangle " << t;
    for (int k = 0; k < 3; ++k) {
      ASSERT_GT(glm::dot(cross, normal(mesh, mesh.indices[3 * t + k])), 0) << "triangle " << t;
    }
  }
}

bool same_bytes(const Mesh& a, const Mesh& b) {
  const auto same = [](const auto& x, const auto& y) {
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof x[0]) == 0;
  };
  return same(a.positions, b.positions) && same(a.normals, b.normals) && same(a.indices, b.indices);
}

// FNV-1a over a mesh's bytes, to pin generated meshes down across platforms and versions.
std::uint64_t fingerprint(const Mesh& mesh) {
  std::uint64_t hash = 0xcbf29ce484222325ull;
  const auto add = [&](const void* data, std::size_t size) {
    const auto* bytes = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < size; ++i) hash = (hash ^ bytes[i]) * 0x100000001b3ull;
  };
  add(mesh.positions.data(), mesh.positions.size() * sizeof(float));
  add(mesh.normals.data(), mesh.normals.size() * sizeof(float));
  add(mesh.indices.data(), mesh.indices.size() * sizeof(std::uint32_t));
  return hash;
}

TEST(MakeSphere, CountsRadiiAndOutwardFaces) {
  const Vec3f center{1, -2, 3};
  const Mesh mesh = make_sphere(16, 8, 2.5f, center);
  expect_well_formed(mesh);
  EXPECT_EQ(mesh.vertex_count(), 2u + 16 * 7);
  EXPECT_EQ(mesh.triangle_count(), 2u * 16 * 7);
  const glm::dvec3 c(center.x, center.y, center.z);
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
    EXPECT_NEAR(glm::distance(position(mesh, v), c), 2.5, 1e-5);
    EXPECT_LT(glm::distance(normal(mesh, v), (position(mesh, v) - c) / 2.5), 1e-5);
  }
  expect_winding_follows_normals(mesh);
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    EXPECT_GT(glm::dot(face_cross(mesh, t), centroid(mesh, t) - glm::dvec3(c)), 0) << "triangle " << t;
  }
}

TEST(MakeTorus, CountsAndOutwardFaces) {
  const Mesh mesh = make_torus(24, 12, 2, 0.5f);
  expect_well_formed(mesh);
  EXPECT_EQ(mesh.vertex_count(), 24u * 12);
  EXPECT_EQ(mesh.triangle_count(), 2u * 24 * 12);
  expect_winding_follows_normals(mesh);
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    // Outwards from the nearest point of the tube's centre circle.
    const glm::dvec3 middle = centroid(mesh, t);
    const glm::dvec3 tube_center = 2.0 * glm::normalize(glm::dvec3(middle.x, 0, middle.z));
    EXPECT_GT(glm::dot(face_cross(mesh, t), middle - tube_center), 0) << "triangle " << t;
  }
}

TEST(MakeTorusKnot, CountsTubeRadiusAndOutwardFaces) {
  // The trefoil: the curve (rho cos 2t, sin 3t, rho sin 2t) with rho = 2 + cos 3t.
  const Mesh mesh = make_torus_knot(2, 3, 120, 10, 2, 1, 0.4f);
  expect_well_formed(mesh);
  EXPECT_EQ(mesh.vertex_count(), 120u * 10);
  EXPECT_EQ(mesh.triangle_count(), 2u * 120 * 10);
  expect_winding_follows_normals(mesh);
  for (std::uint32_t segment = 0; segment < 120; ++segment) {
    const double t = 2 * std::numbers::pi * segment / 120;
    const double rho = 2 + std::cos(3 * t);
    const glm::dvec3 curve(rho * std::cos(2 * t), std::sin(3 * t), rho * std::sin(2 * t));
    for (std::uint32_t side = 0; side < 10; ++side) {
      const std::uint32_t v = segment * 10 + side;
      // On the tube around the curve, the normal pointing from the curve to the vertex.
      EXPECT_LT(glm::distance(position(mesh, v), curve + 0.4 * normal(mesh, v)), 1e-5) << "vertex " << v;
    }
  }
  // Closed: every edge is shared by exactly two triangles, once in each direction.
  std::map<std::pair<std::uint32_t, std::uint32_t>, int> edges;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    for (int k = 0; k < 3; ++k) ++edges[{mesh.indices[3 * t + k], mesh.indices[3 * t + (k + 1) % 3]}];
  }
  for (const auto& [edge, count] : edges) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(edges.count({edge.second, edge.first}), 1u) << edge.first << " - " << edge.second;
  }
}

TEST(MakeBox, TwentyFourVerticesWithFlatOutwardNormals) {
  const Mesh mesh = make_box({-1, 0, 2}, {3, 1, 2.5f});
  expect_well_formed(mesh);
  EXPECT_EQ(mesh.vertex_count(), 24u);
  EXPECT_EQ(mesh.triangle_count(), 12u);
  expect_winding_follows_normals(mesh);
  double area = 0;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const glm::dvec3 n = normal(mesh, mesh.indices[3 * t]);
    EXPECT_LT(glm::distance(glm::normalize(face_cross(mesh, t)), n), 1e-6) << "triangle " << t;
    area += glm::length(face_cross(mesh, t)) / 2;
  }
  EXPECT_DOUBLE_EQ(area, 2 * (4 * 1 + 4 * 0.5 + 1 * 0.5));
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
    const glm::dvec3 p = position(mesh, v);
    EXPECT_TRUE(p.x == -1 || p.x == 3);
    EXPECT_TRUE(p.y == 0 || p.y == 1);
    EXPECT_TRUE(p.z == 2 || p.z == 2.5f);
  }
}

TEST(MakeTerrain, CountsExtentsAndCounterClockwiseFromAbove) {
  const Mesh mesh = make_terrain(40, 30, 8, 6, 1.5f, 7);
  expect_well_formed(mesh);
  EXPECT_EQ(mesh.vertex_count(), 41u * 31);
  EXPECT_EQ(mesh.triangle_count(), 2u * 40 * 30);
  double min_x = INFINITY, max_x = -INFINITY, min_z = INFINITY, max_z = -INFINITY, min_y = INFINITY, max_y = -INFINITY;
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
    const glm::dvec3 p = position(mesh, v);
    min_x = std::min(min_x, p.x), max_x = std::max(max_x, p.x);
    min_y = std::min(min_y, p.y), max_y = std::max(max_y, p.y);
    min_z = std::min(min_z, p.z), max_z = std::max(max_z, p.z);
    EXPECT_GT(normal(mesh, v).y, 0);
  }
  EXPECT_EQ(min_x, -4);
  EXPECT_EQ(max_x, 4);
  EXPECT_EQ(min_z, -3);
  EXPECT_EQ(max_z, 3);
  EXPECT_GE(min_y, -1.5f);
  EXPECT_LE(max_y, 1.5f);
  EXPECT_GT(max_y - min_y, 0.3f) << "a landscape, not a plane";
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) EXPECT_GT(face_cross(mesh, t).y, 0) << "triangle " << t;
  expect_winding_follows_normals(mesh);
}

TEST(MakeTerrain, DeterministicPerSeedAndIndependentOfResolution) {
  const Mesh a = make_terrain(16, 16, 10, 10, 2, 42);
  EXPECT_TRUE(same_bytes(a, make_terrain(16, 16, 10, 10, 2, 42)));
  EXPECT_FALSE(same_bytes(a, make_terrain(16, 16, 10, 10, 2, 43)));
  // Every other grid point of the finer terrain is a grid point of the coarser one.
  const Mesh coarse = make_terrain(8, 8, 10, 10, 2, 42);
  for (std::uint32_t j = 0; j <= 8; ++j) {
    for (std::uint32_t i = 0; i <= 8; ++i) {
      EXPECT_EQ(position(coarse, j * 9 + i), position(a, 2 * j * 17 + 2 * i)) << i << ", " << j;
    }
  }
}

TEST(MakePlane, TilesTheRectangleFacingZ) {
  const Mesh mesh = make_plane(7, 5, 3.5f, 2);
  expect_well_formed(mesh);
  EXPECT_EQ(mesh.vertex_count(), 8u * 6);
  EXPECT_EQ(mesh.triangle_count(), 2u * 7 * 5);
  double area = 0;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    EXPECT_GT(face_cross(mesh, t).z, 0);
    area += glm::length(face_cross(mesh, t)) / 2;
  }
  EXPECT_NEAR(area, 3.5 * 2, 1e-9);
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) EXPECT_EQ(normal(mesh, v), glm::dvec3(0, 0, 1));
}

TEST(MakeRandomTriangles, SeparateTrianglesInsideTheBox) {
  const Vec3f lo{-2, 0, -1}, hi{2, 1, 0};
  const Mesh mesh = make_random_triangles(5000, 1234, lo, hi, 0.5f);
  expect_well_formed(mesh);
  ASSERT_EQ(mesh.triangle_count(), 5000u);
  ASSERT_EQ(mesh.vertex_count(), 15000u);
  for (std::uint32_t i = 0; i < mesh.indices.size(); ++i) ASSERT_EQ(mesh.indices[i], i);
  double largest_extent = 0;
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
    const glm::dvec3 p = position(mesh, v);
    ASSERT_TRUE(p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y && p.z >= lo.z && p.z <= hi.z) << v;
  }
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const glm::dvec3 extent = glm::max(glm::max(corner(mesh, t, 0), corner(mesh, t, 1)), corner(mesh, t, 2)) -
                             glm::min(glm::min(corner(mesh, t, 0), corner(mesh, t, 1)), corner(mesh, t, 2));
    largest_extent = std::max({largest_extent, extent.x, extent.y, extent.z});
  }
  EXPECT_LE(largest_extent, 1.0f);
  EXPECT_GT(largest_extent, 0.25f) << "some triangles are large";
}

TEST(MakeRandomTriangles, SameSeedSameBytesOnEveryPlatform) {
  const Mesh a = make_random_triangles(1000, 99, {0, 0, 0}, {1, 1, 1}, 0.1f);
  EXPECT_TRUE(same_bytes(a, make_random_triangles(1000, 99, {0, 0, 0}, {1, 1, 1}, 0.1f)));
  EXPECT_FALSE(same_bytes(a, make_random_triangles(1000, 100, {0, 0, 0}, {1, 1, 1}, 0.1f)));
  // Pinned: a change here changes every stress test and benchmark scene.
  EXPECT_EQ(fingerprint(a), 11526743923031533918u);
  EXPECT_EQ(fingerprint(make_terrain(32, 32, 10, 10, 2, 5)), 3824801519471437668u);
}

TEST(Merge, AppendsVerticesAndOffsetsIndices) {
  const Mesh box = make_box({0, 0, 0}, {1, 1, 1});
  const Mesh sphere = make_sphere(8, 4, 1, {5, 0, 0});
  const Mesh merged = merge({box, sphere, Mesh{}});
  expect_well_formed(merged);
  ASSERT_EQ(merged.vertex_count(), box.vertex_count() + sphere.vertex_count());
  ASSERT_EQ(merged.triangle_count(), box.triangle_count() + sphere.triangle_count());
  for (std::size_t t = 0; t < merged.triangle_count(); ++t) {
    const bool from_box = t < box.triangle_count();
    const Mesh& source = from_box ? box : sphere;
    const std::size_t source_triangle = from_box ? t : t - box.triangle_count();
    for (int k = 0; k < 3; ++k) EXPECT_EQ(corner(merged, t, k), corner(source, source_triangle, k));
  }
  EXPECT_EQ(merge({}).vertex_count(), 0u);
}

TEST(Merge, GivesMeshesWithoutTexcoordsZerosWhenOthersHaveThem) {
  Mesh textured = make_box({0, 0, 0}, {1, 1, 1});
  for (std::size_t v = 0; v < textured.vertex_count(); ++v) {
    textured.texcoords.insert(textured.texcoords.end(), {0.5f, static_cast<float>(v)});
  }
  const Mesh plain = make_sphere(8, 4, 1);
  const Mesh merged = merge({plain, textured});
  expect_well_formed(merged);
  ASSERT_EQ(merged.texcoords.size(), 2 * merged.vertex_count());
  EXPECT_EQ(std::vector<float>(merged.texcoords.begin(), merged.texcoords.begin() + 2 * plain.vertex_count()),
            std::vector<float>(2 * plain.vertex_count(), 0.0f));
  EXPECT_EQ(std::vector<float>(merged.texcoords.begin() + 2 * plain.vertex_count(), merged.texcoords.end()),
            textured.texcoords);
  EXPECT_TRUE(merge({plain, plain}).texcoords.empty());

  Mesh short_texcoords = textured;
  short_texcoords.texcoords.pop_back();
  EXPECT_THROW(merge({short_texcoords}), InvalidArgument);
}

TEST(Transform, MovesPositionsAndTurnsNormals) {
  Mesh mesh = make_box({-1, -1, -1}, {1, 1, 1});
  const glm::mat4 matrix = glm::rotate(glm::translate(glm::mat4(1), glm::vec3(10, 0, 0)), glm::radians(90.0f),
                                       glm::vec3(0, 0, 1));
  const Mesh original = mesh;
  transform(mesh, matrix);
  expect_well_formed(mesh);
  EXPECT_EQ(mesh.indices, original.indices);
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
    const glm::dvec3 p = position(original, v), n = normal(original, v);
    EXPECT_LT(glm::distance(position(mesh, v), glm::dvec3(10 - p.y, p.x, p.z)), 1e-5);
    EXPECT_LT(glm::distance(normal(mesh, v), glm::dvec3(-n.y, n.x, n.z)), 1e-6);
  }
}

TEST(Transform, NonUniformScaleUsesTheInverseTranspose) {
  // A normal (1, 1, 0)/sqrt(2) on the plane x + y = 0, stretched by 4 in x: the plane becomes
  // x/4 + y = 0, with normal (1/4, 1, 0) normalized.
  Mesh mesh;
  mesh.positions = {0, 0, 0, 1, -1, 0, 0, 0, 1};
  const float h = 1 / std::sqrt(2.0f);
  mesh.normals = {h, h, 0, h, h, 0, h, h, 0};
  mesh.indices = {0, 2, 1};
  transform(mesh, glm::scale(glm::mat4(1), glm::vec3(4, 1, 1)));
  const glm::dvec3 expected = glm::normalize(glm::dvec3(0.25, 1, 0));
  for (std::uint32_t v = 0; v < 3; ++v) EXPECT_LT(glm::distance(normal(mesh, v), expected), 1e-6);
  expect_winding_follows_normals(mesh);
}

TEST(Transform, MirroringKeepsFrontFacesFront) {
  Mesh mesh = make_sphere(12, 6, 1);
  transform(mesh, glm::scale(glm::mat4(1), glm::vec3(-1, 1, 1)));
  expect_well_formed(mesh);
  expect_winding_follows_normals(mesh);
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
    EXPECT_LT(glm::distance(normal(mesh, v), position(mesh, v)), 1e-5f);
  }
}

TEST(Transform, FlatteningKeepsTheNormalsOfTheFlatAxis) {
  // Singular matrix: no inverse, but the plane's normal is still defined.
  Mesh mesh = make_plane(2, 2, 1, 1);
  transform(mesh, glm::scale(glm::mat4(1), glm::vec3(3, 2, 0)));
  expect_well_formed(mesh);
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) EXPECT_EQ(normal(mesh, v), glm::dvec3(0, 0, 1));
}

TEST(Procedural, InvalidArgumentsAreErrors) {
  EXPECT_THROW(make_sphere(2, 4, 1), InvalidArgument);
  EXPECT_THROW(make_sphere(8, 1, 1), InvalidArgument);
  EXPECT_THROW(make_sphere(8, 4, 0), InvalidArgument);
  EXPECT_THROW(make_sphere(8, 4, NAN), InvalidArgument);
  EXPECT_THROW(make_sphere(8, 4, 1, {INFINITY, 0, 0}), InvalidArgument);
  EXPECT_THROW(make_torus(2, 8, 1, 0.5f), InvalidArgument);
  EXPECT_THROW(make_torus(8, 8, 1, -0.5f), InvalidArgument);
  EXPECT_THROW(make_box({0, 0, 0}, {1, 0, 1}), InvalidArgument);
  EXPECT_THROW(make_torus_knot(0, 3, 64, 8, 2, 1, 0.4f), InvalidArgument);
  EXPECT_THROW(make_torus_knot(2, 4, 64, 8, 2, 1, 0.4f), InvalidArgument);  // not coprime: two loops
  EXPECT_THROW(make_torus_knot(2, 3, 2, 8, 2, 1, 0.4f), InvalidArgument);
  EXPECT_THROW(make_torus_knot(2, 3, 64, 8, 1, 1, 0.4f), InvalidArgument);  // the curve would reach the axis
  EXPECT_THROW(make_torus_knot(2, 3, 64, 8, 2, 1, 0), InvalidArgument);
  EXPECT_THROW(make_terrain(0, 8, 1, 1, 1, 0), InvalidArgument);
  EXPECT_THROW(make_terrain(8, 8, 1, 1, INFINITY, 0), InvalidArgument);
  EXPECT_THROW(make_plane(8, 8, 0, 1), InvalidArgument);
  EXPECT_THROW(make_random_triangles(-1, 0, {0, 0, 0}, {1, 1, 1}, 1), InvalidArgument);
  EXPECT_THROW(make_random_triangles(10, 0, {0, 0, 0}, {-1, 1, 1}, 1), InvalidArgument);
  EXPECT_THROW(make_random_triangles(10, 0, {0, 0, 0}, {1, 1, 1}, -1), InvalidArgument);
  Mesh no_normals = make_box({0, 0, 0}, {1, 1, 1});
  no_normals.normals.clear();
  EXPECT_THROW(merge({no_normals}), InvalidArgument);
  EXPECT_THROW(transform(no_normals, glm::mat4(1)), InvalidArgument);
  // 70001^2 vertices do not fit 32-bit indices; refused before anything is allocated.
  try {
    make_plane(70000, 70000, 1, 1);
    ADD_FAILURE() << "no error";
  } catch (const InvalidArgument& error) {
    EXPECT_STREQ(error.what(), "make_plane: 4900140001 vertices is more than 32-bit indices can address (4294967295)");
  }
}

}  // namespace
}  // namespace clraster::io
