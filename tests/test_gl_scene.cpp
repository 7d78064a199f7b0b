// Checks that the oracle's scene layer itself is right: every expected value here follows by hand
// from OpenGL's rules (blend equations, stencil operations, texel addressing, KHR advanced blending,
// derivatives of linear functions), with values chosen so that float results are exact.
#include <gtest/gtest.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include "oracle/gl_scene.hpp"

namespace {

using clraster::AttributeType;
using clraster::BlendEquation;
using clraster::BlendFactor;
using clraster::CompareFunc;
using clraster::Format;
using clraster::InvalidArgument;
using clraster::Sampler;
using clraster::StencilOp;
using clraster::oracle::AdvancedBlend;
using clraster::oracle::GlAttribute;
using clraster::oracle::GlDrawCall;
using clraster::oracle::GlFramebuffer;
using clraster::oracle::GlProgram;
using clraster::oracle::GlTexture;
using clraster::oracle::GlVertexInput;
using Vec4 = std::array<float, 4>;

template <typename T>
std::span<const std::byte> bytes(const std::vector<T>& values) {
  return std::as_bytes(std::span<const T>(values));
}

// Texels read back as values of T.
template <typename T>
std::vector<T> as(const std::vector<std::byte>& texels) {
  std::vector<T> values(texels.size() / sizeof(T));
  std::memcpy(values.data(), texels.data(), values.size() * sizeof(T));
  return values;
}

// One triangle covering the whole viewport, and a vertex shader passing it through.
const std::vector<float> kFullScreen = {-1, -1, 3, -1, -1, 3};
constexpr const char* kFullScreenVertex = R"(#version 450 core
in vec2 position;
void main() { gl_Position = vec4(position, 0.0, 1.0); }
)";

GlDrawCall full_screen(const GlProgram& program) {
  GlDrawCall call{&program};
  call.attributes = {{"position", bytes(kFullScreen), AttributeType::Float2}};
  call.state.depth_test = false;
  return call;
}

// A program writing `body` (GLSL statements) with the full-screen vertex shader.
GlProgram fragment_program(const std::string& declarations, const std::string& body) {
  return GlProgram(kFullScreenVertex, "#version 450 core\n" + declarations + "\nvoid main() {\n" + body + "\n}\n");
}

TEST(GlScene, MesaOffersTheExtensionsTheOracleDocuments) {
  for (const char* name : {"GL_KHR_blend_equation_advanced", "GL_KHR_blend_equation_advanced_coherent",
                           "GL_EXT_shader_framebuffer_fetch", "GL_EXT_shader_framebuffer_fetch_non_coherent",
                           "GL_ARB_derivative_control", "GL_ARB_shader_stencil_export"}) {
    EXPECT_TRUE(clraster::oracle::has_gl_extension(name)) << name;
  }
  EXPECT_FALSE(clraster::oracle::has_gl_extension("GL_NOT_AN_EXTENSION"));
}

TEST(GlScene, ShaderBuildErrorsCarryTheInfoLog) {
  try {
    GlProgram(kFullScreenVertex, "#version 450 core\nout vec4 c;\nvoid main() { c = undeclared; }\n", "broken");
    FAIL() << "expected a BuildError";
  } catch (const clraster::BuildError& error) {
    const std::string what = error.what();
    EXPECT_NE(what.find("program 'broken' fragment shader"), std::string::npos) << what;
    EXPECT_NE(error.log().find("undeclared"), std::string::npos) << error.log();
    EXPECT_EQ(what.find('\n'), std::string::npos) << "one line";
  }
}

// GL's blend on a float attachment: rgb = src * ConstantColor + dst * (1 - src alpha) and
// alpha = dst * 1 - src * constant alpha (ReverseSubtract); every product is exact in float.
TEST(GlScene, BlendFactorsAndEquationsFollowGlFormulas) {
  GlTexture color(4, 4, Format::RGBA32F);
  GlFramebuffer target({&color});
  target.clear({0.25f, 0.5f, 0.75f, 1.0f});
  GlProgram program = fragment_program("out vec4 c;", "c = vec4(1.0, 0.5, 0.25, 0.5);");
  GlDrawCall call = full_screen(program);
  call.state.blend[0] = {true,
                         BlendEquation::Add,
                         BlendEquation::ReverseSubtract,
                         BlendFactor::ConstantColor,
                         BlendFactor::OneMinusSrcAlpha,
                         BlendFactor::ConstantAlpha,
                         BlendFactor::One,
                         {true, true, true, true}};
  call.state.blend_color = {0.5f, 0.25f, 0.125f, 0.75f};
  target.draw(call);
  const Vec4 expected = {1.0f * 0.5f + 0.25f * 0.5f, 0.5f * 0.25f + 0.5f * 0.5f, 0.25f * 0.125f + 0.75f * 0.5f,
                         1.0f - 0.5f * 0.75f};
  const std::vector<float> texels = as<float>(color.read());
  for (std::size_t i = 0; i < texels.size(); ++i) ASSERT_EQ(texels[i], expected[i % 4]) << "value " << i;
}

