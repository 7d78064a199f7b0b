// Textures: one device buffer per texture (resources/texture_layout.hpp), filled from the host, from
// image files (stb_image), or by the texture_downsample kernel (resources/texture.cl).
#include "api/errors.hpp"
#include "api/impl.hpp"
#include "resources/texture_layout.hpp"
#include "runtime/launch.hpp"

#include <stb/stb_image.h>

#include <algorithm>
#include <cerrno>
#include <climits>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>

namespace clraster {
namespace {

std::string size_text(int width, int height) { return std::to_string(width) + "x" + std::to_string(height); }

void check_format_and_size(Format format, int width, int height) {
  format_info(format);  // throws for a format that does not exist
  if (width < 1 || height < 1 || width > kMaxTextureSize || height > kMaxTextureSize) {
    throw InvalidArgument("texture size " + size_text(width, height) + " is out of range: each side must be 1.." +
                          std::to_string(kMaxTextureSize));
  }
}

// The level count `levels` asks for (kFullMipChain: all of them), checked.
int resolve_levels(Format format, int width, int height, int levels) {
  const int full = resources::full_mip_chain(width, height);
  if (levels == kFullMipChain) levels = full;
  if (levels < 1 || levels > full) {
    throw InvalidArgument(std::to_string(levels) + " mip levels requested for a " + size_text(width, height) +
                          " texture: it has 1.." + std::to_string(full) + " (or kFullMipChain)");
  }
  if (format_info(format).stencil && levels != 1) {
    // The stencil plane follows level 0 (TextureDesc::stencil_offset): there is room for one level.
    throw InvalidArgument(std::string(format_info(format).name) + " textures have one level; " +
                          std::to_string(levels) + " requested");
  }
  return levels;
}

// `texels` must be exactly the level's texels.
void check_level_data(Format format, int width, int height, int level, std::size_t texels) {
  const int level_width = resources::level_extent(width, level), level_height = resources::level_extent(height, level);
  const std::size_t bytes = static_cast<std::size_t>(level_width) * static_cast<std::size_t>(level_height) *
                            static_cast<std::size_t>(format_info(format).bytes_per_texel);
  if (texels != bytes) {
    throw InvalidArgument("level " + std::to_string(level) + " of the " + size_text(width, height) + " " +
                          format_info(format).name + " texture is " + size_text(level_width, level_height) +
                          " texels, " + std::to_string(bytes) + " bytes; got " + std::to_string(texels) + " bytes");
  }
}

void check_mipmappable(Format format) {
  const FormatInfo& info = format_info(format);
  if (info.integer || info.depth) {
    throw InvalidArgument(std::string("cannot generate mipmaps for ") + info.name +
                          " textures: " + (info.integer ? "integer" : "depth") + " formats cannot be filtered");
  }
}

// A new zero-filled texture.
std::unique_ptr<Texture::Impl> make_texture(Context& context, int width, int height, Format format, int levels) {
  check_format_and_size(format, width, height);
  auto impl = std::make_unique<Texture::Impl>();
  impl->state = context.impl().state;
  impl->format = format;
  impl->width = width;
  impl->height = height;
  impl->levels = resolve_levels(format, width, height, levels);
  const std::size_t bytes = resources::texture_layout(format, width, height, impl->levels).total_bytes;
  const std::string what = "the " + size_text(width, height) + " " + format_info(format).name + " texture's " +
                           std::to_string(impl->levels) + " levels";
  check_allocation(*impl->state, bytes, what.c_str());
  translate_cl_errors([&] {
    impl->data = cl::Buffer(impl->state->context, CL_MEM_READ_WRITE, bytes);
    impl->state->queue.get().enqueueFillBuffer(impl->data, cl_uchar{0}, 0, bytes);
  });
  return impl;
}

// Fills level 0's plane at byte `offset` of `texture` with `value` through the clear kernel of its
// kind ("float", "int", "uint"), which converts it as rendered fragments are (clear.cl). `format`: the
// plane's layout.
template <typename Value>
void clear_texels(ContextState& state, const Texture::Impl& texture, Format format, const char* kind, Value value) {
  cl::Kernel kernel(state.core_program(), (std::string("clear_texels_") + kind).c_str());
  const auto count = static_cast<cl_uint>(std::size_t(texture.width) * std::size_t(texture.height));
  runtime::set_args(kernel, cl_int{static_cast<int>(format)}, texture.data, count, value);
  state.queue.set_stage(runtime::Stage::Other);
  const std::size_t items = runtime::divide_round_up(count, CLR_CLEAR_TEXELS_PER_ITEM);  // clear.cl
  runtime::enqueue_items(state.queue, kernel, items, CLR_ITEM_GROUP_SIZE);
}

void check_level(const Texture::Impl& texture, int level) {
  if (level < 0 || level >= texture.levels) {
    throw InvalidArgument("texture level " + std::to_string(level) + " does not exist: the texture has " +
                          std::to_string(texture.levels) + (texture.levels == 1 ? " level" : " levels"));
  }
}

// ---- Image files --------------------------------------------------------------------------------

struct FileCloser {
  void operator()(std::FILE* file) const { std::fclose(file); }
};

// stb_image reads at most this many encoded bytes (its lengths are ints).
constexpr std::size_t kMaxEncodedBytes = INT_MAX;

std::string too_large(const std::string& name) {
  return "cannot decode " + name + ": it is larger than the " + std::to_string(kMaxEncodedBytes >> 20) +
         " MiB stb_image reads";
}

// The whole file. Opened and read here rather than by stb, so failures carry the system's reason
// ("No such file or directory", "Is a directory") rather than stb's generic one. Stops past
// kMaxEncodedBytes, so an endless file (a device, a pipe) cannot exhaust memory.
std::vector<std::byte> read_file(const std::string& path) {
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "rb"));
  if (!file) throw InvalidArgument("cannot read " + path + ": " + std::strerror(errno));
  std::vector<std::byte> bytes;
  std::byte chunk[1 << 16];
  while (const std::size_t count = std::fread(chunk, 1, sizeof chunk, file.get())) {
    bytes.insert(bytes.end(), chunk, chunk + count);
    if (bytes.size() > kMaxEncodedBytes) throw InvalidArgument(too_large(path));
  }
  if (std::ferror(file.get())) throw InvalidArgument("cannot read " + path + ": " + std::strerror(errno));
  return bytes;
}

