// The examples (examples/*.cpp) run as tests: each writes its picture, and the test checks that the
// picture is right, against the OpenGL oracle drawing the same scene with equivalent GLSL programs,
// or against the formulas the picture illustrates. The scenes' constants (sizes, cameras, lights,
// colours) repeat the examples': change one and the other must follow.
#include "io/camera.hpp"
#include "io/image_io.hpp"
#include "io/model_loader.hpp"
#include "io/procedural.hpp"
#include "oracle/gl_scene.hpp"
#include "support/cli_support.hpp"
#include "support/test_support.hpp"

#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <ostream>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace clraster::test {
namespace {

using oracle::GlAttribute;
using oracle::GlDrawCall;
using oracle::GlFramebuffer;
using oracle::GlProgram;
using oracle::GlTexture;

// ---- Running the examples and drawing with the oracle ---------------------------------------------

// Runs examples/<name> with the output path and then `args`, and reads the picture it wrote.
Image run_example(const std::string& name, const std::vector<std::string>& args = {}) {
  const std::string picture = (scratch_directory() / (name + ".png")).string();
  std::vector<std::string> arguments{picture};
  arguments.insert(arguments.end(), args.begin(), args.end());
  const CliResult result = run_executable(std::string(CLRASTER_EXAMPLES_DIR) + "/" + name, arguments);
  if (const ::testing::AssertionResult ran = succeeded(result); !ran) {
    throw std::runtime_error("examples/" + name + ": " + ran.message());
  }
  return io::load_png(picture);
}

// An RGBA8 or SRGB8_A8 texture's level 0 as a picture (rows from the top; the texture's from t = 0).
Image picture_of(const GlTexture& color) {
  const std::vector<std::byte> texels = color.read();
  Image image{color.width(), color.height(), std::vector<std::uint8_t>(texels.size())};
  const std::size_t row = 4 * std::size_t(image.width);
  for (int y = 0; y < image.height; ++y) {
    std::memcpy(&image.rgba[row * y], &texels[row * (image.height - 1 - y)], row);
  }
  return image;
}

// A picture's rows in texture order (from t = 0), as Texture::load(..., flip_vertically = true)
// uploads an image file.
std::vector<std::byte> texels_of(const Image& image) {
  std::vector<std::byte> texels(image.rgba.size());
  const std::size_t row = 4 * std::size_t(image.width);
  for (int y = 0; y < image.height; ++y) {
    std::memcpy(&texels[row * (image.height - 1 - y)], &image.rgba[row * y], row);
  }
  return texels;
}

GlAttribute attribute(const std::string& name, const std::vector<float>& values, AttributeType type) {
  return {name, std::as_bytes(std::span<const float>(values)), type};
}

// The position and normal attributes of a mesh, and its indices, as a draw of `program`.
GlDrawCall mesh_draw(const GlProgram& program, const io::Mesh& mesh) {
  GlDrawCall call{&program};
  call.attributes = {attribute("position", mesh.positions, AttributeType::Float3),
                     attribute("normal", mesh.normals, AttributeType::Float3)};
  call.indices = mesh.indices;
  return call;
}

Mat4 camera_mvp(const io::Camera& camera, int width, int height) {
  const float aspect = float(width) / float(height);
  return io::to_mat4(io::projection_matrix(camera, aspect) * io::view_matrix(camera));
}

// Pictures of the same scene by clraster and by the oracle: the same triangles, so the same
// pixels, but vertex transforms on different hardware round differently, so the odd pixel on a
// silhouette or a shadow's edge can go either way; and texture filtering may differ by 2/255.
constexpr Tolerance kSameScene{0, 0.005, 2, ~0ull, false};

// ---- textured_model.cpp ---------------------------------------------------------------------------

constexpr const char* kTexturedVertex = R"(#version 450 core
in vec3 position;
in vec3 normal;
in vec2 uv;
uniform mat4 mvp;
out vec3 v_normal;
out vec2 v_uv;
void main() {
  gl_Position = mvp * vec4(position, 1.0);
  v_normal = normal;
  v_uv = uv;
}
)";
constexpr const char* kTexturedFragment = R"(#version 450 core
in vec3 v_normal;
in vec2 v_uv;
uniform vec3 light_direction;
uniform vec3 light_color;
uniform vec3 ambient;
uniform vec4 base_color_factor;
uniform sampler2D base_color;
out vec4 color;
void main() {
  vec4 base = base_color_factor * texture(base_color, v_uv);
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;
  float diffuse = max(dot(n, light_direction), 0.0);
  color = vec4(base.rgb * (ambient + light_color * diffuse), base.a);
}
)";