TEST(GlScene, BlendAndWriteMasksArePerAttachment) {
  GlTexture first(2, 2, Format::RGBA8), second(2, 2, Format::RGBA8);
  GlFramebuffer target({&first, &second});
  target.clear({51 / 255.0f, 102 / 255.0f, 153 / 255.0f, 1.0f});
  GlProgram program = fragment_program("layout(location = 0) out vec4 a;\nlayout(location = 1) out vec4 b;",
                                       "a = vec4(51.0, 51.0, 51.0, 0.0) / 255.0; b = a;");
  GlDrawCall call = full_screen(program);
  call.state.blend[0] = clraster::kAdditiveBlend;                 // 51 + 51, 102 + 51, ...
  call.state.blend[1].write_mask = {false, true, false, false};   // replaces green only
  target.draw(call);
  EXPECT_EQ(as<std::uint8_t>(first.read()), (std::vector<std::uint8_t>{102, 153, 204, 255, 102, 153, 204, 255,
                                                                         102, 153, 204, 255, 102, 153, 204, 255}));
  EXPECT_EQ(as<std::uint8_t>(second.read()), (std::vector<std::uint8_t>{51, 51, 153, 255, 51, 51, 153, 255,
                                                                          51, 51, 153, 255, 51, 51, 153, 255}));
}

TEST(GlScene, ProgramBlendAndCompareFunctionsHaveNoGlEquivalent) {
  GlTexture color(2, 2, Format::RGBA8), depth(2, 2, Format::Depth32F);
  GlFramebuffer target({&color}, &depth);
  GlProgram program = fragment_program("out vec4 c;", "c = vec4(1.0);");
  GlDrawCall call = full_screen(program);
  call.state.blend[3] = clraster::kProgramBlend;
  EXPECT_THROW(target.draw(call), InvalidArgument);
  call = full_screen(program);
  call.state.depth_test = true;
  call.state.depth_func = CompareFunc::Program;
  EXPECT_THROW(target.draw(call), InvalidArgument);
}

// Three formats at once, each pixel's values derived from its window position, so the read-back
// also shows that rows run from t = 0 (window y = 0) up.
TEST(GlScene, MultipleRenderTargetsReadBackInClrasterLayout) {
  constexpr int kWidth = 3, kHeight = 2;
  GlTexture normalized(kWidth, kHeight, Format::RGBA8), real(kWidth, kHeight, Format::R32F),
      unsigned_int(kWidth, kHeight, Format::RGBA32UI), half(kWidth, kHeight, Format::RGBA16F);
  GlFramebuffer target({&normalized, &real, &unsigned_int, &half});
  target.clear({0, 0, 0, 0});
  GlProgram program = fragment_program(
      "layout(location = 0) out vec4 a;\nlayout(location = 1) out float b;\n"
      "layout(location = 2) out uvec4 c;\nlayout(location = 3) out vec4 d;",
      "ivec2 p = ivec2(gl_FragCoord.xy);\n"
      "a = vec4(float(p.x) * 51.0, float(p.y) * 51.0, 255.0, 0.0) / 255.0;\n"
      "b = gl_FragCoord.x + 10.0 * gl_FragCoord.y;\n"
      "c = uvec4(p.x, p.y, 7u, 0xffffffffu);\n"
      "d = vec4(1.0, 0.5, -2.0, 0.25);");
  target.draw(full_screen(program));

  const std::vector<std::uint8_t> a = as<std::uint8_t>(normalized.read());
  const std::vector<float> b = as<float>(real.read());
  const std::vector<std::uint32_t> c = as<std::uint32_t>(unsigned_int.read());
  const std::vector<std::uint16_t> d = as<std::uint16_t>(half.read());
  ASSERT_EQ(a.size(), std::size_t(kWidth * kHeight * 4));
  ASSERT_EQ(b.size(), std::size_t(kWidth * kHeight));
  ASSERT_EQ(c.size(), std::size_t(kWidth * kHeight * 4));
  ASSERT_EQ(d.size(), std::size_t(kWidth * kHeight * 4));
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const std::size_t i = std::size_t(y * kWidth + x);
      EXPECT_EQ((std::array{a[i * 4], a[i * 4 + 1], a[i * 4 + 2], a[i * 4 + 3]}),
                (std::array<std::uint8_t, 4>{std::uint8_t(51 * x), std::uint8_t(51 * y), 255, 0}));
      EXPECT_EQ(b[i], (x + 0.5f) + 10.0f * (y + 0.5f));
      EXPECT_EQ((std::array{c[i * 4], c[i * 4 + 1], c[i * 4 + 2], c[i * 4 + 3]}),
                (std::array<std::uint32_t, 4>{std::uint32_t(x), std::uint32_t(y), 7, 0xffffffffu}));
      // Half floats 1.0, 0.5, -2.0 and 0.25.
      EXPECT_EQ((std::array{d[i * 4], d[i * 4 + 1], d[i * 4 + 2], d[i * 4 + 3]}),
                (std::array<std::uint16_t, 4>{0x3c00, 0x3800, 0xc000, 0x3400}));
    }
  }
}