struct StbiFree {
  void operator()(stbi_uc* pixels) const { stbi_image_free(pixels); }
};

}  // namespace

// ---- The private side -----------------------------------------------------------------------------

TextureDesc Texture::Impl::describe(const Sampler& sampler) const {
  static_assert(static_cast<int>(Filter::Linear) == CLR_FILTER_LINEAR &&
                    static_cast<int>(MipFilter::Linear) == CLR_MIP_LINEAR &&
                    static_cast<int>(Wrap::MirroredRepeat) == CLR_WRAP_MIRRORED_REPEAT,
                "the sampler enums must follow CLR_FILTER_*, CLR_MIP_* and CLR_WRAP_*");
  const auto in_range = [](auto value, auto last) {
    return static_cast<int>(value) >= 0 && static_cast<int>(value) <= static_cast<int>(last);
  };
  if (!in_range(sampler.mag_filter, Filter::Linear) || !in_range(sampler.min_filter, Filter::Linear) ||
      !in_range(sampler.mip_filter, MipFilter::Linear) || !in_range(sampler.wrap_s, Wrap::MirroredRepeat) ||
      !in_range(sampler.wrap_t, Wrap::MirroredRepeat)) {
    throw InvalidArgument("sampler has a filter or wrap mode that does not exist");
  }
  const resources::TextureLayout layout = resources::texture_layout(format, width, height, levels);
  TextureDesc desc{};
  std::copy(layout.level_offset.begin(), layout.level_offset.end(), desc.level_offset);
  desc.stencil_offset = static_cast<clr_uint>(layout.stencil_offset);
  desc.format = static_cast<clr_int>(format);
  desc.width = width;
  desc.height = height;
  desc.levels = levels;
  desc.mag_filter = static_cast<clr_int>(sampler.mag_filter);
  desc.min_filter = static_cast<clr_int>(sampler.min_filter);
  desc.mip_filter = static_cast<clr_int>(sampler.mip_filter);
  desc.wrap_s = static_cast<clr_int>(sampler.wrap_s);
  desc.wrap_t = static_cast<clr_int>(sampler.wrap_t);
  desc.lod_bias = sampler.lod_bias;
  desc.min_lod = sampler.min_lod;
  desc.max_lod = sampler.max_lod;
  return desc;
}

std::size_t Texture::Impl::level_offset_bytes(int level) const {
  const resources::TextureLayout layout = resources::texture_layout(format, width, height, levels);
  return std::size_t{layout.level_offset[level]} * static_cast<std::size_t>(format_info(format).bytes_per_texel);
}

