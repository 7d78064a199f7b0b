// Cameras: the OpenGL matrices against values worked out by hand, framing a bounding sphere,
// validation, and parsing of the command line's X,Y,Z vectors.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>
#include <string>

#include "clraster/clraster.hpp"
#include "io/camera.hpp"
#include "io/mesh.hpp"
#include "io/procedural.hpp"

namespace clraster::io {
namespace {

glm::vec3 apply(const glm::mat4& matrix, glm::vec3 point) { return glm::vec3(matrix * glm::vec4(point, 1)); }

TEST(ViewMatrix, LooksDownMinusZFromTheEye) {
  Camera camera;
  camera.eye = {3, 0, 0};
  camera.target = {0, 0, 0};
  camera.up = {0, 1, 0};
  const glm::mat4 view = view_matrix(camera);
  // Looking along -x with y up, the right-hand side is -z.
  EXPECT_EQ(apply(view, {0, 0, 0}), glm::vec3(0, 0, -3));
  EXPECT_EQ(apply(view, {0, 0, -1}), glm::vec3(1, 0, -3));
  EXPECT_EQ(apply(view, {0, 2, 0}), glm::vec3(0, 2, -3));
  EXPECT_EQ(apply(view, {3, 0, 0}), glm::vec3(0, 0, 0));
  // Rows (0,0,-1), (0,1,0), (1,0,0), translation (0,0,-3), column by column.
  const Mat4 expected = {0, 0, 1, 0, 0, 1, 0, 0, -1, 0, 0, 0, 0, 0, -3, 1};
  EXPECT_EQ(to_mat4(view), expected);
}

TEST(ProjectionMatrix, MatchesGluPerspective) {
  Camera camera;
  camera.fov_degrees = 90;
  camera.near_plane = 1;
  camera.far_plane = 3;
  const glm::mat4 projection = projection_matrix(camera, 2);
  // f = cot(45 deg) = 1: f / aspect, f, (far + near) / (near - far), -1, 2 far near / (near - far).
  const Mat4 expected = {0.5f, 0, 0, 0, 0, 1, 0, 0, 0, 0, -2, -1, 0, 0, -3, 0};
  const Mat4 actual = to_mat4(projection);
  for (int i = 0; i < 16; ++i) EXPECT_NEAR(actual[i], expected[i], 1e-6f) << "element " << i;
  // The near plane maps to z = -w, the far plane to z = w.
  const glm::vec4 near_point = projection * glm::vec4(0, 0, -1, 1);
  const glm::vec4 far_point = projection * glm::vec4(0, 0, -3, 1);
  EXPECT_FLOAT_EQ(near_point.z / near_point.w, -1);
  EXPECT_FLOAT_EQ(far_point.z / far_point.w, 1);
  EXPECT_THROW(projection_matrix(camera, 0), InvalidArgument);
  EXPECT_THROW(projection_matrix(camera, NAN), InvalidArgument);
}

// Whether the eye-space point projects strictly inside the clip volume.
bool inside_clip_volume(const glm::mat4& view_projection, glm::vec3 point, float* largest_ndc = nullptr) {
  const glm::vec4 clip = view_projection * glm::vec4(point, 1);
  const float largest = std::max(std::abs(clip.x), std::abs(clip.y)) / clip.w;
  if (largest_ndc != nullptr) *largest_ndc = std::max(*largest_ndc, largest);
  return clip.w > 0 && largest < 1 && std::abs(clip.z) < clip.w;
}

TEST(FitCamera, KeepsTheWholeSphereInViewAndFillsIt) {
  const Mesh box = make_box({-1, -2, -0.5f}, {1, 2, 3});
  const BoundingSphere sphere = bounding_sphere(box);
  for (float aspect : {0.4f, 1.0f, 16.0f / 9, 3.0f}) {
    for (float fov : {20.0f, 45.0f, 90.0f, 150.0f}) {
      SCOPED_TRACE("aspect " + std::to_string(aspect) + ", fov " + std::to_string(fov));
      const Camera camera = fit_camera(sphere, aspect, fov);
      EXPECT_NO_THROW(validate_camera(camera));
      const glm::mat4 view_projection = projection_matrix(camera, aspect) * view_matrix(camera);
      for (std::uint32_t v = 0; v < box.vertex_count(); ++v) {
        const glm::vec3 p(box.positions[3 * v], box.positions[3 * v + 1], box.positions[3 * v + 2]);
        EXPECT_TRUE(inside_clip_volume(view_projection, p)) << "corner " << v;
      }
      // Points all over the sphere: inside, and the outermost where the margin puts them.
      const glm::vec3 center(sphere.center.x, sphere.center.y, sphere.center.z);
      float largest_ndc = 0;
      for (int i = 0; i < 2000; ++i) {
        // A Fibonacci lattice: evenly spread directions.
        const double y = 1 - (i + 0.5) / 1000.0;
        const double angle = i * 2.399963229728653;
        const double r = std::sqrt(1 - y * y);
        const glm::vec3 direction(r * std::cos(angle), y, r * std::sin(angle));
        EXPECT_TRUE(inside_clip_volume(view_projection, center + sphere.radius * direction, &largest_ndc)) << i;
      }
      // The tighter half angle a frames the sphere grown by 10%: its edge is seen at
      // asin(sin(a) / 1.1) from the axis.
      const double half_vertical = glm::radians(double{fov}) / 2;
      const double a = std::min(half_vertical, std::atan(std::tan(half_vertical) * aspect));
      EXPECT_NEAR(largest_ndc, std::tan(std::asin(std::sin(a) / 1.1)) / std::tan(a), 0.01);
    }
  }
}

TEST(FitCamera, DirectionPlanesAndUp) {
  const BoundingSphere sphere{{1, 2, 3}, 2};
  const Camera camera = fit_camera(sphere, 1.5f);
  EXPECT_EQ(camera.target, glm::vec3(1, 2, 3));
  EXPECT_EQ(camera.up, glm::vec3(0, 1, 0));
  EXPECT_EQ(camera.fov_degrees, 45);
  EXPECT_LT(glm::distance(glm::normalize(camera.eye - camera.target), glm::normalize(glm::vec3(0.5f, 0.4f, 1))), 1e-6f);
  const float distance = glm::distance(camera.eye, camera.target);
  EXPECT_NEAR(camera.near_plane, distance - 2 * 1.05f, 1e-4f);
  EXPECT_NEAR(camera.far_plane, distance + 2 * 1.05f, 1e-4f);
}

TEST(FitCamera, DegenerateSpheres) {
  // From 1.1 radii over the sine of the half field of view (the vertical one at aspect 1), near and
  // far 1.05 radii before and behind the centre.
  const double inverse_sine = 1 / std::sin(22.5 * std::numbers::pi / 180);
  // A single point: framed as a unit sphere around it.
  const Camera point = fit_camera({{5, -1, 2}, 0}, 1);
  EXPECT_NO_THROW(validate_camera(point));
  EXPECT_EQ(point.target, glm::vec3(5, -1, 2));
  EXPECT_NEAR(glm::distance(point.eye, point.target), 1.1 * inverse_sine, 1e-5);
  EXPECT_NEAR(point.near_plane, 1.1 * inverse_sine - 1.05, 1e-5);
  EXPECT_NEAR(point.far_plane, 1.1 * inverse_sine + 1.05, 1e-5);
  // Tiny: framed as it is, however small.
  const Camera tiny = fit_camera({{0, 0, 0}, 1e-3f}, 1);
  EXPECT_NO_THROW(validate_camera(tiny));
  EXPECT_NEAR(glm::distance(tiny.eye, tiny.target), 1.1e-3 * inverse_sine, 1e-8);
  EXPECT_NEAR(tiny.near_plane, 1.1e-3 * inverse_sine - 1.05e-3, 1e-8);
  EXPECT_THROW(fit_camera({{0, 0, 0}, 3e38f}, 1), InvalidArgument);
  EXPECT_THROW(fit_camera({{0, 0, 0}, 1}, 0), InvalidArgument);
  EXPECT_THROW(fit_camera({{0, 0, 0}, 1}, 1, 180), InvalidArgument);
}

// The message validate_camera throws for `camera`.
std::string validation_error(const Camera& camera) {
  try {
    validate_camera(camera);
  } catch (const InvalidArgument& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.find('\n'), std::string::npos);
    return message;
  }
  ADD_FAILURE() << "no error";
  return {};
}

TEST(ValidateCamera, NamesTheBadValue) {
  EXPECT_NO_THROW(validate_camera(Camera{}));
  const auto with = [](auto change) {
    Camera camera;
    change(camera);
    return validation_error(camera);
  };
  EXPECT_EQ(with([](Camera& c) { c.fov_degrees = 0; }), "camera: fov_degrees must be in (0, 180), got 0");
  EXPECT_EQ(with([](Camera& c) { c.fov_degrees = 180; }), "camera: fov_degrees must be in (0, 180), got 180");
  EXPECT_EQ(with([](Camera& c) { c.fov_degrees = -30; }), "camera: fov_degrees must be in (0, 180), got -30");
  EXPECT_EQ(with([](Camera& c) { c.fov_degrees = NAN; }), "camera: fov_degrees must be finite, got nan");
  EXPECT_EQ(with([](Camera& c) { c.near_plane = 0; }), "camera: near_plane must be greater than 0, got 0");
  EXPECT_EQ(with([](Camera& c) { c.near_plane = -1; }), "camera: near_plane must be greater than 0, got -1");
  EXPECT_EQ(with([](Camera& c) { c.far_plane = 0.1f; }),
            "camera: far_plane must be greater than near_plane (0.1), got 0.1");
  EXPECT_EQ(with([](Camera& c) { c.far_plane = INFINITY; }), "camera: far_plane must be finite, got inf");
  EXPECT_EQ(with([](Camera& c) { c.eye = c.target = {1, 2, 3}; }),
            "camera: eye and target are the same point (1, 2, 3)");
  EXPECT_EQ(with([](Camera& c) { c.eye = {0, 5, 0}; }),
            "camera: up (0, 1, 0) is zero or parallel to the view direction (0, -5, 0)");
  EXPECT_EQ(with([](Camera& c) { c.up = {0, 0, 0}; }),
            "camera: up (0, 0, 0) is zero or parallel to the view direction (0, 0, -3)");
  EXPECT_EQ(with([](Camera& c) { c.eye.x = NAN; }), "camera: eye must be finite, got (nan, 0, 3)");
  EXPECT_EQ(with([](Camera& c) { c.target.y = -INFINITY; }), "camera: target must be finite, got (0, -inf, 0)");
}

TEST(ParseVec3, AcceptsThreeNumbers) {
  EXPECT_EQ(parse_vec3("-3,1,2", "--eye"), glm::vec3(-3, 1, 2));
  EXPECT_EQ(parse_vec3("1e-3,0,2.5", "--eye"), glm::vec3(1e-3f, 0, 2.5f));
  EXPECT_EQ(parse_vec3(" -0.5 , 4 ,-1e2 ", "--eye"), glm::vec3(-0.5f, 4, -100));
  EXPECT_EQ(parse_vec3(".5,-.25,7.", "--eye"), glm::vec3(0.5f, -0.25f, 7));
}

TEST(ParseVec3, RejectsAnythingElse) {
  try {
    parse_vec3("abc", "--eye");
    ADD_FAILURE() << "no error";
  } catch (const InvalidArgument& error) {
    EXPECT_STREQ(error.what(), "--eye: expected three numbers X,Y,Z, got 'abc'");
  }
  for (const char* text : {"", "1,2", "1,2,3,4", "1,,3", ",1,2", "1,2,", "1,2,3x", "1 2 3", "1;2;3", "nan,0,0",
                           "0,inf,0", "1e99,0,0", "+1,2,3", "0x1,2,3", "1,2,--3"}) {
    EXPECT_THROW(parse_vec3(text, "--target"), InvalidArgument) << "'" << text << "'";
  }
}

}  // namespace
}  // namespace clraster::io