TEST(GlScene, ClearsEachAttachmentByItsKind) {
  GlTexture signed_int(2, 1, Format::R32I), unsigned_int(2, 1, Format::RGBA32UI), depth(2, 1, Format::Depth32FStencil8);
  GlFramebuffer target({&signed_int, &unsigned_int}, &depth);
  target.clear({-1.75f, 2.5f, 0, 0}, 2.0f, 9);  // integers truncated toward zero, depth clamped
  EXPECT_EQ(as<std::int32_t>(signed_int.read()), (std::vector<std::int32_t>{-1, -1}));
  EXPECT_EQ(as<std::uint32_t>(unsigned_int.read()), (std::vector<std::uint32_t>{0, 2, 0, 0, 0, 2, 0, 0}));
  EXPECT_EQ(as<float>(depth.read()), (std::vector<float>{1.0f, 1.0f}));
  EXPECT_EQ(depth.read_stencil(), (std::vector<std::uint8_t>{9, 9}));

  target.clear_color_int(0, {-7, 0, 0, 0});
  target.clear_color_uint(1, {1, 2, 3, 0xffffffffu});
  target.clear_depth(0.25f);
  target.clear_stencil(200);
  EXPECT_EQ(as<std::int32_t>(signed_int.read()), (std::vector<std::int32_t>{-7, -7}));
  EXPECT_EQ(as<std::uint32_t>(unsigned_int.read()),
            (std::vector<std::uint32_t>{1, 2, 3, 0xffffffffu, 1, 2, 3, 0xffffffffu}));
  EXPECT_EQ(as<float>(depth.read()), (std::vector<float>{0.25f, 0.25f}));
  EXPECT_EQ(depth.read_stencil(), (std::vector<std::uint8_t>{200, 200}));

  EXPECT_THROW(target.clear_color_uint(0, {1, 1, 1, 1}), InvalidArgument);
  EXPECT_THROW(target.clear_color_int(1, {1, 1, 1, 1}), InvalidArgument);
  GlTexture depth_only(2, 1, Format::Depth32F);
  GlFramebuffer no_stencil({}, &depth_only);
  EXPECT_THROW(no_stencil.clear_stencil(1), InvalidArgument);
}

// Linear values go in, sRGB-encoded bytes are stored: linear 0.25 is 0.5371 encoded, byte 137
// (136.94). llvmpipe encodes fragment outputs approximately (linear 0.5, 187.52 encoded, gives 187), so
// the values keep away from rounding ties.
TEST(GlScene, SrgbAttachmentsStoreEncodedValues) {
  GlTexture color(1, 1, Format::SRGB8_A8);
  GlFramebuffer target({&color});
  target.clear({0.25f, 0.0f, 1.0f, 0.2f});  // alpha is linear in sRGB formats
  EXPECT_EQ(as<std::uint8_t>(color.read()), (std::vector<std::uint8_t>{137, 0, 255, 51}));
  GlProgram program = fragment_program("out vec4 c;", "c = vec4(1.0, 0.25, 0.0, 0.8);");
  target.draw(full_screen(program));
  EXPECT_EQ(as<std::uint8_t>(color.read()), (std::vector<std::uint8_t>{255, 137, 0, 204}));
}

TEST(GlScene, DepthStencilTexelsRoundTripInClrasterPlanes) {
  const std::vector<float> depth = {0.0f, 0.25f, 0.5f, 1.0f};
  const std::vector<std::uint8_t> stencil = {1, 2, 128, 255};
  std::vector<std::byte> planes(bytes(depth).begin(), bytes(depth).end());
  planes.insert(planes.end(), bytes(stencil).begin(), bytes(stencil).end());
  GlTexture texture(2, 2, Format::Depth32FStencil8, planes, /*mipmaps=*/false);
  EXPECT_EQ(as<float>(texture.read()), depth);
  EXPECT_EQ(texture.read_stencil(), stencil);
  EXPECT_THROW(texture.upload(0, bytes(depth)), InvalidArgument);  // the stencil plane is missing
}