// The base colour image of a material, as the example uploads it.
GlTexture base_color_texture(const io::Material& material) {
  if (!material.base_color_texture) {
    const std::byte white[4] = {std::byte{255}, std::byte{255}, std::byte{255}, std::byte{255}};
    return GlTexture(1, 1, Format::SRGB8_A8, white, false);
  }
  const io::MaterialTexture& source = *material.base_color_texture;
  std::string path = source.file;
  if (source.embedded()) {
    const auto* bytes = reinterpret_cast<const char*>(source.encoded.data());
    path = write_scratch_file("embedded-image", std::string_view(bytes, source.encoded.size())).string();
  }
  const Image image = io::load_png(path);
  return GlTexture(image.width, image.height, Format::SRGB8_A8, texels_of(image), true);
}

Image textured_model_gl(const std::string& model_path) {
  constexpr int kWidth = 512, kHeight = 320;
  std::vector<std::string> warnings;
  io::Model model = io::load_model(model_path, warnings);
  if (model.texcoords.empty()) model.texcoords.assign(2 * model.vertex_count(), 0.0f);
  const io::Camera camera = io::fit_camera(io::bounding_sphere(model), float(kWidth) / kHeight);
  const Mat4 mvp = camera_mvp(camera, kWidth, kHeight);
  const float length = std::sqrt(0.3f * 0.3f + 1.0f * 1.0f + 0.6f * 0.6f);
  const std::vector<float> light_direction{0.3f / length, 1.0f / length, 0.6f / length};

  GlTexture color(kWidth, kHeight, Format::SRGB8_A8), depth(kWidth, kHeight, Format::Depth32F);
  GlFramebuffer target({&color}, &depth);
  target.clear({0.6f, 0.7f, 0.85f, 1.0f}, 1.0f);
  GlProgram program(kTexturedVertex, kTexturedFragment, "textured");
  program.set("mvp", mvp)
      .set("light_direction", light_direction)
      .set("light_color", std::vector<float>{0.85f, 0.85f, 0.8f})
      .set("ambient", std::vector<float>{0.25f, 0.25f, 0.3f});
  std::vector<GlTexture> textures;
  for (const io::Material& material : model.materials) textures.push_back(base_color_texture(material));
  for (const io::ModelPart& part : model.parts) {
    program.set("base_color_factor", model.materials[part.material].base_color_factor)
        .set_texture("base_color", textures[part.material], Sampler{});
    GlDrawCall call{&program};
    call.attributes = {attribute("position", model.positions, AttributeType::Float3),
                       attribute("normal", model.normals, AttributeType::Float3),
                       attribute("uv", model.texcoords, AttributeType::Float2)};
    call.indices = model.indices;
    call.first = part.first_index;
    call.count = part.index_count;
    target.draw(call);
  }
  return picture_of(color);
}

struct TexturedModelCase {
  const char* name;
  const char* path;  // under /usr/share/assimp/models
};

void PrintTo(const TexturedModelCase& model, std::ostream* out) { *out << model.path; }

class TexturedModelExample : public ::testing::TestWithParam<TexturedModelCase> {};

