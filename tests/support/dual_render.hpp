// One scene rendered twice: by clraster, with a program in OpenCL C, and by the OpenGL oracle
// (Mesa's llvmpipe), with the equivalent GLSL program, from the same data and the same DrawState;
// then every attachment of one compared with the other's, texel by texel.
//
//   DualProgram program(opencl_source, vertex_glsl, fragment_glsl, "grid");
//   program.set("scale", 0.5f);                                   // sets both programs' uniform
//   DualBuffer vertices(interleaved_floats);
//   DualFramebuffer target(64, 64, {Format::RGBA8, Format::R32F});  // plus a Depth32FStencil8
//   target.clear({0, 0, 0, 1});
//   DualDraw draw{&program};
//   draw.attributes = {{"position", &vertices, AttributeType::Float2, 0, 24},
//                      {"color", &vertices, AttributeType::Float4, 8, 24}};
//   draw.state.blend[0] = ...;
//   target.draw(draw);
//   EXPECT_TRUE(target.matches());
//
// Comparisons are exact unless a test asks for a tolerance, and say which attachment differs,
// where and with which values, and leave result, reference and diff pictures in
// output_directory() (float and depth values clamped to [0, 1], integers as their low byte).
#pragma once

#include "oracle/gl_scene.hpp"
#include "support/test_support.hpp"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <vector>

namespace clraster::test {

template <typename T>
std::vector<std::byte> to_bytes(const std::vector<T>& values) {
  const std::span<const std::byte> bytes = std::as_bytes(std::span<const T>(values));
  return {bytes.begin(), bytes.end()};
}

// A texture in both renderers, of the same size and format, zero-filled.
struct DualTexture {
  DualTexture(int width, int height, Format format);

  Texture clraster;
  oracle::GlTexture gl;
};

// Vertex data: clraster's device buffer and the host copy the oracle draws from.
struct DualBuffer {
  explicit DualBuffer(std::vector<std::byte> bytes);
  template <typename T>
  explicit DualBuffer(const std::vector<T>& values) : DualBuffer(to_bytes(values)) {}

  std::vector<std::byte> host;
  Buffer device;
};

// A program in OpenCL C for clraster and the same program in GLSL ("#version 450 core" sources)
// for the oracle, with their uniforms and textures set alike. Setters take the value in the GLSL
// type's components (a float4 uniform takes 4 floats, a float16 a column-major matrix, an array of
// N float4 4 * N floats); clraster's layout pads only 3-vectors in arrays, which tests avoid.
class DualProgram {
 public:
  DualProgram(const std::string& opencl, const std::string& vertex_glsl, const std::string& fragment_glsl,
              const std::string& name);
  DualProgram(const DualProgram&) = delete;  // bindings refer to the program
  DualProgram& operator=(const DualProgram&) = delete;

  DualProgram& set(const std::string& name, float value);
  DualProgram& set(const std::string& name, std::int32_t value);
  DualProgram& set(const std::string& name, std::span<const float> values);
  template <std::size_t N>
  DualProgram& set(const std::string& name, const std::array<float, N>& values) {
    return set(name, std::span<const float>(values));
  }
  DualProgram& set_texture(const std::string& name, const DualTexture& texture, const Sampler& sampler);

  Program clraster;
  Bindings bindings;
  oracle::GlProgram gl;
};

// An attribute as clraster::VertexAttribute, from a DualBuffer.
struct DualAttribute {
  std::string name;
  const DualBuffer* buffer = nullptr;
  AttributeType type = AttributeType::Float4;
  std::size_t offset = 0;
  std::size_t stride = 0;  // 0: tightly packed
  bool per_instance = false;
};

// One draw, as clraster::DrawCall (indices: empty for a non-indexed draw).
struct DualDraw {
  const DualProgram* program = nullptr;
  std::vector<DualAttribute> attributes;
  std::vector<std::uint32_t> indices;
  std::uint32_t first = 0;
  std::uint32_t count = kAllElements;
  std::uint32_t instance_count = 1;
  DrawState state{};
};

// How far clraster's texels may be from the oracle's.
struct TexelTolerance {
  int unorm8 = 0;         // in steps of 1/255, for R8, RG8 and RGBA8 texels
  float absolute = 0.0f;  // for float, half and depth texels
};

// What a test drew at window pixel (x, y), for failure messages: e.g. which blend factors.
using PixelNamer = std::function<std::string(int x, int y)>;

// A framebuffer in each renderer over the same attachments: colour and depth-stencil textures the
// caller owns (DualTexture), or ones the framebuffer makes and owns.
class DualFramebuffer {
 public:
  DualFramebuffer(std::vector<DualTexture*> colors, DualTexture* depth_stencil);
  // Owns a colour texture per format and, unless depth_stencil is false, a Depth32FStencil8 one.
  DualFramebuffer(int width, int height, const std::vector<Format>& colors, bool depth_stencil = true);

  int width() const { return clraster_.width(); }
  int height() const { return clraster_.height(); }
  DualTexture& color(int index) { return *colors_[static_cast<std::size_t>(index)]; }
  DualTexture* depth_stencil() { return depth_stencil_; }

  void clear(std::array<float, 4> color, float depth = 1.0f, std::uint8_t stencil = 0);
  void clear_color_int(int index, std::array<std::int32_t, 4> value);
  void clear_color_uint(int index, std::array<std::uint32_t, 4> value);
  void clear_color(std::array<float, 4> color);  // every colour attachment
  void clear_depth(float depth);
  void clear_stencil(std::uint8_t stencil);

  // Draws with both renderers.
  void draw(const DualDraw& draw);

  // Colour attachment `index`, its depth or its stencil in clraster against the oracle; `where`, if
  // given, names what was drawn at the first differing pixels.
  ::testing::AssertionResult color_matches(int index, const TexelTolerance& tolerance = {},
                                           const PixelNamer& where = {}) const;
  ::testing::AssertionResult depth_matches(float tolerance = 0.0f, const PixelNamer& where = {}) const;
  ::testing::AssertionResult stencil_matches(const PixelNamer& where = {}) const;
  // Every attachment there is.
  ::testing::AssertionResult matches(const TexelTolerance& tolerance = {}, const PixelNamer& where = {}) const;

 private:
  std::vector<std::unique_ptr<DualTexture>> owned_;
  std::vector<DualTexture*> colors_;
  DualTexture* depth_stencil_ = nullptr;
  Framebuffer clraster_;
  oracle::GlFramebuffer gl_;
};

// The number of different texels among `texels` of `bytes_per_texel` bytes each: a test's check
// that its reference shows what it is meant to test (a uniform picture proves little).
std::size_t distinct_texels(std::span<const std::byte> texels, int bytes_per_texel);
std::size_t distinct_texels(std::span<const std::uint8_t> texels);

}  // namespace clraster::test