// Three quads drawn with stencil op Increment: the left half, the bottom half, then everything, so
// the quadrants count 1 to 3 overlaps. Then only pixels counting exactly 2 pass an Equal 2 test.
TEST(GlScene, StencilCountsOverlapsAndGatesLaterDraws) {
  GlTexture color(4, 4, Format::R8), depth(4, 4, Format::Depth32FStencil8);
  GlFramebuffer target({&color}, &depth);
  target.clear({0, 0, 0, 0});
  GlProgram program(R"(#version 450 core
in vec2 position;
uniform vec4 rect;  // x0, y0, x1, y1 in NDC
void main() { gl_Position = vec4(mix(rect.xy, rect.zw, position), 0.0, 1.0); }
)",
                    "#version 450 core\nout vec4 c;\nvoid main() { c = vec4(1.0); }\n");
  const std::vector<float> unit_square = {0, 0, 1, 0, 0, 1, 1, 1};  // a strip
  GlDrawCall call{&program};
  call.attributes = {{"position", bytes(unit_square), AttributeType::Float2}};
  call.state.topology = clraster::Topology::TriangleStrip;
  call.state.depth_test = false;
  call.state.stencil_test = true;
  call.state.stencil_front.depth_pass = StencilOp::Increment;
  call.state.stencil_back.depth_pass = StencilOp::Increment;
  call.state.blend[0].write_mask = {false, false, false, false};
  for (const Vec4& rect : {Vec4{-1, -1, 0, 1}, Vec4{-1, -1, 1, 0}, Vec4{-1, -1, 1, 1}}) {
    program.set("rect", rect);
    target.draw(call);
  }
  // Rows from window y = 0: the bottom-left quadrant is in all three quads.
  const std::vector<std::uint8_t> expected = {3, 3, 2, 2, 3, 3, 2, 2, 2, 2, 1, 1, 2, 2, 1, 1};
  EXPECT_EQ(depth.read_stencil(), expected);

  call.state.stencil_front = {CompareFunc::Equal, 2, 0xff, 0xff, StencilOp::Keep, StencilOp::Keep, StencilOp::Keep};
  call.state.blend[0].write_mask = {true, true, true, true};
  target.draw(call);  // the whole screen, once more
  const std::vector<std::uint8_t> drawn = as<std::uint8_t>(color.read());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(drawn[i], expected[i] == 2 ? 255 : 0) << i;
}

// Front and back faces keep separate stencil state: a clockwise (back-facing) triangle pair replaces
// with its reference where the counter-clockwise one inverts.
TEST(GlScene, StencilStateIsSeparateForFrontAndBackFaces) {
  GlTexture depth(2, 1, Format::Depth32FStencil8);
  GlFramebuffer target({}, &depth);
  target.clear({0, 0, 0, 0}, 1.0f, 0x0f);
  GlProgram program(kFullScreenVertex, "#version 450 core\nvoid main() {}\n");
  // Left pixel: a counter-clockwise quad; right pixel: the same quad wound clockwise.
  const std::vector<float> quads = {-1, -1, 0, -1, 0, 1, -1, -1, 0, 1, -1, 1,
                                    0, -1, 1, 1, 1, -1, 0, -1, 0, 1, 1, 1};
  GlDrawCall call{&program};
  call.attributes = {{"position", bytes(quads), AttributeType::Float2}};
  call.state.depth_test = false;
  call.state.stencil_test = true;
  call.state.stencil_front.depth_pass = StencilOp::Invert;
  call.state.stencil_back = {CompareFunc::Always, 77, 0xff, 0xff, StencilOp::Keep, StencilOp::Keep, StencilOp::Replace};
  target.draw(call);
  EXPECT_EQ(depth.read_stencil(), (std::vector<std::uint8_t>{0xf0, 77}));
}

// ARB_shader_stencil_export: the fragment's own reference replaces the stencil value.
TEST(GlScene, ShadersExportStencilReferences) {
  GlTexture depth(3, 1, Format::Depth32FStencil8);
  GlFramebuffer target({}, &depth);
  target.clear({0, 0, 0, 0});
  GlProgram program = fragment_program("#extension GL_ARB_shader_stencil_export : require",
                                       "gl_FragStencilRefARB = 7 + int(gl_FragCoord.x);");
  GlDrawCall call = full_screen(program);
  call.state.stencil_test = true;
  call.state.stencil_front.depth_pass = StencilOp::Replace;
  target.draw(call);
  EXPECT_EQ(depth.read_stencil(), (std::vector<std::uint8_t>{7, 8, 9}));
}

// A 2x2 texture drawn onto a 2x2 framebuffer: every pixel centre samples its texel's centre, so
// nearest and linear filtering both return the texels exactly.
TEST(GlScene, SamplingAtTexelCentresReturnsTheTexels) {
  const std::vector<std::uint8_t> texels = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 10, 20, 30, 40};
  const GlTexture texture(2, 2, Format::RGBA8, bytes(texels), /*mipmaps=*/false);
  for (clraster::Filter filter : {clraster::Filter::Nearest, clraster::Filter::Linear}) {
    GlTexture color(2, 2, Format::RGBA8);
    GlFramebuffer target({&color});
    GlProgram program = fragment_program("uniform sampler2D image;\nout vec4 c;",
                                         "c = texture(image, gl_FragCoord.xy / 2.0);");
    program.set_texture("image", texture, Sampler{filter, filter, clraster::MipFilter::None});
    target.draw(full_screen(program));
    EXPECT_EQ(as<std::uint8_t>(color.read()), texels);
  }
}