// The default model has its textures in a file of their own; the boxes' is embedded in the .glb.
TEST_P(TexturedModelExample, MatchesOpenGL) {
  const std::string path = std::string("/usr/share/assimp/models/") + GetParam().path;
  const Image picture = GetParam().name == std::string("CesiumMilkTruck") ? run_example("textured_model")
                                                                           : run_example("textured_model", {path});
  EXPECT_TRUE(images_match(picture, textured_model_gl(path), kSameScene));
}

INSTANTIATE_TEST_SUITE_P(Examples, TexturedModelExample,
                         ::testing::Values(TexturedModelCase{"CesiumMilkTruck",
                                                             "glTF/CesiumMilkTruck/CesiumMilkTruck.gltf"},
                                           TexturedModelCase{"EmbeddedTexture",
                                                             "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb"}),
                         [](const auto& info) { return std::string(info.param.name); });

// ---- shadow_map.cpp -------------------------------------------------------------------------------

// The scene of shadow_map.cpp: meshes and their colours.
struct ShadowScene {
  std::vector<io::Mesh> meshes;
  std::vector<std::vector<float>> albedos;
};

ShadowScene shadow_scene() {
  io::Mesh floor = io::make_plane(1, 1, 8, 8);
  io::transform(floor, glm::rotate(glm::mat4(1), glm::radians(-90.0f), glm::vec3(1, 0, 0)));
  const std::vector<float> grey{0.8f, 0.8f, 0.75f}, orange{0.9f, 0.5f, 0.2f}, blue{0.3f, 0.5f, 0.9f};
  return {{floor, io::make_box({-1.8f, 0, -0.6f}, {-0.6f, 1.2f, 0.6f}), io::make_box({0.6f, 0, -1.6f}, {1.2f, 2.2f, -1.0f}),
           io::make_sphere(48, 24, 0.7f, {0.4f, 0.7f, 1.0f})},
          {grey, orange, orange, blue}};
}

const glm::vec3 kTowardsLight = glm::normalize(glm::vec3(0.5f, 1.0f, 0.3f));

io::Camera shadow_camera() {
  io::Camera camera;
  camera.eye = {5.0f, 4.5f, 7.0f};
  camera.target = {0.0f, 0.5f, 0.0f};
  camera.near_plane = 0.5f;
  camera.far_plane = 30.0f;
  return camera;
}

constexpr const char* kLightVertex = R"(#version 450 core
in vec3 position;
uniform mat4 light_mvp;
void main() { gl_Position = light_mvp * vec4(position, 1.0); }
)";
constexpr const char* kDepthOnlyFragment = R"(#version 450 core
void main() {}
)";
constexpr const char* kShadowedVertex = R"(#version 450 core
in vec3 position;
in vec3 normal;
uniform mat4 mvp;
uniform mat4 light_mvp;
out vec3 v_normal;
out vec3 v_light_window;
void main() {
  vec4 world = vec4(position, 1.0);
  gl_Position = mvp * world;
  v_light_window = (light_mvp * world).xyz * 0.5 + 0.5;
  v_normal = normal;
}
)";
// clr_texel_fetch reads zero outside the texture; GL's texelFetch is undefined there.
constexpr const char* kShadowedFragment = R"(#version 450 core
in vec3 v_normal;
in vec3 v_light_window;
uniform vec3 light_direction;
uniform vec3 albedo;
uniform float bias;
uniform float slope_bias;
uniform sampler2D shadow_map;
out vec4 color;
float lit_fraction(float tan_angle) {
  float tolerance = bias + slope_bias * tan_angle;
  ivec2 size = textureSize(shadow_map, 0);
  ivec2 texel = ivec2(floor(v_light_window.xy * vec2(size)));
  int lit = 0;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      ivec2 t = texel + ivec2(dx, dy);
      bool inside = all(greaterThanEqual(t, ivec2(0))) && all(lessThan(t, size));
      float occluder = inside ? texelFetch(shadow_map, t, 0).r : 0.0;
      lit += v_light_window.z - tolerance <= occluder ? 1 : 0;
    }
  }
  return float(lit) / 9.0;
}
void main() {
  vec3 n = normalize(v_normal);
  float cosine = dot(n, light_direction);
  float light = 0.2;
  if (cosine > 0.0) {
    float tan_angle = min(sqrt(1.0 - cosine * cosine) / cosine, 10.0);
    light += 0.8 * cosine * lit_fraction(tan_angle);
  }
  color = vec4(albedo * light, 1.0);
}
)";

