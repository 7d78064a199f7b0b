// Reading a clraster::io::Mesh back in tests: vertices, texture coordinates, corners and face
// normals, in double so that checks on the float data are not blurred by the arithmetic that
// inspects it.
#pragma once

#include "io/mesh.hpp"

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

namespace clraster::test {

inline glm::dvec3 position(const io::Mesh& mesh, std::uint32_t v) {
  return {mesh.positions[3 * v], mesh.positions[3 * v + 1], mesh.positions[3 * v + 2]};
}

inline glm::dvec3 normal(const io::Mesh& mesh, std::uint32_t v) {
  return {mesh.normals[3 * v], mesh.normals[3 * v + 1], mesh.normals[3 * v + 2]};
}

inline glm::dvec2 texcoord(const io::Mesh& mesh, std::uint32_t v) {
  return {mesh.texcoords[2 * v], mesh.texcoords[2 * v + 1]};
}

// Corner k (0..2) of a triangle.
inline glm::dvec3 corner(const io::Mesh& mesh, std::size_t triangle, int k) {
  return position(mesh, mesh.indices[3 * triangle + k]);
}

// cross(v1 - v0, v2 - v0): twice the area, pointing to the side from which the triangle is
// counter-clockwise.
inline glm::dvec3 face_cross(const io::Mesh& mesh, std::size_t triangle) {
  const glm::dvec3 v0 = corner(mesh, triangle, 0);
  return glm::cross(corner(mesh, triangle, 1) - v0, corner(mesh, triangle, 2) - v0);
}

}  // namespace clraster::test
