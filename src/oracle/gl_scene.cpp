#include "oracle/gl_scene.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <optional>
#include <type_traits>

#include "oracle/gl_context.hpp"
#include "oracle/gl_state.hpp"

namespace clraster::oracle {
namespace {

using gl::Context;

std::string hex(GLenum value) {
  char text[16];
  std::snprintf(text, sizeof text, "0x%04X", value);
  return text;
}

// How shaders read a value: float (sampler2D, float/vec/mat), signed integer (isampler2D, int/ivec,
// bool/bvec) or unsigned integer (usampler2D, uint/uvec). Host values, formats and GLSL types must agree.
enum class Kind { Float, Int, UInt };

const char* kind_name(Kind kind) {
  switch (kind) {
    case Kind::Float: return "float";
    case Kind::Int: return "signed integer";
    case Kind::UInt: return "unsigned integer";
  }
  return "?";
}

// ---- Formats --------------------------------------------------------------------------------------

struct GlFormat {
  Format format;
  GLenum internal_format;
  GLenum transfer_format;  // with transfer_type: how GL uploads and reads back texels
  GLenum transfer_type;
  int bytes_per_texel;     // clraster's (Depth32FStencil8: of its depth plane; a stencil plane follows)
  Kind kind;
  GLenum attachment;       // GL_COLOR_ATTACHMENT0, GL_DEPTH_ATTACHMENT or GL_DEPTH_STENCIL_ATTACHMENT
  const char* name;

