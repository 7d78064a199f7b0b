// User programs against Mesa's OpenGL (llvmpipe), through the whole pipeline: each test draws with an
// OpenCL C program on clraster and with the equivalent GLSL on the oracle, from the same data and
// state, and compares the attachments (support/program_scene.hpp). Texture filtering is held to the
// issue's tolerance (2/255 on 99.5% of the pixels), derivatives, framebuffer fetch, blending and
// depth tests to what their arithmetic allows; each test says which and why.
#include "support/program_scene.hpp"
#include "support/test_support.hpp"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <ostream>
#include <string>
#include <vector>

namespace clraster::test {
namespace {

constexpr double kFilterTolerance = 2.0 / 255;    // the issue's texture filtering tolerance
constexpr double kFilterMinFraction = 0.995;      // of the pixels

Mat4 to_mat4(const glm::mat4& m) {
  Mat4 result;
  std::memcpy(result.data(), glm::value_ptr(m), sizeof(result));
  return result;
}

// ---- 1. Texture filtering and mipmap selection ----------------------------------------------------------

constexpr int kTextureSize = 64;   // 7 levels
constexpr int kPictureSize = 128;

// RGBA values in [0, 1] with detail at every scale, so that every mip level differs from its
// neighbours: per-texel noise (which dies out after a few levels) over waves 64 and 16 texels long
// (which last to the small levels), in different phases per channel.
std::vector<float> pattern_rgba(int size) {
  std::vector<float> values;
  std::uint32_t state = 12345;
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      for (int c = 0; c < 4; ++c) {
        state = state * 1664525u + 1013904223u;
        const float noise = float(state >> 8) / float(1u << 24);
        const float phase = 1.7f * float(c);
        const float wave = std::sin(6.2831853f * float(x + 2 * y) / 64.0f + phase) +
                           0.5f * std::sin(6.2831853f * float(3 * x - y) / 16.0f + phase);
        values.push_back(std::clamp(0.5f + 0.3f * (noise - 0.5f) + 0.2f * wave, 0.0f, 1.0f));
      }
    }
  }
  return values;
}

// The pattern in `format`: its first channels, as the format stores them.
std::vector<std::byte> pattern_texels(Format format, int size) {
  const std::vector<float> rgba = pattern_rgba(size);
  const int channels = format_info(format).channels;
  std::vector<float> values;
  for (std::size_t texel = 0; texel < rgba.size() / 4; ++texel) {
    for (int c = 0; c < channels; ++c) values.push_back(rgba[texel * 4 + c]);
  }
  return encode_texels(format, values);
}

// A ground plane y = 0, x in [-40, 40], z in [-60, 1], with texture coordinates (x, z) / 2.
const std::vector<float> kGroundPositions = {-40, 0, 1, 40, 0, 1, 40, 0, -60, -40, 0, -60};
const std::vector<float> kGroundUvs = {-19.6246f, 0.8714f, 19.8714f, 0.8714f, 19.8714f, -29.2443f, -19.6246f, -29.2443f};
const std::vector<std::uint32_t> kQuadIndices = {0, 1, 2, 0, 2, 3};

enum class View {
  Horizon,  // from 1 above the ground, pitched down 32 degrees: the ground fills the picture, from a
            // magnified foreground (level of detail about -2.5) to the horizon just above the top edge
  CloseUp,  // straight down from 0.8 above, turned 30 degrees: magnified everywhere (about -2)
};

Mat4 view_matrix(View view) {
  const glm::mat4 projection = glm::perspective(glm::radians(60.0f), 1.0f, 0.1f, 100.0f);
  const float pitch = glm::radians(32.0f);
  const glm::mat4 look = view == View::Horizon
                             ? glm::lookAt(glm::vec3(0, 1, 0), glm::vec3(0, 1 - std::sin(pitch), -std::cos(pitch)),
                                           glm::vec3(0, 1, 0))
                             : glm::lookAt(glm::vec3(0.3f, 0.8f, -2), glm::vec3(0.3f, 0, -2),
                                           glm::vec3(std::sin(glm::radians(30.0f)), 0, -std::cos(glm::radians(30.0f))));
  return to_mat4(projection * look);
}

constexpr const char* kTexturedProgram = R"(
clr_attribute(float3, position)
clr_attribute(float2, uv)
clr_varying(float2, uv)
clr_uniform(float16, mvp)
clr_texture(image)
clr_output(float4, color)

void vertex(clr_vertex* v) {
  v->position = clr_mul(v->uniforms->mvp, (float4)(v->in.position, 1.0f));
  v->out.uv = v->in.uv;
}
void fragment(clr_fragment* f) { f->out.color = clr_sample(f, f->textures.image, f->in.uv); }
)";

// The vertex shader every GLSL program here shares: the attributes position and uv, through mvp.
constexpr const char* kGlslVertex = R"(#version 450 core
in vec3 position;
in vec2 uv;
uniform mat4 mvp;
out vec2 v_uv;
void main() {
  gl_Position = mvp * vec4(position, 1.0);
  v_uv = uv;
}
)";

constexpr const char* kGlslTextured = R"(#version 450 core
in vec2 v_uv;
uniform sampler2D image;
out vec4 color;
void main() { color = texture(image, v_uv); }
)";

ProgramDraw ground_draw() {
  ProgramDraw draw;
  draw.attributes = {{"position", AttributeType::Float3, kGroundPositions}, {"uv", AttributeType::Float2, kGroundUvs}};
  draw.indices = kQuadIndices;
  draw.state.depth_test = false;
  return draw;
}