// Texture coordinate s on a 2x1 texture of texels 10 and 20, sampled with nearest filtering.
TEST(GlScene, WrapModesMapCoordinatesOutsideTheTexture) {
  const std::vector<float> texels = {10, 20};
  const GlTexture texture(2, 1, Format::R32F, bytes(texels), /*mipmaps=*/false);
  GlTexture color(1, 1, Format::R32F);
  GlFramebuffer target({&color});
  GlProgram program = fragment_program("uniform sampler2D image;\nuniform float s;\nout float c;",
                                       "c = texture(image, vec2(s, 0.5)).r;");
  auto sample = [&](clraster::Wrap wrap, float s) {
    program.set("s", s).set_texture("image", texture, Sampler{clraster::Filter::Nearest, clraster::Filter::Nearest,
                                                              clraster::MipFilter::None, wrap, wrap});
    target.draw(full_screen(program));
    return as<float>(color.read())[0];
  };
  using clraster::Wrap;
  EXPECT_EQ(sample(Wrap::Repeat, 1.25f), 10);          // 0.25
  EXPECT_EQ(sample(Wrap::MirroredRepeat, 1.25f), 20);  // 0.75
  EXPECT_EQ(sample(Wrap::MirroredRepeat, -0.25f), 10); // 0.25
  EXPECT_EQ(sample(Wrap::ClampToEdge, 1.25f), 20);
  EXPECT_EQ(sample(Wrap::ClampToEdge, -0.25f), 10);
}

// A 4x4 texture whose level l holds the value l, stretched over one pixel: the level of detail is
// log2(4) = 2, then moved by the sampler's bias and limits.
TEST(GlScene, SamplerLevelOfDetailStateSelectsMipLevels) {
  GlTexture texture(4, 4, Format::R32F, clraster::kFullMipChain);
  ASSERT_EQ(texture.levels(), 3);
  for (int level = 0; level < 3; ++level) {
    texture.upload(level, bytes(std::vector<float>(std::size_t(texture.width(level) * texture.height(level)),
                                                   float(level))));
  }
  GlTexture color(1, 1, Format::R32F);
  GlFramebuffer target({&color});
  GlProgram program = fragment_program("uniform sampler2D image;\nout float c;",
                                       "c = texture(image, gl_FragCoord.xy).r;");
  auto level_sampled = [&](Sampler sampler) {
    sampler.min_filter = sampler.mag_filter = clraster::Filter::Nearest;
    program.set_texture("image", texture, sampler);
    target.draw(full_screen(program));
    return as<float>(color.read())[0];
  };
  using clraster::MipFilter;
  EXPECT_EQ(level_sampled({.mip_filter = MipFilter::Nearest}), 2);
  EXPECT_EQ(level_sampled({.mip_filter = MipFilter::None}), 0);
  EXPECT_EQ(level_sampled({.mip_filter = MipFilter::Nearest, .lod_bias = -1.0f}), 1);
  EXPECT_EQ(level_sampled({.mip_filter = MipFilter::Nearest, .lod_bias = -0.25f}), 2);  // the nearer level
  EXPECT_EQ(level_sampled({.mip_filter = MipFilter::Nearest, .max_lod = 1.0f}), 1);
  EXPECT_EQ(level_sampled({.mip_filter = MipFilter::Nearest, .lod_bias = -2.0f, .min_lod = 1.0f}), 1);
  EXPECT_EQ(level_sampled({.mip_filter = MipFilter::Linear, .lod_bias = -0.5f}), 1.5f);
}

// glGenerateMipmap's 2x2 box filter, on values whose mean is exact.
TEST(GlScene, GeneratedMipmapsAverageTheLevelAbove) {
  const std::vector<std::uint8_t> texels = {0, 40, 200, 255, 100, 40, 0, 255, 200, 40, 100, 255, 100, 40, 100, 255};
  const GlTexture texture(2, 2, Format::RGBA8, bytes(texels));
  ASSERT_EQ(texture.levels(), 2);
  EXPECT_EQ(as<std::uint8_t>(texture.read(1)), (std::vector<std::uint8_t>{100, 40, 100, 255}));
  EXPECT_THROW(GlTexture(2, 2, Format::R32I, bytes(std::vector<std::int32_t>(4))), InvalidArgument);
}

