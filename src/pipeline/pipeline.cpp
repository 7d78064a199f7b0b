#include "pipeline/pipeline.hpp"

#include "pipeline/draw_state.hpp"
#include "program/generator.hpp"
#include "runtime/launch.hpp"
#include "shared/clr_limits.h"
#include "shared/types.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstring>
#include <optional>
#include <string>

namespace clraster::pipeline {

using runtime::read_uint;
using runtime::Scratch;

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

// The state of a draw that the raster stage reads: draws sharing it can share a raster pass. What
// only the geometry stages read (which elements, the viewport transform, culling) and the clears
// (the pass's first draw carries them) may differ.
DrawUniforms raster_state(DrawUniforms u) {
  std::fill(std::begin(u.viewport_scale), std::end(u.viewport_scale), 0.0f);
  std::fill(std::begin(u.viewport_offset), std::end(u.viewport_offset), 0.0f);
  std::fill(std::begin(u.guard_min), std::end(u.guard_min), 0.0f);
  std::fill(std::begin(u.guard_max), std::end(u.guard_max), 0.0f);
  u.topology = u.index_size = u.cull = u.front_face_ccw = 0;
  u.first = u.instance = u.batch_draw = u.view = 0;
  // Set-up keeps each triangle within its draw's clip rectangle; the pass loads and stores the union.
  std::fill(std::begin(u.clip_rect), std::end(u.clip_rect), 0);
  for (auto& color : u.clear_color) std::fill(std::begin(color), std::end(color), 0u);
  u.clear_depth = 0.0f;
  u.clear_stencil = 0;
  return u;
}

// Grows `into`'s clip rectangle to the smallest that holds `u`'s too (empty ones hold nothing).
void unite_clip_rects(DrawUniforms& into, const DrawUniforms& u) {
  const auto empty = [](const DrawUniforms& d) { return d.clip_rect[0] >= d.clip_rect[2] || d.clip_rect[1] >= d.clip_rect[3]; };
  if (empty(u)) return;
  if (empty(into)) {
    std::copy(std::begin(u.clip_rect), std::end(u.clip_rect), std::begin(into.clip_rect));
    return;
  }
  for (int k = 0; k < 2; ++k) into.clip_rect[k] = std::min(into.clip_rect[k], u.clip_rect[k]);
  for (int k = 2; k < 4; ++k) into.clip_rect[k] = std::max(into.clip_rect[k], u.clip_rect[k]);
}

bool same_buffers(const std::vector<cl::Buffer>& a, const std::vector<cl::Buffer>& b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(),
                    [](const cl::Buffer& x, const cl::Buffer& y) { return x() == y(); });
}

template <typename T>
bool same_bytes(const T& a, const T& b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

}  // namespace

Pipeline::Pipeline(const cl::Context& context, runtime::Queue& queue, const cl::Program& core, std::size_t memory_cap,
                   std::size_t buffer_bytes, std::size_t constant_bytes)
    : context_(context),
      queue_(queue),
      memory_cap_(memory_cap),
      buffer_bytes_(buffer_bytes),
      constant_bytes_(constant_bytes),
      placeholder_(context, CL_MEM_READ_WRITE, 16),
      counters_(context, CL_MEM_READ_WRITE, CLR_COUNTER_COUNT * sizeof(cl_uint)),
      scratch_(context),
      index_bounds_(core, "index_bounds"),
      block_index_ranges_(core, "block_index_ranges"),
      scan_(core),
      sort_(core, scan_) {}

cl::Buffer Pipeline::table(const void* data, std::size_t bytes) const {
  if (bytes == 0) return cl::Buffer(context_, CL_MEM_READ_ONLY, 16);
  return cl::Buffer(context_, CL_MEM_READ_ONLY | CL_MEM_COPY_HOST_PTR, bytes, const_cast<void*>(data));
}