  bool color() const { return attachment == GL_COLOR_ATTACHMENT0; }
  bool depth_stencil() const { return attachment == GL_DEPTH_STENCIL_ATTACHMENT; }
  // Bytes GL transfers per texel: Depth32FStencil8 is interleaved, a float and a 32-bit stencil word.
  int transfer_bytes_per_texel() const { return depth_stencil() ? 8 : bytes_per_texel; }
};

// The one mapping of clraster's formats to GL's, in the order of clraster::Format.
constexpr GlFormat kFormats[] = {
    {Format::R8, GL_R8, GL_RED, GL_UNSIGNED_BYTE, 1, Kind::Float, GL_COLOR_ATTACHMENT0, "R8"},
    {Format::RG8, GL_RG8, GL_RG, GL_UNSIGNED_BYTE, 2, Kind::Float, GL_COLOR_ATTACHMENT0, "RG8"},
    {Format::RGBA8, GL_RGBA8, GL_RGBA, GL_UNSIGNED_BYTE, 4, Kind::Float, GL_COLOR_ATTACHMENT0, "RGBA8"},
    {Format::SRGB8_A8, GL_SRGB8_ALPHA8, GL_RGBA, GL_UNSIGNED_BYTE, 4, Kind::Float, GL_COLOR_ATTACHMENT0, "SRGB8_A8"},
    {Format::R32F, GL_R32F, GL_RED, GL_FLOAT, 4, Kind::Float, GL_COLOR_ATTACHMENT0, "R32F"},
    {Format::RG32F, GL_RG32F, GL_RG, GL_FLOAT, 8, Kind::Float, GL_COLOR_ATTACHMENT0, "RG32F"},
    {Format::RGBA16F, GL_RGBA16F, GL_RGBA, GL_HALF_FLOAT, 8, Kind::Float, GL_COLOR_ATTACHMENT0, "RGBA16F"},
    {Format::RGBA32F, GL_RGBA32F, GL_RGBA, GL_FLOAT, 16, Kind::Float, GL_COLOR_ATTACHMENT0, "RGBA32F"},
    {Format::R32I, GL_R32I, GL_RED_INTEGER, GL_INT, 4, Kind::Int, GL_COLOR_ATTACHMENT0, "R32I"},
    {Format::R32UI, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, 4, Kind::UInt, GL_COLOR_ATTACHMENT0, "R32UI"},
    {Format::RGBA32I, GL_RGBA32I, GL_RGBA_INTEGER, GL_INT, 16, Kind::Int, GL_COLOR_ATTACHMENT0, "RGBA32I"},
    {Format::RGBA32UI, GL_RGBA32UI, GL_RGBA_INTEGER, GL_UNSIGNED_INT, 16, Kind::UInt, GL_COLOR_ATTACHMENT0,
     "RGBA32UI"},
    {Format::Depth32F, GL_DEPTH_COMPONENT32F, GL_DEPTH_COMPONENT, GL_FLOAT, 4, Kind::Float, GL_DEPTH_ATTACHMENT,
     "Depth32F"},
    {Format::Depth32FStencil8, GL_DEPTH32F_STENCIL8, GL_DEPTH_STENCIL, GL_FLOAT_32_UNSIGNED_INT_24_8_REV, 4,
     Kind::Float, GL_DEPTH_STENCIL_ATTACHMENT, "Depth32FStencil8"},
};

constexpr bool formats_in_enum_order() {
  for (std::size_t i = 0; i < std::size(kFormats); ++i) {
    if (kFormats[i].format != static_cast<Format>(i)) return false;
  }
  return true;
}
static_assert(formats_in_enum_order(), "kFormats must list every clraster::Format in declaration order");

const GlFormat& gl_format(Format format) {
  const auto index = static_cast<std::size_t>(format);
  if (index >= std::size(kFormats)) throw InvalidArgument("unknown texture format " + std::to_string(index));
  return kFormats[index];
}

// clraster keeps Depth32FStencil8 as a plane of float depths followed by a plane of stencil bytes; GL
// transfers it interleaved (GL_FLOAT_32_UNSIGNED_INT_24_8_REV): per texel the float, then a 32-bit
// word whose low 8 bits are the stencil value. Other formats are the same bytes in both.
std::vector<std::byte> to_gl_layout(const GlFormat& format, std::span<const std::byte> texels, std::size_t count) {
  if (!format.depth_stencil()) return {texels.begin(), texels.end()};
  std::vector<std::byte> interleaved(count * 8, std::byte{0});
  for (std::size_t i = 0; i < count; ++i) {
    std::memcpy(&interleaved[i * 8], &texels[i * 4], 4);
    const auto stencil = static_cast<std::uint32_t>(texels[count * 4 + i]);
    std::memcpy(&interleaved[i * 8 + 4], &stencil, 4);
  }
  return interleaved;
}

std::vector<std::byte> from_gl_layout(const GlFormat& format, std::vector<std::byte> texels, std::size_t count) {
  if (!format.depth_stencil()) return texels;
  std::vector<std::byte> planes(count * 5);
  for (std::size_t i = 0; i < count; ++i) {
    std::memcpy(&planes[i * 4], &texels[i * 8], 4);
    std::uint32_t stencil = 0;
    std::memcpy(&stencil, &texels[i * 8 + 4], 4);
    planes[count * 4 + i] = static_cast<std::byte>(stencil & 0xff);
  }
  return planes;
}

// ---- Samplers -------------------------------------------------------------------------------------

GLenum filter(Filter filter) { return filter == Filter::Linear ? GL_LINEAR : GL_NEAREST; }

// GL folds the mip filter into the minification filter.
GLenum min_filter(Filter min, MipFilter mip) {
  const bool linear = min == Filter::Linear;
  switch (mip) {
    case MipFilter::None: return linear ? GL_LINEAR : GL_NEAREST;
    case MipFilter::Nearest: return linear ? GL_LINEAR_MIPMAP_NEAREST : GL_NEAREST_MIPMAP_NEAREST;
    case MipFilter::Linear: return linear ? GL_LINEAR_MIPMAP_LINEAR : GL_NEAREST_MIPMAP_LINEAR;
  }
  throw InvalidArgument("unknown mip filter " + std::to_string(static_cast<int>(mip)));
}

GLenum wrap(Wrap wrap) {
  switch (wrap) {
    case Wrap::Repeat: return GL_REPEAT;
    case Wrap::ClampToEdge: return GL_CLAMP_TO_EDGE;
    case Wrap::MirroredRepeat: return GL_MIRRORED_REPEAT;
  }
  throw InvalidArgument("unknown wrap mode " + std::to_string(static_cast<int>(wrap)));
}

// A sampler object with `sampler`'s state. Integer textures are only complete with nearest filters
// (GL returns zeros otherwise); clraster reads them with texel fetches, which never filter, so they
// get nearest filters whatever `sampler` says.
gl::Sampler make_sampler(const Sampler& sampler, Kind kind) {
  const bool integer = kind != Kind::Float;
  GLuint id = 0;
  glCreateSamplers(1, &id);
  gl::Sampler object(id);
  glSamplerParameteri(id, GL_TEXTURE_MAG_FILTER, integer ? GL_NEAREST : filter(sampler.mag_filter));
  glSamplerParameteri(id, GL_TEXTURE_MIN_FILTER,
                      integer ? GL_NEAREST : min_filter(sampler.min_filter, sampler.mip_filter));
  glSamplerParameteri(id, GL_TEXTURE_WRAP_S, wrap(sampler.wrap_s));
  glSamplerParameteri(id, GL_TEXTURE_WRAP_T, wrap(sampler.wrap_t));
  glSamplerParameterf(id, GL_TEXTURE_LOD_BIAS, sampler.lod_bias);
  glSamplerParameterf(id, GL_TEXTURE_MIN_LOD, sampler.min_lod);
  glSamplerParameterf(id, GL_TEXTURE_MAX_LOD, sampler.max_lod);
  gl::check("creating a sampler");
  return object;
}

bool same_sampler(const Sampler& a, const Sampler& b) {
  return a.mag_filter == b.mag_filter && a.min_filter == b.min_filter && a.mip_filter == b.mip_filter &&
         a.wrap_s == b.wrap_s && a.wrap_t == b.wrap_t && a.lod_bias == b.lod_bias && a.min_lod == b.min_lod &&
         a.max_lod == b.max_lod;
}

// ---- GLSL value types -------------------------------------------------------------------------------

// The uniform and attribute types the oracle sets; components counts all of a matrix's floats.
struct ValueType {
  GLenum type;
  Kind kind;
  int components;
  bool matrix;
  const char* glsl;
};

constexpr ValueType kValueTypes[] = {
    {GL_FLOAT, Kind::Float, 1, false, "float"},
    {GL_FLOAT_VEC2, Kind::Float, 2, false, "vec2"},
    {GL_FLOAT_VEC3, Kind::Float, 3, false, "vec3"},
    {GL_FLOAT_VEC4, Kind::Float, 4, false, "vec4"},
    {GL_FLOAT_MAT2, Kind::Float, 4, true, "mat2"},
    {GL_FLOAT_MAT3, Kind::Float, 9, true, "mat3"},
    {GL_FLOAT_MAT4, Kind::Float, 16, true, "mat4"},
    {GL_INT, Kind::Int, 1, false, "int"},
    {GL_INT_VEC2, Kind::Int, 2, false, "ivec2"},
    {GL_INT_VEC3, Kind::Int, 3, false, "ivec3"},
    {GL_INT_VEC4, Kind::Int, 4, false, "ivec4"},
    {GL_BOOL, Kind::Int, 1, false, "bool"},
    {GL_BOOL_VEC2, Kind::Int, 2, false, "bvec2"},
    {GL_BOOL_VEC3, Kind::Int, 3, false, "bvec3"},
    {GL_BOOL_VEC4, Kind::Int, 4, false, "bvec4"},
    {GL_UNSIGNED_INT, Kind::UInt, 1, false, "uint"},
    {GL_UNSIGNED_INT_VEC2, Kind::UInt, 2, false, "uvec2"},
    {GL_UNSIGNED_INT_VEC3, Kind::UInt, 3, false, "uvec3"},
    {GL_UNSIGNED_INT_VEC4, Kind::UInt, 4, false, "uvec4"},
};

// Null for types the oracle does not set (doubles, non-square matrices, ...).
const ValueType* value_type(GLenum type) {
  for (const ValueType& value : kValueTypes) {
    if (value.type == type) return &value;
  }
  return nullptr;
}

// The 2D samplers and the texture kind each reads.
std::optional<Kind> sampler_kind(GLenum type) {
  switch (type) {
    case GL_SAMPLER_2D: return Kind::Float;
    case GL_INT_SAMPLER_2D: return Kind::Int;
    case GL_UNSIGNED_INT_SAMPLER_2D: return Kind::UInt;
    default: return std::nullopt;
  }
}

// The attribute types of clraster: 1 to 4 32-bit components of one kind.
struct AttributeFormat {
  Kind kind;
  int components;
  GLenum type;
  std::size_t bytes() const { return std::size_t(components) * 4; }
};

AttributeFormat attribute_format(AttributeType type) {
  const auto index = static_cast<int>(type);
  if (index < 0 || index > static_cast<int>(AttributeType::UInt4)) {
    throw InvalidArgument("unknown attribute type " + std::to_string(index));
  }
  // AttributeType lists Float..Float4, Int..Int4, UInt..UInt4.
  static constexpr AttributeFormat kKinds[] = {{Kind::Float, 0, GL_FLOAT}, {Kind::Int, 0, GL_INT},
                                               {Kind::UInt, 0, GL_UNSIGNED_INT}};
  AttributeFormat format = kKinds[index / 4];
  format.components = index % 4 + 1;
  return format;
}

// An attribute a program uses: where it goes and what the vertex shader declares.
struct ProgramAttribute {
  GLint location;
  const ValueType* type;
};

// Reads the name of active resource `index` of `program` with glGetActiveUniform or glGetActiveAttrib.
template <typename GetActive>
std::string active_name(GLuint program, GLenum max_length_query, GLuint index, GLint* size, GLenum* type,
                        GetActive get_active) {
  GLint max_length = 0;
  glGetProgramiv(program, max_length_query, &max_length);
  std::string name(std::size_t(std::max(max_length, 1)), '\0');
  GLsizei length = 0;
  get_active(program, index, GLsizei(name.size()), &length, size, type, name.data());
  name.resize(std::size_t(length));
  // Arrays are listed as their first element, "weights[0]".
  if (name.ends_with("[0]")) name.resize(name.size() - 3);
  return name;
}

bool built_in(const std::string& name) { return name.starts_with("gl_"); }

// value truncated toward zero and saturated to Int's range (NaN: 0).
template <typename Int>
Int truncate(float value) {
  if (std::isnan(value)) return 0;
  const double truncated = std::trunc(double{value});
  if (truncated <= double{std::numeric_limits<Int>::min()}) return std::numeric_limits<Int>::min();
  if (truncated >= double{std::numeric_limits<Int>::max()}) return std::numeric_limits<Int>::max();
  return static_cast<Int>(truncated);
}

GLenum advanced_equation(AdvancedBlend blend) {
  switch (blend) {
    case AdvancedBlend::Multiply: return GL_MULTIPLY_KHR;
    case AdvancedBlend::Screen: return GL_SCREEN_KHR;
    case AdvancedBlend::Overlay: return GL_OVERLAY_KHR;
    case AdvancedBlend::Darken: return GL_DARKEN_KHR;
    case AdvancedBlend::Lighten: return GL_LIGHTEN_KHR;
    case AdvancedBlend::ColorDodge: return GL_COLORDODGE_KHR;
    case AdvancedBlend::ColorBurn: return GL_COLORBURN_KHR;
    case AdvancedBlend::HardLight: return GL_HARDLIGHT_KHR;
    case AdvancedBlend::SoftLight: return GL_SOFTLIGHT_KHR;
    case AdvancedBlend::Difference: return GL_DIFFERENCE_KHR;
    case AdvancedBlend::Exclusion: return GL_EXCLUSION_KHR;
    case AdvancedBlend::HslHue: return GL_HSL_HUE_KHR;
    case AdvancedBlend::HslSaturation: return GL_HSL_SATURATION_KHR;
    case AdvancedBlend::HslColor: return GL_HSL_COLOR_KHR;
    case AdvancedBlend::HslLuminosity: return GL_HSL_LUMINOSITY_KHR;
  }
  throw InvalidArgument("unknown advanced blend equation " + std::to_string(static_cast<int>(blend)));
}

}  // namespace

bool has_gl_extension(std::string_view name) { return Context::instance().has_extension(name); }

// ---- GlTexture ------------------------------------------------------------------------------------

struct GlTexture::Impl {
  Format format;
  int width;
  int height;
  int levels;
  gl::Texture texture;