// The ground's texture coordinates themselves, in an RGBA32F attachment: what every sampling test
// below starts from. GL's are within 3e-6 of the exact values (computed in double) everywhere, and
// clraster's within 3.1e-5 of GL's (they were 3.3e-3 off, near the horizon, while clraster
// interpolated over the snapped triangle); uv reaches 30 (1920 texels), so 1e-4 is 1/150 of a texel
// of the 64-texel level 0.
TEST(Interpolation, PerspectiveCorrectVaryingsAreAsPreciseAsOpenGl) {
  ProgramPair program(R"(
clr_attribute(float3, position)
clr_attribute(float2, uv)
clr_varying(float2, uv)
clr_uniform(float16, mvp)
clr_output(float4, color)
void vertex(clr_vertex* v) {
  v->position = clr_mul(v->uniforms->mvp, (float4)(v->in.position, 1.0f));
  v->out.uv = v->in.uv;
}
void fragment(clr_fragment* f) { f->out.color = (float4)(f->in.uv, 0.0f, 1.0f); }
)",
                      kGlslVertex,
                      "#version 450 core\nin vec2 v_uv;\nout vec4 color;\nvoid main() { color = vec4(v_uv, 0.0, 1.0); }\n",
                      "uv.cl");
  program.set("mvp", view_matrix(View::Horizon));
  FramebufferPair target(kPictureSize, kPictureSize, {Format::RGBA32F});
  target.clear({0, 0, 0, 0});
  target.draw(program, ground_draw());
  ASSERT_TRUE(drawn(target.color(0)));
  EXPECT_TRUE(texels_match(target.color(0), {.tolerance = 1e-4}));
}

// The fragment's window depth and 1 / w (gl_FragCoord.zw) over the same ground, with the depth test
// off and on: raster/shade.cl works out a span's depth before the tests when the depth test needs
// it, and only for fragments that passed them otherwise; both ways must give GL's. Both are within
// 7.8e-7 of GL's (measured; depth is in [0, 1], 1 / w up to about 10 here).
TEST(Interpolation, FragmentCoordinatesMatchOpenGlWithAndWithoutTheDepthTest) {
  ProgramPair program(R"(
clr_attribute(float3, position)
clr_uniform(float16, mvp)
clr_output(float4, color)
void vertex(clr_vertex* v) { v->position = clr_mul(v->uniforms->mvp, (float4)(v->in.position, 1.0f)); }
void fragment(clr_fragment* f) { f->out.color = (float4)(f->frag_coord.z, f->frag_coord.w, 0.0f, 1.0f); }
)",
                      "#version 450 core\nin vec3 position;\nuniform mat4 mvp;\n"
                      "void main() { gl_Position = mvp * vec4(position, 1.0); }\n",
                      "#version 450 core\nout vec4 color;\n"
                      "void main() { color = vec4(gl_FragCoord.z, gl_FragCoord.w, 0.0, 1.0); }\n",
                      "frag_coord.cl");
  program.set("mvp", view_matrix(View::Horizon));
  for (const bool depth_test : {false, true}) {
    SCOPED_TRACE(depth_test ? "depth test on" : "depth test off");
    FramebufferPair target(kPictureSize, kPictureSize, {Format::RGBA32F}, Format::Depth32F);
    target.clear({0, 0, 0, 0}, 1.0f);
    ProgramDraw draw = ground_draw();
    draw.attributes.resize(1);  // the position
    draw.state.depth_test = depth_test;
    target.draw(program, draw);
    EXPECT_TRUE(drawn(target.color(0)));
    EXPECT_TRUE(texels_match(target.color(0), {.tolerance = 2e-6}));
  }
}

// The level of detail itself: a texture whose level k holds the value k everywhere, sampled
// trilinearly, returns lambda clamped to [0, 6] (lerps between whole levels are exact). llvmpipe
// takes one lambda per 2x2 quad from the differences along the quad's first row and column, as
// clr_sample does, and approximates log2 (see clr_sample_grad); what is left is the rounding of
// differently interpolated coordinates, below 0.0004 of a level.
TEST(Interpolation, LevelOfDetailMatchesOpenGlPerQuad) {
  TexturePair texture(kTextureSize, kTextureSize, Format::R32F, kFullMipChain);
  for (int level = 0; level < texture.clr.levels(); ++level) {
    const std::size_t texels = std::size_t(texture.clr.width(level)) * texture.clr.height(level);
    texture.upload(level, encode_texels(Format::R32F, std::vector<float>(texels, float(level))));
  }
  ProgramPair program(kTexturedProgram, kGlslVertex, kGlslTextured, "textured.cl");
  program.set("mvp", view_matrix(View::Horizon)).set_texture("image", texture, Sampler{});
  FramebufferPair target(kPictureSize, kPictureSize, {Format::R32F});
  target.clear({-1, 0, 0, 1});
  target.draw(program, ground_draw());
  ASSERT_TRUE(drawn(target.color(0)));
  EXPECT_TRUE(texels_match(target.color(0), {.tolerance = 0.001}));
}

struct SamplingCase {
  const char* name;
  Format format = Format::RGBA8;
  Sampler sampler{};
  View view = View::Horizon;
};
void PrintTo(const SamplingCase& c, std::ostream* out) { *out << c.name; }

