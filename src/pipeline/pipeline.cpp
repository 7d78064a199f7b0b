#include "pipeline/pipeline.hpp"

#include "cl/launch.hpp"
#include "clr_limits.h"
#include "pipeline/draw_state.hpp"
#include "program/generator.hpp"
#include "stages/types.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <string>

namespace clraster::pipeline {

using cl_host::read_uint;
using resources::Scratch;

namespace {

constexpr std::uint32_t kSaturated = 0xffffffffu;  // what a scan whose total overflows returns

std::uint32_t primitives_of(int topology, std::uint64_t elements) {
  if (topology == CLR_TOPOLOGY_LIST) return static_cast<std::uint32_t>(elements / 3);
  return elements >= 3 ? static_cast<std::uint32_t>(elements - 2) : 0u;
}

// The pending clears of the attachments a draw's raster pass writes (the colour attachments of its
// program's outputs, the depth and stencil attachment), as CLR_CLEAR_* bits; their values go into
// `uniforms`.
std::uint32_t pending_clears(const RenderTarget& target, std::size_t outputs, DrawUniforms& uniforms) {
  std::uint32_t clears = 0;
  for (std::size_t k = 0; k < outputs && k < target.color_clears.size(); ++k) {
    const resources::PendingClear& pending = *target.color_clears[k];
    if (!pending.color) continue;
    clears |= 1u << k;
    std::copy(pending.color_bits.begin(), pending.color_bits.end(), uniforms.clear_color[k]);
  }
  if (target.depth_clear != nullptr && target.depth_clear->depth) {
    clears |= CLR_CLEAR_DEPTH;
    uniforms.clear_depth = target.depth_clear->depth_value;
  }
  if (target.depth_clear != nullptr && target.has_stencil && target.depth_clear->stencil) {
    clears |= CLR_CLEAR_STENCIL;
    uniforms.clear_stencil = target.depth_clear->stencil_value;
  }
  return clears;
}

void mark_clears_written(const RenderTarget& target, std::uint32_t clears) {
  for (std::size_t k = 0; k < target.color_clears.size(); ++k) {
    if ((clears >> k) & 1u) target.color_clears[k]->color = false;
  }
  if (clears & CLR_CLEAR_DEPTH) target.depth_clear->depth = false;
  if (clears & CLR_CLEAR_STENCIL) target.depth_clear->stencil = false;
}

}  // namespace

Pipeline::Pipeline(const cl::Context& context, cl_host::Queue& queue, const cl::Program& core, std::size_t memory_cap,
                   std::size_t buffer_bytes)
    : context_(context),
      queue_(queue),
      memory_cap_(memory_cap),
      buffer_bytes_(buffer_bytes),
      placeholder_(context, CL_MEM_READ_WRITE, 16),
      uniforms_(context, CL_MEM_READ_ONLY, sizeof(DrawUniforms)),
      counters_(context, CL_MEM_READ_WRITE, CLR_COUNTER_COUNT * sizeof(cl_uint)),
      scratch_(context),
      index_max_(core, "index_max"),
      block_index_ranges_(core, "block_index_ranges"),
      scan_(core),
      sort_(core, scan_) {}

void Pipeline::upload(cl::Buffer& buffer, std::size_t& capacity, const void* data, std::size_t bytes) {
  const std::size_t size = std::max<std::size_t>(bytes, 16);  // OpenCL has no empty buffers
  if (size > capacity) {
    buffer = cl::Buffer(context_, CL_MEM_READ_ONLY, size);
    capacity = size;
  }
  // Blocking: the caller's data need not outlive the call.
  if (bytes > 0) queue_.get().enqueueWriteBuffer(buffer, CL_TRUE, 0, bytes, data, nullptr, queue_.event());
}

std::uint32_t Pipeline::largest_index(const DrawSource& source, std::uint32_t first, std::uint32_t count) {
  IndexRangeCache& cache = *source.index_cache;
  if (cache.valid && cache.first == first && cache.count == count) return cache.largest;
  cl_host::fill(queue_, counters_, cl_uint{0}, CLR_COUNTER_MAX_INDEX * sizeof(cl_uint), sizeof(cl_uint));
  cl_host::set_args(index_max_, source.indices, cl_int{source.index_size}, cl_uint{first}, cl_uint{count}, counters_);
  cl_host::enqueue_blocks(queue_, index_max_, count, CLR_SCAN_BLOCK, cl_host::compiled_group_size(index_max_));
  cache.valid = true;
  cache.first = first;
  cache.count = count;
  cache.largest = read_uint(queue_, counters_, CLR_COUNTER_MAX_INDEX);
  return cache.largest;
}

const cl::Buffer& Pipeline::block_index_ranges(const DrawSource& source, std::uint32_t first, std::uint32_t count,
                                               int topology, std::uint32_t primitives) {
  IndexRangeCache& cache = *source.index_cache;
  if (cache.blocks_valid && cache.blocks_first == first && cache.blocks_count == count &&
      cache.blocks_topology == topology) {
    return cache.block_ranges;
  }
  const std::size_t blocks = cl_host::divide_round_up(primitives, CLR_CULL_BLOCK_PRIMITIVES);
  cache.block_ranges = cl::Buffer(context_, CL_MEM_READ_WRITE, blocks * sizeof(cl_uint4));
  cl_host::set_args(block_index_ranges_, source.indices, cl_int{source.index_size}, cl_uint{first}, cl_uint{primitives},
                    cl_int{topology}, cache.block_ranges);
  cl_host::enqueue_items(queue_, block_index_ranges_, blocks, CLR_ITEM_GROUP_SIZE);
  cache.blocks_valid = true;
  cache.blocks_first = first;
  cache.blocks_count = count;
  cache.blocks_topology = topology;
  return cache.block_ranges;
}

std::uint32_t Pipeline::read_offset(const cl::Buffer& offsets, std::uint32_t index, std::uint32_t count,
                                    std::uint32_t total) {
  if (index == 0) return 0;
  if (index == count) return total;
  return read_uint(queue_, offsets, index);
}

std::uint32_t Pipeline::last_offset_within(const cl::Buffer& offsets, std::uint32_t lo, std::uint32_t hi,
                                           std::uint32_t end_value, std::uint64_t base, std::uint64_t limit) {
  while (lo < hi) {
    const std::uint32_t mid = lo + (hi - lo + 1) / 2;
    const std::uint32_t value = mid == hi ? end_value : read_uint(queue_, offsets, mid);
    if (value - base <= limit) lo = mid; else hi = mid - 1;
  }
  return lo;
}

DrawStats Pipeline::draw(const RenderTarget& target, const DrawSource& source, std::uint32_t first,
                         std::uint32_t count, const DrawState& state) {
  queue_.set_stage(cl_host::Stage::Other);
  const program::ParsedProgram& program = *source.program;
  const bool indexed = source.index_size != 0;
  const char* elements = indexed ? "indices" : "vertices";
  // Indices, or vertices when non-indexed: how many the draw may take from `first`.
  const std::uint64_t element_limit = indexed ? source.index_count : source.vertex_limit;
  if (element_limit == kUnlimited && count == kAllElements) {
    throw InvalidArgument("a non-indexed draw without per-vertex attributes needs an explicit vertex count");
  }
  if (element_limit != kUnlimited && first > element_limit) {
    throw InvalidArgument("draw starts at element " + std::to_string(first) + " but there are only " +
                          std::to_string(element_limit) + " " + elements);
  }
  const std::uint64_t available = element_limit == kUnlimited ? kUnlimited : element_limit - first;
  const std::uint64_t element_count = count == kAllElements ? available : count;
  if (element_count > available) {
    throw InvalidArgument("draw of " + std::to_string(element_count) + " elements from element " +
                          std::to_string(first) + " runs past the " + std::to_string(element_limit) + " " + elements);
  }
  if (element_count > 0xffffffffull - 2 || std::uint64_t{first} + element_count > 0xffffffffull) {
    throw InvalidArgument("draw of more than 2^32 - 3 elements, or past element 2^32");
  }
  if (source.instance_count > source.instance_limit) {
    throw InvalidArgument("draw of " + std::to_string(source.instance_count) + " instances, but the per-instance attributes hold " +
                          std::to_string(source.instance_limit));
  }

  DrawUniforms uniforms = make_uniforms(state, target, program);
  const int topology = uniforms.topology;
  DrawStats stats;
  const std::uint32_t primitives = primitives_of(topology, element_count);
  stats.triangles = std::uint64_t{primitives} * source.instance_count;
  stats.peak_memory_bytes = scratch_.peak_bytes();
  if (primitives == 0 || source.instance_count == 0) return stats;

  // Every vertex the draw references: checked before anything renders.
  const auto used_elements = static_cast<std::uint32_t>(topology == CLR_TOPOLOGY_LIST ? 3ull * primitives : element_count);
  std::uint64_t vertex_count = std::uint64_t{first} + element_count;  // non-indexed: vertices [0, first + count)
  if (indexed) {
    const std::uint32_t largest = largest_index(source, first, used_elements);
    if (largest >= source.vertex_limit) {
      throw InvalidArgument("index " + std::to_string(largest) + " is out of range: the vertex attributes hold " +
                            std::to_string(source.vertex_limit) + " vertices");
    }
    vertex_count = std::min<std::uint64_t>(source.vertex_limit, std::uint64_t{largest} + 1);
  }

  Frame frame;
  frame.target = &target;
  frame.source = &source;
  frame.topology = topology;
  frame.vertex_count = vertex_count;
  const int tile_size = source.stages->tile_size;
  frame.tiles_x = static_cast<std::uint32_t>(cl_host::divide_round_up(target.width, tile_size));
  frame.tiles_y = static_cast<std::uint32_t>(cl_host::divide_round_up(target.height, tile_size));
  frame.shaded_vertex_bytes = program::shaded_vertex_bytes(program);
  frame.setup_triangle_bytes = program::setup_triangle_bytes(program);
  frame.plan = plan_memory({memory_cap_, buffer_bytes_, vertex_count, indexed, topology, primitives,
                            frame.tiles_x * frame.tiles_y, frame.shaded_vertex_bytes, frame.setup_triangle_bytes});

  // Validated: from here on the draw renders.
  uniforms.index_size = source.index_size;
  uniforms.first = first;
  frame.clears = pending_clears(target, program.interface.outputs.size(), uniforms);
  cl_host::fill(queue_, counters_, cl_uint{0}, 0, CLR_COUNTER_COUNT * sizeof(cl_uint));
  scratch_.set_capacities(frame.plan.buffer_bytes);
  stages::ProgramResources resources;
  upload(uniform_block_, uniform_block_bytes_, source.uniforms.data(), source.uniforms.size());
  resources.uniform_block = uniform_block_;
  upload(texture_descs_, texture_descs_bytes_, source.texture_descs.data(), source.texture_descs.size() * sizeof(TextureDesc));
  resources.texture_descs = texture_descs_;
  resources.textures = source.textures;
  resources.buffers = source.buffers;
  stages::DrawBuffers buffers;
  buffers.indices = indexed ? source.indices : placeholder_;
  buffers.uniforms = uniforms_;
  buffers.counters = counters_;
  buffers.resources = &resources;
  upload(attribute_descs_, attribute_descs_bytes_, source.attributes.data(), source.attributes.size() * sizeof(AttributeDesc));
  buffers.attribute_descs = attribute_descs_;
  buffers.attributes = source.attribute_buffers;
  frame.buffers = &buffers;

  // Block culling (clr_limits.h), where every vertex is shaded once per draw (indexed draws only).
  if (frame.plan.shade_all_vertices) {
    frame.block_ranges = block_index_ranges(source, first, used_elements, topology, primitives);
    frame.group_codes = scratch_.get(Scratch::GroupCodes, code_groups(vertex_count) * sizeof(cl_uint));
  }

  // Instances are drawn one after the other, in order, as OpenGL orders their primitives.
  for (std::uint32_t instance = 0; instance < source.instance_count; ++instance) {
    uniforms.instance = instance;
    queue_.get().enqueueWriteBuffer(uniforms_, CL_TRUE, 0, sizeof uniforms, &uniforms, nullptr, queue_.event());
    if (frame.plan.shade_all_vertices) {
      if (source.stages->vertex.ands_group_codes()) {
        queue_.set_stage(cl_host::Stage::Vertex);
        cl_host::fill(queue_, frame.group_codes, ~cl_uint{0}, 0, code_groups(vertex_count) * sizeof(cl_uint));
      }
      source.stages->vertex.run(queue_, {&buffers, true, 0, 0, static_cast<std::uint32_t>(vertex_count),
                                         scratch_.get(Scratch::ShadedVertices, vertex_count * frame.shaded_vertex_bytes),
                                         frame.group_codes});
    }
    for (std::uint32_t begin = 0; begin < primitives;) {
      begin += run_chunk(frame, begin, std::min(frame.plan.chunk_primitives, primitives - begin), stats);
    }
  }

  stats.triangles_dropped = read_uint(queue_, counters_, CLR_COUNTER_DROPPED);
  stats.peak_memory_bytes = scratch_.peak_bytes();
  stats.stage_times = queue_.collect();
  return stats;
}

std::uint32_t Pipeline::run_chunk(Frame& frame, std::uint32_t begin, std::uint32_t count, DrawStats& stats) {
  // Vertex stage: done once for the draw, or this chunk's stream positions.
  SlotMap slots{1, 0, 0};
  cl::Buffer shaded;
  if (frame.plan.shade_all_vertices) {
    shaded = scratch_.get(Scratch::ShadedVertices, frame.vertex_count * frame.shaded_vertex_bytes);
  } else {
    const StreamRange range = stream_range(frame.topology, begin, count);
    shaded = scratch_.get(Scratch::ShadedVertices, std::size_t{range.slot_count} * frame.shaded_vertex_bytes);
    frame.source->stages->vertex.run(
        queue_, {frame.buffers, false, range.begin, range.count, range.slot_count, shaded, placeholder_});
    slots = {0, range.begin, range.count};
  }

  // Set-up: a record per primitive, and for primitives that cross a clip plane the number of
  // triangles clipping leaves; bin pair counts for all of them. Both count arrays get one more
  // entry, zero (set-up writes it), whose exclusive scan is the total.
  const std::size_t count_bytes = (std::size_t{count} + 1) * sizeof(cl_uint);
  const cl::Buffer records = scratch_.get(Scratch::Records, std::size_t{count} * frame.setup_triangle_bytes);
  const cl::Buffer bin_boxes = scratch_.get(Scratch::BinBoxes, std::size_t{count} * sizeof(cl_uint2));
  const cl::Buffer pair_offsets = scratch_.get(Scratch::PairCounts, count_bytes);
  const cl::Buffer clipped_offsets = scratch_.get(Scratch::ClippedCounts, count_bytes);
  const cl::Buffer block_sums = scratch_.get(Scratch::ScanBlockSums, parallel::Scan::scratch_bytes(count + 1));
  ProgramStages& stages = *frame.source->stages;
  cl::Buffer culled_blocks = placeholder_;
  if (frame.plan.shade_all_vertices) {  // block culling
    const std::uint32_t first_block = begin / CLR_CULL_BLOCK_PRIMITIVES;
    const std::uint32_t block_count = (begin + count - 1) / CLR_CULL_BLOCK_PRIMITIVES - first_block + 1;
    culled_blocks = scratch_.get(Scratch::CulledBlocks, block_count);
    stages.setup.run_cull(queue_, {first_block, block_count, frame.block_ranges, frame.group_codes, culled_blocks});
  }
  stages.setup.run(queue_, {frame.buffers, slots, shaded, begin, count, frame.plan.shade_all_vertices, culled_blocks,
                            records, bin_boxes, pair_offsets, clipped_offsets});

  // Where each primitive's bin pairs go, and, in the same read, whether any primitive was clipped.
  scan_.exclusive(queue_, pair_offsets, count + 1, block_sums, counters_);
  std::array<std::uint32_t, CLR_COUNTER_COUNT> counters{};
  cl_host::read_uints(queue_, counters_, 0, counters);
  std::uint32_t pairs = counters[CLR_COUNTER_SCAN_TOTAL];

  // Clipped primitives (rare, so only scanned when the draw's count of them moved): where their
  // triangles go in the overflow records.
  std::uint32_t clipped = 0;
  if (counters[CLR_COUNTER_CLIPPED] != frame.clipped_primitives) {
    frame.clipped_primitives = counters[CLR_COUNTER_CLIPPED];
    scan_.exclusive(queue_, clipped_offsets, count + 1, block_sums, counters_);
    clipped = read_uint(queue_, counters_, CLR_COUNTER_SCAN_TOTAL);
    if (clipped > frame.plan.overflow_capacity) {  // more clipping than planned for: shorten the chunk
      count = last_offset_within(clipped_offsets, 0, count, clipped, 0, frame.plan.overflow_capacity);
      clipped = read_uint(queue_, clipped_offsets, count);
      pairs = read_uint(queue_, pair_offsets, count);
    }
  }
  const cl::Buffer overflow =
      scratch_.get(Scratch::OverflowRecords, std::max<std::size_t>(clipped, 1) * frame.setup_triangle_bytes);
  if (clipped > 0) {
    stages.setup.run_clipped(queue_, {frame.buffers, slots, shaded, begin, count, clipped_offsets, overflow});
  }

  if (pairs == kSaturated) {
    // More bin pairs than 32-bit offsets count (the scan saturated): end the chunk at the last
    // primitive whose offset is still exact; the next chunk starts with the rest.
    count = last_offset_within(pair_offsets, 0, count, pairs, 0, kSaturated - 1);
    pairs = read_uint(queue_, pair_offsets, count);
  }
  ++stats.chunks;
  stats.tile_triangle_pairs += pairs;
  if (pairs > 0) bin_and_rasterize(frame, {records, bin_boxes, overflow, clipped_offsets, pair_offsets}, count, pairs);
  return count;
}

void Pipeline::bin_and_rasterize(Frame& frame, const ChunkTriangles& chunk, std::uint32_t primitives,
                                 std::uint32_t pairs) {
  const std::uint32_t tile_count = frame.tiles_x * frame.tiles_y;
  // In batches of primitives whose pairs fit the plan, in order.
  for (std::uint32_t batch_begin = 0; batch_begin < primitives;) {
    const std::uint32_t pair_base = read_offset(chunk.pair_offsets, batch_begin, primitives, pairs);
    const std::uint32_t batch_end =
        pairs - pair_base <= frame.plan.pair_capacity
            ? primitives
            : last_offset_within(chunk.pair_offsets, batch_begin, primitives, pairs, pair_base, frame.plan.pair_capacity);
    // Never: the plan holds the most pairs one primitive makes (memory_plan.cpp). But not a hang.
    if (batch_end == batch_begin) {
      throw Error("primitive " + std::to_string(batch_begin) + " of a chunk makes more bin pairs than a raster batch " +
                  "holds (" + std::to_string(frame.plan.pair_capacity) + ")");
    }
    const std::uint32_t batch_pairs = read_offset(chunk.pair_offsets, batch_end, primitives, pairs) - pair_base;
    const std::size_t pair_bytes = std::size_t{batch_pairs} * sizeof(cl_uint);

    stages::BinParams bin;
    bin.bin_boxes = chunk.bin_boxes;
    bin.overflow = chunk.overflow;
    bin.clipped_offsets = chunk.clipped_offsets;
    bin.pair_offsets = chunk.pair_offsets;
    bin.primitive_begin = batch_begin;
    bin.primitive_count = batch_end - batch_begin;
    bin.pair_base = pair_base;
    bin.pair_count = batch_pairs;
    bin.tiles_x = frame.tiles_x;
    bin.tile_count = tile_count;
    bin.tile_keys[0] = scratch_.get(Scratch::TileKeys0, pair_bytes);
    bin.tile_keys[1] = scratch_.get(Scratch::TileKeys1, pair_bytes);
    bin.triangle_ids[0] = scratch_.get(Scratch::TriangleIds0, pair_bytes);
    bin.triangle_ids[1] = scratch_.get(Scratch::TriangleIds1, pair_bytes);
    bin.histogram = scratch_.get(Scratch::RadixHistogram, parallel::RadixSort::histogram_bytes(batch_pairs));
    bin.block_sums = scratch_.get(Scratch::ScanBlockSums, parallel::RadixSort::scan_scratch_bytes(batch_pairs));
    bin.counters = counters_;
    bin.tile_ranges = scratch_.get(Scratch::TileRanges, std::size_t{tile_count} * 2 * sizeof(cl_uint));
    ProgramStages& stages = *frame.source->stages;
    const int sorted = stages.bin.run(queue_, bin);

    const RenderTarget& target = *frame.target;
    stages::RasterParams raster{chunk.records, chunk.overflow, bin.triangle_ids[sorted], bin.tile_ranges, frame.tiles_x,
                                frame.tiles_y, static_cast<std::uint32_t>(target.width), uniforms_,
                                target.depth_stencil() != nullptr ? target.depth_stencil : placeholder_, target.stencil_offset,
                                frame.clears, {}, frame.buffers->resources};
    for (std::size_t k = 0; k < frame.source->program->interface.outputs.size(); ++k) {
      raster.colors.push_back(k < target.colors.size() ? target.colors[k] : placeholder_);
    }
    stages.raster.run(queue_, raster);
    mark_clears_written(target, frame.clears);  // once: later passes load what this one stored
    frame.clears = 0;
    batch_begin = batch_end;
  }
}

}  // namespace clraster::pipeline
