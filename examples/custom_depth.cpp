// A programmable depth test: two-layer transparency by depth peeling.
//
//   custom_depth [OUT.png]
//
// A tilted torus and a sphere that cuts through it, both drawn as translucent surfaces: at each
// pixel the nearest surface (the first layer) is blended over the one right behind it (the second
// layer), in three passes:
//   1. the scene into a depth texture: the first layer's depth;
//   2. the scene again, with a depth test of the program's own (programs/second_layer.cl) that
//      keeps the nearest fragment behind the first layer: the second layer, opaque, over the
//      background;
//   3. the scene a third time over that, translucent, with the depth test EQUAL against the first
//      layer's depth texture, so that only the first layer's fragments blend.
// Unlike sorting objects back to front, this gets intersecting and self-overlapping surfaces right.
#include <clraster/clraster.hpp>

#include <array>
#include <exception>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <glm/ext/matrix_transform.hpp>

#include "io/camera.hpp"
#include "io/image_io.hpp"
#include "io/procedural.hpp"

namespace {

constexpr int kWidth = 384;
constexpr int kHeight = 320;

struct Object {
  clraster::VertexBuffer vertices;  // "position" and "normal"
  clraster::IndexBuffer indices;
  std::array<float, 3> albedo;
};

Object upload(clraster::Context& context, const clraster::io::Mesh& mesh, std::array<float, 3> albedo) {
  return {clraster::VertexBuffer(context, mesh.positions, mesh.normals), clraster::IndexBuffer(context, mesh.indices),
          albedo};
}

std::vector<Object> make_scene(clraster::Context& context) {
  namespace io = clraster::io;
  io::Mesh torus = io::make_torus(64, 32, 0.8f, 0.3f);
  io::transform(torus, glm::rotate(glm::mat4(1), glm::radians(15.0f), glm::vec3(1, 0, 0)));
  std::vector<Object> scene;
  scene.push_back(upload(context, torus, {0.95f, 0.7f, 0.2f}));
  scene.push_back(upload(context, io::make_sphere(48, 24, 0.5f, {0.7f, 0.05f, 0.3f}), {0.25f, 0.45f, 0.95f}));
  return scene;
}

std::string read_text(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw clraster::Error("cannot open " + path);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

// Draws every object of the scene with `program`, `bindings` (whose "albedo" it sets per object)
// and `state`.
void draw_scene(clraster::Framebuffer& framebuffer, const std::vector<Object>& scene, const clraster::Program& program,
                clraster::Bindings& bindings, const clraster::DrawState& state) {
  for (const Object& object : scene) {
    bindings.set("albedo", object.albedo);
    clraster::DrawCall call;
    call.program = &program;
    call.bindings = &bindings;
    call.vertices = &object.vertices;
    call.indices = &object.indices;
    call.state = state;
    call.state.cull = clraster::CullMode::Back;  // layers of outside surfaces only
    framebuffer.draw(call);
  }
}

void render(const std::string& output) {
  clraster::Context context;
  const std::vector<Object> scene = make_scene(context);

  // A program is one OpenCL C text: the second layer's program is lit.cl with the depth test added.
  const std::string lit_source = read_text(CLRASTER_EXAMPLE_PROGRAMS "/lit.cl");
  const clraster::Program lit(context, lit_source, "lit.cl");
  const clraster::Program second_layer(
      context, lit_source + read_text(CLRASTER_EXAMPLE_PROGRAMS "/second_layer.cl"), "lit.cl+second_layer.cl");

  clraster::io::Camera camera;
  camera.eye = {0.0f, 1.2f, 3.2f};
  camera.near_plane = 1.0f;
  camera.far_plane = 10.0f;
  const clraster::Mat4 mvp = clraster::io::to_mat4(clraster::io::projection_matrix(camera, float(kWidth) / kHeight) *
                                                   clraster::io::view_matrix(camera));
  const std::array<float, 3> light_direction{0.48f, 0.64f, 0.6f};  // unit length
  clraster::Bindings bindings(lit);
  bindings.set("mvp", mvp).set("light_direction", light_direction).set("alpha", 1.0f);

  clraster::Texture first_depth(context, kWidth, kHeight, clraster::Format::Depth32F);
  clraster::Texture second_depth(context, kWidth, kHeight, clraster::Format::Depth32F);
  clraster::Texture color(context, kWidth, kHeight, clraster::Format::RGBA8);

  // ---- 1. The first layer's depth: the usual LESS test, into a depth-only framebuffer (lit.cl's
  // colour output has no attachment to go to, and is dropped).
  clraster::Framebuffer first_pass(context, {}, &first_depth);
  first_pass.clear_depth(1.0f);
  draw_scene(first_pass, scene, lit, bindings, clraster::DrawState{});

  // ---- 2. The second layer, with the program's depth test (CompareFunc::Program): see
  // second_layer.cl. Its bindings are lit.cl's plus the first layer's depth texture.
  clraster::Framebuffer second_pass(context, {&color}, &second_depth);
  second_pass.clear({0.3f, 0.32f, 0.4f, 1.0f}, 1.0f);
  clraster::Bindings peel_bindings(second_layer);
  peel_bindings.set("mvp", mvp).set("light_direction", light_direction).set("alpha", 1.0f);
  peel_bindings.set_texture("first_layer", first_depth).set("separation", 1e-4f);
  clraster::DrawState peel;
  peel.depth_func = clraster::CompareFunc::Program;
  draw_scene(second_pass, scene, second_layer, peel_bindings, peel);

  // ---- 3. The first layer over it, 60% opaque: the same colour texture, now with the first
  // layer's depth as the depth attachment. Drawn as in pass 1, the first layer's fragments have
  // exactly the depths stored there, and EQUAL passes them alone; nothing is written to depth.
  clraster::Framebuffer composite(context, {&color}, &first_depth);
  bindings.set("alpha", 0.6f);
  clraster::DrawState over;
  over.depth_func = clraster::CompareFunc::Equal;
  over.depth_write = false;
  over.blend[0] = {true,
                   clraster::BlendEquation::Add,
                   clraster::BlendEquation::Add,
                   clraster::BlendFactor::SrcAlpha,
                   clraster::BlendFactor::OneMinusSrcAlpha,
                   clraster::BlendFactor::One,
                   clraster::BlendFactor::OneMinusSrcAlpha,
                   {true, true, true, true}};
  draw_scene(composite, scene, lit, bindings, over);

  clraster::io::save_png(output, composite.read_color());
}

}  // namespace

int main(int argc, char** argv) {
  const std::string output = argc > 1 ? argv[1] : "custom_depth.png";
  try {
    render(output);
  } catch (const std::exception& error) {
    std::cerr << "custom_depth: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
