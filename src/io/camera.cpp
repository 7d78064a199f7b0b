#include "io/camera.hpp"
#include "io/format.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string_view>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

namespace clraster::io {
namespace {

std::string format_vec3(glm::vec3 v) {
  return "(" + format_number(v.x) + ", " + format_number(v.y) + ", " + format_number(v.z) + ")";
}

bool is_finite(glm::vec3 v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

void require_finite_vec3(const char* name, glm::vec3 value) {
  if (!is_finite(value)) {
    throw InvalidArgument(std::string("camera: ") + name + " must be finite, got " + format_vec3(value));
  }
}

void require_finite(const char* name, float value) {
  if (!std::isfinite(value)) {
    throw InvalidArgument(std::string("camera: ") + name + " must be finite, got " + format_number(value));
  }
}

void require_aspect(const char* function, float aspect) {
  if (!(std::isfinite(aspect) && aspect > 0)) {
    throw InvalidArgument(std::string(function) + ": aspect must be a positive finite number, got " +
                          format_number(aspect));
  }
}

std::string_view trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t");
  if (first == std::string_view::npos) return {};
  return text.substr(first, text.find_last_not_of(" \t") - first + 1);
}

}  // namespace

glm::mat4 view_matrix(const Camera& camera) { return glm::lookAtRH(camera.eye, camera.target, camera.up); }

glm::mat4 projection_matrix(const Camera& camera, float aspect) {
  require_aspect("projection_matrix", aspect);
  // The _NO variant (z from -1 to 1) whatever GLM_FORCE_DEPTH_ZERO_TO_ONE says.
  return glm::perspectiveRH_NO(glm::radians(camera.fov_degrees), aspect, camera.near_plane, camera.far_plane);
}

clraster::Mat4 to_mat4(const glm::mat4& matrix) {
  clraster::Mat4 columns;
  for (int column = 0; column < 4; ++column) {
    for (int row = 0; row < 4; ++row) columns[4 * column + row] = matrix[column][row];
  }
  return columns;
}

Camera fit_camera(const BoundingSphere& sphere, float aspect, float fov_degrees) {
  require_aspect("fit_camera", aspect);
  validate_lens(fov_degrees);
  const double radius = sphere.radius > 0 ? sphere.radius : 1.0;
  // A sphere at distance d fits between two planes through the eye at angle a to the view axis
  // when d * sin(a) >= radius. The horizontal half angle follows from the vertical one and the aspect.
  const double half_vertical = glm::radians(double{fov_degrees}) / 2;
  const double half_horizontal = std::atan(std::tan(half_vertical) * aspect);
  const double distance = 1.1 * radius / std::sin(std::min(half_vertical, half_horizontal));
  if (!std::isfinite(static_cast<float>(distance + 1.05 * radius))) {
    throw InvalidArgument("fit_camera: a sphere of radius " + format_number(sphere.radius) + " is too large to frame");
  }

  Camera camera;
  camera.target = glm::vec3(sphere.center.x, sphere.center.y, sphere.center.z);
  camera.eye = camera.target + glm::vec3(glm::normalize(glm::dvec3(kFitDirection)) * distance);
  camera.up = {0, 1, 0};
  camera.fov_degrees = fov_degrees;
  camera.near_plane = static_cast<float>(std::max(distance - 1.05 * radius, 0.001 * distance));
  camera.far_plane = static_cast<float>(distance + 1.05 * radius);
  // Catches the cases float cannot represent, such as a small sphere far from the origin that
  // leaves eye == target.
  validate_camera(camera);
  return camera;
}

void validate_lens(float fov_degrees, std::optional<float> near_plane, std::optional<float> far_plane) {
  require_finite("fov_degrees", fov_degrees);
  if (near_plane) require_finite("near_plane", *near_plane);
  if (far_plane) require_finite("far_plane", *far_plane);
  if (!(fov_degrees > 0 && fov_degrees < 180)) {
    throw InvalidArgument("camera: fov_degrees must be in (0, 180), got " + format_number(fov_degrees));
  }
  if (near_plane && !(*near_plane > 0)) {
    throw InvalidArgument("camera: near_plane must be greater than 0, got " + format_number(*near_plane));
  }
  if (near_plane && far_plane && !(*far_plane > *near_plane)) {
    throw InvalidArgument("camera: far_plane must be greater than near_plane (" + format_number(*near_plane) +
                          "), got " + format_number(*far_plane));
  }
}

void validate_camera(const Camera& camera) {
  require_finite_vec3("eye", camera.eye);
  require_finite_vec3("target", camera.target);
  require_finite_vec3("up", camera.up);
  validate_lens(camera.fov_degrees, camera.near_plane, camera.far_plane);
  if (camera.eye == camera.target) {
    throw InvalidArgument("camera: eye and target are the same point " + format_vec3(camera.eye));
  }
  // In double: products of large floats would overflow.
  const glm::dvec3 forward = glm::dvec3(camera.target) - glm::dvec3(camera.eye);
  const glm::dvec3 up(camera.up);
  if (glm::length(glm::cross(forward, up)) <= 1e-6 * glm::length(forward) * glm::length(up)) {
    throw InvalidArgument("camera: up " + format_vec3(camera.up) + " is zero or parallel to the view direction " +
                          format_vec3(glm::vec3(forward)));
  }
}

glm::vec3 parse_vec3(const std::string& text, const std::string& option_name) {
  const auto malformed = [&] {
    return InvalidArgument(option_name + ": expected three numbers X,Y,Z, got '" + text + "'");
  };
  glm::vec3 result;
  std::string_view rest = text;
  for (int axis = 0; axis < 3; ++axis) {
    const std::size_t comma = rest.find(',');
    if ((comma == std::string_view::npos) != (axis == 2)) throw malformed();
    const std::string_view part = trim(rest.substr(0, comma));
    const auto [end, error] = std::from_chars(part.data(), part.data() + part.size(), result[axis]);
    if (part.empty() || error != std::errc() || end != part.data() + part.size() || !std::isfinite(result[axis])) {
      throw malformed();
    }
    if (comma != std::string_view::npos) rest.remove_prefix(comma + 1);
  }
  return result;
}

}  // namespace clraster::io