constexpr Sampler filtered(Filter filter, MipFilter mip) { return Sampler{filter, filter, mip}; }
constexpr Sampler wrapped(Wrap wrap, Filter filter = Filter::Linear) {
  return Sampler{filter, filter, MipFilter::Linear, wrap, wrap};
}
constexpr Sampler lod_range(float bias, float min_lod, float max_lod) {
  return Sampler{Filter::Linear, Filter::Linear, MipFilter::Linear, Wrap::Repeat, Wrap::Repeat, bias, min_lod, max_lod};
}

class TextureSampling : public ::testing::TestWithParam<SamplingCase> {};

TEST_P(TextureSampling, MatchesOpenGl) {
  const SamplingCase& c = GetParam();
  const TexturePair texture =
      TexturePair::with_clraster_mipmaps(kTextureSize, kTextureSize, c.format, pattern_texels(c.format, kTextureSize));
  ProgramPair program(kTexturedProgram, kGlslVertex, kGlslTextured, "textured.cl");
  program.set("mvp", view_matrix(c.view)).set_texture("image", texture, c.sampler);
  FramebufferPair target(kPictureSize, kPictureSize, {Format::RGBA32F});
  target.clear({1, 0, 1, 1});  // magenta where the ground would not be drawn
  target.draw(program, ground_draw());
  ASSERT_TRUE(drawn(target.color(0)));
  EXPECT_TRUE(texels_match(target.color(0), {.tolerance = kFilterTolerance, .min_fraction = kFilterMinFraction}));
}

INSTANTIATE_TEST_SUITE_P(
    Filters, TextureSampling,
    ::testing::Values(SamplingCase{"Nearest", Format::RGBA8, filtered(Filter::Nearest, MipFilter::None)},
                      SamplingCase{"Bilinear", Format::RGBA8, filtered(Filter::Linear, MipFilter::None)},
                      SamplingCase{"NearestMipmapNearest", Format::RGBA8, filtered(Filter::Nearest, MipFilter::Nearest)},
                      SamplingCase{"LinearMipmapNearest", Format::RGBA8, filtered(Filter::Linear, MipFilter::Nearest)},
                      SamplingCase{"NearestMipmapLinear", Format::RGBA8, filtered(Filter::Nearest, MipFilter::Linear)},
                      SamplingCase{"Trilinear", Format::RGBA8, filtered(Filter::Linear, MipFilter::Linear)},
                      // Linear magnification with nearest minification: the switch between them at
                      // level of detail 0 runs across the picture.
                      SamplingCase{"MagLinearMinNearestMipmapNearest", Format::RGBA8,
                                   Sampler{Filter::Linear, Filter::Nearest, MipFilter::Nearest}},
                      SamplingCase{"MagNearestMinTrilinear", Format::RGBA8,
                                   Sampler{Filter::Nearest, Filter::Linear, MipFilter::Linear}}),
    [](const auto& info) { return std::string(info.param.name); });

INSTANTIATE_TEST_SUITE_P(
    WrapModes, TextureSampling,
    ::testing::Values(SamplingCase{"ClampToEdge", Format::RGBA8, wrapped(Wrap::ClampToEdge)},
                      SamplingCase{"MirroredRepeat", Format::RGBA8, wrapped(Wrap::MirroredRepeat)},
                      SamplingCase{"MirroredRepeatNearest", Format::RGBA8, wrapped(Wrap::MirroredRepeat, Filter::Nearest)},
                      SamplingCase{"MixedWraps", Format::RGBA8,
                                   Sampler{Filter::Linear, Filter::Linear, MipFilter::Linear, Wrap::ClampToEdge,
                                           Wrap::MirroredRepeat}}),
    [](const auto& info) { return std::string(info.param.name); });

INSTANTIATE_TEST_SUITE_P(
    LevelOfDetail, TextureSampling,
    ::testing::Values(SamplingCase{"BiasUp", Format::RGBA8, lod_range(1.5f, -1000, 1000)},
                      SamplingCase{"BiasDown", Format::RGBA8, lod_range(-1.25f, -1000, 1000)},
                      SamplingCase{"MinLod", Format::RGBA8, lod_range(0, 1.5f, 1000)},
                      SamplingCase{"MaxLod", Format::RGBA8, lod_range(0, -1000, 2.25f)},
                      SamplingCase{"BiasAndRange", Format::RGBA8, lod_range(0.75f, 0.5f, 3.0f)},
                      SamplingCase{"MagnifiedNearest", Format::RGBA8, filtered(Filter::Nearest, MipFilter::Linear),
                                   View::CloseUp},
                      SamplingCase{"MagnifiedLinear", Format::RGBA8, filtered(Filter::Linear, MipFilter::Linear),
                                   View::CloseUp}),
    [](const auto& info) { return std::string(info.param.name); });

INSTANTIATE_TEST_SUITE_P(
    Formats, TextureSampling,
    ::testing::Values(SamplingCase{"R8", Format::R8}, SamplingCase{"RG8", Format::RG8},
                      SamplingCase{"SRGB8_A8", Format::SRGB8_A8}, SamplingCase{"R32F", Format::R32F},
                      SamplingCase{"RGBA16F", Format::RGBA16F}, SamplingCase{"RGBA32F", Format::RGBA32F},
                      SamplingCase{"SRGB8_A8Nearest", Format::SRGB8_A8, filtered(Filter::Nearest, MipFilter::Nearest)}),
    [](const auto& info) { return std::string(info.param.name); });



