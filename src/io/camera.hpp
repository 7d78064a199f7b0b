// A pinhole camera as the command line describes it, and the OpenGL matrices it stands for.
#pragma once

#include <optional>
#include <string>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

#include "clraster/clraster.hpp"
#include "io/mesh.hpp"

namespace clraster::io {

struct Camera {
  glm::vec3 eye{0, 0, 3};
  glm::vec3 target{0, 0, 0};
  glm::vec3 up{0, 1, 0};
  float fov_degrees = 45;  // vertical field of view
  float near_plane = 0.1f;
  float far_plane = 100;
};

// The direction from target to eye that fit_camera uses: a three-quarter view from the front
// right, slightly from above, so that three faces of an axis-aligned box are visible.
inline const glm::vec3 kFitDirection{0.5f, 0.4f, 1.0f};

// The world-to-eye matrix, as gluLookAt (right-handed, looking down -z).
glm::mat4 view_matrix(const Camera& camera);

// The eye-to-clip matrix, as gluPerspective: vertical field of view, aspect = width / height, clip
// z in [-w, w] from the near to the far plane. Throws InvalidArgument for an aspect that is not a
// positive finite number. Expects a camera that passes validate_camera.
glm::mat4 projection_matrix(const Camera& camera, float aspect);

// The same matrix as clraster takes it (column-major).
clraster::Mat4 to_mat4(const glm::mat4& matrix);

// A camera looking at the sphere's centre from direction kFitDirection, up +y, far enough that the
// sphere (radius 1 if it is 0) fills the vertical or horizontal field of view, whichever is
// tighter, with a margin of 10% of its radius; near and far planes enclose it with a margin of 5%.
// Throws InvalidArgument for a non-positive or non-finite aspect or fov, or a sphere too large to
// frame in float.
Camera fit_camera(const BoundingSphere& sphere, float aspect, float fov_degrees = 45);

// Throws InvalidArgument naming the first bad value of those given: a non-finite value,
// fov_degrees outside (0, 180), near_plane <= 0, far_plane <= near_plane. (A camera's own numbers,
// which a command line can check before it has a scene to fit a camera to.)
void validate_lens(float fov_degrees, std::optional<float> near_plane = {}, std::optional<float> far_plane = {});

// Throws InvalidArgument naming the first bad value: a non-finite value, fov_degrees outside
// (0, 180), near_plane <= 0, far_plane <= near_plane, eye == target, or up zero or parallel to the
// view direction.
void validate_camera(const Camera& camera);

// Parses "X,Y,Z" (three finite decimal numbers, spaces around them allowed) for the command-line
// option `option_name`; throws InvalidArgument("--eye: expected three numbers X,Y,Z, got 'abc'").
glm::vec3 parse_vec3(const std::string& text, const std::string& option_name);

}  // namespace clraster::io