  Impl(int w, int h, Format f, int level_count) : format(f), width(w), height(h), levels(level_count) {
    const GlFormat& gl = gl_format(f);
    if (w < 1 || h < 1 || w > kMaxTextureSize || h > kMaxTextureSize) {
      throw InvalidArgument("texture size " + std::to_string(w) + "x" + std::to_string(h) + " is outside 1.." +
                            std::to_string(kMaxTextureSize));
    }
    const int full_chain = int(std::bit_width(unsigned(std::max(w, h))));
    if (levels == kFullMipChain) levels = full_chain;
    if (levels < 1 || levels > full_chain) {
      throw InvalidArgument(std::to_string(level_count) + " levels for a " + std::to_string(w) + "x" +
                            std::to_string(h) + " texture: it has 1.." + std::to_string(full_chain));
    }
    if (gl.depth_stencil() && levels != 1) {
      throw InvalidArgument(std::string(gl.name) + " textures have one level, not " + std::to_string(levels));
    }
    Context::instance().make_current();
    GLuint id = 0;
    glCreateTextures(GL_TEXTURE_2D, 1, &id);
    texture = gl::Texture(id);
    glTextureStorage2D(id, levels, gl.internal_format, w, h);
    glTextureParameteri(id, GL_TEXTURE_MAX_LEVEL, levels - 1);
    // Storage starts undefined; clraster's textures start at zero.
    for (int level = 0; level < levels; ++level) {
      glClearTexImage(id, level, gl.transfer_format, gl.transfer_type, nullptr);
    }
    gl::check("creating a texture");
  }

  ~Impl() { Context::instance().make_current_for_cleanup(); }  // the texture's glDelete* needs the context

  const GlFormat& gl() const { return gl_format(format); }
  int level_width(int level) const { return std::max(1, width >> level); }
  int level_height(int level) const { return std::max(1, height >> level); }
  std::size_t texels(int level) const { return std::size_t(level_width(level)) * std::size_t(level_height(level)); }
  // clraster's bytes of a level, with Depth32FStencil8's stencil plane.
  std::size_t level_bytes(int level) const {
    return texels(level) * std::size_t(gl().bytes_per_texel + (gl().depth_stencil() ? 1 : 0));
  }

  void check_level(int level) const {
    if (level < 0 || level >= levels) {
      throw InvalidArgument("level " + std::to_string(level) + " of a texture with " + std::to_string(levels) +
                            " levels");
    }
  }

