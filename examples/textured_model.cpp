// A textured glTF model lit by a directional light.
//
//   textured_model [OUT.png] [MODEL]
//
// Loads MODEL (by default the Cesium milk truck from Debian's assimp-testmodels), uploads its
// positions, normals and texture coordinates as vertex buffers and each material's base colour
// image as a mipmapped texture, and draws the model part by part with programs/textured.cl: one
// draw per part, each with the bindings (texture and colour factor) of its material.
#include <clraster/clraster.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "io/camera.hpp"
#include "io/image_io.hpp"
#include "io/model_loader.hpp"

namespace {

constexpr int kWidth = 512;
constexpr int kHeight = 320;
const std::string kDefaultModel = "/usr/share/assimp/models/glTF/CesiumMilkTruck/CesiumMilkTruck.gltf";

// The base colour texture of a material. Colour images are sRGB-encoded, so they become SRGB8_A8
// textures, which programs sample as linear values. Texture coordinates count v from the bottom
// of the image (Mesh::texcoords), and image files store their top row first: flip_vertically.
// A material without a texture gets a 1x1 white one, so one program draws every part.
clraster::Texture base_color_texture(clraster::Context& context, const clraster::io::Material& material) {
  const bool srgb = true, flip_vertically = true;
  if (!material.base_color_texture) {
    const std::byte white[4] = {std::byte{255}, std::byte{255}, std::byte{255}, std::byte{255}};
    return clraster::Texture(context, 1, 1, clraster::Format::SRGB8_A8, white);
  }
  const clraster::io::MaterialTexture& image = *material.base_color_texture;
  if (image.embedded()) {  // e.g. inside a .glb file
    return clraster::Texture::decode(context, image.encoded, srgb, flip_vertically, image.reference);
  }
  return clraster::Texture::load(context, image.file, srgb, flip_vertically);
}

void render(const std::string& model_path, const std::string& output) {
  clraster::Context context;

  // ---- The model: one triangle list, cut into parts that each use one material.
  std::vector<std::string> warnings;
  clraster::io::Model model = clraster::io::load_model(model_path, warnings);
  for (const std::string& warning : warnings) std::cerr << "textured_model: " << model_path << ": " << warning << "\n";
  if (model.texcoords.empty()) model.texcoords.assign(2 * model.vertex_count(), 0.0f);

  // Vertex attributes are plain buffers; the draw says how to read them (VertexAttribute).
  const clraster::Buffer positions(context, model.positions);
  const clraster::Buffer normals(context, model.normals);
  const clraster::Buffer uvs(context, model.texcoords);
  const clraster::IndexBuffer indices(context, model.indices);

  // ---- The program and one set of bindings per material.
  const clraster::Program program = clraster::Program::load(context, CLRASTER_EXAMPLE_PROGRAMS "/textured.cl");

  // The camera frames the model's bounding sphere (glm matrices, as OpenGL's lookAt/perspective).
  const clraster::io::Camera camera =
      clraster::io::fit_camera(clraster::io::bounding_sphere(model), float(kWidth) / kHeight);
  const clraster::Mat4 mvp = clraster::io::to_mat4(clraster::io::projection_matrix(camera, float(kWidth) / kHeight) *
                                                   clraster::io::view_matrix(camera));
  // Light from above, in front and to the right; the model is drawn in its own space, so the light
  // direction is given in that space too.
  const float length = std::sqrt(0.3f * 0.3f + 1.0f * 1.0f + 0.6f * 0.6f);
  const std::array<float, 3> light_direction{0.3f / length, 1.0f / length, 0.6f / length};

  // Mipmapped, trilinear, repeating textures: the default Sampler, as glTF's default sampler.
  std::vector<clraster::Texture> textures;
  std::vector<clraster::Bindings> bindings;
  for (const clraster::io::Material& material : model.materials) {
    textures.push_back(base_color_texture(context, material));
    clraster::Bindings& b = bindings.emplace_back(program);
    b.set("mvp", mvp)
        .set("light_direction", light_direction)
        .set("light_color", std::array<float, 3>{0.85f, 0.85f, 0.8f})
        .set("ambient", std::array<float, 3>{0.25f, 0.25f, 0.3f})
        .set("base_color_factor", material.base_color_factor)
        .set_texture("base_color", textures.back(), clraster::Sampler{});
  }

  // ---- Render into textures: an sRGB colour attachment (the program writes linear colour, the
  // attachment stores it encoded, ready for a PNG) and a depth attachment.
  clraster::Texture color(context, kWidth, kHeight, clraster::Format::SRGB8_A8);
  clraster::Texture depth(context, kWidth, kHeight, clraster::Format::Depth32F);
  clraster::Framebuffer framebuffer(context, {&color}, &depth);
  framebuffer.clear({0.6f, 0.7f, 0.85f, 1.0f}, 1.0f);

  for (const clraster::io::ModelPart& part : model.parts) {
    clraster::DrawCall call;
    call.program = &program;
    call.bindings = &bindings[part.material];
    call.attributes = {{"position", &positions, clraster::AttributeType::Float3},
                       {"normal", &normals, clraster::AttributeType::Float3},
                       {"uv", &uvs, clraster::AttributeType::Float2}};
    call.indices = &indices;
    call.first = part.first_index;  // this part's range of the index buffer
    call.count = part.index_count;
    // The default state: depth test LESS with writes, no culling, no blending.
    framebuffer.draw(call);
  }

  // read_color gives RGBA8 rows from the top, as image files want them.
  clraster::io::save_png(output, framebuffer.read_color());
}

}  // namespace

int main(int argc, char** argv) {
  const std::string output = argc > 1 ? argv[1] : "textured_model.png";
  const std::string model = argc > 2 ? argv[2] : kDefaultModel;
  try {
    render(model, output);
  } catch (const std::exception& error) {  // clraster::Error and its kinds: one-line messages
    std::cerr << "textured_model: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
