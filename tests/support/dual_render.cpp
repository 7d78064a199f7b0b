#include "support/dual_render.hpp"

#include "io/image_compare.hpp"
#include "io/image_io.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <optional>
#include <set>
#include <sstream>

namespace clraster::test {
namespace {

// How one channel of a format is stored.
enum class ChannelKind { Unorm8, Half, Float, Int, Uint };

struct TexelLayout {
  ChannelKind kind;
  int channels;
  int channel_bytes;
};

TexelLayout texel_layout(Format format) {
  const FormatInfo& info = format_info(format);
  if (info.depth) return {ChannelKind::Float, 1, 4};  // the depth plane
  if (info.integer) return {info.is_signed ? ChannelKind::Int : ChannelKind::Uint, info.channels, 4};
  if (format == Format::RGBA16F) return {ChannelKind::Half, 4, 2};
  if (info.bytes_per_texel == info.channels) return {ChannelKind::Unorm8, info.channels, 1};
  return {ChannelKind::Float, info.channels, 4};
}

double half_to_double(std::uint16_t bits) {
  const int sign = bits >> 15, exponent = (bits >> 10) & 0x1f, mantissa = bits & 0x3ff;
  double magnitude = 0;
  if (exponent == 0x1f) {
    magnitude = mantissa ? std::nan("") : INFINITY;
  } else if (exponent == 0) {
    magnitude = std::ldexp(mantissa, -24);
  } else {
    magnitude = std::ldexp(1024 + mantissa, exponent - 25);
  }
  return sign ? -magnitude : magnitude;
}

// Channel c of texel i, as a number.
double channel_value(const TexelLayout& layout, std::span<const std::byte> texels, std::size_t i, int c) {
  const std::byte* p = texels.data() + (i * static_cast<std::size_t>(layout.channels) + c) * layout.channel_bytes;
  switch (layout.kind) {
    case ChannelKind::Unorm8: return std::to_integer<int>(*p);
    case ChannelKind::Half: {
      std::uint16_t bits = 0;
      std::memcpy(&bits, p, 2);
      return half_to_double(bits);
    }
    case ChannelKind::Float: {
      float value = 0;
      std::memcpy(&value, p, 4);
      return value;
    }
    case ChannelKind::Int: {
      std::int32_t value = 0;
      std::memcpy(&value, p, 4);
      return value;
    }
    case ChannelKind::Uint: {
      std::uint32_t value = 0;
      std::memcpy(&value, p, 4);
      return value;
    }
  }
  return 0;
}

bool channels_agree(ChannelKind kind, double a, double b, const TexelTolerance& tolerance) {
  switch (kind) {
    case ChannelKind::Unorm8: return std::abs(a - b) <= tolerance.unorm8;
    case ChannelKind::Half:
    case ChannelKind::Float: return a == b || (std::isnan(a) && std::isnan(b)) || std::abs(a - b) <= tolerance.absolute;
    case ChannelKind::Int:
    case ChannelKind::Uint: return a == b;
  }
  return false;
}

std::string texel_text(const TexelLayout& layout, std::span<const std::byte> texels, std::size_t i) {
  std::ostringstream text;
  text.precision(9);
  text << "(";
  for (int c = 0; c < layout.channels; ++c) text << (c ? ", " : "") << channel_value(layout, texels, i, c);
  text << ")";
  return text.str();
}

// A channel's value as a byte of a picture: 8-bit channels as they are, float and half ones (depth
// too) clamped to [0, 1], integer ones their low byte.
std::uint8_t picture_byte(ChannelKind kind, double value) {
  switch (kind) {
    case ChannelKind::Unorm8: return static_cast<std::uint8_t>(value);
    case ChannelKind::Half:
    case ChannelKind::Float:
      return static_cast<std::uint8_t>(std::isnan(value) ? 0 : std::lround(std::clamp(value, 0.0, 1.0) * 255));
    case ChannelKind::Int:
    case ChannelKind::Uint: return static_cast<std::uint8_t>(static_cast<std::int64_t>(value) & 0xff);
  }
  return 0;
}

// Texels (rows from t = 0) as a picture (rows from the top): one channel (R8, R32F, depth, stencil)
// as grey, a missing blue 0, a missing alpha opaque.
Image to_image(const TexelLayout& layout, std::span<const std::byte> texels, int width, int height) {
  Image image{width, height, std::vector<std::uint8_t>(static_cast<std::size_t>(width) * height * 4)};
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const auto from = static_cast<std::size_t>((height - 1 - y) * width + x);
      std::uint8_t* to = &image.rgba[static_cast<std::size_t>(y * width + x) * 4];
      to[3] = 255;
      for (int c = 0; c < layout.channels; ++c) {
        to[c] = picture_byte(layout.kind, channel_value(layout, texels, from, c));
      }
      if (layout.channels == 1) to[1] = to[2] = to[0];
    }
  }
  return image;
}

