#include "support/program_scene.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <memory>
#include <sstream>

#include "io/image_compare.hpp"
#include "io/image_io.hpp"
#include "support/test_support.hpp"

namespace clraster::test {
namespace {

template <typename T>
std::span<const std::byte> as_bytes(const std::vector<T>& values) {
  return std::as_bytes(std::span<const T>(values));
}

float half_to_float(std::uint16_t half) {
  const int exponent = (half >> 10) & 0x1f;
  const int mantissa = half & 0x3ff;
  const float sign = (half & 0x8000) ? -1.0f : 1.0f;
  if (exponent == 0) return sign * std::ldexp(float(mantissa), -24);
  if (exponent == 31) return mantissa ? NAN : sign * INFINITY;
  return sign * std::ldexp(float(mantissa | 0x400), exponent - 25);
}

// The nearest half float (ties to even) of a finite value within the half range.
std::uint16_t float_to_half(float value) {
  const std::uint16_t sign = std::signbit(value) ? 0x8000 : 0;
  const float magnitude = std::fabs(value);
  if (magnitude < 0x1p-14f) return sign | std::uint16_t(std::nearbyint(magnitude * 0x1p24f));  // subnormal
  int exponent = 0;
  std::frexp(magnitude, &exponent);  // magnitude = m * 2^exponent, m in [0.5, 1)
  const float mantissa = std::nearbyint(std::ldexp(magnitude, 11 - exponent));  // 11 significant bits
  // A mantissa rounded up to 2^11 carries into the exponent, which the addition does by itself.
  return sign | std::uint16_t(((exponent + 14) << 10) + int(mantissa) - 0x400);
}

// Stored values as a picture: normalized values as bytes, float ones clamped to [0, 1]; missing
// channels 0, a missing alpha opaque.
Image to_image(Format format, std::span<const std::byte> texels, int width, int height) {
  const std::vector<float> values = stored_values(format, texels);
  const int channels = format_info(format).channels;
  Image image{width, height, std::vector<std::uint8_t>(std::size_t(width) * height * 4)};
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const std::size_t texel = std::size_t(y) * width + x;
      const std::size_t pixel = (std::size_t(height - 1 - y) * width + x) * 4;  // rows from the top
      for (int c = 0; c < 4; ++c) {
        const float value = c < channels ? values[texel * channels + c] : (c == 3 ? 1.0f : 0.0f);
        image.rgba[pixel + c] = std::uint8_t(std::lround(std::clamp(value, 0.0f, 1.0f) * 255));
      }
    }
  }
  return image;
}

}  // namespace

// ---- TexturePair ------------------------------------------------------------------------------------

TexturePair::TexturePair(int width, int height, Format format, int levels)
    : clr(shared_context(), width, height, format, levels), gl(width, height, format, clr.levels()) {}

TexturePair TexturePair::with_clraster_mipmaps(int width, int height, Format format,
                                               std::span<const std::byte> level0) {
  TexturePair pair(width, height, format, kFullMipChain);
  pair.clr.upload(0, level0);
  pair.clr.generate_mipmaps();
  for (int level = 0; level < pair.clr.levels(); ++level) pair.gl.upload(level, pair.clr.read(level));
  return pair;
}

void TexturePair::upload(int level, std::span<const std::byte> texels) {
  clr.upload(level, texels);
  gl.upload(level, texels);
}

// ---- ProgramPair ------------------------------------------------------------------------------------

ProgramPair::ProgramPair(const std::string& clraster_source, const std::string& glsl_vertex,
                         const std::string& glsl_fragment, const std::string& name)
    : program_(shared_context(), clraster_source, name), bindings_(program_), gl_(glsl_vertex, glsl_fragment, name) {}

ProgramPair& ProgramPair::set(const std::string& name, std::span<const float> values) {
  bindings_.set_bytes(name, std::as_bytes(values));
  gl_.set(name, values);
  return *this;
}

ProgramPair& ProgramPair::set_texture(const std::string& name, const TexturePair& texture, const Sampler& sampler) {
  bindings_.set_texture(name, texture.clr, sampler);
  gl_.set_texture(name, texture.gl, sampler);
  return *this;
}

