// One scene drawn with a user program on clraster (OpenCL C) and with the equivalent GLSL program on
// the OpenGL oracle, from the same vertex data, uniforms, textures and state, into attachments of
// the same formats, so that a test compares what the two renderers stored texel for texel.
//
//   ProgramPair program(clraster_source, glsl_vertex, glsl_fragment);
//   program.set("mvp", mvp).set_texture("image", texture, sampler);
//   FramebufferPair target(64, 64, {Format::RGBA32F}, Format::Depth32F);
//   target.clear({0, 0, 0, 1});
//   target.draw(program, {.attributes = {{"position", AttributeType::Float3, positions}}});
//   EXPECT_TRUE(texels_match(target.color(0), {.tolerance = 2.0 / 255}));
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "clraster/clraster.hpp"
#include "oracle/gl_scene.hpp"

namespace clraster::test {

// The same texture on both renderers: one size, format and level count, and every level uploaded to
// both, so a test compares sampling and not how the levels were made.
struct TexturePair {
  TexturePair(int width, int height, Format format, int levels = 1);
  // Level 0 from `level0` and the rest from clraster's generate_mipmaps, read back and uploaded to
  // the oracle level by level.
  static TexturePair with_clraster_mipmaps(int width, int height, Format format, std::span<const std::byte> level0);

  void upload(int level, std::span<const std::byte> texels);  // to both

  Texture clr;
  oracle::GlTexture gl;
};

// A program in OpenCL C for clraster and in GLSL ("#version 450 core" sources) for the oracle, and
// the values bound to both under the same names.
class ProgramPair {
 public:
  ProgramPair(const std::string& clraster_source, const std::string& glsl_vertex, const std::string& glsl_fragment,
              const std::string& name = "program.cl");

  // A float uniform (float to float4, or a float16 / mat4 as 16 column-major floats).
  ProgramPair& set(const std::string& name, std::span<const float> values);
  ProgramPair& set(const std::string& name, float value) { return set(name, std::span(&value, 1)); }
  template <std::size_t N>
  ProgramPair& set(const std::string& name, const std::array<float, N>& values) {
    return set(name, std::span<const float>(values));
  }
  // The pair's textures must outlive the draws.
  ProgramPair& set_texture(const std::string& name, const TexturePair& texture, const Sampler& sampler);

  const Program& program() const { return program_; }
  const Bindings& bindings() const { return bindings_; }
  const oracle::GlProgram& gl() const { return gl_; }

 private:
  Program program_;
  Bindings bindings_;
  oracle::GlProgram gl_;
};

// A per-vertex attribute of float components, from host memory.
struct SceneAttribute {
  std::string name;
  AttributeType type = AttributeType::Float3;  // Float .. Float4
  std::vector<float> values;
};

// One draw of a ProgramPair. `state` is clraster's; the oracle draws with `gl_state` where the two
// must differ (a CompareFunc::Program or BlendEquation::Program has no GL state: the GL side
// expresses it in its program, with `gl_advanced_blend`, or with the equivalent standard function).
struct ProgramDraw {
  std::vector<SceneAttribute> attributes;
  std::vector<std::uint32_t> indices;  // empty: non-indexed
  DrawState state{};
  std::optional<DrawState> gl_state;
  std::optional<oracle::AdvancedBlend> gl_advanced_blend;
};

// Colour attachments (and optionally a depth or depth-stencil attachment) of one size on both.
class FramebufferPair {
 public:
  FramebufferPair(int width, int height, const std::vector<Format>& colors,
                  std::optional<Format> depth_stencil = std::nullopt);

  int width() const { return width_; }
  int height() const { return height_; }
  TexturePair& color(int index) { return *colors_[static_cast<std::size_t>(index)]; }
  TexturePair* depth_stencil() { return depth_stencil_.get(); }

  void clear(std::array<float, 4> color, float depth = 1.0f, std::uint8_t stencil = 0);
  void clear_depth(float depth);
  void draw(const ProgramPair& program, const ProgramDraw& draw);

 private:
  int width_;
  int height_;
  std::vector<std::unique_ptr<TexturePair>> colors_;
  std::unique_ptr<TexturePair> depth_stencil_;
  Framebuffer clraster_;
  oracle::GlFramebuffer gl_;
};

// Texels in a format's stored values as floats, `channels` a texel: normalized formats as stored
// bytes / 255 (sRGB ones still encoded), float formats as stored (half floats widened).
std::vector<float> stored_values(Format format, std::span<const std::byte> texels);

// Bytes of `values` (channels per texel of the format, in [0, 1] for normalized formats) in the
// format's layout: normalized formats rounded to bytes, RGBA16F to the nearest half float.
std::vector<std::byte> encode_texels(Format format, std::span<const float> values);

// How far a level of a TexturePair on clraster is from the same level on GL, in stored values.
struct TexelDifference {
  std::uint64_t texels = 0;
  std::uint64_t texels_beyond = 0;  // some channel differs by more than the tolerance
  double max_difference = 0;        // largest channel difference
  double mean_difference = 0;       // over all channels
  double fraction_within() const { return texels ? 1.0 - double(texels_beyond) / double(texels) : 1.0; }
  std::string summary() const;      // one line, for reports
};
TexelDifference compare_texels(Format format, std::span<const std::byte> result, std::span<const std::byte> reference,
                               double tolerance);

struct TexelTolerance {
  double tolerance = 0;          // largest channel difference that counts as equal, in stored values
  double min_fraction = 1.0;     // of texels that must be within it
  int level = 0;
};
// Level `level` of the pair equal within the tolerance. On failure writes
// <test-output>/<test name>/{reference,result,diff}.png (GL, clraster, and where they differ) and
// fails with the numbers; on success records them as the test's "texels" property.
::testing::AssertionResult texels_match(const TexturePair& pair, const TexelTolerance& tolerance);
// Whether the GL side of level 0 holds more than one value: a comparison of a picture that nothing
// was drawn into, both sides the clear value, would prove nothing.
::testing::AssertionResult drawn(const TexturePair& pair);

}  // namespace clraster::test
