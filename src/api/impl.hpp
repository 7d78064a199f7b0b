// The private side of the public API objects (clraster.hpp): what each handle owns.
#pragma once

#include "clraster/clraster.hpp"
#include "pipeline/pipeline.hpp"
#include "program/interface.hpp"
#include "resources/pending_clear.hpp"
#include "runtime/device.hpp"
#include "runtime/program_cache.hpp"
#include "runtime/queue.hpp"
#include "shared/types.h"

#include <array>
#include <memory>
#include <optional>

namespace clraster {

inline constexpr std::size_t kShadingCount = static_cast<std::size_t>(Shading::Constant) + 1;

// Shared by the Context and every resource made from it, so a resource that outlives its Context
// still holds a valid OpenCL context and queue.
struct ContextState : std::enable_shared_from_this<ContextState> {
  ContextOptions options;  // as given, with the shape and the tile size resolved
  // Whether the context chose options.tile_size (kDeviceTileSize): then a program whose stages do not
  // fit the device at that size takes a smaller one (compile_program).
  bool tile_size_chosen = false;
  runtime::Device device;
  cl::Context context;
  runtime::Queue queue;
  runtime::ProgramCache programs;
  std::unique_ptr<pipeline::Pipeline> pipeline;  // built by the first draw
  // The built-in program of each Shading, compiled by its first use.
  std::array<std::unique_ptr<Program>, kShadingCount> builtins;

  ContextState(const ContextOptions& options, runtime::Device device);
  // The context-wide kernels: scans, sorts, index validation, textures.
  const cl::Program& core_program();
  pipeline::Pipeline& get_pipeline();
  const Program& builtin_program(Shading shading);
  // Build options of the core program, and of a program's stages at a tile size.
  std::string core_build_options() const;
  std::string stage_build_options(int tile_size) const;
  bool cpu_shapes() const;         // the work-group shapes of a CPU device (clr_limits.h)
  std::size_t scan_items() const;  // work-items per block of scans and sorts (clr_limits.h)
  std::size_t vertex_lanes() const;  // vertex slots per work-item of the vertex stage (clr_limits.h)

 private:
  std::optional<cl::Program> core_;
};

struct Context::Impl {
  std::shared_ptr<ContextState> state;
};

struct Buffer::Impl {
  std::shared_ptr<ContextState> state;
  cl::Buffer buffer;
  std::size_t bytes = 0;
};

struct VertexBuffer::Impl {
  std::shared_ptr<ContextState> state;
  std::optional<Buffer> positions;
  std::optional<Buffer> normals;  // none: the attribute "normal" reads zeros
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
  // A clear of level 0 not written yet (resources/pending_clear.hpp). Mutable: writing it changes
  // where the texels are, not what they are.
  mutable resources::PendingClear pending_clear;
  // Enqueues the pending clear's writes, for whatever reads or writes the texels other than a draw
  // into them.
  void write_pending_clear() const;
  // What kernels see of this texture when sampled with `sampler` (or rendered into).
  TextureDesc describe(const Sampler& sampler = {}) const;
  // Byte offset and size of a level's texels in `data`.
  std::size_t level_offset_bytes(int level) const;
  std::size_t level_bytes(int level) const;
  // The texels of `rect` of level 0, rows from the bottom.
  std::vector<std::byte> read_rect(const Rect& rect) const;
};

struct Program::Impl {
  std::shared_ptr<ContextState> state;
  std::string file_name;
  program::ParsedProgram parsed;
  cl::Program program;
  int tile_size = 0;  // the context's, or smaller where the device needs it (compile_program)
  std::unique_ptr<pipeline::ProgramStages> stages;  // the program's stage kernels, made by its first draw
};

// Parses, generates and builds a program's stage kernels (throws what Program's constructor documents).
std::unique_ptr<Program::Impl> compile_program(const std::shared_ptr<ContextState>& state, const std::string& source,
                                               const std::string& file_name);

struct Bindings::Impl {
  const Program::Impl* program = nullptr;
  std::vector<std::byte> uniforms;            // the uniform block, ProgramInterface::uniform_bytes
  std::vector<bool> uniform_set;              // per declared uniform
  struct BoundTexture {
    const Texture::Impl* texture = nullptr;
    Sampler sampler;
  };
  std::vector<BoundTexture> textures;         // per declared texture
  std::vector<const Buffer::Impl*> buffers;   // per declared buffer
};

struct Framebuffer::Impl {
  std::shared_ptr<ContextState> state;
  std::vector<Texture> owned;                 // the attachments of Framebuffer(context, width, height)
  std::vector<Texture*> colors;
  Texture* depth_stencil = nullptr;
  int width = 0;   // of a layer
  int height = 0;
  int layers = 1;
  int layer_columns = 1;
  Rect layer_rect(int layer) const;  // checked
};

}  // namespace clraster