std::size_t Texture::Impl::level_bytes(int level) const {
  return static_cast<std::size_t>(resources::level_extent(width, level)) *
         static_cast<std::size_t>(resources::level_extent(height, level)) *
         static_cast<std::size_t>(format_info(format).bytes_per_texel);
}

// ---- The public side ------------------------------------------------------------------------------

Texture::Texture(Context& context, int width, int height, Format format, int levels)
    : impl_(make_texture(context, width, height, format, levels)) {}

Texture::Texture(Context& context, int width, int height, Format format, std::span<const std::byte> level0,
                 bool mipmaps) {
  // Everything is checked before the texture is allocated.
  check_format_and_size(format, width, height);
  check_level_data(format, width, height, 0, level0.size());
  if (mipmaps) check_mipmappable(format);
  impl_ = make_texture(context, width, height, format, mipmaps ? kFullMipChain : 1);
  upload(0, level0);
  if (mipmaps) generate_mipmaps();
}

Texture Texture::load(Context& context, const std::string& path, bool srgb, bool flip_vertically) {
  return decode(context, read_file(path), srgb, flip_vertically, path);
}

Texture Texture::decode(Context& context, std::span<const std::byte> encoded, bool srgb, bool flip_vertically,
                        const std::string& name) {
  if (encoded.size() > kMaxEncodedBytes) throw InvalidArgument(too_large(name));
  const auto* bytes = reinterpret_cast<const stbi_uc*>(encoded.data());
  const int length = static_cast<int>(encoded.size());
  // The size first, so an oversized picture is refused before it is decoded into memory.
  int width = 0, height = 0, channels_in_file = 0;
  if (!stbi_info_from_memory(bytes, length, &width, &height, &channels_in_file)) {
    throw InvalidArgument("cannot decode " + name + ": " + stbi_failure_reason());
  }
  if (width > kMaxTextureSize || height > kMaxTextureSize) {
    throw InvalidArgument("cannot load " + name + ": its " + size_text(width, height) +
                          " pixels exceed the texture size limit of " + std::to_string(kMaxTextureSize) + " per side");
  }
  const std::unique_ptr<stbi_uc, StbiFree> pixels(
      stbi_load_from_memory(bytes, length, &width, &height, &channels_in_file, 4));
  if (!pixels) throw InvalidArgument("cannot decode " + name + ": " + stbi_failure_reason());

  const std::size_t row_bytes = static_cast<std::size_t>(width) * 4;
  std::vector<std::byte> texels(row_bytes * static_cast<std::size_t>(height));
  for (int y = 0; y < height; ++y) {
    // The file's first row is t = 0, unless flipped: then its last row is.
    const int row = flip_vertically ? height - 1 - y : y;
    std::memcpy(texels.data() + static_cast<std::size_t>(y) * row_bytes,
                pixels.get() + static_cast<std::size_t>(row) * row_bytes, row_bytes);
  }
  return Texture(context, width, height, srgb ? Format::SRGB8_A8 : Format::RGBA8, texels);
}

Texture::~Texture() = default;
Texture::Texture(Texture&&) noexcept = default;
Texture& Texture::operator=(Texture&&) noexcept = default;

int Texture::width(int level) const {
  check_level(*impl_, level);
  return resources::level_extent(impl_->width, level);
}

int Texture::height(int level) const {
  check_level(*impl_, level);
  return resources::level_extent(impl_->height, level);
}

int Texture::levels() const { return impl_->levels; }
Format Texture::format() const { return impl_->format; }

void Texture::Impl::write_pending_clear() const {
  if (!pending_clear.any()) return;
  ContextState& context = *state;
  const FormatInfo& info = format_info(format);
  if (pending_clear.color) {
    const auto& bits = pending_clear.color_bits;
    if (!info.integer) {
      cl_float4 value;
      std::memcpy(&value, bits.data(), sizeof value);
      clear_texels(context, *this, format, "float", value);
    } else if (info.is_signed) {
      clear_texels(context, *this, format, "int", cl_int4{{static_cast<cl_int>(bits[0]), static_cast<cl_int>(bits[1]), static_cast<cl_int>(bits[2]), static_cast<cl_int>(bits[3])}});
    } else {
      clear_texels(context, *this, format, "uint", cl_uint4{{bits[0], bits[1], bits[2], bits[3]}});
    }
  }
  const std::size_t texels = std::size_t(width) * std::size_t(height);
  if (pending_clear.depth) {
    context.queue.get().enqueueFillBuffer(data, pending_clear.depth_value, 0, texels * sizeof(float));
  }
  if (pending_clear.stencil) {
    context.queue.get().enqueueFillBuffer(data, cl_uchar{pending_clear.stencil_value}, describe().stencil_offset, texels);
  }
  pending_clear = {};
}