  // A level in clraster's layout (both planes of Depth32FStencil8).
  std::vector<std::byte> read_level(int level) const {
    check_level(level);
    Context::instance().make_current();
    std::vector<std::byte> texels_gl(texels(level) * std::size_t(gl().transfer_bytes_per_texel()));
    glGetTextureImage(texture.get(), level, gl().transfer_format, gl().transfer_type, GLsizei(texels_gl.size()),
                      texels_gl.data());
    gl::check("reading a texture");
    return from_gl_layout(gl(), std::move(texels_gl), texels(level));
  }
};

GlTexture::GlTexture(int width, int height, Format format, int levels)
    : impl_(std::make_unique<Impl>(width, height, format, levels)) {}

GlTexture::GlTexture(int width, int height, Format format, std::span<const std::byte> level0, bool mipmaps)
    : impl_(std::make_unique<Impl>(width, height, format, mipmaps ? kFullMipChain : 1)) {
  upload(0, level0);
  if (mipmaps) generate_mipmaps();
}

GlTexture::~GlTexture() = default;
GlTexture::GlTexture(GlTexture&&) noexcept = default;
GlTexture& GlTexture::operator=(GlTexture&&) noexcept = default;

int GlTexture::width(int level) const {
  impl_->check_level(level);
  return impl_->level_width(level);
}
int GlTexture::height(int level) const {
  impl_->check_level(level);
  return impl_->level_height(level);
}
int GlTexture::levels() const { return impl_->levels; }
Format GlTexture::format() const { return impl_->format; }

void GlTexture::upload(int level, std::span<const std::byte> texels) {
  impl_->check_level(level);
  if (texels.size() != impl_->level_bytes(level)) {
    throw InvalidArgument(std::to_string(texels.size()) + " bytes for level " + std::to_string(level) + " of a " +
                          impl_->gl().name + " texture, which holds " + std::to_string(impl_->level_bytes(level)));
  }
  const GlFormat& gl = impl_->gl();
  const std::vector<std::byte> texels_gl = to_gl_layout(gl, texels, impl_->texels(level));
  Context::instance().make_current();
  glTextureSubImage2D(impl_->texture.get(), level, 0, 0, impl_->level_width(level), impl_->level_height(level),
                      gl.transfer_format, gl.transfer_type, texels_gl.data());
  gl::check("uploading a texture");
}

void GlTexture::generate_mipmaps() {
  const GlFormat& gl = impl_->gl();
  if (gl.kind != Kind::Float || !gl.color()) {
    throw InvalidArgument(std::string("OpenGL generates mipmaps of normalized and float colour formats, not ") +
                          gl.name);
  }
  Context::instance().make_current();
  glGenerateTextureMipmap(impl_->texture.get());
  gl::check("glGenerateMipmap");
}

std::vector<std::byte> GlTexture::read(int level) const {
  std::vector<std::byte> texels = impl_->read_level(level);
  texels.resize(impl_->texels(level) * std::size_t(impl_->gl().bytes_per_texel));  // the depth plane only
  return texels;
}

std::vector<std::uint8_t> GlTexture::read_stencil() const {
  if (!impl_->gl().depth_stencil()) {
    throw InvalidArgument(std::string("a ") + impl_->gl().name + " texture has no stencil");
  }
  const std::vector<std::byte> planes = impl_->read_level(0);
  std::vector<std::uint8_t> stencil(impl_->texels(0));
  std::memcpy(stencil.data(), planes.data() + stencil.size() * 4, stencil.size());
  return stencil;
}

// ---- GlProgram ------------------------------------------------------------------------------------

struct GlProgram::Impl {
  struct Uniform {
    GLint location;
    GLenum type;
    GLint array_size;
    bool is_set = false;
  };
  struct TextureBinding {
    GLint location;
    const GlTexture* texture;
    Sampler settings;
    gl::Sampler sampler;  // made with `settings`
  };

  std::string name;
  gl::Program program;
  std::map<std::string, Uniform> uniforms;             // active uniforms, arrays by their name without "[0]"
  std::map<std::string, ProgramAttribute> attributes;  // active attributes, built-ins excluded
  std::map<std::string, TextureBinding> textures;      // by sampler name; unit i is the i-th

  Impl(const std::string& vertex_source, const std::string& fragment_source, std::string program_name)
      : name(std::move(program_name)) {
    Context::instance().make_current();
    const char* vertex[] = {vertex_source.c_str()};
    const char* fragment[] = {fragment_source.c_str()};
    program = gl::build_program(vertex, fragment, "program '" + name + "'");
    const GLuint id = program.get();

    GLint blocks = 0;
    glGetProgramiv(id, GL_ACTIVE_UNIFORM_BLOCKS, &blocks);
    if (blocks != 0) throw InvalidArgument("program '" + name + "' uses uniform blocks, which the oracle cannot set");
    GLint count = 0;
    glGetProgramiv(id, GL_ACTIVE_UNIFORMS, &count);
    for (GLint i = 0; i < count; ++i) {
      GLint size = 0;
      GLenum type = 0;
      std::string uniform = active_name(id, GL_ACTIVE_UNIFORM_MAX_LENGTH, GLuint(i), &size, &type, glGetActiveUniform);
      if (built_in(uniform)) continue;
      if (!value_type(type) && !(sampler_kind(type) && size == 1)) {
        throw InvalidArgument("program '" + name + "': uniform '" + uniform + "' has a GL type (" + hex(type) +
                              (size > 1 ? ", array" : "") + ") the oracle cannot set");
      }
      const GLint location = glGetUniformLocation(id, uniform.c_str());
      uniforms.emplace(std::move(uniform), Uniform{location, type, size});
    }
    glGetProgramiv(id, GL_ACTIVE_ATTRIBUTES, &count);
    for (GLint i = 0; i < count; ++i) {
      GLint size = 0;
      GLenum type = 0;
      std::string attribute =
          active_name(id, GL_ACTIVE_ATTRIBUTE_MAX_LENGTH, GLuint(i), &size, &type, glGetActiveAttrib);
      if (built_in(attribute)) continue;
      const ValueType* value = value_type(type);
      if (!value || value->matrix || size != 1) {
        throw InvalidArgument("program '" + name + "': attribute '" + attribute +
                              "' is not a scalar or vector (GL type " + hex(type) + "), which the oracle cannot feed");
      }
      const GLint location = glGetAttribLocation(id, attribute.c_str());
      attributes.emplace(std::move(attribute), ProgramAttribute{location, value});
    }
    gl::check("inspecting a program");
  }