// ---- FramebufferPair --------------------------------------------------------------------------------

namespace {

std::vector<std::unique_ptr<TexturePair>> make_attachments(int width, int height, const std::vector<Format>& formats) {
  std::vector<std::unique_ptr<TexturePair>> attachments;
  for (Format format : formats) attachments.push_back(std::make_unique<TexturePair>(width, height, format));
  return attachments;
}

template <typename Texture, typename Member>
std::vector<Texture*> attachment_pointers(const std::vector<std::unique_ptr<TexturePair>>& pairs, Member member) {
  std::vector<Texture*> pointers;
  for (const auto& pair : pairs) pointers.push_back(&((*pair).*member));
  return pointers;
}

}  // namespace

FramebufferPair::FramebufferPair(int width, int height, const std::vector<Format>& colors,
                                 std::optional<Format> depth_stencil)
    : width_(width),
      height_(height),
      colors_(make_attachments(width, height, colors)),
      depth_stencil_(depth_stencil ? std::make_unique<TexturePair>(width, height, *depth_stencil) : nullptr),
      clraster_(shared_context(), attachment_pointers<Texture>(colors_, &TexturePair::clr),
                depth_stencil_ ? &depth_stencil_->clr : nullptr),
      gl_(attachment_pointers<oracle::GlTexture>(colors_, &TexturePair::gl),
          depth_stencil_ ? &depth_stencil_->gl : nullptr) {}

void FramebufferPair::clear(std::array<float, 4> color, float depth, std::uint8_t stencil) {
  clraster_.clear(color, depth, stencil);
  gl_.clear(color, depth, stencil);
}

void FramebufferPair::clear_depth(float depth) {
  clraster_.clear_depth(depth);
  gl_.clear_depth(depth);
}

