// The pipeline: runs a draw through every stage, chunk by chunk, within the memory cap.
//
//   vertex -> setup (assembly, clipping, culling, set-up) -> scans -> bin (emit pairs, radix sort by
//   tile, tile ranges) -> raster (coverage, fragment program, per-fragment operations)
//
// The scans and the sort are context-wide kernels; the stages that run a program's code are
// compiled per program (ProgramStages). All per-vertex, per-triangle and per-pixel work runs in
// kernels. The host only reads back the totals that size the next step (clipped triangles and pairs
// per chunk) and, when a chunk overflows what the plan gave it, binary-searches the offsets to split it.
#pragma once

#include "clraster/clraster.hpp"
#include "parallel/radix_sort.hpp"
#include "pipeline/memory_plan.hpp"
#include "program/interface.hpp"
#include "resources/pending_clear.hpp"
#include "resources/scratch.hpp"
#include "stages/bin.hpp"
#include "stages/raster.hpp"
#include "stages/setup.hpp"
#include "stages/vertex.hpp"

#include <limits>

namespace clraster::pipeline {

// The stage kernels of one program.
struct ProgramStages {
  ProgramStages(const cl::Program& program, parallel::RadixSort& sort, std::size_t vertex_lanes, int tile_size)
      : tile_size(tile_size), vertex(program, vertex_lanes), setup(program), bin(program, sort), raster(program) {}
  int tile_size;  // the program's stages were compiled for tiles of tile_size x tile_size pixels
  stages::VertexStage vertex;
  stages::SetupStage setup;
  stages::BinStage bin;
  stages::RasterStage raster;
};

// Where a draw renders to: level 0 of the framebuffer's attachments.
struct RenderTarget {
  std::vector<cl::Buffer> colors;
  std::vector<int> formats;  // CLR_FORMAT_* of each colour attachment
  cl::Buffer depth_stencil;  // null when there is no depth attachment
  bool has_stencil = false;
  std::uint32_t stencil_offset = 0;
  int width = 0;
  int height = 0;
  // The attachments' clears not written yet: the draw's first raster pass writes those of the
  // attachments it renders to, and marks them written.
  std::vector<resources::PendingClear*> color_clears;  // per colour attachment
  resources::PendingClear* depth_clear = nullptr;     // of the depth (and stencil) attachment
};

// The largest index of the range an index buffer was last drawn with, and the index range of each
// block of its primitives (block culling, clr_limits.h): index buffers cannot change after upload,
// so repeated draws of the same range validate their indices, and find their blocks' ranges, once.
struct IndexRangeCache {
  bool valid = false;
  std::uint32_t first = 0;
  std::uint32_t count = 0;
  std::uint32_t largest = 0;

  bool blocks_valid = false;
  std::uint32_t blocks_first = 0;
  std::uint32_t blocks_count = 0;
  int blocks_topology = 0;
  cl::Buffer block_ranges;  // cl_uint4 per block: two ranges that hold its indices (block_index_ranges)
};

inline constexpr std::uint64_t kUnlimited = std::numeric_limits<std::uint64_t>::max();

// What the draw reads, resolved from the public objects and checked against the program.
struct DrawSource {
  const program::ParsedProgram* program = nullptr;
  ProgramStages* stages = nullptr;
  std::vector<cl::Buffer> attribute_buffers;  // per declared attribute
  std::vector<AttributeDesc> attributes;
  std::uint64_t vertex_limit = kUnlimited;    // elements of the shortest per-vertex attribute
  std::uint64_t instance_limit = kUnlimited;  // elements of the shortest per-instance attribute
  cl::Buffer indices;                         // null for non-indexed draws
  int index_size = 0;                         // 0, 2 or 4
  IndexRangeCache* index_cache = nullptr;
  std::uint64_t index_count = 0;
  std::vector<std::byte> uniforms;            // the program's uniform block
  std::vector<TextureDesc> texture_descs;
  std::vector<cl::Buffer> textures;
  std::vector<cl::Buffer> buffers;
  std::uint32_t instance_count = 1;
};

class Pipeline {
 public:
  // buffer_bytes: the most one buffer may take (the device's CL_DEVICE_MAX_MEM_ALLOC_SIZE).
  Pipeline(const cl::Context& context, cl_host::Queue& queue, const cl::Program& core, std::size_t memory_cap,
           std::size_t buffer_bytes);