// Saves both renderers' texels of `what` as pictures; returns where.
std::string save_pictures(const std::string& what, std::span<const std::byte> result,
                          std::span<const std::byte> reference, const TexelLayout& layout, int width, int height) {
  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string test_name = std::string(test->test_suite_name()) + "." + test->name();
  for (char& c : test_name) {
    if (c == '/') c = '_';
  }
  const std::filesystem::path dir = std::filesystem::path(output_directory()) / test_name;
  std::filesystem::create_directories(dir);
  const Image a = to_image(layout, result, width, height), b = to_image(layout, reference, width, height);
  io::save_png((dir / (what + "-result.png")).string(), a);
  io::save_png((dir / (what + "-reference.png")).string(), b);
  io::save_png((dir / (what + "-diff.png")).string(), io::diff_image(a, b, 0));
  return (dir / (what + "-*.png")).string();
}

// clraster's texels against the oracle's, both rows from t = 0.
::testing::AssertionResult texels_match(const std::string& what, Format format, std::span<const std::byte> result,
                                        std::span<const std::byte> reference, int width, int height,
                                        const TexelTolerance& tolerance, const PixelNamer& where) {
  const TexelLayout layout = texel_layout(format);
  if (result.size() != reference.size()) {
    return ::testing::AssertionFailure() << what << ": clraster has " << result.size() << " bytes, the oracle "
                                         << reference.size();
  }
  const std::size_t count = static_cast<std::size_t>(width) * height;
  std::size_t differing = 0;
  std::ostringstream examples;
  for (std::size_t i = 0; i < count; ++i) {
    bool same = true;
    for (int c = 0; c < layout.channels; ++c) {
      same = same && channels_agree(layout.kind, channel_value(layout, result, i, c),
                                    channel_value(layout, reference, i, c), tolerance);
    }
    if (same) continue;
    if (++differing <= 8) {
      const int x = static_cast<int>(i % width), y = static_cast<int>(i / width);
      examples << "\n  at x " << x << ", y " << y << (where ? " (" + where(x, y) + ")" : std::string())
               << ": clraster " << texel_text(layout, result, i) << ", OpenGL " << texel_text(layout, reference, i);
    }
  }
  if (differing == 0) return ::testing::AssertionSuccess();
  ::testing::AssertionResult failure = ::testing::AssertionFailure();
  failure << what << " (" << format_info(format).name << "): " << differing << " of " << count
          << " texels differ (window y up)" << examples.str();
  failure << "\n  pictures: " << save_pictures(what, result, reference, layout, width, height);
  return failure;
}

std::vector<std::unique_ptr<DualTexture>> make_textures(int width, int height, const std::vector<Format>& colors,
                                                        bool depth_stencil) {
  std::vector<std::unique_ptr<DualTexture>> textures;
  for (const Format format : colors) textures.push_back(std::make_unique<DualTexture>(width, height, format));
  if (depth_stencil) textures.push_back(std::make_unique<DualTexture>(width, height, Format::Depth32FStencil8));
  return textures;
}

