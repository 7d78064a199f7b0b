// Shadow mapping in two passes.
//
//   shadow_map [OUT.png]
//
// Pass 1 renders the scene from the light into a depth texture (a framebuffer with a depth
// attachment only, drawn with programs/depth_only.cl). Pass 2 renders it from the camera with
// programs/shadowed.cl, which looks each fragment up in that texture: a fragment farther from the
// light than what the light saw at its place is in shadow.
#include <clraster/clraster.hpp>

#include <array>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>

#include "io/camera.hpp"
#include "io/image_io.hpp"
#include "io/procedural.hpp"

namespace {

constexpr int kWidth = 512;
constexpr int kHeight = 384;
constexpr int kShadowMapSize = 1024;

// One object of the scene, uploaded: a VertexBuffer holds positions and normals, the attributes
// "position" and "normal" that programs may declare (a program need not read both).
struct Object {
  clraster::VertexBuffer vertices;
  clraster::IndexBuffer indices;
  std::array<float, 3> albedo;
};

Object upload(clraster::Context& context, const clraster::io::Mesh& mesh, std::array<float, 3> albedo) {
  return {clraster::VertexBuffer(context, mesh.positions, mesh.normals), clraster::IndexBuffer(context, mesh.indices),
          albedo};
}

// A floor, two boxes and a sphere, in world space (y up).
std::vector<Object> make_scene(clraster::Context& context) {
  namespace io = clraster::io;
  io::Mesh floor = io::make_plane(1, 1, 8, 8);  // in the xy plane, facing +z: turned to face +y
  io::transform(floor, glm::rotate(glm::mat4(1), glm::radians(-90.0f), glm::vec3(1, 0, 0)));
  std::vector<Object> scene;
  scene.push_back(upload(context, floor, {0.8f, 0.8f, 0.75f}));
  scene.push_back(upload(context, io::make_box({-1.8f, 0, -0.6f}, {-0.6f, 1.2f, 0.6f}), {0.9f, 0.5f, 0.2f}));
  scene.push_back(upload(context, io::make_box({0.6f, 0, -1.6f}, {1.2f, 2.2f, -1.0f}), {0.9f, 0.5f, 0.2f}));
  scene.push_back(upload(context, io::make_sphere(48, 24, 0.7f, {0.4f, 0.7f, 1.0f}), {0.3f, 0.5f, 0.9f}));
  return scene;
}

// A draw of one object with `program` (either pass's: both read the VertexBuffer).
clraster::DrawCall object_draw(const Object& object, const clraster::Program& program,
                               const clraster::Bindings& bindings) {
  clraster::DrawCall call;
  call.program = &program;
  call.bindings = &bindings;
  call.vertices = &object.vertices;
  call.indices = &object.indices;
  return call;
}

void render(const std::string& output) {
  clraster::Context context;
  const std::vector<Object> scene = make_scene(context);

  // ---- The light: directional, so its view is an orthographic projection along its direction,
  // framing the floor (its diagonal is 11.3 units long).
  const glm::vec3 towards_light = glm::normalize(glm::vec3(0.5f, 1.0f, 0.3f));
  const glm::mat4 light_view = glm::lookAt(10.0f * towards_light, glm::vec3(0), glm::vec3(0, 1, 0));
  const glm::mat4 light_projection = glm::ortho(-6.0f, 6.0f, -6.0f, 6.0f, 1.0f, 20.0f);
  const clraster::Mat4 light_mvp = clraster::io::to_mat4(light_projection * light_view);

  // ---- Pass 1: depth from the light. A Framebuffer of no colour attachment and a Depth32F
  // texture; the program has no outputs, so the pass only tests and writes depth.
  clraster::Texture shadow_map(context, kShadowMapSize, kShadowMapSize, clraster::Format::Depth32F);
  {
    clraster::Framebuffer light_pass(context, {}, &shadow_map);
    light_pass.clear_depth(1.0f);
    const clraster::Program depth_only = clraster::Program::load(context, CLRASTER_EXAMPLE_PROGRAMS "/depth_only.cl");
    clraster::Bindings bindings(depth_only);
    bindings.set("light_mvp", light_mvp);
    for (const Object& object : scene) light_pass.draw(object_draw(object, depth_only, bindings));
  }

  // ---- Pass 2: the camera's view, sampling the shadow map.
  clraster::io::Camera camera;
  camera.eye = {5.0f, 4.5f, 7.0f};
  camera.target = {0.0f, 0.5f, 0.0f};
  camera.near_plane = 0.5f;
  camera.far_plane = 30.0f;
  const clraster::Mat4 mvp = clraster::io::to_mat4(clraster::io::projection_matrix(camera, float(kWidth) / kHeight) *
                                                   clraster::io::view_matrix(camera));

  const clraster::Program shadowed = clraster::Program::load(context, CLRASTER_EXAMPLE_PROGRAMS "/shadowed.cl");
  clraster::Bindings bindings(shadowed);
  bindings.set("mvp", mvp)
      .set("light_mvp", light_mvp)
      .set("light_direction", std::array<float, 3>{towards_light.x, towards_light.y, towards_light.z})
      // In depth units, which are 19 world units here (the light's near and far planes). A texel of
      // the shadow map is 12 / 1024 world units wide: the slope bias allows 2.5 texels' worth.
      .set("bias", 0.0005f)
      .set("slope_bias", 0.0015f)
      // Texel fetches read exact texels; the sampler matters only to sampling functions.
      .set_texture("shadow_map", shadow_map);

  clraster::Framebuffer framebuffer(context, kWidth, kHeight);  // RGBA8 colour and depth
  framebuffer.clear({0.55f, 0.65f, 0.8f, 1.0f}, 1.0f);
  for (const Object& object : scene) {
    // A draw reads the bindings' values when it is made: changing one between draws is fine.
    bindings.set("albedo", object.albedo);
    clraster::DrawCall call = object_draw(object, shadowed, bindings);
    call.state.cull = clraster::CullMode::Back;  // closed objects: their back faces are hidden anyway
    framebuffer.draw(call);
  }
  clraster::io::save_png(output, framebuffer.read_color());
}

}  // namespace

int main(int argc, char** argv) {
  const std::string output = argc > 1 ? argv[1] : "shadow_map.png";
  try {
    render(output);
  } catch (const std::exception& error) {
    std::cerr << "shadow_map: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