void Texture::upload(int level, std::span<const std::byte> texels) {
  check_level(*impl_, level);
  check_level_data(impl_->format, impl_->width, impl_->height, level, texels.size());
  translate_cl_errors([&] {
    impl_->write_pending_clear();  // before the texels it would otherwise overwrite
    impl_->state->queue.get().enqueueWriteBuffer(impl_->data, CL_TRUE, impl_->level_offset_bytes(level), texels.size(),
                                                 texels.data());
  });
}

void Texture::generate_mipmaps() {
  check_mipmappable(impl_->format);
  ContextState& state = *impl_->state;
  translate_cl_errors([&] {
    // texture_downsample samples each level bilinearly, clamped to its edges.
    const TextureDesc desc =
        impl_->describe(Sampler{Filter::Linear, Filter::Linear, MipFilter::None, Wrap::ClampToEdge, Wrap::ClampToEdge});
    cl::Buffer desc_buffer(state.context, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, sizeof desc,
                           const_cast<TextureDesc*>(&desc));
    impl_->write_pending_clear();
    cl::Kernel kernel(state.core_program(), "texture_downsample");
    // Level by level: each reads the one before, and the queue runs commands in order.
    for (int level = 1; level < impl_->levels; ++level) {
      runtime::set_args(kernel, impl_->data, desc_buffer, cl_int{level - 1});
      const std::size_t texels = static_cast<std::size_t>(width(level)) * static_cast<std::size_t>(height(level));
      state.queue.get().enqueueNDRangeKernel(kernel, cl::NullRange,
                                             cl::NDRange(runtime::round_up(texels, CLR_ITEM_GROUP_SIZE)),
                                             cl::NDRange(CLR_ITEM_GROUP_SIZE));
    }
  });
}

std::size_t Texture::memory_bytes() const { return impl_->data.getInfo<CL_MEM_SIZE>(); }

std::vector<std::byte> Texture::read(int level) const {
  check_level(*impl_, level);
  std::vector<std::byte> texels(impl_->level_bytes(level));
  translate_cl_errors([&] {
    impl_->write_pending_clear();
    impl_->state->queue.get().enqueueReadBuffer(impl_->data, CL_TRUE, impl_->level_offset_bytes(level), texels.size(),
                                                texels.data());
  });
  return texels;
}

std::vector<std::byte> Texture::Impl::read_rect(const Rect& rect) const {
  const std::size_t texel = format_info(format).bytes_per_texel;
  std::vector<std::byte> texels(static_cast<std::size_t>(rect.width) * static_cast<std::size_t>(rect.height) * texel);
  translate_cl_errors([&] {
    write_pending_clear();
    const cl::array<cl::size_type, 3> buffer_origin{static_cast<std::size_t>(rect.x) * texel,
                                                    static_cast<std::size_t>(rect.y), 0};
    const cl::array<cl::size_type, 3> region{static_cast<std::size_t>(rect.width) * texel,
                                             static_cast<std::size_t>(rect.height), 1};
    state->queue.get().enqueueReadBufferRect(data, CL_TRUE, buffer_origin, {0, 0, 0}, region,
                                             static_cast<std::size_t>(width) * texel, 0,
                                             static_cast<std::size_t>(rect.width) * texel, 0, texels.data());
  });
  return texels;
}

std::vector<std::uint8_t> Texture::read_stencil() const {
  const FormatInfo& info = format_info(impl_->format);
  if (!info.stencil)
    throw InvalidArgument(std::string("read_stencil needs a texture with stencil; this one is ") + info.name);
  std::vector<std::uint8_t> stencil(static_cast<std::size_t>(impl_->width) * static_cast<std::size_t>(impl_->height));
  const std::size_t offset = resources::texture_layout(impl_->format, impl_->width, impl_->height, 1).stencil_offset;
  translate_cl_errors([&] {
    impl_->write_pending_clear();
    impl_->state->queue.get().enqueueReadBuffer(impl_->data, CL_TRUE, offset, stencil.size(), stencil.data());
  });
  return stencil;
}

}  // namespace clraster