// ---- 2. Derivatives ------------------------------------------------------------------------------------

constexpr int kDerivativeSize = 64;

// Triangles of every size down to a few pixels, in perspective (w from 0.6 to 2) and off the
// 1/256-pixel grid, with texture coordinates: their edges cut through quads, whose uncovered pixels
// run as helpers. Deterministic (a fixed linear congruential sequence).
struct ClipTriangles {
  std::vector<float> positions;  // x, y, z, w per vertex
  std::vector<float> uvs;        // 2 per vertex
};
ClipTriangles random_triangles(int count) {
  ClipTriangles triangles;
  std::uint32_t state = 2024;
  auto next = [&state] {
    state = state * 1664525u + 1013904223u;
    return float(state >> 8) / float(1u << 24);
  };
  for (int t = 0; t < count; ++t) {
    const float cx = 1.6f * next() - 0.8f, cy = 1.6f * next() - 0.8f, size = 0.05f + 0.6f * next();
    for (int k = 0; k < 3; ++k) {
      const float x = std::clamp(cx + size * (2 * next() - 1), -1.0f, 1.0f);
      const float y = std::clamp(cy + size * (2 * next() - 1), -1.0f, 1.0f);
      const float w = 0.6f + 1.4f * next();
      triangles.positions.insert(triangles.positions.end(), {x * w, y * w, 0.5f * w, w});
      triangles.uvs.insert(triangles.uvs.end(), {4 * next(), 4 * next()});
    }
  }
  return triangles;
}

// g(uv) = (u^2, sin(3v), uv, v^3): second derivatives that are not zero, so that fine and coarse
// derivatives differ (by about 0.01 here).
constexpr const char* kDerivativeProgram = R"(
clr_attribute(float4, position)
clr_attribute(float2, uv)
clr_varying(float2, uv)
clr_output(float4, dx_fine)
clr_output(float4, dy_fine)
clr_output(float4, dx_coarse)
clr_output(float4, dy_coarse)
clr_output(float4, dx)
clr_output(float4, dy)
clr_output(float4, width)

void vertex(clr_vertex* v) {
  v->position = v->in.position;
  v->out.uv = v->in.uv;
}
void fragment(clr_fragment* f) {
  const float2 uv = f->in.uv;
  const float4 g = (float4)(uv.x * uv.x, sin(3.0f * uv.y), uv.x * uv.y, uv.y * uv.y * uv.y);
  f->out.dx_fine = clr_dfdx_fine(f, g);
  f->out.dy_fine = clr_dfdy_fine(f, g);
  f->out.dx_coarse = clr_dfdx_coarse(f, g);
  f->out.dy_coarse = clr_dfdy_coarse(f, g);
  f->out.dx = clr_dfdx(f, g);
  f->out.dy = clr_dfdy(f, g);
  f->out.width = clr_fwidth(f, g);
}
)";

constexpr const char* kGlslClipVertex = R"(#version 450 core
in vec4 position;
in vec2 uv;
out vec2 v_uv;
void main() {
  gl_Position = position;
  v_uv = uv;
}
)";

constexpr const char* kGlslDerivatives = R"(#version 450 core
in vec2 v_uv;
layout(location = 0) out vec4 dx_fine;
layout(location = 1) out vec4 dy_fine;
layout(location = 2) out vec4 dx_coarse;
layout(location = 3) out vec4 dy_coarse;
layout(location = 4) out vec4 dx;
layout(location = 5) out vec4 dy;
layout(location = 6) out vec4 width;
void main() {
  vec4 g = vec4(v_uv.x * v_uv.x, sin(3.0 * v_uv.y), v_uv.x * v_uv.y, v_uv.y * v_uv.y * v_uv.y);
  dx_fine = dFdxFine(g);
  dy_fine = dFdyFine(g);
  dx_coarse = dFdxCoarse(g);
  dy_coarse = dFdyCoarse(g);
  dx = dFdx(g);
  dy = dFdy(g);
  width = fwidth(g);
}
)";

enum DerivativeOutput { kDxFine, kDyFine, kDxCoarse, kDyCoarse, kDx, kDy, kFwidth, kDerivativeOutputs };

// Every derivative of the program into its own RGBA32F attachment (pixels no triangle covers keep -100).
class Derivatives : public ::testing::Test {
 protected:
  void SetUp() override {
    const ClipTriangles triangles = random_triangles(24);
    ProgramDraw draw;
    draw.attributes = {{"position", AttributeType::Float4, triangles.positions},
                       {"uv", AttributeType::Float2, triangles.uvs}};
    draw.state.depth_test = false;
    target_.clear({-100, -100, -100, -100});
    target_.draw(program_, draw);
  }

  // Output `clr` of clraster against output `gl` of GL. 1e-3: llvmpipe's sin is a polynomial
  // approximation, and differences of neighbouring values magnify its error; fine and coarse
  // derivatives differ by 0.01 and more where they differ.
  TexelDifference difference(DerivativeOutput clr, DerivativeOutput gl) {
    return compare_texels(Format::RGBA32F, target_.color(clr).clr.read(), target_.color(gl).gl.read(), 1e-3);
  }
  std::vector<float> clraster_values(DerivativeOutput output) {
    return stored_values(Format::RGBA32F, target_.color(output).clr.read());
  }

