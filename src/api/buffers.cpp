#include "api/errors.hpp"
#include "api/impl.hpp"

#include <algorithm>
#include <string>

namespace clraster {
namespace {

// Device buffer holding a copy of `bytes` bytes (at least a few bytes: OpenCL has no empty buffers).
cl::Buffer upload(ContextState& state, const void* data, std::size_t bytes, const char* what) {
  check_allocation(state, bytes, what);
  if (bytes == 0) return cl::Buffer(state.context, CL_MEM_READ_WRITE, 16);
  return cl::Buffer(state.context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, bytes, const_cast<void*>(data));
}

// Index and vertex numbers travel in 32-bit kernel arguments.
constexpr std::size_t kMaxElements = 0xfffffff0u;

}  // namespace

Buffer::Buffer(Context& context, std::size_t bytes) : impl_(std::make_unique<Impl>()) {
  impl_->state = context.impl().state;
  check_allocation(*impl_->state, bytes, "buffer");
  translate_cl_errors([&] {
    impl_->buffer = cl::Buffer(impl_->state->context, CL_MEM_READ_WRITE, std::max<std::size_t>(bytes, 16));
    impl_->state->queue.get().enqueueFillBuffer(impl_->buffer, cl_uchar{0}, 0, std::max<std::size_t>(bytes, 16));
  });
  impl_->bytes = bytes;
}

Buffer::Buffer(Context& context, std::span<const std::byte> data) : impl_(std::make_unique<Impl>()) {
  impl_->state = context.impl().state;
  translate_cl_errors([&] { impl_->buffer = upload(*impl_->state, data.data(), data.size(), "buffer"); });
  impl_->bytes = data.size();
}
Buffer::~Buffer() = default;
Buffer::Buffer(Buffer&&) noexcept = default;
Buffer& Buffer::operator=(Buffer&&) noexcept = default;
std::size_t Buffer::size_bytes() const { return impl_->bytes; }

void Buffer::write(std::size_t offset, std::span<const std::byte> data) {
  if (offset > impl_->bytes || data.size() > impl_->bytes - offset) {
    throw InvalidArgument("writing " + std::to_string(data.size()) + " bytes at offset " + std::to_string(offset) +
                          " runs past the buffer's " + std::to_string(impl_->bytes) + " bytes");
  }
  if (data.empty()) return;
  translate_cl_errors(
      [&] { impl_->state->queue.get().enqueueWriteBuffer(impl_->buffer, CL_TRUE, offset, data.size(), data.data()); });
}

std::vector<std::byte> Buffer::read() const {
  std::vector<std::byte> bytes(impl_->bytes);
  if (!bytes.empty()) {
    translate_cl_errors(
        [&] { impl_->state->queue.get().enqueueReadBuffer(impl_->buffer, CL_TRUE, 0, bytes.size(), bytes.data()); });
  }
  return bytes;
}

VertexBuffer::VertexBuffer(Context& context, std::span<const float> positions, std::span<const float> normals)
    : impl_(std::make_unique<Impl>()) {
  if (positions.size() % 3 != 0) {
    throw InvalidArgument("vertex positions need three floats per vertex; got " + std::to_string(positions.size()) +
                          " floats");
  }
  if (!normals.empty() && normals.size() != positions.size()) {
    throw InvalidArgument("vertex normals need three floats per vertex: " + std::to_string(normals.size()) +
                          " floats for " + std::to_string(positions.size() / 3) + " vertices");
  }
  if (positions.size() / 3 > kMaxElements) throw InvalidArgument("more than 2^32 - 16 vertices in one buffer");
  impl_->state = context.impl().state;
  impl_->positions.emplace(context, std::as_bytes(positions));
  if (!normals.empty()) impl_->normals.emplace(context, std::as_bytes(normals));
  impl_->count = positions.size() / 3;
}
VertexBuffer::~VertexBuffer() = default;
VertexBuffer::VertexBuffer(VertexBuffer&&) noexcept = default;
VertexBuffer& VertexBuffer::operator=(VertexBuffer&&) noexcept = default;
std::size_t VertexBuffer::size() const { return impl_->count; }

namespace {

template <typename Index>
std::unique_ptr<IndexBuffer::Impl> make_index_buffer(Context& context, std::span<const Index> indices) {
  if (indices.size() > kMaxElements) throw InvalidArgument("more than 2^32 - 16 indices in one buffer");
  auto impl = std::make_unique<IndexBuffer::Impl>();
  impl->state = context.impl().state;
  translate_cl_errors([&] { impl->indices = upload(*impl->state, indices.data(), indices.size_bytes(), "indices"); });
  impl->count = indices.size();
  impl->index_size = sizeof(Index);
  return impl;
}

}  // namespace

IndexBuffer::IndexBuffer(Context& context, std::span<const std::uint32_t> indices)
    : impl_(make_index_buffer(context, indices)) {}
IndexBuffer::IndexBuffer(Context& context, std::span<const std::uint16_t> indices)
    : impl_(make_index_buffer(context, indices)) {}
IndexBuffer::~IndexBuffer() = default;
IndexBuffer::IndexBuffer(IndexBuffer&&) noexcept = default;
IndexBuffer& IndexBuffer::operator=(IndexBuffer&&) noexcept = default;
std::size_t IndexBuffer::size() const { return impl_->count; }
int IndexBuffer::index_size() const { return impl_->index_size; }

}  // namespace clraster