Image shadow_map_gl() {
  constexpr int kWidth = 512, kHeight = 384, kShadowMapSize = 1024;
  const ShadowScene scene = shadow_scene();
  const Mat4 light_mvp = io::to_mat4(glm::ortho(-6.0f, 6.0f, -6.0f, 6.0f, 1.0f, 20.0f) *
                                     glm::lookAt(10.0f * kTowardsLight, glm::vec3(0), glm::vec3(0, 1, 0)));

  GlTexture shadow_map(kShadowMapSize, kShadowMapSize, Format::Depth32F);
  GlFramebuffer light_pass({}, &shadow_map);
  light_pass.clear_depth(1.0f);
  GlProgram depth_only(kLightVertex, kDepthOnlyFragment, "depth_only");
  depth_only.set("light_mvp", light_mvp);
  for (const io::Mesh& mesh : scene.meshes) {
    GlDrawCall call{&depth_only};
    call.attributes = {attribute("position", mesh.positions, AttributeType::Float3)};
    call.indices = mesh.indices;
    light_pass.draw(call);
  }

  GlTexture color(kWidth, kHeight, Format::RGBA8), depth(kWidth, kHeight, Format::Depth32F);
  GlFramebuffer camera_pass({&color}, &depth);
  camera_pass.clear({0.55f, 0.65f, 0.8f, 1.0f}, 1.0f);
  GlProgram shadowed(kShadowedVertex, kShadowedFragment, "shadowed");
  shadowed.set("mvp", camera_mvp(shadow_camera(), kWidth, kHeight))
      .set("light_mvp", light_mvp)
      .set("light_direction", std::vector<float>{kTowardsLight.x, kTowardsLight.y, kTowardsLight.z})
      .set("bias", 0.0005f)
      .set("slope_bias", 0.0015f)
      .set_texture("shadow_map", shadow_map, Sampler{});
  for (std::size_t i = 0; i < scene.meshes.size(); ++i) {
    shadowed.set("albedo", scene.albedos[i]);
    GlDrawCall call = mesh_draw(shadowed, scene.meshes[i]);
    call.state.cull = CullMode::Back;
    camera_pass.draw(call);
  }
  return picture_of(color);
}

// The pixel (column, row from the top) where the shadow camera sees a world point.
std::array<int, 2> shadow_camera_pixel(glm::vec3 world, int width, int height) {
  const io::Camera camera = shadow_camera();
  const glm::vec4 clip = io::projection_matrix(camera, float(width) / height) * io::view_matrix(camera) * glm::vec4(world, 1);
  const float x = (clip.x / clip.w + 1) / 2 * width, y = (clip.y / clip.w + 1) / 2 * height;
  return {static_cast<int>(x), height - 1 - static_cast<int>(y)};
}

int brightness(const Image& image, std::array<int, 2> pixel) {
  const std::size_t i = 4 * (std::size_t(pixel[1]) * image.width + pixel[0]);
  return image.rgba[i] + image.rgba[i + 1] + image.rgba[i + 2];
}