  ~Impl() { Context::instance().make_current_for_cleanup(); }  // the members' glDelete* need the context

  Uniform& uniform(const std::string& uniform_name) {
    const auto found = uniforms.find(uniform_name);
    if (found == uniforms.end()) {
      throw InvalidArgument("program '" + name + "' has no active uniform '" + uniform_name +
                            "' (misspelt, or unused and optimized away)");
    }
    return found->second;
  }

  template <typename T>
  void set(const std::string& uniform_name, std::span<const T> values, int element) {
    constexpr Kind given = std::is_same_v<T, float> ? Kind::Float : std::is_signed_v<T> ? Kind::Int : Kind::UInt;
    Uniform& target = uniform(uniform_name);
    const ValueType* type = value_type(target.type);
    const std::string what = "uniform '" + uniform_name + "' of program '" + name + "'";
    if (!type) throw InvalidArgument(what + " is a sampler: give it a texture with set_texture");
    if (type->kind != given) {
      throw InvalidArgument(what + " is " + type->glsl + ", not set from " + kind_name(given) + " values");
    }
    const auto components = std::size_t(type->components);
    if (values.empty() || values.size() % components != 0) {
      throw InvalidArgument(what + " is " + type->glsl + ": " + std::to_string(values.size()) +
                            " values are not a whole number of " + std::to_string(components) + "-component values");
    }
    const auto count = GLsizei(values.size() / components);
    if (element < 0 || element + count > target.array_size) {
      throw InvalidArgument(what + " has " + std::to_string(target.array_size) + " elements: cannot set " +
                            std::to_string(count) + " from element " + std::to_string(element));
    }
    Context::instance().make_current();
    const std::string element_name = uniform_name + "[" + std::to_string(element) + "]";
    const GLint location = element == 0 ? target.location : glGetUniformLocation(program.get(), element_name.c_str());
    write(location, type->type, count, values.data());
    gl::check("setting a uniform");
    target.is_set = true;
  }

  void write(GLint location, GLenum type, GLsizei count, const float* values) const {
    const GLuint id = program.get();
    switch (type) {
      case GL_FLOAT: return glProgramUniform1fv(id, location, count, values);
      case GL_FLOAT_VEC2: return glProgramUniform2fv(id, location, count, values);
      case GL_FLOAT_VEC3: return glProgramUniform3fv(id, location, count, values);
      case GL_FLOAT_VEC4: return glProgramUniform4fv(id, location, count, values);
      case GL_FLOAT_MAT2: return glProgramUniformMatrix2fv(id, location, count, GL_FALSE, values);
      case GL_FLOAT_MAT3: return glProgramUniformMatrix3fv(id, location, count, GL_FALSE, values);
      case GL_FLOAT_MAT4: return glProgramUniformMatrix4fv(id, location, count, GL_FALSE, values);
    }
  }
  void write(GLint location, GLenum type, GLsizei count, const std::int32_t* values) const {
    switch (value_type(type)->components) {
      case 1: return glProgramUniform1iv(program.get(), location, count, values);
      case 2: return glProgramUniform2iv(program.get(), location, count, values);
      case 3: return glProgramUniform3iv(program.get(), location, count, values);
      case 4: return glProgramUniform4iv(program.get(), location, count, values);
    }
  }
  void write(GLint location, GLenum type, GLsizei count, const std::uint32_t* values) const {
    switch (value_type(type)->components) {
      case 1: return glProgramUniform1uiv(program.get(), location, count, values);
      case 2: return glProgramUniform2uiv(program.get(), location, count, values);
      case 3: return glProgramUniform3uiv(program.get(), location, count, values);
      case 4: return glProgramUniform4uiv(program.get(), location, count, values);
    }
  }

  // Throws unless every active uniform has a value.
  void check_complete() const {
    for (const auto& [uniform_name, uniform] : uniforms) {
      if (!uniform.is_set) {
        throw InvalidArgument("uniform '" + uniform_name + "' of program '" + name + "' was never set" +
                              (sampler_kind(uniform.type) ? " (give it a texture with set_texture)" : ""));
      }
    }
  }

