#include "cli/demo_scene.hpp"

#include "io/procedural.hpp"

#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace clraster::cli {

io::Mesh make_demo_scene() {
  io::Mesh terrain = io::make_terrain(400, 400, 12.0f, 12.0f, 0.6f, 7);

  io::Mesh torus = io::make_torus(160, 64, 1.2f, 0.35f);
  io::transform(torus, glm::rotate(glm::translate(glm::mat4(1), {0.0f, 1.9f, 0.0f}), glm::radians(70.0f), {1, 0, 0}));

  std::vector<io::Mesh> parts = {terrain, torus};
  // A ring of spheres and boxes around the torus.
  for (int i = 0; i < 8; ++i) {
    const float angle = glm::radians(45.0f * static_cast<float>(i) + 22.5f);
    const io::Vec3f at{3.2f * std::cos(angle), 1.0f, 3.2f * std::sin(angle)};
    if (i % 2 == 0) {
      parts.push_back(io::make_sphere(96, 48, 0.55f, at));
    } else {
      io::Mesh box = io::make_box({-0.4f, -0.4f, -0.4f}, {0.4f, 0.4f, 0.4f});
      io::transform(box, glm::rotate(glm::translate(glm::mat4(1), {at.x, at.y, at.z}), angle, {0.3f, 1.0f, 0.2f}));
      parts.push_back(box);
    }
  }
  return io::merge(parts);
}

io::Camera demo_camera(float fov_degrees) {
  io::Camera camera;
  camera.eye = {4.2f, 4.0f, 7.0f};
  camera.target = {0.0f, 0.8f, 0.0f};
  camera.fov_degrees = fov_degrees;
  camera.near_plane = 1.0f;
  camera.far_plane = 25.0f;
  return camera;
}

}  // namespace clraster::cli
