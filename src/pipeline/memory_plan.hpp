// How a draw divides the context's memory cap among the pipeline's intermediate buffers, and so how
// many primitives each chunk takes and how many bin pairs each raster batch takes.
#pragma once

#include "runtime/launch.hpp"
#include "runtime/scratch.hpp"
#include "shared/clr_limits.h"
#include "shared/types.h"

#include <cstddef>
#include <cstdint>

namespace clraster::pipeline {

struct PlanInput {
  std::size_t memory_cap = 0;
  std::size_t buffer_bytes = 0;   // the most one buffer may take (the device's largest allocation)
  std::uint64_t vertex_count = 0;
  bool indexed = false;
  int topology = 0;               // CLR_TOPOLOGY_*
  std::uint32_t primitive_count = 0;
  std::uint32_t tile_count = 0;
  std::size_t shaded_vertex_bytes = 0;   // of the program: a clip position, its window part and varyings
  std::size_t setup_triangle_bytes = 0;  // of the program: a SetupTriangle with its varyings
  // A pass of several draws (Pipeline::render): each draw's vertices in slots of its own, at most a
  // list's stream positions for the chunk (pass_slots), with block culling for any of them.
  bool pass = false;
};

struct MemoryPlan {
  // Indexed draws whose transformed vertices fit in a share of the cap (CLR_SHADE_ALL_CAP_DIVISOR)
  // shade each vertex once per draw; others shade each chunk's stream positions.
  bool shade_all_vertices = false;
  std::uint32_t chunk_primitives = 0;   // primitives per geometry chunk
  std::uint32_t overflow_capacity = 0;  // triangles of a chunk's clipped primitives (more shorten it)
  std::uint64_t pair_capacity = 0;     // bin pairs per raster batch
  runtime::ScratchSizes buffer_bytes{};
};

// Block culling (clr_limits.h): the groups of vertex slots whose clip codes are ANDed, and the most
// blocks of primitives a chunk of `primitives` overlaps, wherever it starts.
inline std::uint64_t code_groups(std::uint64_t vertices) {
  return runtime::divide_round_up(vertices, CLR_CODE_GROUP_SLOTS);
}
inline std::uint32_t chunk_blocks(std::uint32_t primitives) { return primitives / CLR_CULL_BLOCK_PRIMITIVES + 2; }
// The vertex slots of a pass of `primitives` primitives: a list's stream positions, in whole groups.
inline std::uint64_t pass_slots(std::uint64_t primitives) {
  return code_groups(3 * primitives) * CLR_CODE_GROUP_SLOTS;
}

// The plan with the largest chunks that fit the cap, each buffer within buffer_bytes. Throws
// InvalidArgument when they cannot hold even one primitive together with the most bin pairs one
// primitive makes (CLR_MAX_CLIP_TRIANGLES screen-covering triangles).
MemoryPlan plan_memory(const PlanInput& input);

// Stream positions (relative to the draw's first element) that primitives [first, first + count)
// use, for vertex shading per chunk: [begin, begin + count), plus a fan's centre in one more slot.
struct StreamRange {
  std::uint32_t begin = 0;
  std::uint32_t count = 0;
  std::uint32_t slot_count = 0;  // count, + 1 for a fan's centre
};
StreamRange stream_range(int topology, std::uint32_t first_primitive, std::uint32_t primitive_count);

}  // namespace clraster::pipeline