  // Makes the program current with texture unit i holding the i-th bound texture and its sampler.
  void bind() const {
    glUseProgram(program.get());
    GLuint unit = 0;
    for (const auto& [uniform_name, binding] : textures) {
      glBindTextureUnit(unit, binding.texture->impl_->texture.get());
      glBindSampler(unit, binding.sampler.get());
      glProgramUniform1i(program.get(), binding.location, GLint(unit));
      ++unit;
    }
  }
};

GlProgram::GlProgram(const std::string& vertex_source, const std::string& fragment_source, std::string name)
    : impl_(std::make_unique<Impl>(vertex_source, fragment_source, std::move(name))) {}
GlProgram::~GlProgram() = default;
GlProgram::GlProgram(GlProgram&&) noexcept = default;
GlProgram& GlProgram::operator=(GlProgram&&) noexcept = default;

const std::string& GlProgram::name() const { return impl_->name; }

GlProgram& GlProgram::set(const std::string& name, float value) { return set(name, std::span(&value, 1)); }
GlProgram& GlProgram::set(const std::string& name, std::int32_t value) { return set(name, std::span(&value, 1)); }
GlProgram& GlProgram::set(const std::string& name, std::uint32_t value) { return set(name, std::span(&value, 1)); }

GlProgram& GlProgram::set(const std::string& name, std::span<const float> values, int element) {
  impl_->set(name, values, element);
  return *this;
}
GlProgram& GlProgram::set(const std::string& name, std::span<const std::int32_t> values, int element) {
  impl_->set(name, values, element);
  return *this;
}
GlProgram& GlProgram::set(const std::string& name, std::span<const std::uint32_t> values, int element) {
  impl_->set(name, values, element);
  return *this;
}

GlProgram& GlProgram::set_texture(const std::string& name, const GlTexture& texture, const Sampler& sampler) {
  Impl::Uniform& uniform = impl_->uniform(name);
  const std::optional<Kind> reads = sampler_kind(uniform.type);
  const GlFormat& format = texture.impl_->gl();
  const std::string what = "uniform '" + name + "' of program '" + impl_->name + "'";
  if (!reads) throw InvalidArgument(what + " is not a sampler2D, isampler2D or usampler2D");
  if (*reads != format.kind) {
    throw InvalidArgument(what + " reads " + kind_name(*reads) + " textures, not " + format.name);
  }
  // A model's parts set the same texture one after the other: that keeps the sampler object it has.
  const auto bound = impl_->textures.find(name);
  if (bound == impl_->textures.end() || bound->second.texture != &texture ||
      !same_sampler(bound->second.settings, sampler)) {
    Context::instance().make_current();
    impl_->textures.insert_or_assign(name, Impl::TextureBinding{uniform.location, &texture, sampler,
                                                                make_sampler(sampler, format.kind)});
  }
  uniform.is_set = true;
  return *this;
}

// ---- GlVertexInput --------------------------------------------------------------------------------

namespace {

// Elements of `attribute` that lie in its data: i such that offset + i * stride + element size <= size.
std::uint64_t available_elements(const GlAttribute& attribute) {
  const std::size_t bytes = attribute_format(attribute.type).bytes();
  const std::size_t stride = attribute.stride != 0 ? attribute.stride : bytes;
  if (attribute.data.size() < attribute.offset + bytes) return 0;
  return (attribute.data.size() - attribute.offset - bytes) / stride + 1;
}

}  // namespace

// Attributes and indices checked against a program, then uploaded into a vertex array and its
// buffers: by GlVertexInput once, or by a draw with data of its own for that draw.
struct GlVertexInput::Impl {
  const GlProgram::Impl* program;  // the one whose attribute locations the vertex array feeds
  std::string program_name;
  std::optional<std::uint64_t> vertices;   // elements of the shortest per-vertex attribute
  std::optional<std::uint64_t> instances;  // elements of the shortest per-instance attribute
  std::string shortest_per_instance;       // and its name, for errors
  GLenum index_type = 0;  // GL_UNSIGNED_SHORT or GL_UNSIGNED_INT; 0 without indices
  std::size_t index_size = 0;
  std::uint64_t index_count = 0;
  gl::VertexArray vertex_array;
  std::vector<gl::Buffer> buffers;

  // Checks `attributes` against the program: each given names an attribute it uses, once, with data
  // of the kind it declares, and each it uses is given. Throws InvalidArgument otherwise.
  Impl(const GlProgram::Impl& program_impl, std::span<const GlAttribute> attributes, const GlIndices& indices)
      : program(&program_impl), program_name(program_impl.name) {
    const std::string program_text = "program '" + program_name + "'";
    std::map<std::string, const GlAttribute*> given;
    for (const GlAttribute& attribute : attributes) {
      const auto found = program->attributes.find(attribute.name);
      if (found == program->attributes.end()) {
        throw InvalidArgument(program_text + " has no active attribute '" + attribute.name +
                              "' (misspelt, or unused and optimized away)");
      }
      if (!given.emplace(attribute.name, &attribute).second) {
        throw InvalidArgument("attribute '" + attribute.name + "' is given twice");
      }
      const AttributeFormat format = attribute_format(attribute.type);
      if (format.kind != found->second.type->kind) {
        throw InvalidArgument("attribute '" + attribute.name + "' of " + program_text + " is " +
                              found->second.type->glsl + ", not fed from " + kind_name(format.kind) + " data");
      }
      const std::uint64_t elements = available_elements(attribute);
      if (!attribute.per_instance) {
        vertices = std::min(vertices.value_or(elements), elements);
      } else if (!instances || elements < *instances) {
        instances = elements;
        shortest_per_instance = attribute.name;
      }
    }
    for (const auto& [name, attribute] : program->attributes) {
      if (!given.contains(name)) throw InvalidArgument("attribute '" + name + "' of " + program_text + " has no data");
    }
    std::visit(
        [&](const auto& list) {
          if constexpr (!std::is_same_v<std::decay_t<decltype(list)>, std::monostate>) {
            index_size = sizeof(list[0]);
            index_type = index_size == 2 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT;
            index_count = list.size();
          }
        },
        indices);
  }

  ~Impl() { Context::instance().make_current_for_cleanup(); }  // the members' glDelete* need the context

  // Throws InvalidArgument when indices[first, first + count) name a vertex past the shortest
  // per-vertex attribute.
  void check_indices(const GlIndices& indices, std::size_t first, std::size_t count) const {
    std::uint64_t vertex_end = 0;  // one past the highest vertex named
    std::visit(
        [&](const auto& list) {
          if constexpr (!std::is_same_v<std::decay_t<decltype(list)>, std::monostate>) {
            for (const auto index : list.subspan(first, count)) {
              vertex_end = std::max(vertex_end, std::uint64_t{index} + 1);
            }
          }
        },
        indices);
    if (vertices && vertex_end > *vertices) {
      throw InvalidArgument("the draw's indices name vertex " + std::to_string(vertex_end - 1) +
                            " but the shortest per-vertex attribute holds " + std::to_string(*vertices));
    }
  }

  // The number of elements `call` draws. Throws InvalidArgument for more instances than a
  // per-instance attribute holds and for a range past the end of the indices (or, without them, of
  // the per-vertex attributes).
  std::uint32_t draw_elements(const GlDrawCall& call) const {
    if (instances && call.instance_count > *instances) {
      throw InvalidArgument(std::to_string(call.instance_count) + " instances, but per-instance attribute '" +
                            shortest_per_instance + "' holds " + std::to_string(*instances));
    }
    if (call.instance_count > std::uint32_t(std::numeric_limits<GLsizei>::max())) {
      throw InvalidArgument(std::to_string(call.instance_count) + " instances exceed OpenGL's 32-bit signed counts");
    }
    if (index_type != 0) return gl::draw_range(call.first, call.count, index_count, "the indices");
    if (!vertices && call.count == kAllElements) {
      throw InvalidArgument("a draw with neither indices nor per-vertex attributes must give its count");
    }
    const std::uint64_t available = vertices.value_or(std::uint64_t{call.first} + call.count);
    return gl::draw_range(call.first, call.count, available, "the per-vertex attributes");
  }

