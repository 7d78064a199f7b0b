// The private side of the public API objects (clraster.hpp): what each handle owns.
#pragma once

#include "cl/device.hpp"
#include "cl/program_cache.hpp"
#include "cl/queue.hpp"
#include "clraster/clraster.hpp"
#include "pipeline/pipeline.hpp"
#include "stages/types.h"

#include <memory>

namespace clraster {

// Shared by the Context and every resource made from it, so a resource that outlives its Context
// still holds a valid OpenCL context and queue.
struct ContextState {
  ContextOptions options;
  cl_host::Device device;
  cl::Context context;
  cl_host::Queue queue;
  cl_host::ProgramCache programs;
  cl::Program core;                              // built by the first core_program()
  std::unique_ptr<pipeline::Pipeline> pipeline;  // built by the first draw

  ContextState(const ContextOptions& options, cl_host::Device device);
  // The program of every embedded kernel (cl_sources::pipeline_program()), built once.
  const cl::Program& core_program();
  pipeline::Pipeline& get_pipeline();
};

struct Context::Impl {
  std::shared_ptr<ContextState> state;
};

struct VertexBuffer::Impl {
  std::shared_ptr<ContextState> state;
  cl::Buffer positions;
  cl::Buffer normals;
  bool has_normals = false;
  std::size_t count = 0;
};

struct IndexBuffer::Impl {
  std::shared_ptr<ContextState> state;
  cl::Buffer indices;
  std::size_t count = 0;
  int index_size = 0;
  pipeline::IndexRangeCache range_cache;
};

struct Texture::Impl {
  std::shared_ptr<ContextState> state;
  cl::Buffer data;  // every level, level after level (TextureDesc::level_offset), then the stencil plane
  Format format = Format::RGBA8;
  int width = 0;
  int height = 0;
  int levels = 1;
  // What kernels see of this texture when sampled with `sampler` (or rendered into).
  TextureDesc describe(const Sampler& sampler = {}) const;
  // Byte offset and size of a level's texels in `data`.
  std::size_t level_offset_bytes(int level) const;
  std::size_t level_bytes(int level) const;
};

struct Framebuffer::Impl {
  std::shared_ptr<ContextState> state;
  pipeline::RenderTarget target;
};

}  // namespace clraster