void FramebufferPair::draw(const ProgramPair& program, const ProgramDraw& draw) {
  std::vector<Buffer> buffers;
  buffers.reserve(draw.attributes.size());
  DrawCall call;
  call.program = &program.program();
  call.bindings = &program.bindings();
  call.state = draw.state;
  oracle::GlDrawCall gl_call{&program.gl()};
  gl_call.state = draw.gl_state.value_or(draw.state);
  gl_call.advanced_blend = draw.gl_advanced_blend;
  for (const SceneAttribute& attribute : draw.attributes) {
    buffers.emplace_back(shared_context(), attribute.values);
    call.attributes.push_back({attribute.name, &buffers.back(), attribute.type});
    gl_call.attributes.push_back({attribute.name, as_bytes(attribute.values), attribute.type});
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

// ---- Texel comparisons -----------------------------------------------------------------------------

std::vector<float> stored_values(Format format, std::span<const std::byte> texels) {
  std::vector<float> values;
  switch (format) {
    case Format::R8:
    case Format::RG8:
    case Format::RGBA8:
    case Format::SRGB8_A8:
      for (std::byte b : texels) values.push_back(float(std::to_integer<int>(b)) / 255.0f);
      return values;
    case Format::RGBA16F:
      values.resize(texels.size() / 2);
      for (std::size_t i = 0; i < values.size(); ++i) {
        std::uint16_t half;
        std::memcpy(&half, texels.data() + 2 * i, 2);
        values[i] = half_to_float(half);
      }
      return values;
    case Format::R32F:
    case Format::RG32F:
    case Format::RGBA32F:
    case Format::Depth32F:
      values.resize(texels.size() / 4);
      std::memcpy(values.data(), texels.data(), values.size() * 4);
      return values;
    default: throw InvalidArgument(std::string("stored_values: unsupported format ") + format_info(format).name);
  }
}

std::vector<std::byte> encode_texels(Format format, std::span<const float> values) {
  std::vector<std::byte> bytes;
  switch (format) {
    case Format::R8:
    case Format::RG8:
    case Format::RGBA8:
    case Format::SRGB8_A8:
      for (float v : values) bytes.push_back(std::byte(std::lround(std::clamp(v, 0.0f, 1.0f) * 255)));
      return bytes;
    case Format::RGBA16F:
      bytes.resize(values.size() * 2);
      for (std::size_t i = 0; i < values.size(); ++i) {
        const std::uint16_t half = float_to_half(values[i]);
        std::memcpy(bytes.data() + 2 * i, &half, 2);
      }
      return bytes;
    case Format::R32F:
    case Format::RG32F:
    case Format::RGBA32F:
      bytes.resize(values.size() * 4);
      std::memcpy(bytes.data(), values.data(), bytes.size());
      return bytes;
    default: throw InvalidArgument(std::string("encode_texels: unsupported format ") + format_info(format).name);
  }
}

std::string TexelDifference::summary() const {
  std::ostringstream out;
  out << texels - texels_beyond << " of " << texels << " texels within tolerance (" << std::setprecision(5)
      << 100.0 * fraction_within() << "%), largest difference " << max_difference << " (" << max_difference * 255
      << "/255), mean " << mean_difference;
  return out.str();
}

TexelDifference compare_texels(Format format, std::span<const std::byte> result, std::span<const std::byte> reference,
                               double tolerance) {
  const std::vector<float> a = stored_values(format, result);
  const std::vector<float> b = stored_values(format, reference);
  if (a.size() != b.size()) throw InvalidArgument("compare_texels: the texel counts differ");
  const std::size_t channels = std::size_t(format_info(format).channels);
  TexelDifference difference;
  difference.texels = a.size() / channels;
  double total = 0;
  for (std::size_t texel = 0; texel < difference.texels; ++texel) {
    bool beyond = false;
    for (std::size_t c = 0; c < channels; ++c) {
      const float x = a[texel * channels + c], y = b[texel * channels + c];
      // NaN in one only, or infinities of different signs, count as the largest difference.
      const double d = x == y ? 0.0 : std::isnan(x) && std::isnan(y) ? 0.0 : std::fabs(double(x) - double(y));
      const double counted = std::isnan(d) ? INFINITY : d;
      // Within float rounding of the tolerance counts as within (8-bit values are k / 255 in float).
      beyond = beyond || counted > tolerance * (1 + 1e-4);
      difference.max_difference = std::max(difference.max_difference, counted);
      total += counted;
    }
    difference.texels_beyond += beyond;
  }
  difference.mean_difference = a.empty() ? 0 : total / double(a.size());
  return difference;
}

::testing::AssertionResult drawn(const TexturePair& pair) {
  const std::vector<std::byte> texels = pair.gl.read();
  const auto size = static_cast<std::size_t>(format_info(pair.gl.format()).bytes_per_texel);
  for (std::size_t offset = size; offset + size <= texels.size(); offset += size) {
    if (std::memcmp(texels.data(), texels.data() + offset, size) != 0) return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << "every texel of the OpenGL reference holds one value: nothing was drawn";
}

::testing::AssertionResult texels_match(const TexturePair& pair, const TexelTolerance& tolerance) {
  const Format format = pair.clr.format();
  const std::vector<std::byte> result = pair.clr.read(tolerance.level);
  const std::vector<std::byte> reference = pair.gl.read(tolerance.level);
  const TexelDifference difference = compare_texels(format, result, reference, tolerance.tolerance);
  ::testing::Test::RecordProperty("texels", difference.summary());
  if (difference.fraction_within() >= tolerance.min_fraction) return ::testing::AssertionSuccess();

  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path dir = std::filesystem::path(output_directory()) /
                                    (std::string(test->test_suite_name()) + "." + test->name());
  std::filesystem::create_directories(dir);
  const int width = pair.clr.width(tolerance.level), height = pair.clr.height(tolerance.level);
  const Image result_image = to_image(format, result, width, height);
  const Image reference_image = to_image(format, reference, width, height);
  io::save_png((dir / "reference.png").string(), reference_image);
  io::save_png((dir / "result.png").string(), result_image);
  io::save_png((dir / "diff.png").string(),
               io::diff_image(result_image, reference_image, int(std::floor(tolerance.tolerance * 255))));
  return ::testing::AssertionFailure() << format_info(format).name << " level " << tolerance.level << ": "
                                       << difference.summary() << ", needed " << 100.0 * tolerance.min_fraction
                                       << "% within " << tolerance.tolerance << "\n  pictures in " << dir.string();
}

}  // namespace clraster::test