// Integer textures are read with texel fetches (and given nearest filters whatever the sampler says,
// which GL needs to call them complete); depth textures sample as their depth in .r.
TEST(GlScene, IntegerAndDepthTexturesAreSampled) {
  const std::vector<std::int32_t> integers = {-5, 6, 7, -8};
  const std::vector<float> depths = {0.125f, 0.25f, 0.5f, 0.75f};
  const GlTexture integer(2, 2, Format::R32I, bytes(integers), /*mipmaps=*/false);
  const GlTexture depth(2, 2, Format::Depth32F, bytes(depths), /*mipmaps=*/false);
  GlTexture out_integer(2, 2, Format::R32I), out_depth(2, 2, Format::R32F);
  GlFramebuffer target({&out_integer, &out_depth});
  GlProgram program = fragment_program(
      "uniform isampler2D integers;\nuniform sampler2D depths;\n"
      "layout(location = 0) out int i;\nlayout(location = 1) out float d;",
      "i = texelFetch(integers, ivec2(gl_FragCoord.xy), 0).r;\n"
      "d = texture(depths, gl_FragCoord.xy / 2.0).r;");
  program.set_texture("integers", integer);
  program.set_texture("depths", depth, Sampler{.mip_filter = clraster::MipFilter::None});
  EXPECT_THROW(program.set_texture("depths", integer), InvalidArgument);  // isampler2D texture to a sampler2D
  target.draw(full_screen(program));
  EXPECT_EQ(as<std::int32_t>(out_integer.read()), integers);
  EXPECT_EQ(as<float>(out_depth.read()), depths);
}

// Pass 1 renders into a texture that pass 2 samples.
TEST(GlScene, ATextureRenderedInOnePassIsSampledInTheNext) {
  GlTexture intermediate(4, 2, Format::R32F);
  GlFramebuffer first_pass({&intermediate});
  GlProgram pattern = fragment_program("out float c;", "c = gl_FragCoord.x * gl_FragCoord.y;");
  first_pass.draw(full_screen(pattern));

  GlTexture result(4, 2, Format::RG32F);
  GlFramebuffer second_pass({&result});
  GlProgram doubled = fragment_program("uniform sampler2D previous;\nout vec2 c;",
                                       "float v = texelFetch(previous, ivec2(gl_FragCoord.xy), 0).r;\n"
                                       "c = vec2(v, 2.0 * v);");
  doubled.set_texture("previous", intermediate);
  second_pass.draw(full_screen(doubled));
  const std::vector<float> values = as<float>(result.read());
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < 4; ++x) {
      const float v = (x + 0.5f) * (y + 0.5f);
      EXPECT_EQ(values[std::size_t(y * 4 + x) * 2], v);
      EXPECT_EQ(values[std::size_t(y * 4 + x) * 2 + 1], 2 * v);
    }
  }
}

// float, vecN, int, uint, mat4 and arrays (whole, and from an element on) reach the shader.
TEST(GlScene, UniformsOfEveryKindAreSetByName) {
  GlTexture color(1, 1, Format::RGBA32F);
  GlFramebuffer target({&color});
  GlProgram program = fragment_program(
      "uniform float f;\nuniform vec3 v;\nuniform int i;\nuniform uvec2 u;\nuniform mat4 m;\n"
      "uniform float w[4];\nout vec4 c;",
      "c = m * vec4(v, 1.0) + vec4(f, float(i), float(u.x + u.y), w[0] + w[1] + w[2] + w[3]);");
  const clraster::Mat4 translate = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 10, 20, 30, 1};  // column-major
  program.set("f", 0.5f).set("v", std::array{1.0f, 2.0f, 3.0f}).set("i", std::int32_t{-4});
  program.set("u", std::array<std::uint32_t, 2>{5, 6}).set("m", translate);
  program.set("w", std::vector<float>{1, 2, 4, 8}).set("w", std::vector<float>{16, 32}, 2);
  target.draw(full_screen(program));
  EXPECT_EQ(as<float>(color.read()), (std::vector<float>{11.5f, 18.0f, 44.0f, 1 + 1 + 2 + 16 + 32}));

  EXPECT_THROW(program.set("f", std::int32_t{1}), InvalidArgument);             // float set from an int
  EXPECT_THROW(program.set("v", std::array{1.0f, 2.0f}), InvalidArgument);     // not a whole vec3
  EXPECT_THROW(program.set("w", std::vector<float>{1, 2}, 3), InvalidArgument);  // past the end
  EXPECT_THROW(program.set("missing", 1.0f), InvalidArgument);
}

TEST(GlScene, DrawsRefuseUnsetUniformsAndMismatchedAttributes) {
  GlTexture color(1, 1, Format::RGBA8);
  GlFramebuffer target({&color});
  GlProgram program = fragment_program("uniform vec4 tint;\nout vec4 c;", "c = tint;");
  EXPECT_THROW(target.draw(full_screen(program)), InvalidArgument);  // tint never set
  program.set("tint", Vec4{1, 1, 1, 1});
  target.draw(full_screen(program));

  GlDrawCall call = full_screen(program);
  call.attributes[0].type = AttributeType::Int2;  // a vec2 fed from integers
  EXPECT_THROW(target.draw(call), InvalidArgument);
  call = full_screen(program);
  call.attributes.push_back({"unused", bytes(kFullScreen), AttributeType::Float2});
  EXPECT_THROW(target.draw(call), InvalidArgument);
  call = full_screen(program);
  call.attributes.clear();
  call.count = 3;
  EXPECT_THROW(target.draw(call), InvalidArgument);  // "position" has no data
  call = full_screen(program);
  call.count = 4;  // three vertices only
  EXPECT_THROW(target.draw(call), InvalidArgument);
  call = full_screen(program);
  call.indices = std::vector<std::uint32_t>{0, 1, 3};
  EXPECT_THROW(target.draw(call), InvalidArgument);  // vertex 3 does not exist
}

