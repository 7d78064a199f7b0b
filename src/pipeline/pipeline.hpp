// The pipeline: runs a draw through every stage, chunk by chunk, within the memory cap.
//
//   vertex -> setup (assembly, clipping, culling, set-up) -> scans -> bin (emit pairs, radix sort by
//   tile, tile ranges) -> raster
//
// All per-vertex, per-triangle and per-pixel work runs in kernels. The host only reads back the
// totals that size the next step (clipped triangles and pairs per chunk) and, when a chunk overflows
// what the plan gave it, binary-searches the offsets to split it.
#pragma once

#include "clraster/clraster.hpp"
#include "parallel/radix_sort.hpp"
#include "pipeline/memory_plan.hpp"
#include "resources/scratch.hpp"
#include "stages/bin.hpp"
#include "stages/raster.hpp"
#include "stages/setup.hpp"
#include "stages/vertex.hpp"

namespace clraster::pipeline {

// Where a draw renders to.
struct RenderTarget {
  cl::Buffer color;  // RGBA8 per pixel, row 0 at the bottom
  cl::Buffer depth;  // float per pixel
  int width = 0;
  int height = 0;
};

// The largest index of the range an index buffer was last drawn with: index buffers cannot change
// after upload, so repeated draws of the same range validate their indices once.
struct IndexRangeCache {
  bool valid = false;
  std::uint32_t first = 0;
  std::uint32_t count = 0;
  std::uint32_t largest = 0;
};

// What the draw reads, resolved from the public buffers.
struct DrawSource {
  cl::Buffer positions;
  cl::Buffer normals;
  bool has_normals = false;
  std::uint64_t vertex_count = 0;
  cl::Buffer indices;       // null for non-indexed draws
  int index_size = 0;       // 0, 2 or 4
  IndexRangeCache* index_cache = nullptr;
  std::uint64_t element_count = 0;  // indices, or vertices when non-indexed
};

class Pipeline {
 public:
  Pipeline(const cl::Context& context, cl_host::Queue& queue, const cl::Program& program, int tile_size,
           std::size_t memory_cap);

  DrawStats draw(const RenderTarget& target, const DrawSource& source, std::uint32_t first, std::uint32_t count,
                 const DrawState& state);

  std::size_t peak_memory_bytes() const { return scratch_.peak_bytes(); }

 private:
  // What every step of one draw needs.
  struct Frame {
    const RenderTarget* target = nullptr;
    const stages::DrawBuffers* buffers = nullptr;
    MemoryPlan plan;
    int topology = 0;
    std::uint64_t vertex_count = 0;
    std::uint32_t tiles_x = 0, tiles_y = 0;
  };

  std::uint32_t largest_index(const DrawSource& source, std::uint32_t first, std::uint32_t count);
  // Runs primitives [begin, begin + count) through every stage; returns how many it took (fewer
  // when the chunk had to be shortened).
  std::uint32_t run_chunk(const Frame& frame, std::uint32_t begin, std::uint32_t count, DrawStats& stats);
  // A chunk's set-up triangles, ready for binning.
  struct ChunkTriangles {
    cl::Buffer records;          // per primitive
    cl::Buffer overflow;         // of clipped primitives
    cl::Buffer clipped_offsets;  // per primitive, into overflow
    cl::Buffer pair_offsets;     // per primitive, of its bin pairs
  };
  // Bins and rasterizes the triangles of primitives [0, primitives) of the chunk.
  void bin_and_rasterize(const Frame& frame, const ChunkTriangles& chunk, std::uint32_t primitives,
                         std::uint32_t pairs);
  // Largest k in [lo, hi] with offsets[k] - base <= limit, for an exclusive scan whose value at hi
  // (one past its last element) is `end_value`.
  std::uint32_t last_offset_within(const cl::Buffer& offsets, std::uint32_t lo, std::uint32_t hi,
                                   std::uint32_t end_value, std::uint64_t base, std::uint64_t limit);
  // offsets[index] of an exclusive scan of `count` values whose total is known (read only when needed).
  std::uint32_t read_offset(const cl::Buffer& offsets, std::uint32_t index, std::uint32_t count, std::uint32_t total);

  cl_host::Queue& queue_;
  int tile_size_;
  std::size_t memory_cap_;
  cl::Buffer placeholder_;  // bound to kernel arguments a draw does not use
  cl::Buffer uniforms_;
  cl::Buffer counters_;
  resources::ScratchArena scratch_;
  cl::Kernel index_max_;
  parallel::Scan scan_;
  parallel::RadixSort sort_;
  stages::VertexStage vertex_;
  stages::SetupStage setup_;
  stages::BinStage bin_;
  stages::RasterStage raster_;
};

}  // namespace clraster::pipeline
