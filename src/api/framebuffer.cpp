#include "api/errors.hpp"
#include "api/impl.hpp"
#include "clr_limits.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <string>

namespace clraster {
namespace {

std::uint8_t to_unorm8(float value) {
  if (!(value > 0.0f)) return 0;  // also NaN
  return static_cast<std::uint8_t>(std::min(value, 1.0f) * 255.0f + 0.5f);
}

void check_same_context(const Framebuffer::Impl& target, const std::shared_ptr<ContextState>& state, const char* what) {
  if (target.state != state) throw InvalidArgument(std::string(what) + " belongs to another context than the framebuffer");
}

// Copies rows of `width` elements in reverse order: the device keeps row 0 at the bottom, images
// put it at the top.
template <typename T>
void flip_rows(const std::vector<T>& bottom_up, int width, int height, T* top_down) {
  const auto row = static_cast<std::size_t>(width);
  for (int y = 0; y < height; ++y) {
    std::memcpy(top_down + static_cast<std::size_t>(height - 1 - y) * row, bottom_up.data() + y * row, row * sizeof(T));
  }
}

}  // namespace

Framebuffer::Framebuffer(Context& context, int width, int height) : impl_(std::make_unique<Impl>()) {
  if (width < 1 || height < 1 || width > CLR_MAX_FRAMEBUFFER_SIZE || height > CLR_MAX_FRAMEBUFFER_SIZE) {
    throw InvalidArgument("framebuffer size " + std::to_string(width) + "x" + std::to_string(height) +
                          " is out of range: each side must be 1.." + std::to_string(CLR_MAX_FRAMEBUFFER_SIZE));
  }
  impl_->state = context.impl().state;
  const std::size_t bytes = static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4;
  check_allocation(*impl_->state, bytes, "framebuffer attachments");
  translate_cl_errors([&] {
    impl_->target.color = cl::Buffer(impl_->state->context, CL_MEM_READ_WRITE, bytes);
    impl_->target.depth = cl::Buffer(impl_->state->context, CL_MEM_READ_WRITE, bytes);
  });
  impl_->target.width = width;
  impl_->target.height = height;
  clear({0, 0, 0, 1}, 1.0f);
}
Framebuffer::~Framebuffer() = default;
Framebuffer::Framebuffer(Framebuffer&&) noexcept = default;
Framebuffer& Framebuffer::operator=(Framebuffer&&) noexcept = default;

int Framebuffer::width() const { return impl_->target.width; }
int Framebuffer::height() const { return impl_->target.height; }

void Framebuffer::clear(std::array<float, 4> color, float depth, std::uint8_t) {
  clear_color(color);
  clear_depth(depth);
}

void Framebuffer::clear_color(std::array<float, 4> color) {
  const cl_uint packed = cl_uint{to_unorm8(color[0])} | cl_uint{to_unorm8(color[1])} << 8 |
                         cl_uint{to_unorm8(color[2])} << 16 | cl_uint{to_unorm8(color[3])} << 24;
  const std::size_t bytes = static_cast<std::size_t>(width()) * static_cast<std::size_t>(height()) * 4;
  translate_cl_errors([&] { impl_->state->queue.get().enqueueFillBuffer(impl_->target.color, packed, 0, bytes); });
}

void Framebuffer::clear_depth(float depth) {
  // As glClearDepth: clamped to [0, 1].
  const float value = std::isnan(depth) ? 0.0f : std::clamp(depth, 0.0f, 1.0f);
  const std::size_t bytes = static_cast<std::size_t>(width()) * static_cast<std::size_t>(height()) * 4;
  translate_cl_errors([&] { impl_->state->queue.get().enqueueFillBuffer(impl_->target.depth, value, 0, bytes); });
}

DrawStats Framebuffer::draw(const DrawCall& call) {
  if (call.vertices == nullptr) throw InvalidArgument("draw call has no vertex buffer");
  const VertexBuffer::Impl& vertices = call.vertices->impl();
  check_same_context(*impl_, vertices.state, "vertex buffer");
  pipeline::DrawSource source;
  source.positions = vertices.positions;
  source.normals = vertices.normals;
  source.has_normals = vertices.has_normals;
  source.vertex_count = vertices.count;
  source.element_count = vertices.count;
  if (call.indices != nullptr) {
    IndexBuffer::Impl& indices = call.indices->impl();
    check_same_context(*impl_, indices.state, "index buffer");
    source.indices = indices.indices;
    source.index_size = indices.index_size;
    source.index_cache = &indices.range_cache;
    source.element_count = indices.count;
  }
  return translate_cl_errors(
      [&] { return impl_->state->get_pipeline().draw(impl_->target, source, call.first, call.count, call.state); });
}

Image Framebuffer::read_color(int) const {
  Image image;
  image.width = width();
  image.height = height();
  const std::size_t pixels = static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
  std::vector<cl_uint> bottom_up(pixels);
  translate_cl_errors([&] {
    impl_->state->queue.get().enqueueReadBuffer(impl_->target.color, CL_TRUE, 0, pixels * 4, bottom_up.data());
  });
  image.rgba.resize(pixels * 4);
  // Packed as R | G << 8 | B << 16 | A << 24; on the little-endian hosts OpenCL runs on, that is the
  // byte order R, G, B, A.
  static_assert(std::endian::native == std::endian::little);
  flip_rows(bottom_up, image.width, image.height, reinterpret_cast<cl_uint*>(image.rgba.data()));
  return image;
}

std::vector<float> Framebuffer::read_depth() const {
  const std::size_t pixels = static_cast<std::size_t>(width()) * static_cast<std::size_t>(height());
  std::vector<float> bottom_up(pixels);
  translate_cl_errors([&] {
    impl_->state->queue.get().enqueueReadBuffer(impl_->target.depth, CL_TRUE, 0, pixels * 4, bottom_up.data());
  });
  std::vector<float> top_down(pixels);
  flip_rows(bottom_up, width(), height(), top_down.data());
  return top_down;
}

}  // namespace clraster
