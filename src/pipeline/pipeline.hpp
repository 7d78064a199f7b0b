// The pipeline: renders a frame of draws through every stage, within the memory cap.
//
//   vertex -> setup (assembly, clipping, culling, set-up) -> scans -> bin (emit pairs, radix sort by
//   tile, tile ranges) -> raster (coverage, fragment program, per-fragment operations)
//
// A frame's draws are validated first (prepare), then rendered in passes (render): consecutive
// draws (and each draw's instances) that share a program, its textures and the state the raster
// stage reads go through the geometry stages one after the other into shared buffers, are binned
// together and rasterized in one pass that takes each tile once; per-draw uniforms travel as
// tables indexed by the draw's entry in the pass. A draw too large for a pass runs alone, chunk by
// chunk (draw_chunked). The scans and the sort are context-wide kernels; the stages that run a
// program's code are compiled per program (ProgramStages). The host reads back only the totals that
// size binning (once per pass) and, when a pass or chunk overflows what the plan gave it, the
// offsets to split it.
#pragma once

#include "clraster/clraster.hpp"
#include "geometry/bin.hpp"
#include "geometry/setup.hpp"
#include "geometry/vertex.hpp"
#include "parallel/radix_sort.hpp"
#include "pipeline/memory_plan.hpp"
#include "program/interface.hpp"
#include "raster/raster.hpp"
#include "resources/pending_clear.hpp"
#include "runtime/scratch.hpp"

#include <limits>
#include <map>
#include <tuple>

namespace clraster::pipeline {

// The stage kernels of one program.
struct ProgramStages {
  ProgramStages(const cl::Program& program, parallel::RadixSort& sort, std::size_t vertex_lanes, int tile_size)
      : tile_size(tile_size), vertex(program, vertex_lanes), setup(program), bin(program, sort), raster(program) {}
  int tile_size;  // the program's stages were compiled for tiles of tile_size x tile_size pixels
  geometry::VertexStage vertex;
  geometry::SetupStage setup;
  geometry::BinStage bin;
  raster::RasterStage raster;
};

// Where a draw renders to: level 0 of the framebuffer's attachments.
struct RenderTarget {
  std::vector<cl::Buffer> colors;
  std::vector<int> formats;  // CLR_FORMAT_* of each colour attachment
  cl::Buffer depth_stencil;  // null when there is no depth attachment
  bool has_stencil = false;
  std::uint32_t stencil_offset = 0;
  int width = 0;   // of the attachments
  int height = 0;
  // Layers side by side in the attachments, layer l at column l % layer_columns (Framebuffer's
  // layer_rect); unlayered, one layer of width x height.
  int layer_width = 0;
  int layer_height = 0;
  int layer_columns = 1;
  // The attachments' clears not written yet: the draw's first raster pass writes those of the
  // attachments it renders to, and marks them written.
  std::vector<resources::PendingClear*> color_clears;  // per colour attachment
  resources::PendingClear* depth_clear = nullptr;     // of the depth (and stencil) attachment
};

// What the index ranges an index buffer was drawn with hold: index buffers cannot change after
// upload, so repeated draws of the same range validate their indices, and find their blocks' ranges
// (block culling, clr_limits.h), once.
struct IndexRangeCache {
  struct Bounds {
    std::uint32_t smallest = 0;
    std::uint32_t largest = 0;
  };
  std::map<std::pair<std::uint32_t, std::uint32_t>, Bounds> bounds;  // by (first, count)
  // cl_uint4 per block: two ranges that hold its indices (block_index_ranges), by (first, count, topology)
  std::map<std::tuple<std::uint32_t, std::uint32_t, int>, cl::Buffer> block_ranges;
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

// A draw of a frame, validated (Pipeline::prepare): what rendering it needs.
struct FrameDraw {
  const DrawSource* source = nullptr;
  DrawUniforms uniforms{};        // instance and batch_draw set per entry of a pass
  int topology = 0;
  std::uint32_t first = 0;
  std::uint32_t primitives = 0;   // per instance
  std::uint32_t used_elements = 0;
  std::uint64_t vertex_count = 0;  // vertices [0, vertex_count) hold every one it uses
  std::uint32_t smallest_index = 0;  // indexed: of the indices it uses
  bool indexed() const { return source->index_size != 0; }
};

class Pipeline {
 public:
  // buffer_bytes: the most one buffer may take (the device's CL_DEVICE_MAX_MEM_ALLOC_SIZE);
  // constant_bytes: the device's CL_DEVICE_MAX_CONSTANT_BUFFER_SIZE, which bounds a pass's tables.
  Pipeline(const cl::Context& context, runtime::Queue& queue, const cl::Program& core, std::size_t memory_cap,
           std::size_t buffer_bytes, std::size_t constant_bytes);

  // Checks a draw (element ranges, indices, instances) without rendering anything. `source` must
  // outlive the render of the frame.
  FrameDraw prepare(const RenderTarget& target, const DrawSource& source, std::uint32_t first, std::uint32_t count,
                    const DrawState& state, std::uint32_t view);
  // Renders prepared draws, in order, into `target`.
  DrawStats render(const RenderTarget& target, const std::vector<FrameDraw>& draws);

  parallel::RadixSort& sort() { return sort_; }