TEST(Examples, ShadowMapMatchesOpenGL) {
  const Image picture = run_example("shadow_map");
  EXPECT_TRUE(images_match(picture, shadow_map_gl(), kSameScene));

  // The floor where the tall box's axis casts its shadow from half the box's height is lit by the
  // ambient term alone (0.2), the open floor also by the light (0.2 + 0.8 * 0.86): far brighter.
  const glm::vec3 shadowed = glm::vec3(0.9f, 1.1f, -1.3f) - kTowardsLight * (1.1f / kTowardsLight.y);
  const glm::vec3 lit(2.5f, 0, 2.5f);
  const int dark = brightness(picture, shadow_camera_pixel(shadowed, picture.width, picture.height));
  const int bright = brightness(picture, shadow_camera_pixel(lit, picture.width, picture.height));
  EXPECT_LT(dark * 3, bright) << "shadowed floor " << dark << ", lit floor " << bright;
}

// ---- pdf_blend.cpp --------------------------------------------------------------------------------

// f(Cs, Cd) of the separable modes of KHR_blend_equation_advanced (table X.1), in pdf_blend.cl's
// order, on non-premultiplied channels.
double blend_function(int mode, double s, double d) {
  switch (mode) {
    case 0: return s * d;                                                      // multiply
    case 1: return s + d - s * d;                                              // screen
    case 2: return d <= 0.5 ? 2 * s * d : 1 - 2 * (1 - s) * (1 - d);           // overlay
    case 3: return std::min(s, d);                                             // darken
    case 4: return d <= 0 ? 0 : s >= 1 ? 1 : std::min(1.0, d / (1 - s));       // colour dodge
    default: return std::abs(d - s);                                           // difference
  }
}

// Over an opaque destination (Ad = 1) the extension's result is f(Cs, Cd) * As + Cd * (1 - As),
// with alpha 1.
std::array<int, 4> blended(int mode, const std::array<int, 3>& source, double source_alpha,
                           const std::array<int, 3>& destination) {
  std::array<int, 4> result{0, 0, 0, 255};
  for (int c = 0; c < 3; ++c) {
    const double s = source[c] / 255.0, d = destination[c] / 255.0;
    const double value = blend_function(mode, s, d) * source_alpha + d * (1 - source_alpha);
    result[c] = static_cast<int>(std::lround(value * 255));
  }
  return result;
}

std::array<int, 4> pixel_at(const Image& image, int x, int y_from_bottom) {
  const std::size_t i = 4 * (std::size_t(image.height - 1 - y_from_bottom) * image.width + x);
  return {image.rgba[i], image.rgba[i + 1], image.rgba[i + 2], image.rgba[i + 3]};
}

::testing::AssertionResult within_one(const std::array<int, 4>& actual, const std::array<int, 4>& expected) {
  for (int c = 0; c < 4; ++c) {
    if (std::abs(actual[c] - expected[c]) > 1) {
      return ::testing::AssertionFailure() << "got (" << actual[0] << ", " << actual[1] << ", " << actual[2] << ", "
                                           << actual[3] << "), expected (" << expected[0] << ", " << expected[1]
                                           << ", " << expected[2] << ", " << expected[3] << ") within 1";
    }
  }
  return ::testing::AssertionSuccess();
}

