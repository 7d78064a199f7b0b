#include "frontend/gl_model_draws.hpp"

#include "io/image_io.hpp"

#include <cstring>

namespace clraster::frontend {
namespace {

// The uniforms of the GLSL material program that stay the same for every part.
constexpr const char* kGlViewUniforms[] = {"mvp", "normal_matrix", "light_direction"};

// The model's positions, normals, texture coordinates (or zeros) and indices, uploaded once for the
// GLSL material program.
oracle::GlVertexInput gl_vertex_input(const oracle::GlProgram& program, const io::Model& model) {
  const std::vector<float> uvs = texcoords_or_zeros(model);
  const oracle::GlAttribute attributes[] = {
      {kPositionAttribute, std::as_bytes(std::span(model.positions)), AttributeType::Float3},
      {kNormalAttribute, std::as_bytes(std::span(model.normals)), AttributeType::Float3},
      {kUvAttribute, std::as_bytes(std::span(uvs)), AttributeType::Float2}};
  return oracle::GlVertexInput(program, attributes, std::span<const std::uint32_t>(model.indices));
}

// A picture's texels as a texture holds them: the bottom row (t = 0) first.
std::vector<std::byte> bottom_row_first(const Image& image) {
  const std::size_t row_bytes = std::size_t(image.width) * 4;
  std::vector<std::byte> texels(image.rgba.size());
  for (int row = 0; row < image.height; ++row) {
    std::memcpy(texels.data() + std::size_t(image.height - 1 - row) * row_bytes,
                image.rgba.data() + std::size_t(row) * row_bytes, row_bytes);
  }
  return texels;
}

}  // namespace

// Keep in step with programs/material.cl (tests/test_cli_programs.cpp compares what they draw).
const char* const kGlMaterialVertexShader = R"(#version 450 core
in vec3 position;
in vec3 normal;
in vec2 uv;
uniform mat4 mvp;
uniform mat4 normal_matrix;
out vec3 eye_normal;
out vec2 texcoord;

void main() {
  gl_Position = mvp * vec4(position, 1.0);
  eye_normal = mat3(normal_matrix) * normal;
  texcoord = uv;
}
)";

const char* const kGlMaterialFragmentShader = R"(#version 450 core
in vec3 eye_normal;
in vec2 texcoord;
uniform vec4 base_color;
uniform vec3 light_direction;
uniform sampler2D base_color_texture;
layout(location = 0) out vec4 color;

const float AMBIENT = 0.2;

void main() {
  vec4 base = texture(base_color_texture, texcoord) * base_color;
  float length_of_normal = length(eye_normal);
  float diffuse = length_of_normal > 0.0 ? abs(dot(eye_normal / length_of_normal, light_direction)) : 0.0;
  color = vec4(base.rgb * (AMBIENT + (1.0 - AMBIENT) * diffuse), 1.0);
}
)";

GlMaterialDraws::GlMaterialDraws(const io::Model& model, const ProgramInputs& view, std::vector<std::string>& warnings)
    : model_(model),
      program_(kGlMaterialVertexShader, kGlMaterialFragmentShader, "material program (GLSL)"),
      vertex_input_(gl_vertex_input(program_, model)),
      textures_(
          model, oracle::GlTexture(1, 1, Format::RGBA8, kWhiteTexel, false),
          [](const io::MaterialTexture& image) {
            const Image decoded =
                image.embedded() ? io::decode_image(image.encoded, image_name(image)) : io::load_png(image.file);
            return oracle::GlTexture(decoded.width, decoded.height, Format::RGBA8, bottom_row_first(decoded), true);
          },
          warnings) {
  for (const char* name : kGlViewUniforms) program_.set(name, view.uniform(name));
}

void GlMaterialDraws::draw(oracle::GlRenderer& target, const DrawState& state) {
  for (const io::ModelPart& part : model_.parts) {
    program_.set("base_color", std::span<const float>(model_.materials.at(part.material).base_color_factor));
    program_.set_texture(kBaseColorTexture, textures_[part.material], Sampler{});
    oracle::GlDrawCall call;
    call.program = &program_;
    call.vertex_input = &vertex_input_;
    call.first = part.first_index;
    call.count = part.index_count;
    call.state = state;
    target.draw(call);
  }
}

void draw_gl_frame(oracle::GlRenderer& target, const DrawState& state, const std::optional<oracle::GlMesh>& mesh,
                   std::optional<GlMaterialDraws>& material_draws) {
  target.clear({0, 0, 0, 1}, 1.0f);
  if (material_draws) {
    material_draws->draw(target, state);
  } else {
    target.draw(mesh.value(), 0, kAllElements, state);
  }
  target.finish();
}

}  // namespace clraster::frontend