  ProgramPair program_{kDerivativeProgram, kGlslClipVertex, kGlslDerivatives, "derivatives.cl"};
  FramebufferPair target_{kDerivativeSize, kDerivativeSize, std::vector<Format>(kDerivativeOutputs, Format::RGBA32F)};
};

// llvmpipe computes every derivative fine: dFdxCoarse, dFdx and dFdxFine all difference the
// fragment's own row of its quad (gallivm's lp_build_ddx), which the extension allows for coarse
// ones. So clr_dfdx_fine and clr_dfdy_fine match all three, and clr_dfdx, clr_dfdy and clr_fwidth,
// fine by default as in llvmpipe (CLR_DEFAULT_DERIVATIVE_COARSE), match dFdx, dFdy and fwidth.
TEST_F(Derivatives, FineOnesMatchLlvmpipesEveryVariant) {
  for (const auto& [clr, gl] : {std::pair{kDxFine, kDxFine}, {kDxFine, kDxCoarse}, {kDxFine, kDx},
                                {kDyFine, kDyFine}, {kDyFine, kDyCoarse}, {kDyFine, kDy}, {kDx, kDx},
                                {kDy, kDy}, {kFwidth, kFwidth}}) {
    const TexelDifference d = difference(clr, gl);
    RecordProperty("clraster_" + std::to_string(clr) + "_gl_" + std::to_string(gl), d.summary());
    EXPECT_EQ(d.texels_beyond, 0u) << "clraster output " << clr << " against GL output " << gl << ": " << d.summary();
  }
}

// GL has no strictly coarse derivative to compare with, so clraster's are checked against their
// definition: the fine derivative of the quad's first (lowest) row, or first (left) column, exactly.
// On one triangle covering the whole picture, so that every pixel's neighbours are its own triangle's
// and no helper's. That they differ from the fine ones at all shows the scene tells the two apart.
TEST_F(Derivatives, CoarseOnesAreTheFineOnesOfTheQuadsFirstRowOrColumn) {
  FramebufferPair target(kDerivativeSize, kDerivativeSize, std::vector<Format>(kDerivativeOutputs, Format::RGBA32F));
  ProgramDraw draw;
  draw.attributes = {{"position", AttributeType::Float4, {-1, -1, 0.5f, 1, 3, -1, 0.5f, 1, -1, 3, 0.5f, 1}},
                     {"uv", AttributeType::Float2, {0.5f, 0.25f, 8.5f, 1.25f, -0.5f, 8.25f}}};
  draw.state.depth_test = false;
  target.draw(program_, draw);
  auto values = [&](DerivativeOutput output) { return stored_values(Format::RGBA32F, target.color(output).clr.read()); };
  const std::vector<float> dx_fine = values(kDxFine), dy_fine = values(kDyFine);
  const std::vector<float> dx_coarse = values(kDxCoarse), dy_coarse = values(kDyCoarse);
  int differing_from_fine = 0;
  for (int y = 0; y < kDerivativeSize; ++y) {
    for (int x = 0; x < kDerivativeSize; ++x) {
      const std::size_t pixel = std::size_t(y) * kDerivativeSize + x;
      const std::size_t first_row = std::size_t(y & ~1) * kDerivativeSize + x;
      const std::size_t first_column = std::size_t(y) * kDerivativeSize + (x & ~1);
      for (int c = 0; c < 4; ++c) {
        ASSERT_EQ(dx_coarse[pixel * 4 + c], dx_fine[first_row * 4 + c]) << "x " << x << " y " << y;
        ASSERT_EQ(dy_coarse[pixel * 4 + c], dy_fine[first_column * 4 + c]) << "x " << x << " y " << y;
        differing_from_fine += std::fabs(dx_coarse[pixel * 4 + c] - dx_fine[pixel * 4 + c]) > 1e-3f;
      }
    }
  }
  EXPECT_GT(differing_from_fine, kDerivativeSize * kDerivativeSize / 4);
}

// Quad shading writes the covered pixels only: the same pixels as GL, helpers' outputs thrown away.
TEST_F(Derivatives, HelpersWriteNothing) {
  const std::vector<float> clr = clraster_values(kDx);
  const std::vector<float> gl = stored_values(Format::RGBA32F, target_.color(kDx).gl.read());
  int covered = 0;
  for (std::size_t pixel = 0; pixel < clr.size() / 4; ++pixel) {
    EXPECT_EQ(clr[pixel * 4] == -100, gl[pixel * 4] == -100) << "pixel " << pixel;
    covered += gl[pixel * 4] != -100;
  }
  EXPECT_GT(covered, 500);
}


// ---- 3. Framebuffer fetch --------------------------------------------------------------------------------

// Each fragment reads both attachments as earlier fragments left them (of its own draw too) and
// writes functions of them no blend equation computes: |first - tint * u| and first * second + tint / 4,
// over two draws of overlapping triangles.
constexpr const char* kFetchProgram = R"(
clr_attribute(float4, position)
clr_attribute(float2, uv)
clr_varying(float2, uv)
clr_uniform(float4, tint)
clr_output(float4, first)
clr_output(float4, second)

void vertex(clr_vertex* v) {
  v->position = v->in.position;
  v->out.uv = v->in.uv;
}
void fragment(clr_fragment* f) {
  const float4 a = clr_framebuffer_fetch(f, 0);
  const float4 b = clr_framebuffer_fetch(f, 1);
  f->out.first = fabs(a - f->uniforms->tint * (f->in.uv.x * 0.25f));
  f->out.second = a * b + f->uniforms->tint * 0.25f;
}
)";