// Each panel shows its mode's formula in the blue disc's two regions (over the grey background and
// over the orange disc), and the destination unchanged outside it, to within 1/255.
TEST(Examples, PdfBlendPanelsFollowTheBlendModesFormulas) {
  const Image picture = run_example("pdf_blend");
  constexpr int kPanel = 128;
  ASSERT_EQ(picture.width, 3 * kPanel);
  ASSERT_EQ(picture.height, 2 * kPanel);
  const std::array<int, 3> grey{191, 191, 191}, orange{230, 120, 40}, blue{40, 150, 200};
  const double blue_alpha = 0.8;
  // Points in a panel's normalized device coordinates: discs of radius 0.55 at (-0.25, 0.15)
  // (orange) and (0.25, -0.15) (blue).
  struct Region {
    const char* name;
    double x, y;
  };
  const Region background{"background", 0.9, 0.9}, orange_only{"orange disc", -0.6, 0.4},
      blue_over_grey{"blue disc over the background", 0.6, -0.4}, blue_over_orange{"blue disc over the orange", 0, 0};
  for (int mode = 0; mode < 6; ++mode) {
    const int left = (mode % 3) * kPanel, bottom = (1 - mode / 3) * kPanel;
    const auto at = [&](const Region& r) {
      return pixel_at(picture, left + static_cast<int>((r.x + 1) / 2 * kPanel),
                      bottom + static_cast<int>((r.y + 1) / 2 * kPanel));
    };
    SCOPED_TRACE("mode " + std::to_string(mode));
    EXPECT_TRUE(within_one(at(background), {191, 191, 191, 255})) << background.name;
    EXPECT_TRUE(within_one(at(orange_only), {230, 120, 40, 255})) << orange_only.name;
    EXPECT_TRUE(within_one(at(blue_over_grey), blended(mode, blue, blue_alpha, grey))) << blue_over_grey.name;
    EXPECT_TRUE(within_one(at(blue_over_orange), blended(mode, blue, blue_alpha, orange))) << blue_over_orange.name;
  }
}

// ---- custom_depth.cpp -----------------------------------------------------------------------------

constexpr const char* kLitVertex = R"(#version 450 core
in vec3 position;
in vec3 normal;
uniform mat4 mvp;
out vec3 v_normal;
void main() {
  gl_Position = mvp * vec4(position, 1.0);
  v_normal = normal;
}
)";
// lit.cl, and with PEEL defined, OpenGL's way to peel: discard what is not behind the first layer.
constexpr const char* kLitFragment = R"(
in vec3 v_normal;
uniform vec3 light_direction;
uniform vec3 albedo;
uniform float alpha;
#ifdef PEEL
uniform sampler2D first_layer;
uniform float separation;
#endif
out vec4 color;
void main() {
#ifdef PEEL
  if (!(gl_FragCoord.z > texelFetch(first_layer, ivec2(gl_FragCoord.xy), 0).r + separation)) discard;
#endif
  vec3 n = normalize(v_normal);
  if (!gl_FrontFacing) n = -n;
  float diffuse = max(dot(n, light_direction), 0.0);
  color = vec4(albedo * (0.25 + 0.75 * diffuse), alpha);
}
)";

Image custom_depth_gl() {
  constexpr int kWidth = 384, kHeight = 320;
  io::Mesh torus = io::make_torus(64, 32, 0.8f, 0.3f);
  io::transform(torus, glm::rotate(glm::mat4(1), glm::radians(15.0f), glm::vec3(1, 0, 0)));
  const std::vector<io::Mesh> meshes{torus, io::make_sphere(48, 24, 0.5f, {0.7f, 0.05f, 0.3f})};
  const std::vector<std::vector<float>> albedos{{0.95f, 0.7f, 0.2f}, {0.25f, 0.45f, 0.95f}};
  io::Camera camera;
  camera.eye = {0.0f, 1.2f, 3.2f};
  camera.near_plane = 1.0f;
  camera.far_plane = 10.0f;

  GlProgram lit(kLitVertex, std::string("#version 450 core\n") + kLitFragment, "lit");
  GlProgram peel(kLitVertex, std::string("#version 450 core\n#define PEEL\n") + kLitFragment, "peel");
  for (GlProgram* program : {&lit, &peel}) {
    program->set("mvp", camera_mvp(camera, kWidth, kHeight))
        .set("light_direction", std::vector<float>{0.48f, 0.64f, 0.6f})
        .set("alpha", 1.0f);
  }
  const auto draw_scene = [&](GlFramebuffer& target, GlProgram& program, const DrawState& state) {
    for (std::size_t i = 0; i < meshes.size(); ++i) {
      program.set("albedo", albedos[i]);
      GlDrawCall call = mesh_draw(program, meshes[i]);
      call.state = state;
      call.state.cull = CullMode::Back;
      target.draw(call);
    }
  };

  GlTexture first_depth(kWidth, kHeight, Format::Depth32F), second_depth(kWidth, kHeight, Format::Depth32F);
  GlTexture color(kWidth, kHeight, Format::RGBA8);
  GlFramebuffer first_pass({}, &first_depth);
  first_pass.clear_depth(1.0f);
  draw_scene(first_pass, lit, DrawState{});

  GlFramebuffer second_pass({&color}, &second_depth);
  second_pass.clear({0.3f, 0.32f, 0.4f, 1.0f}, 1.0f);
  peel.set_texture("first_layer", first_depth, Sampler{}).set("separation", 1e-4f);
  draw_scene(second_pass, peel, DrawState{});

  GlFramebuffer composite({&color}, &first_depth);
  lit.set("alpha", 0.6f);
  DrawState over;
  over.depth_func = CompareFunc::Equal;
  over.depth_write = false;
  over.blend[0] = {true,
                   BlendEquation::Add,
                   BlendEquation::Add,
                   BlendFactor::SrcAlpha,
                   BlendFactor::OneMinusSrcAlpha,
                   BlendFactor::One,
                   BlendFactor::OneMinusSrcAlpha,
                   {true, true, true, true}};
  draw_scene(composite, lit, over);
  return picture_of(color);
}