 private:
  // One entry of a pass: instances of a draw, with where their vertices and triangles go.
  struct PassEntry {
    const FrameDraw* draw = nullptr;
    std::uint32_t instance = 0;     // the first
    std::uint32_t instances = 0;
    SlotMap slots{};                // the first instance's
    std::uint32_t main_count = 0;   // stream slots before a fan's centre (vertex.cl)
    std::uint32_t slot_count = 0;   // slots the vertex stage fills per instance, from slots.slot_base
    std::uint32_t instance_slots = 0;  // slot_count in whole groups (block culling): one instance's room
    std::uint32_t record_base = 0;  // its first primitive's entry in the pass's records
  };
  struct Pass {
    MemoryPlan plan;
    std::uint32_t slot_capacity = 0;
    std::vector<PassEntry> entries;
    std::uint32_t primitives = 0;
    std::uint32_t slots = 0;  // used, from 0
    bool culls_blocks = false;  // an entry shades its index range once
  };
  // What the raster stage of a pass or chunk reads besides its triangles.
  struct RasterInputs {
    const RenderTarget* target = nullptr;
    ProgramStages* stages = nullptr;
    std::size_t outputs = 0;  // the program's
    cl::Buffer draws;         // one DrawUniforms: the raster state (a pass: its lead's, over every entry's clip rectangle)
    const geometry::ProgramResources* resources = nullptr;
    std::uint32_t tiles_x = 0, tiles_y = 0;
    std::uint64_t pair_capacity = 0;
    std::uint32_t clears = 0;  // pending clears the next raster pass writes (CLR_CLEAR_*)
  };
  // The target, the program's stages and outputs, and the tile grid of the program's tile size.
  static RasterInputs raster_inputs(const RenderTarget& target, const DrawSource& source);
  // A chunk's or pass's set-up triangles, ready for binning.
  struct ChunkTriangles {
    cl::Buffer records;          // per primitive
    cl::Buffer bin_boxes;        // per primitive, its record's pixel box
    cl::Buffer overflow;         // of clipped primitives
    cl::Buffer clipped_offsets;  // per primitive, into overflow
    cl::Buffer pair_offsets;     // per primitive, of its bin pairs
  };
  // What every step of a draw rendered alone, chunk by chunk, needs.
  struct ChunkedDraw {
    const FrameDraw* draw = nullptr;
    const geometry::DrawBuffers* buffers = nullptr;
    MemoryPlan plan;
    RasterInputs raster;
    std::size_t shaded_vertex_bytes = 0;
    std::size_t setup_triangle_bytes = 0;
    // Block culling (clr_limits.h), where every vertex is shaded once: each block's index ranges,
    // and each group of vertex slots' clip codes.
    cl::Buffer block_ranges;
    cl::Buffer group_codes;
    std::uint32_t clipped_primitives = 0;  // CLR_COUNTER_CLIPPED as the last chunk left it
  };

  IndexRangeCache::Bounds index_bounds(const DrawSource& source, std::uint32_t first, std::uint32_t count);
  // The index range of each block of the draw's primitives, from the index buffer's cache.
  const cl::Buffer& block_index_ranges(const FrameDraw& draw);

  // Whether `draw` may join `pass` (same program, textures and raster state).
  bool shares_raster_pass(const Pass& pass, const FrameDraw& draw) const;
  // Adds as many of `draw`'s instances from `instance` on as the pass has room for, up to `count`;
  // returns how many (0: none fit).
  std::uint32_t add_entry(Pass& pass, const FrameDraw& draw, std::uint32_t instance, std::uint32_t count) const;
  // The pass plan for draws of `primitives` in all (at most CLR_MAX_CHUNK_PRIMITIVES at a time).
  Pass start_pass(const RenderTarget& target, const FrameDraw& draw, std::uint64_t primitives) const;
  void render_pass(const RenderTarget& target, const Pass& pass, DrawStats& stats);

  // Instances [instance_begin, instance_end) of a draw, alone, chunk by chunk.
  void draw_chunked(const RenderTarget& target, const FrameDraw& draw, std::uint32_t instance_begin,
                    std::uint32_t instance_end, DrawStats& stats);
  // Runs primitives [begin, begin + count) through every stage; returns how many it took (fewer
  // when the chunk had to be shortened).
  std::uint32_t run_chunk(ChunkedDraw& chunked, std::uint32_t begin, std::uint32_t count, DrawStats& stats);
  // Bins and rasterizes the triangles of primitives [0, primitives) of a chunk or pass.
  void bin_and_rasterize(RasterInputs& raster, const ChunkTriangles& chunk, std::uint32_t primitives,
                         std::uint32_t pairs);
  // Adds CLR_COUNTER_DROPPED to the frame's count and zeroes it.
  void take_dropped(std::uint32_t counted);

  // Largest k in [lo, hi] with offsets[k] - base <= limit, for an exclusive scan whose value at hi
  // (one past its last element) is `end_value`.
  std::uint32_t last_offset_within(const cl::Buffer& offsets, std::uint32_t lo, std::uint32_t hi,
                                   std::uint32_t end_value, std::uint64_t base, std::uint64_t limit);
  // offsets[index] of an exclusive scan of `count` values whose total is known (read only when needed).
  std::uint32_t read_offset(const cl::Buffer& offsets, std::uint32_t index, std::uint32_t count, std::uint32_t total);
  // A read-only device buffer holding a copy of `bytes` of `data` (at least 16 bytes: OpenCL has no
  // empty buffers); the copy is made at once, so the caller's data need not outlive the call.
  cl::Buffer table(const void* data, std::size_t bytes) const;

  const cl::Context& context_;
  runtime::Queue& queue_;
  std::size_t memory_cap_;
  std::size_t buffer_bytes_;
  std::size_t constant_bytes_;
  cl::Buffer placeholder_;  // bound to kernel arguments a draw does not use
  cl::Buffer counters_;
  std::uint64_t dropped_ = 0;  // of the frame being rendered
  runtime::ScratchArena scratch_;
  cl::Kernel index_bounds_;
  cl::Kernel block_index_ranges_;
  parallel::Scan scan_;
  parallel::RadixSort sort_;
};

}  // namespace clraster::pipeline