constexpr const char* kGlslFetch = R"(#version 450 core
#extension GL_EXT_shader_framebuffer_fetch : require
in vec2 v_uv;
uniform vec4 tint;
layout(location = 0) inout vec4 first;
layout(location = 1) inout vec4 second;
void main() {
  vec4 a = first;
  vec4 b = second;
  first = abs(a - tint * (v_uv.x * 0.25));
  second = a * b + tint * 0.25;
}
)";

struct FetchCase {
  const char* name;
  std::array<Format, 2> formats;
  double tolerance;  // 8-bit: a result within float rounding of a tie may round either way
};
void PrintTo(const FetchCase& c, std::ostream* out) { *out << c.name; }

class FramebufferFetch : public ::testing::TestWithParam<FetchCase> {};

TEST_P(FramebufferFetch, MatchesExtShaderFramebufferFetch) {
  const FetchCase& c = GetParam();
  const ClipTriangles triangles = random_triangles(16);
  ProgramPair program(kFetchProgram, kGlslClipVertex, kGlslFetch, "fetch.cl");
  FramebufferPair target(kDerivativeSize, kDerivativeSize, {c.formats[0], c.formats[1]});
  target.clear({0.2f, 0.4f, 0.6f, 0.8f});
  ProgramDraw draw;
  draw.attributes = {{"position", AttributeType::Float4, triangles.positions},
                     {"uv", AttributeType::Float2, triangles.uvs}};
  draw.state.depth_test = false;
  for (const std::array<float, 4>& tint : {std::array{0.9f, 0.3f, 0.5f, 1.0f}, std::array{0.1f, 0.7f, 0.35f, 0.6f}}) {
    program.set("tint", tint);
    target.draw(program, draw);
  }
  for (int k = 0; k < 2; ++k) {
    EXPECT_TRUE(drawn(target.color(k))) << "attachment " << k;
    EXPECT_TRUE(texels_match(target.color(k), {.tolerance = c.tolerance})) << "attachment " << k;
  }
}

INSTANTIATE_TEST_SUITE_P(Formats, FramebufferFetch,
                         ::testing::Values(FetchCase{"RGBA8", {Format::RGBA8, Format::RGBA8}, 1.0 / 255},
                                           FetchCase{"RGBA32F", {Format::RGBA32F, Format::RGBA32F}, 1e-5},
                                           FetchCase{"RGBA8AndRGBA32F", {Format::RGBA8, Format::RGBA32F}, 1.0 / 255}),
                         [](const auto& info) { return std::string(info.param.name); });

// ---- 4. Programmable blending: the PDF blend modes ----------------------------------------------------------

// The 15 modes, as the library names them and as KHR_blend_equation_advanced does.
struct BlendModeCase {
  const char* function;  // clr_blend_<function>
  oracle::AdvancedBlend equation;
};
void PrintTo(const BlendModeCase& c, std::ostream* out) { *out << c.function; }

// Premultiplied colours from the vertices (alpha 0.25 to 1), drawn over a background of other
// premultiplied colours (alpha 0.4 to 1) that the first draw writes without blending.
constexpr const char* kPremultipliedVertex = R"(#version 450 core
in vec4 position;
in vec4 color;
out vec4 v_color;
void main() {
  gl_Position = position;
  v_color = vec4(color.rgb * color.a, color.a);
}
)";

std::string blend_program(const char* function) {
  return std::string(R"(
clr_attribute(float4, position)
clr_attribute(float4, color)
clr_varying(float4, color)
clr_output(float4, result)

void vertex(clr_vertex* v) {
  v->position = v->in.position;
  v->out.color = (float4)(v->in.color.xyz * v->in.color.w, v->in.color.w);
}
void fragment(clr_fragment* f) { f->out.result = f->in.color; }
float4 blend(clr_fragment* f, uint target, float4 source, float4 destination) {
  return clr_blend_)") + function + "(source, destination);\n}\n";
}

constexpr const char* kGlslAdvancedBlend = R"(#version 450 core
#extension GL_KHR_blend_equation_advanced : require
layout(blend_support_all_equations) out;
in vec4 v_color;
out vec4 result;
void main() { result = v_color; }
)";

// A full-screen pair of triangles with a colour per corner (x, y, z, w and r, g, b, a).
ProgramDraw colored_rectangle(std::array<float, 16> corner_colors) {
  ProgramDraw draw;
  draw.attributes = {{"position", AttributeType::Float4, {-1, -1, 0.5f, 1, 1, -1, 0.5f, 1, 1, 1, 0.5f, 1, -1, 1, 0.5f, 1}},
                     {"color", AttributeType::Float4, std::vector<float>(corner_colors.begin(), corner_colors.end())}};
  draw.indices = kQuadIndices;
  draw.state.depth_test = false;
  return draw;
}

class ProgrammableBlend : public ::testing::TestWithParam<BlendModeCase> {};