// The program's depth test must find the same second layer as OpenGL's discard-based peeling.
TEST(Examples, CustomDepthTestPeelsTheSecondLayerAsOpenGLDoes) {
  EXPECT_TRUE(images_match(run_example("custom_depth"), custom_depth_gl(), kSameScene));
}

// ---- view_batch.cpp -------------------------------------------------------------------------------

// Each of the contact sheet's 16 pictures is what llvmpipe draws from that view's camera alone.
TEST(Examples, ViewBatchDrawsEachViewAsOpenGLDrawsItsCamera) {
  constexpr int kSide = 160, kColumns = 4, kViews = 16;
  const Image sheet = run_example("view_batch");
  ASSERT_EQ(sheet.width, kColumns * kSide);
  ASSERT_EQ(sheet.height, kViews / kColumns * kSide);
  const io::Mesh knot = io::make_torus_knot(2, 3, 256, 16, 1.0f, 0.45f, 0.3f);
  for (int k = 0; k < kViews; ++k) {
    SCOPED_TRACE("view " + std::to_string(k));
    const float degree = std::acos(-1.0f) / 180.0f;
    const float azimuth = degree * (30.0f + 90.0f * static_cast<float>(k % kColumns));
    const float elevation = degree * (-50.0f + 30.0f * static_cast<float>(k / kColumns));
    io::Camera camera;
    camera.eye = {5.0f * std::cos(elevation) * std::sin(azimuth), 5.0f * std::sin(elevation),
                  5.0f * std::cos(elevation) * std::cos(azimuth)};
    camera.near_plane = 1.0f;
    camera.far_plane = 10.0f;
    DrawState state;
    state.model_view = io::to_mat4(io::view_matrix(camera));
    state.projection = io::to_mat4(io::projection_matrix(camera, 1.0f));
    Image picture{kSide, kSide, std::vector<std::uint8_t>(std::size_t(kSide) * kSide * 4)};
    for (int y = 0; y < kSide; ++y) {
      const std::size_t row = std::size_t(k / kColumns * kSide + y) * std::size_t(sheet.width) + std::size_t(k % kColumns * kSide);
      std::copy_n(&sheet.rgba[row * 4], kSide * 4, &picture.rgba[std::size_t(y) * kSide * 4]);
    }
    ASSERT_GT(covered_pixel_count(picture), std::uint64_t{kSide} * kSide / 10);
    EXPECT_TRUE(images_match(picture, render_gl(knot, state, kSide, kSide), kNormalShading));
  }
}

}  // namespace
}  // namespace clraster::test
