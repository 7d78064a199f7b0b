#include "pipeline/memory_plan.hpp"

#include "clraster/clraster.hpp"
#include "clr_limits.h"
#include "parallel/radix_sort.hpp"
#include "stages/types.h"

#include <algorithm>
#include <numeric>
#include <string>

namespace clraster::pipeline {
namespace {

using resources::Scratch;

constexpr std::size_t kShadedVertexBytes = CLR_SHADED_VERTEX_FLOAT4S * 4 * sizeof(float);

std::size_t& at(resources::ScratchSizes& sizes, Scratch id) { return sizes[static_cast<std::size_t>(id)]; }

std::uint64_t stream_slots(int topology, std::uint64_t primitives) {
  // Lists use three positions per primitive; strips and fans one more than the primitives, and fans
  // one slot for the centre.
  if (topology == CLR_TOPOLOGY_LIST) return 3 * primitives;
  return primitives + 2;
}

resources::ScratchSizes buffer_bytes(bool shade_all, const PlanInput& in, std::uint64_t chunk, std::uint64_t setup,
                                     std::uint64_t pairs) {
  resources::ScratchSizes b{};
  at(b, Scratch::ShadedVertices) =
      (shade_all ? in.vertex_count : stream_slots(in.topology, chunk)) * kShadedVertexBytes;
  at(b, Scratch::TriangleCounts) = chunk * sizeof(cl_uint);
  at(b, Scratch::SetupTriangles) = setup * sizeof(SetupTriangle);
  at(b, Scratch::PairCounts) = setup * sizeof(cl_uint);
  for (Scratch s : {Scratch::TileKeys0, Scratch::TileKeys1, Scratch::TriangleIds0, Scratch::TriangleIds1}) {
    at(b, s) = pairs * sizeof(cl_uint);
  }
  at(b, Scratch::TileRanges) = std::size_t{in.tile_count} * 2 * sizeof(cl_uint);
  at(b, Scratch::ScanBlockSums) = std::max(parallel::Scan::scratch_bytes(std::max(chunk, setup)),
                                           parallel::RadixSort::scan_scratch_bytes(pairs));
  at(b, Scratch::RadixHistogram) = parallel::RadixSort::histogram_bytes(pairs);
  return b;
}

std::size_t total(const resources::ScratchSizes& sizes) {
  return std::accumulate(sizes.begin(), sizes.end(), std::size_t{0});
}

}  // namespace

StreamRange stream_range(int topology, std::uint32_t first_primitive, std::uint32_t primitive_count) {
  switch (topology) {
    case CLR_TOPOLOGY_LIST: return {3 * first_primitive, 3 * primitive_count};
    case CLR_TOPOLOGY_STRIP: return {first_primitive, primitive_count + 2};
    default: return {first_primitive + 1, primitive_count + 1};  // the centre gets the extra slot
  }
}

MemoryPlan plan_memory(const PlanInput& in) {
  MemoryPlan plan;
  plan.shade_all_vertices = in.indexed && in.vertex_count * kShadedVertexBytes <= in.memory_cap / 4;
  // Room for the triangles of one primitive at least, however it is clipped.
  const auto setup_for = [](std::uint64_t chunk) { return std::max<std::uint64_t>(chunk, CLR_MAX_CLIP_TRIANGLES); };
  // A raster batch must hold a triangle that covers every tile; aim for two pairs per triangle.
  const auto min_pairs_for = [&](std::uint64_t setup) { return std::max<std::uint64_t>(in.tile_count, 2 * setup); };
  const auto fits = [&](std::uint64_t chunk) {
    const std::uint64_t setup = setup_for(chunk);
    return total(buffer_bytes(plan.shade_all_vertices, in, chunk, setup, min_pairs_for(setup))) <= in.memory_cap;
  };

  std::uint64_t lo = 1;
  std::uint64_t hi = std::min<std::uint64_t>(std::max(in.primitive_count, 1u), CLR_MAX_CHUNK_PRIMITIVES);
  if (!fits(lo)) {
    const std::size_t needed = total(buffer_bytes(plan.shade_all_vertices, in, 1, setup_for(1), min_pairs_for(setup_for(1))));
    throw InvalidArgument("memory cap of " + std::to_string(in.memory_cap >> 10) + " KiB cannot hold one triangle's " +
                          std::to_string(in.tile_count) + " bin entries and the pipeline's buffers (needs " +
                          std::to_string((needed >> 10) + 1) + " KiB): raise the memory cap or the tile size");
  }
  while (lo < hi) {  // the largest chunk that fits
    const std::uint64_t mid = lo + (hi - lo + 1) / 2;
    if (fits(mid)) lo = mid; else hi = mid - 1;
  }
  plan.chunk_primitives = static_cast<std::uint32_t>(lo);
  plan.setup_capacity = static_cast<std::uint32_t>(setup_for(lo));

  // Whatever the chunk leaves goes to the bin pairs (each pair: a key and an id, twice, plus scratch).
  const std::size_t without_pairs = total(buffer_bytes(plan.shade_all_vertices, in, lo, plan.setup_capacity, 0));
  std::uint64_t pairs = (in.memory_cap - without_pairs) / (4 * sizeof(cl_uint) + 1);
  pairs = std::min<std::uint64_t>(pairs, 0xffffffffull);
  while (total(buffer_bytes(plan.shade_all_vertices, in, lo, plan.setup_capacity, pairs)) > in.memory_cap) {
    pairs -= pairs / 64 + 1;
  }
  plan.pair_capacity = pairs;
  plan.buffer_bytes = buffer_bytes(plan.shade_all_vertices, in, lo, plan.setup_capacity, pairs);
  return plan;
}

}  // namespace clraster::pipeline