// Instance k draws the unit quad into pixel column k of a 4x1 picture, with value value + tag.
constexpr const char* kTaggedQuadVertex = R"(#version 450 core
in vec2 corner;
in int tag;
in uint value;
flat out uint result;
void main() {
  gl_Position = vec4((corner.x + float(gl_InstanceID)) / 2.0 - 1.0, corner.y * 2.0 - 1.0, 0.0, 1.0);
  result = value + uint(tag);
}
)";
constexpr const char* kTaggedQuadFragment = "#version 450 core\nflat in uint result;\nout uint c;\nvoid main() { c = result; }\n";

struct TaggedVertex {
  float x, y;
  std::int32_t tag;
};
const std::vector<TaggedVertex> kTaggedQuad = {{0, 0, 5}, {1, 0, 5}, {1, 1, 5}, {0, 1, 5}};
const std::vector<std::uint32_t> kInstanceValues = {10, 20, 30, 40};

// Interleaved per-vertex data (a float2 position and an int, 12-byte stride) and a per-instance uint.
std::vector<GlAttribute> tagged_quad_attributes() {
  const auto data = bytes(kTaggedQuad);
  return {{"corner", data, AttributeType::Float2, 0, sizeof(TaggedVertex)},
          {"tag", data, AttributeType::Int, offsetof(TaggedVertex, tag), sizeof(TaggedVertex)},
          {"value", bytes(kInstanceValues), AttributeType::UInt, 0, 0, /*per_instance=*/true}};
}

// Interleaved attributes, 16-bit indices and instancing: instance k draws the unit quad into pixel
// column k with value 10 * (k + 1) + the vertices' tag.
TEST(GlScene, InterleavedInstancedIndexedAttributes) {
  const std::vector<std::uint16_t> indices = {9, 9, 9, 0, 1, 2, 0, 2, 3};  // the draw starts at index 3
  GlTexture color(4, 1, Format::R32UI);
  GlFramebuffer target({&color});
  GlProgram program(kTaggedQuadVertex, kTaggedQuadFragment);
  GlDrawCall call{&program};
  call.attributes = tagged_quad_attributes();
  call.indices = indices;
  call.first = 3;
  call.instance_count = 3;
  call.state.depth_test = false;
  target.clear({0, 0, 0, 0});
  target.draw(call);
  EXPECT_EQ(as<std::uint32_t>(color.read()), (std::vector<std::uint32_t>{15, 25, 35, 0}));
  call.instance_count = 5;  // more instances than per-instance values
  EXPECT_THROW(target.draw(call), InvalidArgument);
}

// The same quads from a vertex input uploaded once, a triangle per draw; its indices are checked
// at once, and it draws with its own program only.
TEST(GlScene, AVertexInputUploadedOnceDrawsRangesOfIt) {
  const std::vector<std::uint16_t> indices = {0, 1, 2, 0, 2, 3};
  GlTexture color(4, 1, Format::R32UI);
  GlFramebuffer target({&color});
  GlProgram program(kTaggedQuadVertex, kTaggedQuadFragment);
  const GlVertexInput input(program, tagged_quad_attributes(), indices);
  GlDrawCall call{&program};
  call.vertex_input = &input;
  call.count = 3;
  call.instance_count = 3;
  call.state.depth_test = false;
  target.clear({0, 0, 0, 0});
  target.draw(call);
  call.first = 3;
  target.draw(call);
  EXPECT_EQ(as<std::uint32_t>(color.read()), (std::vector<std::uint32_t>{15, 25, 35, 0}));

  call.first = 4;  // past the indices
  EXPECT_THROW(target.draw(call), InvalidArgument);
  call.first = 0;
  call.instance_count = 5;  // more instances than per-instance values
  EXPECT_THROW(target.draw(call), InvalidArgument);
  call.instance_count = 1;
  call.indices = indices;  // data of its own besides the input
  EXPECT_THROW(target.draw(call), InvalidArgument);
  call.indices = {};
  const GlProgram other(kTaggedQuadVertex, kTaggedQuadFragment);
  call.program = &other;
  EXPECT_THROW(target.draw(call), InvalidArgument);
  const std::vector<std::uint16_t> past_the_vertices = {0, 1, 4};
  EXPECT_THROW(GlVertexInput(program, tagged_quad_attributes(), past_the_vertices), InvalidArgument);
}

