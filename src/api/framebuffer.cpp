#include "api/errors.hpp"
#include "api/impl.hpp"
#include "shared/clr_limits.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

namespace clraster {
namespace {

// Copies rows of `row_bytes` in reverse order: textures keep row 0 at the bottom, images at the top.
void flip_rows(const std::byte* bottom_up, std::size_t row_bytes, int height, std::byte* top_down) {
  for (int y = 0; y < height; ++y) {
    std::memcpy(top_down + static_cast<std::size_t>(height - 1 - y) * row_bytes,
                bottom_up + static_cast<std::size_t>(y) * row_bytes, row_bytes);
  }
}

void check_size(int width, int height) {
  if (width < 1 || height < 1 || width > CLR_MAX_FRAMEBUFFER_SIZE || height > CLR_MAX_FRAMEBUFFER_SIZE) {
    throw InvalidArgument("framebuffer size " + std::to_string(width) + "x" + std::to_string(height) +
                          " is out of range: each side must be 1.." + std::to_string(CLR_MAX_FRAMEBUFFER_SIZE));
  }
}

// Clears are recorded, not written: the next draw into the texture writes them with its tiles
// (resources/pending_clear.hpp). A clear replaces the pending one of the same part.
template <typename Channel>
void record_color_clear(const Texture::Impl& texture, std::array<Channel, 4> value) {
  static_assert(sizeof(Channel) == sizeof(std::uint32_t));
  texture.pending_clear.color = true;
  std::memcpy(texture.pending_clear.color_bits.data(), value.data(), sizeof value);
}

}  // namespace

Framebuffer::Framebuffer(Context& context, int width, int height) : Framebuffer(context, width, height, 1) {}

Framebuffer::Framebuffer(Context& context, int width, int height, int layers) : impl_(std::make_unique<Impl>()) {
  check_size(width, height);
  if (layers < 1 || layers > CLR_MAX_LAYERS) {
    throw InvalidArgument("a framebuffer has 1.." + std::to_string(CLR_MAX_LAYERS) + " layers, not " + std::to_string(layers));
  }
  // The smallest square grid that holds the layers.
  int columns = 1;
  while (columns * columns < layers) ++columns;
  const int rows = (layers + columns - 1) / columns;
  if (std::int64_t{width} * columns > CLR_MAX_FRAMEBUFFER_SIZE || std::int64_t{height} * rows > CLR_MAX_FRAMEBUFFER_SIZE) {
    throw InvalidArgument(std::to_string(layers) + " layers of " + std::to_string(width) + "x" + std::to_string(height) +
                          " need attachments of " + std::to_string(std::int64_t{width} * columns) + "x" +
                          std::to_string(std::int64_t{height} * rows) + " pixels, more than " +
                          std::to_string(CLR_MAX_FRAMEBUFFER_SIZE) + " per side");
  }
  impl_->state = context.impl().state;
  impl_->width = width;
  impl_->height = height;
  impl_->layers = layers;
  impl_->layer_columns = columns;
  impl_->owned.reserve(2);
  impl_->owned.emplace_back(context, width * columns, height * rows, Format::RGBA8);
  impl_->owned.emplace_back(context, width * columns, height * rows, Format::Depth32FStencil8);
  impl_->colors = {&impl_->owned[0]};
  impl_->depth_stencil = &impl_->owned[1];
  clear({0, 0, 0, 1}, 1.0f, 0);
}

Framebuffer::Framebuffer(Context& context, std::vector<Texture*> colors, Texture* depth_stencil)
    : impl_(std::make_unique<Impl>()) {
  impl_->state = context.impl().state;
  if (colors.size() > kMaxColorAttachments) {
    throw InvalidArgument("a framebuffer has at most " + std::to_string(kMaxColorAttachments) + " colour attachments, not " +
                          std::to_string(colors.size()));
  }
  std::vector<Texture*> all = colors;
  if (depth_stencil != nullptr) all.push_back(depth_stencil);
  if (all.empty()) throw InvalidArgument("a framebuffer needs at least one attachment");
  for (std::size_t i = 0; i < all.size(); ++i) {
    const std::string name = i < colors.size() ? "colour attachment " + std::to_string(i) : "depth attachment";
    if (all[i] == nullptr) throw InvalidArgument(name + " is null");
    if (all[i]->impl().state != impl_->state) throw InvalidArgument(name + " belongs to another context than the framebuffer");
    if (all[i]->width() != all[0]->width() || all[i]->height() != all[0]->height()) {
      throw InvalidArgument(name + " is " + std::to_string(all[i]->width()) + "x" + std::to_string(all[i]->height()) +
                            " but the framebuffer's first attachment is " + std::to_string(all[0]->width()) + "x" +
                            std::to_string(all[0]->height()));
    }
    const bool depth = format_info(all[i]->format()).depth;
    if (depth != (i >= colors.size())) {
      throw InvalidArgument(name + " has the format " + format_info(all[i]->format()).name + ", which is " +
                            (depth ? "a depth format" : "not a depth format"));
    }
  }
  impl_->colors = std::move(colors);
  impl_->depth_stencil = depth_stencil;
  impl_->width = all[0]->width();
  impl_->height = all[0]->height();
}

Framebuffer::~Framebuffer() = default;
Framebuffer::Framebuffer(Framebuffer&&) noexcept = default;
Framebuffer& Framebuffer::operator=(Framebuffer&&) noexcept = default;

int Framebuffer::width() const { return impl_->width; }
int Framebuffer::height() const { return impl_->height; }
int Framebuffer::layers() const { return impl_->layers; }
int Framebuffer::layer_columns() const { return impl_->layer_columns; }
Rect Framebuffer::layer_rect(int layer) const { return impl_->layer_rect(layer); }

Rect Framebuffer::Impl::layer_rect(int layer) const {
  if (layer < 0 || layer >= layers) {
    throw InvalidArgument("layer " + std::to_string(layer) + " does not exist: the framebuffer has " + std::to_string(layers));
  }
  return {layer % layer_columns * width, layer / layer_columns * height, width, height};
}

int Framebuffer::color_count() const { return static_cast<int>(impl_->colors.size()); }
Texture* Framebuffer::depth_stencil() { return impl_->depth_stencil; }

Texture& Framebuffer::color(int index) {
  if (index < 0 || index >= color_count()) {
    throw InvalidArgument("colour attachment " + std::to_string(index) + " does not exist: the framebuffer has " +
                          std::to_string(color_count()));
  }
  return *impl_->colors[static_cast<std::size_t>(index)];
}

void Framebuffer::clear(std::array<float, 4> color, float depth, std::uint8_t stencil) {
  clear_color(color);
  clear_depth(depth);
  clear_stencil(stencil);
}

namespace {

// A float clear value for an integer attachment (OpenGL leaves it undefined): truncated toward
// zero, as llvmpipe does, and saturated to the integer's range, NaN as 0, where a plain conversion
// would be undefined behaviour.
template <typename Integer>
std::array<Integer, 4> saturated(std::array<float, 4> color) {
  constexpr Integer lowest = std::numeric_limits<Integer>::min(), highest = std::numeric_limits<Integer>::max();
  std::array<Integer, 4> value{};
  for (std::size_t c = 0; c < 4; ++c) {
    const float v = color[c];
    if (std::isnan(v)) value[c] = 0;
    else if (v <= static_cast<float>(lowest)) value[c] = lowest;
    else if (v >= static_cast<float>(highest)) value[c] = highest;  // the float is 2^31 or 2^32, past it
    else value[c] = static_cast<Integer>(v);
  }
  return value;
}

}  // namespace

void Framebuffer::clear_color(std::array<float, 4> color) {
  for (int k = 0; k < color_count(); ++k) {
    const FormatInfo& info = format_info(impl_->colors[static_cast<std::size_t>(k)]->format());
    if (!info.integer) clear_color(k, color);
    else if (info.is_signed) clear_color_int(k, saturated<std::int32_t>(color));
    else clear_color_uint(k, saturated<std::uint32_t>(color));
  }
}

void Framebuffer::clear_color(int index, std::array<float, 4> color) {
  const Texture::Impl& texture = this->color(index).impl();
  if (format_info(texture.format).integer) {
    throw InvalidArgument("colour attachment " + std::to_string(index) + " is " + format_info(texture.format).name +
                          ": clear it with clear_color_int or clear_color_uint");
  }
  record_color_clear(texture, color);
}

void Framebuffer::clear_color_int(int index, std::array<std::int32_t, 4> value) {
  const Texture::Impl& texture = color(index).impl();
  const FormatInfo& info = format_info(texture.format);
  if (!info.integer || !info.is_signed) {
    throw InvalidArgument("colour attachment " + std::to_string(index) + " is " + info.name + ", not a signed integer format");
  }
  record_color_clear(texture, value);
}

void Framebuffer::clear_color_uint(int index, std::array<std::uint32_t, 4> value) {
  const Texture::Impl& texture = color(index).impl();
  const FormatInfo& info = format_info(texture.format);
  if (!info.integer || info.is_signed) {
    throw InvalidArgument("colour attachment " + std::to_string(index) + " is " + info.name + ", not an unsigned integer format");
  }
  record_color_clear(texture, value);
}

void Framebuffer::clear_depth(float depth) {
  if (impl_->depth_stencil == nullptr) return;
  // As glClearDepth: clamped to [0, 1].
  const float value = std::isnan(depth) ? 0.0f : std::clamp(depth, 0.0f, 1.0f);
  resources::PendingClear& pending = impl_->depth_stencil->impl().pending_clear;
  pending.depth = true;
  pending.depth_value = value;
}

void Framebuffer::clear_stencil(std::uint8_t stencil) {
  if (impl_->depth_stencil == nullptr || !format_info(impl_->depth_stencil->format()).stencil) return;
  resources::PendingClear& pending = impl_->depth_stencil->impl().pending_clear;
  pending.stencil = true;
  pending.stencil_value = stencil;
}

Image Framebuffer::read_color(int index, int layer) const {
  Texture& texture = const_cast<Framebuffer*>(this)->color(index);
  const FormatInfo& info = format_info(texture.format());
  if (info.integer || info.bytes_per_texel != info.channels) {
    throw InvalidArgument(std::string("read_color converts 8-bit normalized attachments; attachment ") +
                          std::to_string(index) + " is " + info.name + ": read it with color(" + std::to_string(index) +
                          ").read()");
  }
  const std::vector<std::byte> texels = texture.impl().read_rect(impl_->layer_rect(layer));
  Image image;
  image.width = width();
  image.height = height();
  const std::size_t pixels = std::size_t(image.width) * std::size_t(image.height);
  std::vector<std::byte> rgba(pixels * 4);
  for (std::size_t i = 0; i < pixels; ++i) {
    for (int c = 0; c < 4; ++c) {
      // Missing channels read as 0, a missing alpha as 1 (OpenGL's rule for R and RG formats).
      rgba[i * 4 + c] = c < info.channels ? texels[i * std::size_t(info.channels) + c] : std::byte{static_cast<unsigned char>(c == 3 ? 255 : 0)};
    }
  }
  image.rgba.resize(pixels * 4);
  flip_rows(rgba.data(), std::size_t(image.width) * 4, image.height, reinterpret_cast<std::byte*>(image.rgba.data()));
  return image;
}

std::vector<float> Framebuffer::read_depth(int layer) const {
  if (impl_->depth_stencil == nullptr) throw InvalidArgument("the framebuffer has no depth attachment");
  const Rect rect = impl_->layer_rect(layer);
  const std::vector<std::byte> texels = impl_->depth_stencil->impl().read_rect(rect);
  std::vector<float> top_down(std::size_t(width()) * std::size_t(height()));
  flip_rows(texels.data(), std::size_t(width()) * sizeof(float), height(), reinterpret_cast<std::byte*>(top_down.data()));
  return top_down;
}

std::vector<std::uint8_t> Framebuffer::read_stencil(int layer) const {
  if (impl_->depth_stencil == nullptr || !format_info(impl_->depth_stencil->format()).stencil) {
    throw InvalidArgument("the framebuffer has no stencil attachment");
  }
  const Rect rect = impl_->layer_rect(layer);
  // The stencil plane is one byte a pixel: read whole, and the layer's rows taken from it.
  const std::vector<std::uint8_t> bottom_up = impl_->depth_stencil->read_stencil();
  const auto attachment_width = static_cast<std::size_t>(impl_->depth_stencil->width());
  std::vector<std::uint8_t> top_down(std::size_t(width()) * std::size_t(height()));
  for (int y = 0; y < height(); ++y) {
    const std::uint8_t* row = bottom_up.data() + (std::size_t(rect.y) + std::size_t(y)) * attachment_width + std::size_t(rect.x);
    std::copy(row, row + width(), top_down.begin() + static_cast<std::ptrdiff_t>(std::size_t(height() - 1 - y) * std::size_t(width())));
  }
  return top_down;
}

}  // namespace clraster