  // Copies `attributes` (those the constructor checked) and `indices` into GL buffers that the
  // vertex array reads.
  void upload(std::span<const GlAttribute> attributes, const GlIndices& indices) {
    GLuint id = 0;
    glCreateVertexArrays(1, &id);
    vertex_array = gl::VertexArray(id);
    for (std::size_t i = 0; i < attributes.size(); ++i) {
      const GlAttribute& attribute = attributes[i];
      const AttributeFormat format = attribute_format(attribute.type);
      const auto binding = GLuint(i);
      const auto location = GLuint(program->attributes.at(attribute.name).location);
      buffers.push_back(gl::upload_buffer(attribute.data));
      glVertexArrayVertexBuffer(id, binding, buffers.back().get(), GLintptr(attribute.offset),
                                GLsizei(attribute.stride != 0 ? attribute.stride : format.bytes()));
      if (format.kind == Kind::Float) {
        glVertexArrayAttribFormat(id, location, format.components, format.type, GL_FALSE, 0);
      } else {
        glVertexArrayAttribIFormat(id, location, format.components, format.type, 0);
      }
      glVertexArrayAttribBinding(id, location, binding);
      glVertexArrayBindingDivisor(id, binding, attribute.per_instance ? 1 : 0);
      glEnableVertexArrayAttrib(id, location);
    }
    std::visit(
        [&](const auto& list) {
          if constexpr (!std::is_same_v<std::decay_t<decltype(list)>, std::monostate>) {
            buffers.push_back(gl::upload_buffer(std::as_bytes(list)));
            glVertexArrayElementBuffer(id, buffers.back().get());
          }
        },
        indices);
    gl::check("uploading vertex input");
  }
};

GlVertexInput::GlVertexInput(const GlProgram& program, std::span<const GlAttribute> attributes, GlIndices indices)
    : impl_(std::make_unique<Impl>(*program.impl_, attributes, indices)) {
  impl_->check_indices(indices, 0, impl_->index_count);
  Context::instance().make_current();
  impl_->upload(attributes, indices);
}

GlVertexInput::~GlVertexInput() = default;
GlVertexInput::GlVertexInput(GlVertexInput&&) noexcept = default;
GlVertexInput& GlVertexInput::operator=(GlVertexInput&&) noexcept = default;

// ---- GlFramebuffer --------------------------------------------------------------------------------

struct GlFramebuffer::Impl {
  std::vector<GlTexture*> colors;
  GlTexture* depth_stencil;
  int width = 0;
  int height = 0;
  gl::Framebuffer framebuffer;

  Impl(std::vector<GlTexture*> color_textures, GlTexture* depth_stencil_texture)
      : colors(std::move(color_textures)), depth_stencil(depth_stencil_texture) {
    if (colors.size() > std::size_t(kMaxColorAttachments)) {
      throw InvalidArgument(std::to_string(colors.size()) + " colour attachments: at most " +
                            std::to_string(kMaxColorAttachments));
    }
    std::vector<const GlTexture*> all(colors.begin(), colors.end());
    if (depth_stencil) all.push_back(depth_stencil);
    if (all.empty()) throw InvalidArgument("a framebuffer needs at least one attachment");
    for (std::size_t i = 0; i < all.size(); ++i) {
      if (!all[i]) throw InvalidArgument("colour attachment " + std::to_string(i) + " is null");
      const bool is_depth = depth_stencil && i == colors.size();
      const GlFormat& format = all[i]->impl_->gl();
      if (format.color() == is_depth) {
        const std::string attachment = is_depth ? "the depth attachment" : "colour attachment " + std::to_string(i);
        throw InvalidArgument(attachment + " cannot be " + format.name);
      }
    }
    width = all[0]->width();
    height = all[0]->height();
    for (const GlTexture* texture : all) {
      if (texture->width() != width || texture->height() != height) {
        throw InvalidArgument("attachments of " + std::to_string(width) + "x" + std::to_string(height) + " and " +
                              std::to_string(texture->width()) + "x" + std::to_string(texture->height()) +
                              ": all must have one size");
      }
    }

    Context::instance().make_current();
    GLuint id = 0;
    glCreateFramebuffers(1, &id);
    framebuffer = gl::Framebuffer(id);
    std::vector<GLenum> draw_buffers;
    for (std::size_t i = 0; i < colors.size(); ++i) {
      draw_buffers.push_back(GLenum(GL_COLOR_ATTACHMENT0 + i));
      glNamedFramebufferTexture(id, draw_buffers.back(), colors[i]->impl_->texture.get(), 0);
    }
    glNamedFramebufferDrawBuffers(id, GLsizei(draw_buffers.size()), draw_buffers.data());
    if (depth_stencil) {
      glNamedFramebufferTexture(id, depth_stencil->impl_->gl().attachment, depth_stencil->impl_->texture.get(), 0);
    }
    gl::check("creating a framebuffer");
    const GLenum status = glCheckNamedFramebufferStatus(id, GL_DRAW_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
      throw Error("oracle framebuffer is incomplete: " + std::string(gl::framebuffer_status_name(status)));
    }
  }

  ~Impl() { Context::instance().make_current_for_cleanup(); }  // the framebuffer's glDelete* needs the context

  const GlFormat& color_format(int index) const {
    if (index < 0 || index >= int(colors.size())) {
      throw InvalidArgument("colour attachment " + std::to_string(index) + " of a framebuffer with " +
                            std::to_string(colors.size()));
    }
    return colors[std::size_t(index)]->impl_->gl();
  }

  bool has_depth() const { return depth_stencil != nullptr; }
  bool has_stencil() const { return depth_stencil && depth_stencil->impl_->gl().depth_stencil(); }

  // Runs `clear` with nothing masked or scissored, and checks it.
  template <typename Clear>
  void clear(const char* operation, Clear&& clear) const {
    Context::instance().make_current();
    gl::prepare_clear();
    clear(framebuffer.get());
    gl::check(operation);
  }

  void clear_color(int index, const std::array<float, 4>& color) const {
    const GlFormat& format = color_format(index);
    clear("clearing a colour attachment", [&](GLuint id) {
      switch (format.kind) {
        case Kind::Float: return glClearNamedFramebufferfv(id, GL_COLOR, index, color.data());
        case Kind::Int: {
          const std::array<GLint, 4> value = {truncate<GLint>(color[0]), truncate<GLint>(color[1]),
                                              truncate<GLint>(color[2]), truncate<GLint>(color[3])};
          return glClearNamedFramebufferiv(id, GL_COLOR, index, value.data());
        }
        case Kind::UInt: {
          const std::array<GLuint, 4> value = {truncate<GLuint>(color[0]), truncate<GLuint>(color[1]),
                                               truncate<GLuint>(color[2]), truncate<GLuint>(color[3])};
          return glClearNamedFramebufferuiv(id, GL_COLOR, index, value.data());
        }
      }
    });
  }