IndexRangeCache::Bounds Pipeline::index_bounds(const DrawSource& source, std::uint32_t first, std::uint32_t count) {
  IndexRangeCache& cache = *source.index_cache;
  const auto found = cache.bounds.find({first, count});
  if (found != cache.bounds.end()) return found->second;
  const std::array<cl_uint, 2> start{~cl_uint{0}, 0};  // smallest, largest
  queue_.get().enqueueWriteBuffer(counters_, CL_TRUE, CLR_COUNTER_MIN_INDEX * sizeof(cl_uint), sizeof(cl_uint),
                                  &start[0], nullptr, queue_.event());
  queue_.get().enqueueWriteBuffer(counters_, CL_TRUE, CLR_COUNTER_MAX_INDEX * sizeof(cl_uint), sizeof(cl_uint),
                                  &start[1], nullptr, queue_.event());
  runtime::set_args(index_bounds_, source.indices, cl_int{source.index_size}, cl_uint{first}, cl_uint{count}, counters_);
  runtime::enqueue_blocks(queue_, index_bounds_, count, CLR_SCAN_BLOCK, runtime::compiled_group_size(index_bounds_));
  std::array<std::uint32_t, CLR_COUNTER_COUNT> counters{};
  runtime::read_uints(queue_, counters_, 0, counters);
  if (cache.bounds.size() >= CLR_INDEX_RANGE_CACHE_ENTRIES) cache.bounds.clear();
  const IndexRangeCache::Bounds bounds{counters[CLR_COUNTER_MIN_INDEX], counters[CLR_COUNTER_MAX_INDEX]};
  cache.bounds[{first, count}] = bounds;
  return bounds;
}