// 8-bit attachments: both compute in float from the same 8-bit destination and round once, so a
// result may differ by one where it lies within float rounding of a rounding tie.
TEST_P(ProgrammableBlend, MatchesKhrBlendEquationAdvanced) {
  const BlendModeCase& c = GetParam();
  FramebufferPair target(kDerivativeSize, kDerivativeSize, {Format::RGBA8});
  target.clear({0, 0, 0, 0});
  ProgramPair background(blend_program(c.function), kPremultipliedVertex,
                         "#version 450 core\nin vec4 v_color;\nout vec4 result;\nvoid main() { result = v_color; }\n",
                         "background.cl");
  target.draw(background, colored_rectangle({0.9f, 0.1f, 0.3f, 1.0f, 0.2f, 0.8f, 0.4f, 0.4f,  //
                                             0.1f, 0.3f, 0.9f, 0.7f, 0.6f, 0.6f, 0.1f, 1.0f}));
  ProgramPair blended(blend_program(c.function), kPremultipliedVertex, kGlslAdvancedBlend, "blend.cl");
  ProgramDraw draw = colored_rectangle({0.2f, 0.9f, 0.7f, 0.25f, 1.0f, 0.5f, 0.0f, 1.0f,  //
                                        0.4f, 0.2f, 0.6f, 0.6f, 0.95f, 0.95f, 0.3f, 0.8f});
  draw.state.blend[0] = kProgramBlend;
  draw.gl_state = draw.state;
  draw.gl_state->blend[0] = BlendState{};
  draw.gl_advanced_blend = c.equation;
  target.draw(blended, draw);
  ASSERT_TRUE(drawn(target.color(0)));
  EXPECT_TRUE(texels_match(target.color(0), {.tolerance = 1.0 / 255}));
}

using oracle::AdvancedBlend;
INSTANTIATE_TEST_SUITE_P(
    PdfModes, ProgrammableBlend,
    ::testing::Values(BlendModeCase{"multiply", AdvancedBlend::Multiply}, BlendModeCase{"screen", AdvancedBlend::Screen},
                      BlendModeCase{"overlay", AdvancedBlend::Overlay}, BlendModeCase{"darken", AdvancedBlend::Darken},
                      BlendModeCase{"lighten", AdvancedBlend::Lighten},
                      BlendModeCase{"colordodge", AdvancedBlend::ColorDodge},
                      BlendModeCase{"colorburn", AdvancedBlend::ColorBurn},
                      BlendModeCase{"hardlight", AdvancedBlend::HardLight},
                      BlendModeCase{"softlight", AdvancedBlend::SoftLight},
                      BlendModeCase{"difference", AdvancedBlend::Difference},
                      BlendModeCase{"exclusion", AdvancedBlend::Exclusion},
                      BlendModeCase{"hsl_hue", AdvancedBlend::HslHue},
                      BlendModeCase{"hsl_saturation", AdvancedBlend::HslSaturation},
                      BlendModeCase{"hsl_color", AdvancedBlend::HslColor},
                      BlendModeCase{"hsl_luminosity", AdvancedBlend::HslLuminosity}),
    [](const auto& info) { return std::string(info.param.function); });

// ---- 5. Programmable depth test ------------------------------------------------------------------------------

// Window depth (x + 0.5) / 64 at pixel column x: a rectangle from depth 0 at the left edge to 1 at the
// right (clip z from -1 to 1), drawn over depth cleared to 0.5. Vertices on the pixel grid, w = 1.
ProgramDraw depth_ramp(DrawState state) {
  ProgramDraw draw;
  draw.attributes = {{"position", AttributeType::Float4, {-1, -1, -1, 1, 1, -1, 1, 1, 1, 1, 1, 1, -1, 1, -1, 1}},
                     {"uv", AttributeType::Float2, {0, 0, 1, 0, 1, 1, 0, 1}}};
  draw.indices = kQuadIndices;
  draw.state = state;
  return draw;
}

std::string depth_program(const char* depth_test_body) {
  return std::string(R"(
clr_attribute(float4, position)
clr_attribute(float2, uv)
clr_varying(float2, uv)
clr_output(float4, color)

void vertex(clr_vertex* v) {
  v->position = v->in.position;
  v->out.uv = v->in.uv;
}
void fragment(clr_fragment* f) { f->out.color = (float4)(f->in.uv, 1.0f, 1.0f); }
bool depth_test(clr_fragment* f, float fragment_depth, float stored_depth) {
  )") + depth_test_body + "\n}\n";
}

constexpr const char* kGlslUvColor = R"(#version 450 core
in vec2 v_uv;
out vec4 color;
void main() { color = vec4(v_uv, 1.0, 1.0); }
)";

// A depth_test that is a standard function: the same pixels pass, and store the same depths, as
// with GL's GL_GREATER (and with depth writes on).
TEST(ProgrammableDepth, ReversedComparisonMatchesGlGreater) {
  ProgramPair program(depth_program("return fragment_depth > stored_depth;"), kGlslClipVertex, kGlslUvColor, "depth.cl");
  FramebufferPair target(kDerivativeSize, kDerivativeSize, {Format::RGBA8}, Format::Depth32F);
  target.clear({0, 0, 0, 1}, 0.5f);
  DrawState state;
  state.depth_func = CompareFunc::Program;
  ProgramDraw draw = depth_ramp(state);
  draw.gl_state = state;
  draw.gl_state->depth_func = CompareFunc::Greater;
  target.draw(program, draw);
  ASSERT_TRUE(drawn(target.color(0)));
  EXPECT_TRUE(texels_match(target.color(0), {.tolerance = 0}));
  EXPECT_TRUE(texels_match(*target.depth_stencil(), {.tolerance = 0}));
}