// KHR_blend_equation_advanced with opaque colours: multiply gives src * dst, screen src + dst -
// src * dst; the second multiply sees the first one's result.
TEST(GlScene, AdvancedBlendEquationsCombineKnownColours) {
  GlTexture color(2, 2, Format::RGBA32F);
  GlFramebuffer target({&color});
  GlProgram program = fragment_program(
      "#extension GL_KHR_blend_equation_advanced : require\nlayout(blend_support_all_equations) out;\n"
      "layout(location = 0) out vec4 c;\nuniform vec4 source;",
      "c = source;");
  program.set("source", Vec4{0.5f, 0.5f, 0.25f, 1.0f});
  GlDrawCall call = full_screen(program);
  auto blended = [&](AdvancedBlend equation) {
    call.advanced_blend = equation;
    target.draw(call);
    const std::vector<float> values = as<float>(color.read());
    return std::vector<float>(values.begin(), values.begin() + 4);
  };
  target.clear({0.5f, 0.25f, 1.0f, 1.0f});
  EXPECT_EQ(blended(AdvancedBlend::Multiply), (std::vector<float>{0.25f, 0.125f, 0.25f, 1.0f}));
  EXPECT_EQ(blended(AdvancedBlend::Multiply), (std::vector<float>{0.125f, 0.0625f, 0.0625f, 1.0f}));
  target.clear({0.5f, 0.25f, 1.0f, 1.0f});
  EXPECT_EQ(blended(AdvancedBlend::Screen), (std::vector<float>{0.75f, 0.625f, 1.0f, 1.0f}));

  GlTexture second(2, 2, Format::RGBA32F);
  GlFramebuffer two_targets({&color, &second});
  call.advanced_blend = AdvancedBlend::Multiply;
  EXPECT_THROW(two_targets.draw(call), InvalidArgument);  // GL allows one colour attachment only
}

// EXT_shader_framebuffer_fetch: inout outputs start as their attachments' values, float or integer.
TEST(GlScene, FramebufferFetchReadsTheAttachments) {
  GlTexture color(2, 2, Format::RGBA32F), counter(2, 2, Format::R32I);
  GlFramebuffer target({&color, &counter});
  target.clear({0.5f, 1.0f, 0.0f, 0.25f});
  target.clear_color_int(1, {-7, 0, 0, 0});
  GlProgram program = fragment_program(
      "#extension GL_EXT_shader_framebuffer_fetch : require\n"
      "layout(location = 0) inout vec4 c;\nlayout(location = 1) inout int n;",
      "c = c * 0.5 + vec4(0.25);\nn += 3;");
  target.draw(full_screen(program));
  target.draw(full_screen(program));
  const std::vector<float> values = as<float>(color.read());
  EXPECT_EQ(std::vector<float>(values.begin(), values.begin() + 4),
            (std::vector<float>{0.5f, 0.625f, 0.375f, 0.4375f}));
  EXPECT_EQ(as<std::int32_t>(counter.read()), (std::vector<std::int32_t>{-1, -1, -1, -1}));
}

// The derivatives of 3x + 5y (window coordinates) are its slopes, fine or coarse.
TEST(GlScene, DerivativesOfALinearFunctionAreItsSlopes) {
  GlTexture fine(4, 4, Format::RG32F), coarse(4, 4, Format::RG32F);
  GlFramebuffer target({&fine, &coarse});
  GlProgram program = fragment_program(
      "layout(location = 0) out vec2 f;\nlayout(location = 1) out vec2 c;",
      "float v = 3.0 * gl_FragCoord.x + 5.0 * gl_FragCoord.y;\n"
      "f = vec2(dFdxFine(v), dFdyFine(v));\n"
      "c = vec2(dFdxCoarse(v), dFdyCoarse(v));");
  target.draw(full_screen(program));
  for (const GlTexture* texture : {&fine, &coarse}) {
    const std::vector<float> values = as<float>(texture->read());
    for (std::size_t i = 0; i < values.size(); i += 2) {
      ASSERT_EQ(values[i], 3.0f) << "pixel " << i / 2;
      ASSERT_EQ(values[i + 1], 5.0f) << "pixel " << i / 2;
    }
  }
}

TEST(GlScene, RejectsBadTexturesAndFramebuffers) {
  EXPECT_THROW(GlTexture(0, 4, Format::RGBA8), InvalidArgument);
  EXPECT_THROW(GlTexture(4, 4, Format::RGBA8, 4), InvalidArgument);  // a 4x4 chain has 3 levels
  EXPECT_THROW(GlTexture(4, 4, Format::Depth32FStencil8, 2), InvalidArgument);
  EXPECT_THROW(GlTexture(2, 2, Format::RGBA8, bytes(std::vector<std::uint8_t>(15)), false), InvalidArgument);
  GlTexture small(2, 2, Format::RGBA8), large(4, 4, Format::RGBA8), depth(2, 2, Format::Depth32F);
  EXPECT_THROW(GlFramebuffer({&small, &large}), InvalidArgument);  // sizes differ
  EXPECT_THROW(GlFramebuffer({&depth}), InvalidArgument);          // depth as colour
  EXPECT_THROW(GlFramebuffer({&small}, &large), InvalidArgument);
  EXPECT_THROW(GlFramebuffer({}, nullptr), InvalidArgument);
  EXPECT_THROW(small.read_stencil(), InvalidArgument);
}

}  // namespace