const cl::Buffer& Pipeline::block_index_ranges(const FrameDraw& draw) {
  const DrawSource& source = *draw.source;
  IndexRangeCache& cache = *source.index_cache;
  const auto key = std::make_tuple(draw.first, draw.used_elements, draw.topology);
  const auto found = cache.block_ranges.find(key);
  if (found != cache.block_ranges.end()) return found->second;
  if (cache.block_ranges.size() >= CLR_INDEX_RANGE_CACHE_ENTRIES) cache.block_ranges.clear();
  const std::size_t blocks = runtime::divide_round_up(draw.primitives, CLR_CULL_BLOCK_PRIMITIVES);
  cl::Buffer& ranges = cache.block_ranges[key];
  ranges = cl::Buffer(context_, CL_MEM_READ_WRITE, blocks * sizeof(cl_uint4));
  runtime::set_args(block_index_ranges_, source.indices, cl_int{source.index_size}, cl_uint{draw.first},
                    cl_uint{draw.primitives}, cl_int{draw.topology}, ranges);
  runtime::enqueue_items(queue_, block_index_ranges_, blocks, CLR_ITEM_GROUP_SIZE);
  return ranges;
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

FrameDraw Pipeline::prepare(const RenderTarget& target, const DrawSource& source, std::uint32_t first,
                            std::uint32_t count, const DrawState& state, std::uint32_t view) {
  queue_.set_stage(runtime::Stage::Other);
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

  FrameDraw draw;
  draw.source = &source;
  draw.uniforms = make_uniforms(state, target, program, view);
  draw.uniforms.index_size = source.index_size;
  draw.uniforms.first = first;
  draw.topology = draw.uniforms.topology;
  draw.first = first;
  draw.primitives = primitives_of(draw.topology, element_count);
  if (draw.primitives == 0 || source.instance_count == 0) return draw;

  // Every vertex the draw references: checked before anything renders.
  draw.used_elements =
      static_cast<std::uint32_t>(draw.topology == CLR_TOPOLOGY_LIST ? 3ull * draw.primitives : element_count);
  draw.vertex_count = std::uint64_t{first} + element_count;  // non-indexed: vertices [0, first + count)
  if (indexed) {
    const IndexRangeCache::Bounds bounds = index_bounds(source, first, draw.used_elements);
    if (bounds.largest >= source.vertex_limit) {
      throw InvalidArgument("index " + std::to_string(bounds.largest) +
                            " is out of range: the vertex attributes hold " + std::to_string(source.vertex_limit) +
                            " vertices");
    }
    draw.vertex_count = std::min<std::uint64_t>(source.vertex_limit, std::uint64_t{bounds.largest} + 1);
    draw.smallest_index = bounds.smallest;
  }
  return draw;
}

DrawStats Pipeline::render(const RenderTarget& target, const std::vector<FrameDraw>& draws) {
  DrawStats stats;
  dropped_ = 0;
  // Primitives of the draws from each one on, which size the passes.
  std::vector<std::uint64_t> remaining(draws.size() + 1, 0);
  for (std::size_t i = draws.size(); i-- > 0;) {
    const std::uint64_t primitives = std::uint64_t{draws[i].primitives} * draws[i].source->instance_count;
    remaining[i] = remaining[i + 1] + primitives;
    stats.triangles += primitives;
  }
  runtime::fill(queue_, counters_, cl_uint{0}, 0, CLR_COUNTER_COUNT * sizeof(cl_uint));

  std::optional<Pass> pass;
  for (std::size_t i = 0; i < draws.size(); ++i) {
    const FrameDraw& draw = draws[i];
    if (draw.primitives == 0) continue;
    const std::uint32_t instances = draw.source->instance_count;
    for (std::uint32_t instance = 0; instance < instances;) {
      std::uint32_t taken = pass && shares_raster_pass(*pass, draw) ? add_entry(*pass, draw, instance, instances - instance) : 0;
      if (taken == 0) {
        if (pass) render_pass(target, *pass, stats);
        pass = start_pass(target, draw, remaining[i]);
        taken = add_entry(*pass, draw, instance, instances - instance);
      }
      if (taken == 0) {  // too large for a pass: alone, chunk by chunk
        pass.reset();
        draw_chunked(target, draw, instance, instances, stats);
        break;
      }
      instance += taken;
    }
  }
  if (pass) render_pass(target, *pass, stats);

  stats.triangles_dropped = dropped_;
  stats.peak_memory_bytes = scratch_.peak_bytes();
  stats.stage_times = queue_.collect();
  return stats;
}

void Pipeline::take_dropped(std::uint32_t counted) {
  if (counted == 0) return;
  dropped_ += counted;
  runtime::fill(queue_, counters_, cl_uint{0}, CLR_COUNTER_DROPPED * sizeof(cl_uint), sizeof(cl_uint));
}

Pipeline::RasterInputs Pipeline::raster_inputs(const RenderTarget& target, const DrawSource& source) {
  RasterInputs raster;
  raster.target = &target;
  raster.stages = source.stages;
  raster.outputs = source.program->interface.outputs.size();
  raster.tiles_x = static_cast<std::uint32_t>(runtime::divide_round_up(target.width, source.stages->tile_size));
  raster.tiles_y = static_cast<std::uint32_t>(runtime::divide_round_up(target.height, source.stages->tile_size));
  return raster;
}

Pipeline::Pass Pipeline::start_pass(const RenderTarget& target, const FrameDraw& draw, std::uint64_t primitives) const {
  const program::ParsedProgram& program = *draw.source->program;
  const RasterInputs grid = raster_inputs(target, *draw.source);
  const std::uint32_t tiles = grid.tiles_x * grid.tiles_y;
  Pass pass;
  PlanInput input;
  input.memory_cap = memory_cap_;
  input.buffer_bytes = buffer_bytes_;
  input.topology = CLR_TOPOLOGY_LIST;
  input.primitive_count = static_cast<std::uint32_t>(std::min<std::uint64_t>(primitives, CLR_MAX_CHUNK_PRIMITIVES));
  input.tile_count = tiles;
  input.shaded_vertex_bytes = program::shaded_vertex_bytes(program);
  input.setup_triangle_bytes = program::setup_triangle_bytes(program);
  input.pass = true;
  pass.plan = plan_memory(input);
  pass.slot_capacity = static_cast<std::uint32_t>(pass_slots(pass.plan.chunk_primitives));
  return pass;
}

bool Pipeline::shares_raster_pass(const Pass& pass, const FrameDraw& draw) const {
  const DrawSource& a = *pass.entries.front().draw->source;
  const DrawSource& b = *draw.source;
  if (a.stages != b.stages || !same_buffers(a.textures, b.textures) || !same_buffers(a.buffers, b.buffers)) return false;
  if (a.texture_descs.size() != b.texture_descs.size() ||
      std::memcmp(a.texture_descs.data(), b.texture_descs.data(), a.texture_descs.size() * sizeof(TextureDesc)) != 0) {
    return false;
  }
  return same_bytes(raster_state(pass.entries.front().draw->uniforms), raster_state(draw.uniforms));
}

std::uint32_t Pipeline::add_entry(Pass& pass, const FrameDraw& draw, std::uint32_t instance,
                                  std::uint32_t count) const {
  // A pass's tables are constant memory: a quarter of it for each of the draw and uniform tables.
  const std::size_t entry_bytes = std::max<std::size_t>(
      {sizeof(DrawUniforms), draw.source->uniforms.size(), draw.source->attributes.size() * sizeof(AttributeDesc)});
  const std::size_t max_entries =
      std::clamp<std::size_t>(constant_bytes_ / 4 / std::max<std::size_t>(entry_bytes, 1), 1, CLR_MAX_PASS_DRAWS);
  if (pass.entries.size() >= max_entries || draw.primitives > pass.plan.chunk_primitives - pass.primitives) return 0;
  PassEntry entry;
  entry.draw = &draw;
  entry.instance = instance;
  entry.record_base = pass.primitives;
  entry.slots.slot_base = pass.slots;
  // Indexed draws shade their index range once when it is no larger than their stream positions.
  const StreamRange stream = stream_range(draw.topology, 0, draw.primitives);
  const std::uint64_t range = draw.vertex_count - draw.smallest_index;
  if (draw.indexed() && range <= stream.slot_count) {
    entry.slots.shade_all = 1;
    entry.slots.origin = draw.smallest_index;
    entry.slot_count = static_cast<std::uint32_t>(range);
  } else {
    entry.slots.origin = stream.begin;
    entry.slots.fan_centre = stream.count;
    entry.main_count = stream.count;
    entry.slot_count = stream.slot_count;
  }
  // Whole groups of slots each (block culling).
  entry.instance_slots = static_cast<std::uint32_t>(code_groups(entry.slot_count) * CLR_CODE_GROUP_SLOTS);
  entry.instances = static_cast<std::uint32_t>(
      std::min<std::uint64_t>({count, (pass.plan.chunk_primitives - pass.primitives) / draw.primitives,
                               (pass.slot_capacity - pass.slots) / entry.instance_slots}));
  if (entry.instances == 0) return 0;
  pass.slots += entry.instances * entry.instance_slots;
  pass.primitives += entry.instances * draw.primitives;
  pass.culls_blocks = pass.culls_blocks || entry.slots.shade_all;
  pass.entries.push_back(entry);
  return entry.instances;
}

void Pipeline::render_pass(const RenderTarget& target, const Pass& pass, DrawStats& stats) {
  const FrameDraw& lead = *pass.entries.front().draw;
  const DrawSource& lead_source = *lead.source;
  ProgramStages& stages = *lead_source.stages;
  const std::size_t entries = pass.entries.size();

  // The pass's tables: each entry's DrawUniforms, uniform block and attribute descriptions.
  std::vector<DrawUniforms> draw_table(entries);
  const std::size_t uniform_stride = lead_source.uniforms.size();
  const std::size_t attribute_count = lead_source.attributes.size();
  std::vector<std::byte> uniform_table(entries * uniform_stride);
  std::vector<AttributeDesc> attribute_table(entries * attribute_count);
  for (std::size_t k = 0; k < entries; ++k) {
    const PassEntry& entry = pass.entries[k];
    draw_table[k] = entry.draw->uniforms;
    draw_table[k].instance = entry.instance;
    draw_table[k].batch_draw = static_cast<cl_uint>(k);
    std::copy(entry.draw->source->uniforms.begin(), entry.draw->source->uniforms.end(),
              uniform_table.begin() + static_cast<std::ptrdiff_t>(k * uniform_stride));
    std::copy(entry.draw->source->attributes.begin(), entry.draw->source->attributes.end(),
              attribute_table.begin() + static_cast<std::ptrdiff_t>(k * attribute_count));
  }
  const std::uint32_t clears = pending_clears(target, lead_source.program->interface.outputs.size(), draw_table[0]);
  const cl::Buffer draws = table(draw_table.data(), entries * sizeof(DrawUniforms));
  // The raster stage reads the lead's state (raster_state: the same for every entry) over the union
  // of the entries' clip rectangles, the layers of a draw's views for one.
  DrawUniforms raster_uniforms = draw_table[0];
  for (const DrawUniforms& u : draw_table) unite_clip_rects(raster_uniforms, u);
  const cl::Buffer attribute_descs = table(attribute_table.data(), attribute_table.size() * sizeof(AttributeDesc));
  geometry::ProgramResources resources;
  resources.uniform_block = table(uniform_table.data(), uniform_table.size());
  resources.texture_descs =
      table(lead_source.texture_descs.data(), lead_source.texture_descs.size() * sizeof(TextureDesc));
  resources.textures = lead_source.textures;
  resources.buffers = lead_source.buffers;

  const std::size_t shaded_vertex_bytes = program::shaded_vertex_bytes(*lead_source.program);
  const std::size_t setup_triangle_bytes = program::setup_triangle_bytes(*lead_source.program);
  scratch_.set_capacities(pass.plan.buffer_bytes);
  const std::uint32_t count = pass.primitives;
  const std::size_t count_bytes = (std::size_t{count} + 1) * sizeof(cl_uint);
  const cl::Buffer shaded = scratch_.get(Scratch::ShadedVertices, std::size_t{pass.slots} * shaded_vertex_bytes);
  const cl::Buffer group_codes =
      pass.culls_blocks ? scratch_.get(Scratch::GroupCodes, code_groups(pass.slots) * sizeof(cl_uint)) : placeholder_;
  const cl::Buffer records = scratch_.get(Scratch::Records, std::size_t{count} * setup_triangle_bytes);
  const cl::Buffer bin_boxes = scratch_.get(Scratch::BinBoxes, std::size_t{count} * sizeof(cl_uint2));
  const cl::Buffer pair_offsets = scratch_.get(Scratch::PairCounts, count_bytes);
  const cl::Buffer clipped_offsets = scratch_.get(Scratch::ClippedCounts, count_bytes);

  // Each entry through the vertex stage and set-up, into its own slots and records.
  std::vector<geometry::DrawBuffers> buffers(entries);
  for (std::size_t k = 0; k < entries; ++k) {
    const PassEntry& entry = pass.entries[k];
    const FrameDraw& draw = *entry.draw;
    geometry::DrawBuffers& b = buffers[k];
    b.indices = draw.indexed() ? draw.source->indices : placeholder_;
    b.uniforms = draws;
    b.draw = static_cast<std::uint32_t>(k);
    b.counters = counters_;
    b.resources = &resources;
    b.attribute_descs = attribute_descs;
    b.attributes = draw.source->attribute_buffers;
    const bool shade_all = entry.slots.shade_all != 0;
    if (shade_all && stages.vertex.ands_group_codes()) {
      queue_.set_stage(runtime::Stage::Vertex);
      runtime::fill(queue_, group_codes, ~cl_uint{0}, entry.slots.slot_base / CLR_CODE_GROUP_SLOTS * sizeof(cl_uint),
                    std::size_t{entry.instances} * entry.instance_slots / CLR_CODE_GROUP_SLOTS * sizeof(cl_uint));
    }
    stages.vertex.run(queue_, {.draw = &b, .slots = entry.slots, .main_count = entry.main_count,
                               .slot_count = entry.slot_count, .instances = entry.instances,
                               .instance_slots = entry.instance_slots, .shaded = shaded, .group_codes = group_codes});
    cl::Buffer culled_blocks = placeholder_;
    if (shade_all) {
      const auto block_count = static_cast<std::uint32_t>(runtime::divide_round_up(draw.primitives, CLR_CULL_BLOCK_PRIMITIVES));
      culled_blocks = scratch_.get(Scratch::CulledBlocks, std::size_t{block_count} * entry.instances);
      stages.setup.run_cull(queue_, {.first_block = 0, .block_count = block_count,
                                     .index_ranges = block_index_ranges(draw),
                                     .slot_offset = entry.slots.slot_base - entry.slots.origin,
                                     .instances = entry.instances, .instance_slots = entry.instance_slots,
                                     .group_codes = group_codes, .culled = culled_blocks});
    }
    stages.setup.run(queue_, {.draw = &b, .slots = entry.slots, .shaded = shaded, .primitive_begin = 0,
                              .primitive_count = draw.primitives, .instances = entry.instances,
                              .instance_slots = entry.instance_slots, .block_culling = shade_all,
                              .culled_blocks = culled_blocks, .record_base = entry.record_base, .records = records,
                              .bin_boxes = bin_boxes, .pair_counts = pair_offsets, .clipped_counts = clipped_offsets});
  }

  // Where each primitive's bin pairs go, and, in the same read, whether any was clipped or dropped.
  const cl::Buffer block_sums = scratch_.get(Scratch::ScanBlockSums, parallel::Scan::scratch_bytes(count + 1));
  scan_.exclusive(queue_, pair_offsets, count + 1, block_sums, counters_);
  std::array<std::uint32_t, CLR_COUNTER_COUNT> counters{};
  runtime::read_uints(queue_, counters_, 0, counters);
  const std::uint32_t pairs = counters[CLR_COUNTER_SCAN_TOTAL];
  std::uint32_t clipped = 0;
  if (counters[CLR_COUNTER_CLIPPED] != 0) {
    runtime::fill(queue_, counters_, cl_uint{0}, CLR_COUNTER_CLIPPED * sizeof(cl_uint), sizeof(cl_uint));
    scan_.exclusive(queue_, clipped_offsets, count + 1, block_sums, counters_);
    clipped = read_uint(queue_, counters_, CLR_COUNTER_SCAN_TOTAL);
  }
  if (clipped > pass.plan.overflow_capacity || pairs == kSaturated) {
    // More clipping than the plan holds, or more bin pairs than 32-bit offsets count (rare): the
    // pass's geometry is dropped, and its entries rendered alone, chunk by chunk, which split where
    // they must.
    runtime::fill(queue_, counters_, cl_uint{0}, CLR_COUNTER_DROPPED * sizeof(cl_uint), sizeof(cl_uint));
    for (const PassEntry& entry : pass.entries) {
      draw_chunked(target, *entry.draw, entry.instance, entry.instance + entry.instances, stats);
    }
    return;
  }
  take_dropped(counters[CLR_COUNTER_DROPPED]);
  const cl::Buffer overflow =
      scratch_.get(Scratch::OverflowRecords, std::max<std::size_t>(clipped, 1) * setup_triangle_bytes);
  if (clipped > 0) {
    for (std::size_t k = 0; k < entries; ++k) {
      const PassEntry& entry = pass.entries[k];
      stages.setup.run_clipped(queue_, {.draw = &buffers[k], .slots = entry.slots, .shaded = shaded, .primitive_begin = 0,
                                        .primitive_count = entry.draw->primitives, .instances = entry.instances,
                                        .instance_slots = entry.instance_slots, .record_base = entry.record_base,
                                        .clipped_offsets = clipped_offsets, .overflow = overflow});
    }
  }
  ++stats.chunks;
  stats.tile_triangle_pairs += pairs;
  RasterInputs raster = raster_inputs(target, lead_source);
  raster.draws = table(&raster_uniforms, sizeof raster_uniforms);
  raster.resources = &resources;
  raster.pair_capacity = pass.plan.pair_capacity;
  raster.clears = clears;
  if (pairs > 0) bin_and_rasterize(raster, {records, bin_boxes, overflow, clipped_offsets, pair_offsets}, count, pairs);
}

void Pipeline::draw_chunked(const RenderTarget& target, const FrameDraw& draw, std::uint32_t instance_begin,
                            std::uint32_t instance_end, DrawStats& stats) {
  const DrawSource& source = *draw.source;
  const program::ParsedProgram& program = *source.program;
  ChunkedDraw chunked;
  chunked.draw = &draw;
  chunked.shaded_vertex_bytes = program::shaded_vertex_bytes(program);
  chunked.setup_triangle_bytes = program::setup_triangle_bytes(program);
  chunked.raster = raster_inputs(target, source);
  RasterInputs& raster = chunked.raster;
  chunked.plan = plan_memory({memory_cap_, buffer_bytes_, draw.vertex_count, draw.indexed(), draw.topology,
                              draw.primitives, raster.tiles_x * raster.tiles_y, chunked.shaded_vertex_bytes,
                              chunked.setup_triangle_bytes});
  raster.pair_capacity = chunked.plan.pair_capacity;
  scratch_.set_capacities(chunked.plan.buffer_bytes);

  DrawUniforms uniforms = draw.uniforms;
  geometry::ProgramResources resources;
  resources.uniform_block = table(source.uniforms.data(), source.uniforms.size());
  resources.texture_descs = table(source.texture_descs.data(), source.texture_descs.size() * sizeof(TextureDesc));
  resources.textures = source.textures;
  resources.buffers = source.buffers;
  raster.resources = &resources;
  geometry::DrawBuffers buffers;
  buffers.indices = draw.indexed() ? source.indices : placeholder_;
  buffers.counters = counters_;
  buffers.resources = &resources;
  buffers.attribute_descs = table(source.attributes.data(), source.attributes.size() * sizeof(AttributeDesc));
  buffers.attributes = source.attribute_buffers;
  chunked.buffers = &buffers;

  // Block culling (clr_limits.h), where every vertex is shaded once per draw (indexed draws only).
  if (chunked.plan.shade_all_vertices) {
    chunked.block_ranges = block_index_ranges(draw);
    chunked.group_codes = scratch_.get(Scratch::GroupCodes, code_groups(draw.vertex_count) * sizeof(cl_uint));
  }

  // Instances are drawn one after the other, in order, as OpenGL orders their primitives.
  for (std::uint32_t instance = instance_begin; instance < instance_end; ++instance) {
    uniforms.instance = instance;
    raster.clears = pending_clears(target, raster.outputs, uniforms);
    buffers.uniforms = raster.draws = table(&uniforms, sizeof uniforms);
    if (chunked.plan.shade_all_vertices) {
      if (source.stages->vertex.ands_group_codes()) {
        queue_.set_stage(runtime::Stage::Vertex);
        runtime::fill(queue_, chunked.group_codes, ~cl_uint{0}, 0, code_groups(draw.vertex_count) * sizeof(cl_uint));
      }
      source.stages->vertex.run(
          queue_, {.draw = &buffers, .slots = SlotMap{1, 0, 0, 0}, .slot_count = static_cast<std::uint32_t>(draw.vertex_count),
                   .shaded = scratch_.get(Scratch::ShadedVertices, draw.vertex_count * chunked.shaded_vertex_bytes),
                   .group_codes = chunked.group_codes});
    }
    for (std::uint32_t begin = 0; begin < draw.primitives;) {
      begin += run_chunk(chunked, begin, std::min(chunked.plan.chunk_primitives, draw.primitives - begin), stats);
    }
  }
  take_dropped(read_uint(queue_, counters_, CLR_COUNTER_DROPPED));
  runtime::fill(queue_, counters_, cl_uint{0}, CLR_COUNTER_CLIPPED * sizeof(cl_uint), sizeof(cl_uint));
}

std::uint32_t Pipeline::run_chunk(ChunkedDraw& chunked, std::uint32_t begin, std::uint32_t count, DrawStats& stats) {
  // Vertex stage: done once for the draw, or this chunk's stream positions.
  SlotMap slots{1, 0, 0, 0};
  cl::Buffer shaded;
  const FrameDraw& draw = *chunked.draw;
  if (chunked.plan.shade_all_vertices) {
    shaded = scratch_.get(Scratch::ShadedVertices, draw.vertex_count * chunked.shaded_vertex_bytes);
  } else {
    const StreamRange range = stream_range(draw.topology, begin, count);
    shaded = scratch_.get(Scratch::ShadedVertices, std::size_t{range.slot_count} * chunked.shaded_vertex_bytes);
    slots = {0, range.begin, range.count, 0};
    draw.source->stages->vertex.run(queue_, {.draw = chunked.buffers, .slots = slots, .main_count = range.count,
                                             .slot_count = range.slot_count, .shaded = shaded, .group_codes = placeholder_});
  }

  // Set-up: a record per primitive, and for primitives that cross a clip plane the number of
  // triangles clipping leaves; bin pair counts for all of them. Both count arrays get one more
  // entry, zero (set-up writes it), whose exclusive scan is the total.
  const std::size_t count_bytes = (std::size_t{count} + 1) * sizeof(cl_uint);
  const cl::Buffer records = scratch_.get(Scratch::Records, std::size_t{count} * chunked.setup_triangle_bytes);
  const cl::Buffer bin_boxes = scratch_.get(Scratch::BinBoxes, std::size_t{count} * sizeof(cl_uint2));
  const cl::Buffer pair_offsets = scratch_.get(Scratch::PairCounts, count_bytes);
  const cl::Buffer clipped_offsets = scratch_.get(Scratch::ClippedCounts, count_bytes);
  const cl::Buffer block_sums = scratch_.get(Scratch::ScanBlockSums, parallel::Scan::scratch_bytes(count + 1));
  ProgramStages& stages = *draw.source->stages;
  cl::Buffer culled_blocks = placeholder_;
  if (chunked.plan.shade_all_vertices) {  // block culling
    const std::uint32_t first_block = begin / CLR_CULL_BLOCK_PRIMITIVES;
    const std::uint32_t block_count = (begin + count - 1) / CLR_CULL_BLOCK_PRIMITIVES - first_block + 1;
    culled_blocks = scratch_.get(Scratch::CulledBlocks, block_count);
    stages.setup.run_cull(queue_, {.first_block = first_block, .block_count = block_count,
                                   .index_ranges = chunked.block_ranges, .group_codes = chunked.group_codes,
                                   .culled = culled_blocks});
  }
  stages.setup.run(queue_, {.draw = chunked.buffers, .slots = slots, .shaded = shaded, .primitive_begin = begin,
                            .primitive_count = count, .block_culling = chunked.plan.shade_all_vertices,
                            .culled_blocks = culled_blocks, .records = records, .bin_boxes = bin_boxes,
                            .pair_counts = pair_offsets, .clipped_counts = clipped_offsets});

  // Where each primitive's bin pairs go, and, in the same read, whether any primitive was clipped.
  scan_.exclusive(queue_, pair_offsets, count + 1, block_sums, counters_);
  std::array<std::uint32_t, CLR_COUNTER_COUNT> counters{};
  runtime::read_uints(queue_, counters_, 0, counters);
  std::uint32_t pairs = counters[CLR_COUNTER_SCAN_TOTAL];

  // Clipped primitives (rare, so only scanned when the draw's count of them moved): where their
  // triangles go in the overflow records.
  std::uint32_t clipped = 0;
  if (counters[CLR_COUNTER_CLIPPED] != chunked.clipped_primitives) {
    chunked.clipped_primitives = counters[CLR_COUNTER_CLIPPED];
    scan_.exclusive(queue_, clipped_offsets, count + 1, block_sums, counters_);
    clipped = read_uint(queue_, counters_, CLR_COUNTER_SCAN_TOTAL);
    if (clipped > chunked.plan.overflow_capacity) {  // more clipping than planned for: shorten the chunk
      count = last_offset_within(clipped_offsets, 0, count, clipped, 0, chunked.plan.overflow_capacity);
      clipped = read_uint(queue_, clipped_offsets, count);
      pairs = read_uint(queue_, pair_offsets, count);
    }
  }
  const cl::Buffer overflow =
      scratch_.get(Scratch::OverflowRecords, std::max<std::size_t>(clipped, 1) * chunked.setup_triangle_bytes);
  if (clipped > 0) {
    stages.setup.run_clipped(queue_, {.draw = chunked.buffers, .slots = slots, .shaded = shaded, .primitive_begin = begin,
                                      .primitive_count = count, .clipped_offsets = clipped_offsets, .overflow = overflow});
  }

  if (pairs == kSaturated) {
    // More bin pairs than 32-bit offsets count (the scan saturated): end the chunk at the last
    // primitive whose offset is still exact; the next chunk starts with the rest.
    count = last_offset_within(pair_offsets, 0, count, pairs, 0, kSaturated - 1);
    pairs = read_uint(queue_, pair_offsets, count);
  }
  ++stats.chunks;
  stats.tile_triangle_pairs += pairs;
  if (pairs > 0) bin_and_rasterize(chunked.raster, {records, bin_boxes, overflow, clipped_offsets, pair_offsets}, count, pairs);
  return count;
}

void Pipeline::bin_and_rasterize(RasterInputs& inputs, const ChunkTriangles& chunk, std::uint32_t primitives,
                                 std::uint32_t pairs) {
  const std::uint32_t tile_count = inputs.tiles_x * inputs.tiles_y;
  // In batches of primitives whose pairs fit the plan, in order.
  for (std::uint32_t batch_begin = 0; batch_begin < primitives;) {
    const std::uint32_t pair_base = read_offset(chunk.pair_offsets, batch_begin, primitives, pairs);
    const std::uint32_t batch_end =
        pairs - pair_base <= inputs.pair_capacity
            ? primitives
            : last_offset_within(chunk.pair_offsets, batch_begin, primitives, pairs, pair_base, inputs.pair_capacity);
    // Never: the plan holds the most pairs one primitive makes (memory_plan.cpp). But not a hang.
    if (batch_end == batch_begin) {
      throw Error("primitive " + std::to_string(batch_begin) + " of a chunk makes more bin pairs than a raster batch " +
                  "holds (" + std::to_string(inputs.pair_capacity) + ")");
    }
    const std::uint32_t batch_pairs = read_offset(chunk.pair_offsets, batch_end, primitives, pairs) - pair_base;
    const std::size_t pair_bytes = std::size_t{batch_pairs} * sizeof(cl_uint);

    geometry::BinParams bin;
    bin.bin_boxes = chunk.bin_boxes;
    bin.overflow = chunk.overflow;
    bin.clipped_offsets = chunk.clipped_offsets;
    bin.pair_offsets = chunk.pair_offsets;
    bin.primitive_begin = batch_begin;
    bin.primitive_count = batch_end - batch_begin;
    bin.pair_base = pair_base;
    bin.pair_count = batch_pairs;
    bin.tiles_x = inputs.tiles_x;
    bin.tile_count = tile_count;
    bin.tile_keys[0] = scratch_.get(Scratch::TileKeys0, pair_bytes);
    bin.tile_keys[1] = scratch_.get(Scratch::TileKeys1, pair_bytes);
    bin.triangle_ids[0] = scratch_.get(Scratch::TriangleIds0, pair_bytes);
    bin.triangle_ids[1] = scratch_.get(Scratch::TriangleIds1, pair_bytes);
    bin.histogram = scratch_.get(Scratch::RadixHistogram, parallel::RadixSort::histogram_bytes(batch_pairs));
    bin.block_sums = scratch_.get(Scratch::ScanBlockSums, parallel::RadixSort::scan_scratch_bytes(batch_pairs));
    bin.counters = counters_;
    bin.tile_ranges = scratch_.get(Scratch::TileRanges, std::size_t{tile_count} * 2 * sizeof(cl_uint));
    ProgramStages& stages = *inputs.stages;
    const int sorted = stages.bin.run(queue_, bin);

    const RenderTarget& target = *inputs.target;
    raster::RasterParams raster{chunk.records, chunk.overflow, bin.triangle_ids[sorted], bin.tile_ranges, inputs.tiles_x,
                                inputs.tiles_y, static_cast<std::uint32_t>(target.width), inputs.draws,
                                target.depth_stencil() != nullptr ? target.depth_stencil : placeholder_, target.stencil_offset,
                                inputs.clears, {}, inputs.resources};
    for (std::size_t k = 0; k < inputs.outputs; ++k) {
      raster.colors.push_back(k < target.colors.size() ? target.colors[k] : placeholder_);
    }
    stages.raster.run(queue_, raster);
    mark_clears_written(target, inputs.clears);  // once: later passes load what this one stored
    inputs.clears = 0;
    batch_begin = batch_end;
  }
}

}  // namespace clraster::pipeline