// A test GL has no function for: pass within 0.03 of the stored depth. Over depth 0.5, the columns
// x with |(x + 0.5) / 64 - 0.5| < 0.03, x = 30 to 33 (|x + 0.5 - 32| < 1.92), pass: 4 x 64 pixels,
// which store their own depth; every other pixel keeps the clear colour and depth 0.5.
TEST(ProgrammableDepth, CustomToleranceTestPassesExactlyTheExpectedPixels) {
  Program program(shared_context(), depth_program("return fabs(fragment_depth - stored_depth) < 0.03f;"), "near.cl");
  Bindings bindings(program);
  Texture color(shared_context(), kDerivativeSize, kDerivativeSize, Format::RGBA8);
  Texture depth(shared_context(), kDerivativeSize, kDerivativeSize, Format::Depth32F);
  Framebuffer target(shared_context(), {&color}, &depth);
  target.clear({0, 0, 0, 1}, 0.5f);
  const ProgramDraw ramp = depth_ramp(DrawState{.depth_func = CompareFunc::Program});
  const Buffer positions(shared_context(), ramp.attributes[0].values), uvs(shared_context(), ramp.attributes[1].values);
  const IndexBuffer indices(shared_context(), ramp.indices);
  DrawCall call;
  call.program = &program;
  call.bindings = &bindings;
  call.attributes = {{"position", &positions, AttributeType::Float4}, {"uv", &uvs, AttributeType::Float2}};
  call.indices = &indices;
  call.state = ramp.state;
  target.draw(call);

  const std::vector<float> depths = stored_values(Format::Depth32F, depth.read());
  const std::vector<float> colors = stored_values(Format::RGBA8, color.read());
  int passed = 0;
  for (int y = 0; y < kDerivativeSize; ++y) {
    for (int x = 0; x < kDerivativeSize; ++x) {
      const std::size_t pixel = std::size_t(y) * kDerivativeSize + x;
      const bool expected = x >= 30 && x <= 33;
      const bool drawn = colors[pixel * 4 + 2] == 1.0f;  // blue 1 from the program, 0 cleared
      EXPECT_EQ(drawn, expected) << "x " << x << " y " << y;
      EXPECT_FLOAT_EQ(depths[pixel], expected ? (x + 0.5f) / kDerivativeSize : 0.5f) << "x " << x << " y " << y;
      passed += drawn;
    }
  }
  EXPECT_EQ(passed, 4 * kDerivativeSize);
}

// ---- Mipmap generation ---------------------------------------------------------------------------------------

struct MipmapCase {
  const char* name;
  Format format;
  int width, height;
};
void PrintTo(const MipmapCase& c, std::ostream* out) { *out << c.name; }

class MipmapGeneration : public ::testing::TestWithParam<MipmapCase> {};

// clraster's generate_mipmaps against glGenerateMipmap from the same level 0, level by level. Both
// filter each level from the one before, bilinearly at the new texel centres (a 2x2 box where a side
// halves exactly), decoded (sRGB in linear space). Float levels agree to 1e-5 (the weights of odd
// sides, summed in another order, move the last bits). 8-bit ones do not
// round alike: clraster rounds the exact mean (150.00 -> 150, 42.25 -> 42; measured on random
// texels: 4088 of 4096 level-1 values are the rounded mean, the rest ties), llvmpipe's blit filters
// in 8-bit fixed point and lands one above it for about a third of them (150.00 -> 151,
// 42.25 -> 43). Each level is filtered from the previous one, so the bias adds up: level L is
// within L / 255 (measured: 1, 2, 2, 2, 3, 3 for levels 1 to 6 of a 64x64 RGBA8 texture).
TEST_P(MipmapGeneration, MatchesGlGenerateMipmap) {
  const MipmapCase& c = GetParam();
  const std::vector<float> rgba = pattern_rgba(std::max(c.width, c.height));
  const int channels = format_info(c.format).channels;
  std::vector<float> values;
  for (int y = 0; y < c.height; ++y) {
    for (int x = 0; x < c.width; ++x) {
      for (int k = 0; k < channels; ++k) values.push_back(rgba[(std::size_t(y) * std::max(c.width, c.height) + x) * 4 + k]);
    }
  }
  const std::vector<std::byte> level0 = encode_texels(c.format, values);
  TexturePair pair(c.width, c.height, c.format, kFullMipChain);
  pair.upload(0, level0);
  pair.clr.generate_mipmaps();
  pair.gl.generate_mipmaps();
  const bool normalized = c.format == Format::RGBA8 || c.format == Format::SRGB8_A8;
  for (int level = 1; level < pair.clr.levels(); ++level) {
    EXPECT_TRUE(texels_match(pair, {.tolerance = normalized ? level / 255.0 : 1e-5, .level = level})) << "level " << level;
  }
}

INSTANTIATE_TEST_SUITE_P(Formats, MipmapGeneration,
                         ::testing::Values(MipmapCase{"RGBA8", Format::RGBA8, 64, 64},
                                           MipmapCase{"RGBA8NonPowerOfTwo", Format::RGBA8, 45, 27},
                                           MipmapCase{"SRGB8_A8", Format::SRGB8_A8, 64, 64},
                                           MipmapCase{"RGBA32F", Format::RGBA32F, 64, 64},
                                           MipmapCase{"RGBA32FNonPowerOfTwo", Format::RGBA32F, 45, 27}),
                         [](const auto& info) { return std::string(info.param.name); });

}  // namespace
}  // namespace clraster::test