  void require_kind(int index, Kind kind) const {
    const GlFormat& format = color_format(index);
    if (format.kind != kind) {
      throw InvalidArgument("colour attachment " + std::to_string(index) + " is " + format.name + ", not a " +
                            kind_name(kind) + " format");
    }
  }

  void clear_depth(float depth) const {
    const float clamped = std::clamp(depth, 0.0f, 1.0f);
    clear("clearing depth", [&](GLuint id) { glClearNamedFramebufferfv(id, GL_DEPTH, 0, &clamped); });
  }

  void clear_stencil(std::uint8_t stencil) const {
    const GLint value = stencil;
    clear("clearing stencil", [&](GLuint id) { glClearNamedFramebufferiv(id, GL_STENCIL, 0, &value); });
  }
};

GlFramebuffer::GlFramebuffer(std::vector<GlTexture*> colors, GlTexture* depth_stencil)
    : impl_(std::make_unique<Impl>(std::move(colors), depth_stencil)) {}
GlFramebuffer::~GlFramebuffer() = default;
GlFramebuffer::GlFramebuffer(GlFramebuffer&&) noexcept = default;
GlFramebuffer& GlFramebuffer::operator=(GlFramebuffer&&) noexcept = default;

int GlFramebuffer::width() const { return impl_->width; }
int GlFramebuffer::height() const { return impl_->height; }
int GlFramebuffer::color_count() const { return int(impl_->colors.size()); }
GlTexture& GlFramebuffer::color(int index) const {
  impl_->color_format(index);  // checks the index
  return *impl_->colors[std::size_t(index)];
}
GlTexture* GlFramebuffer::depth_stencil() const { return impl_->depth_stencil; }

void GlFramebuffer::clear(std::array<float, 4> color, float depth, std::uint8_t stencil) {
  clear_color(color);
  if (impl_->has_depth()) impl_->clear_depth(depth);
  if (impl_->has_stencil()) impl_->clear_stencil(stencil);
}

void GlFramebuffer::clear_color(std::array<float, 4> color) {
  for (int i = 0; i < color_count(); ++i) impl_->clear_color(i, color);
}

void GlFramebuffer::clear_color(int index, std::array<float, 4> color) { impl_->clear_color(index, color); }

void GlFramebuffer::clear_color_int(int index, std::array<std::int32_t, 4> value) {
  impl_->require_kind(index, Kind::Int);
  impl_->clear("clearing a colour attachment",
               [&](GLuint id) { glClearNamedFramebufferiv(id, GL_COLOR, index, value.data()); });
}

void GlFramebuffer::clear_color_uint(int index, std::array<std::uint32_t, 4> value) {
  impl_->require_kind(index, Kind::UInt);
  impl_->clear("clearing a colour attachment",
               [&](GLuint id) { glClearNamedFramebufferuiv(id, GL_COLOR, index, value.data()); });
}

void GlFramebuffer::clear_depth(float depth) {
  if (!impl_->has_depth()) throw InvalidArgument("clear_depth on a framebuffer without a depth attachment");
  impl_->clear_depth(depth);
}

void GlFramebuffer::clear_stencil(std::uint8_t stencil) {
  if (!impl_->has_stencil()) throw InvalidArgument("clear_stencil on a framebuffer without a stencil attachment");
  impl_->clear_stencil(stencil);
}

void GlFramebuffer::bind_for_drawing(const DrawState& state) const {
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, impl_->framebuffer.get());
  gl::apply_draw_state(state, impl_->width, impl_->height);
}

void GlFramebuffer::draw(const GlDrawCall& call) {
  if (!call.program) throw InvalidArgument("a draw without a program");
  const GlProgram::Impl& program = *call.program->impl_;
  program.check_complete();
  if (call.advanced_blend) {
    advanced_equation(*call.advanced_blend);  // checks the value
    if (color_count() != 1) {
      throw InvalidArgument("advanced blending needs exactly one colour attachment (OpenGL allows no more), not " +
                            std::to_string(color_count()));
    }
  }
  const GLenum mode = gl::topology(call.state.topology);
  // The call's own attributes and indices are checked, and uploaded for this draw only.
  std::optional<GlVertexInput::Impl> own_input;
  const GlVertexInput::Impl* input = nullptr;
  if (call.vertex_input) {
    input = call.vertex_input->impl_.get();
    if (input->program != &program) {
      throw InvalidArgument("a vertex input made for program '" + input->program_name + "' drawn with program '" +
                            program.name + "'");
    }
    if (!call.attributes.empty() || !std::holds_alternative<std::monostate>(call.indices)) {
      throw InvalidArgument("a draw with a vertex input takes no attributes or indices of its own");
    }
  } else {
    input = &own_input.emplace(program, call.attributes, call.indices);
  }
  const std::uint32_t elements = input->draw_elements(call);
  if (own_input) own_input->check_indices(call.indices, call.first, elements);
  Context::instance().make_current();
  if (own_input) own_input->upload(call.attributes, call.indices);

  bind_for_drawing(call.state);
  if (call.advanced_blend) {
    glEnablei(GL_BLEND, 0);
    glBlendEquationi(0, advanced_equation(*call.advanced_blend));
    Context::instance().blend_barrier();
  }
  program.bind();
  gl::check("setting the draw state");
  glBindVertexArray(input->vertex_array.get());
  const auto instances = GLsizei(call.instance_count);
  if (input->index_type != 0) {
    const auto offset = static_cast<std::uintptr_t>(std::size_t(call.first) * input->index_size);
    glDrawElementsInstanced(mode, GLsizei(elements), input->index_type, reinterpret_cast<const void*>(offset),
                            instances);
    gl::check("glDrawElementsInstanced");
  } else {
    glDrawArraysInstanced(mode, GLint(call.first), GLsizei(elements), instances);
    gl::check("glDrawArraysInstanced");
  }
}

}  // namespace clraster::oracle