std::vector<DualTexture*> pointers(const std::vector<std::unique_ptr<DualTexture>>& textures, std::size_t count) {
  std::vector<DualTexture*> result;
  for (std::size_t i = 0; i < count; ++i) result.push_back(textures[i].get());
  return result;
}

std::vector<Texture*> clraster_textures(const std::vector<DualTexture*>& textures) {
  std::vector<Texture*> result;
  for (DualTexture* texture : textures) result.push_back(&texture->clraster);
  return result;
}

std::vector<oracle::GlTexture*> gl_textures(const std::vector<DualTexture*>& textures) {
  std::vector<oracle::GlTexture*> result;
  for (DualTexture* texture : textures) result.push_back(&texture->gl);
  return result;
}

}  // namespace

DualTexture::DualTexture(int width, int height, Format format)
    : clraster(shared_context(), width, height, format), gl(width, height, format) {}

DualBuffer::DualBuffer(std::vector<std::byte> bytes)
    : host(std::move(bytes)), device(shared_context(), std::span<const std::byte>(host)) {}

DualProgram::DualProgram(const std::string& opencl, const std::string& vertex_glsl, const std::string& fragment_glsl,
                         const std::string& name)
    : clraster(shared_context(), opencl, name + ".cl"), bindings(clraster), gl(vertex_glsl, fragment_glsl, name) {}

DualProgram& DualProgram::set(const std::string& name, float value) {
  bindings.set(name, value);
  gl.set(name, value);
  return *this;
}

DualProgram& DualProgram::set(const std::string& name, std::int32_t value) {
  bindings.set(name, value);
  gl.set(name, value);
  return *this;
}

DualProgram& DualProgram::set(const std::string& name, std::span<const float> values) {
  bindings.set_bytes(name, std::as_bytes(values));
  gl.set(name, values);
  return *this;
}

DualProgram& DualProgram::set_texture(const std::string& name, const DualTexture& texture, const Sampler& sampler) {
  bindings.set_texture(name, texture.clraster, sampler);
  gl.set_texture(name, texture.gl, sampler);
  return *this;
}

DualFramebuffer::DualFramebuffer(std::vector<DualTexture*> colors, DualTexture* depth_stencil)
    : colors_(std::move(colors)),
      depth_stencil_(depth_stencil),
      clraster_(shared_context(), clraster_textures(colors_), depth_stencil ? &depth_stencil->clraster : nullptr),
      gl_(gl_textures(colors_), depth_stencil ? &depth_stencil->gl : nullptr) {}

DualFramebuffer::DualFramebuffer(int width, int height, const std::vector<Format>& colors, bool depth_stencil)
    : owned_(make_textures(width, height, colors, depth_stencil)),
      colors_(pointers(owned_, colors.size())),
      depth_stencil_(depth_stencil ? owned_.back().get() : nullptr),
      clraster_(shared_context(), clraster_textures(colors_), depth_stencil_ ? &depth_stencil_->clraster : nullptr),
      gl_(gl_textures(colors_), depth_stencil_ ? &depth_stencil_->gl : nullptr) {}

void DualFramebuffer::clear(std::array<float, 4> color, float depth, std::uint8_t stencil) {
  clraster_.clear(color, depth, stencil);
  gl_.clear(color, depth, stencil);
}

void DualFramebuffer::clear_color_int(int index, std::array<std::int32_t, 4> value) {
  clraster_.clear_color_int(index, value);
  gl_.clear_color_int(index, value);
}

void DualFramebuffer::clear_color_uint(int index, std::array<std::uint32_t, 4> value) {
  clraster_.clear_color_uint(index, value);
  gl_.clear_color_uint(index, value);
}

void DualFramebuffer::clear_color(std::array<float, 4> color) {
  clraster_.clear_color(color);
  gl_.clear_color(color);
}

void DualFramebuffer::clear_depth(float depth) {
  clraster_.clear_depth(depth);
  gl_.clear_depth(depth);
}