  DrawStats draw(const RenderTarget& target, const DrawSource& source, std::uint32_t first, std::uint32_t count,
                 const DrawState& state);

  parallel::RadixSort& sort() { return sort_; }

 private:
  // What every step of one draw needs.
  struct Frame {
    const RenderTarget* target = nullptr;
    const DrawSource* source = nullptr;
    const stages::DrawBuffers* buffers = nullptr;
    MemoryPlan plan;
    int topology = 0;
    std::uint64_t vertex_count = 0;  // slots when every vertex is shaded once
    std::uint32_t tiles_x = 0, tiles_y = 0;
    std::size_t shaded_vertex_bytes = 0;
    std::size_t setup_triangle_bytes = 0;
    std::uint32_t clears = 0;  // pending clears the next raster pass writes (CLR_CLEAR_*)
    // Block culling (clr_limits.h), where every vertex is shaded once: each block's index ranges,
    // and each group of vertex slots' clip codes.
    cl::Buffer block_ranges;
    cl::Buffer group_codes;
    std::uint32_t clipped_primitives = 0;  // CLR_COUNTER_CLIPPED as the last chunk left it
  };

  std::uint32_t largest_index(const DrawSource& source, std::uint32_t first, std::uint32_t count);
  // The index range of each block of the draw's primitives, from the index buffer's cache.
  const cl::Buffer& block_index_ranges(const DrawSource& source, std::uint32_t first, std::uint32_t count,
                                       int topology, std::uint32_t primitives);
  // Runs primitives [begin, begin + count) through every stage; returns how many it took (fewer
  // when the chunk had to be shortened).
  std::uint32_t run_chunk(Frame& frame, std::uint32_t begin, std::uint32_t count, DrawStats& stats);
  // A chunk's set-up triangles, ready for binning.
  struct ChunkTriangles {
    cl::Buffer records;          // per primitive
    cl::Buffer bin_boxes;        // per primitive, its record's pixel box
    cl::Buffer overflow;         // of clipped primitives
    cl::Buffer clipped_offsets;  // per primitive, into overflow
    cl::Buffer pair_offsets;     // per primitive, of its bin pairs
  };
  // Bins and rasterizes the triangles of primitives [0, primitives) of the chunk.
  void bin_and_rasterize(Frame& frame, const ChunkTriangles& chunk, std::uint32_t primitives,
                         std::uint32_t pairs);
  // Largest k in [lo, hi] with offsets[k] - base <= limit, for an exclusive scan whose value at hi
  // (one past its last element) is `end_value`.
  std::uint32_t last_offset_within(const cl::Buffer& offsets, std::uint32_t lo, std::uint32_t hi,
                                   std::uint32_t end_value, std::uint64_t base, std::uint64_t limit);
  // offsets[index] of an exclusive scan of `count` values whose total is known (read only when needed).
  std::uint32_t read_offset(const cl::Buffer& offsets, std::uint32_t index, std::uint32_t count, std::uint32_t total);
  // A device buffer of at least `bytes` holding `data`, reusing `buffer` when it is large enough.
  void upload(cl::Buffer& buffer, std::size_t& capacity, const void* data, std::size_t bytes);

  const cl::Context& context_;
  cl_host::Queue& queue_;
  std::size_t memory_cap_;
  std::size_t buffer_bytes_;
  cl::Buffer placeholder_;  // bound to kernel arguments a draw does not use
  cl::Buffer uniforms_;
  cl::Buffer counters_;
  cl::Buffer uniform_block_, texture_descs_, attribute_descs_;
  std::size_t uniform_block_bytes_ = 0, texture_descs_bytes_ = 0, attribute_descs_bytes_ = 0;
  resources::ScratchArena scratch_;
  cl::Kernel index_max_;
  cl::Kernel block_index_ranges_;
  parallel::Scan scan_;
  parallel::RadixSort sort_;
};

}  // namespace clraster::pipeline