void DualFramebuffer::clear_stencil(std::uint8_t stencil) {
  clraster_.clear_stencil(stencil);
  gl_.clear_stencil(stencil);
}

void DualFramebuffer::draw(const DualDraw& draw) {
  DrawCall call;
  call.program = &draw.program->clraster;
  call.bindings = &draw.program->bindings;
  call.first = draw.first;
  call.count = draw.count;
  call.instance_count = draw.instance_count;
  call.state = draw.state;
  oracle::GlDrawCall gl_call{&draw.program->gl};
  gl_call.first = draw.first;
  gl_call.count = draw.count;
  gl_call.instance_count = draw.instance_count;
  gl_call.state = draw.state;
  for (const DualAttribute& a : draw.attributes) {
    call.attributes.push_back({a.name, &a.buffer->device, a.type, a.offset, a.stride, a.per_instance});
    gl_call.attributes.push_back({a.name, a.buffer->host, a.type, a.offset, a.stride, a.per_instance});
  }
  std::optional<IndexBuffer> indices;
  if (!draw.indices.empty()) {
    indices.emplace(shared_context(), draw.indices);
    call.indices = &*indices;
    gl_call.indices = std::span<const std::uint32_t>(draw.indices);
  }
  clraster_.draw(call);
  gl_.draw(gl_call);
}

::testing::AssertionResult DualFramebuffer::color_matches(int index, const TexelTolerance& tolerance,
                                                         const PixelNamer& where) const {
  const DualTexture& texture = *colors_[static_cast<std::size_t>(index)];
  return texels_match("color" + std::to_string(index), texture.clraster.format(), texture.clraster.read(),
                      texture.gl.read(), width(), height(), tolerance, where);
}

::testing::AssertionResult DualFramebuffer::depth_matches(float tolerance, const PixelNamer& where) const {
  if (!depth_stencil_) return ::testing::AssertionFailure() << "the framebuffer has no depth attachment";
  return texels_match("depth", depth_stencil_->clraster.format(), depth_stencil_->clraster.read(),
                      depth_stencil_->gl.read(), width(), height(), {0, tolerance}, where);
}

::testing::AssertionResult DualFramebuffer::stencil_matches(const PixelNamer& where) const {
  if (!depth_stencil_) return ::testing::AssertionFailure() << "the framebuffer has no stencil attachment";
  const std::vector<std::uint8_t> result = depth_stencil_->clraster.read_stencil();
  const std::vector<std::uint8_t> reference = depth_stencil_->gl.read_stencil();
  return texels_match("stencil", Format::R8, std::as_bytes(std::span(result)), std::as_bytes(std::span(reference)),
                      width(), height(), {}, where);
}

::testing::AssertionResult DualFramebuffer::matches(const TexelTolerance& tolerance, const PixelNamer& where) const {
  std::ostringstream failures;
  const auto check = [&](const ::testing::AssertionResult& result) {
    if (!result) failures << "\n" << result.message();
  };
  for (std::size_t k = 0; k < colors_.size(); ++k) check(color_matches(static_cast<int>(k), tolerance, where));
  if (depth_stencil_) {
    check(depth_matches(tolerance.absolute, where));
    if (format_info(depth_stencil_->clraster.format()).stencil) check(stencil_matches(where));
  }
  if (failures.str().empty()) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "clraster differs from OpenGL:" << failures.str();
}

std::size_t distinct_texels(std::span<const std::byte> texels, int bytes_per_texel) {
  std::set<std::string> values;
  const auto size = static_cast<std::size_t>(bytes_per_texel);
  for (std::size_t i = 0; i + size <= texels.size(); i += size) {
    values.emplace(reinterpret_cast<const char*>(texels.data() + i), size);
  }
  return values.size();
}

std::size_t distinct_texels(std::span<const std::uint8_t> texels) {
  return distinct_texels(std::as_bytes(texels), 1);
}

}  // namespace clraster::test
