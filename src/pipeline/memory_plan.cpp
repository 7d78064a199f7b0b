#include "pipeline/memory_plan.hpp"

#include "clraster/clraster.hpp"
#include "shared/clr_limits.h"
#include "parallel/radix_sort.hpp"
#include "shared/types.h"

#include <algorithm>
#include <numeric>
#include <string>

namespace clraster::pipeline {
namespace {

using runtime::Scratch;

std::size_t& at(runtime::ScratchSizes& sizes, Scratch id) { return sizes[static_cast<std::size_t>(id)]; }

runtime::ScratchSizes buffer_bytes(bool shade_all, const PlanInput& in, std::uint64_t chunk, std::uint64_t overflow,
                                     std::uint64_t pairs) {
  runtime::ScratchSizes b{};
  const std::uint64_t slots = in.pass        ? pass_slots(chunk)
                              : shade_all    ? in.vertex_count
                                             : stream_range(in.topology, 0, static_cast<std::uint32_t>(chunk)).slot_count;
  at(b, Scratch::ShadedVertices) = slots * in.shaded_vertex_bytes;
  if (shade_all || in.pass) {  // block culling (clr_limits.h)
    at(b, Scratch::GroupCodes) = code_groups(slots) * sizeof(cl_uint);
    // A byte per block, and 4 bytes at least, as the arena allocates.
    // (A pass's instances each take their draw's blocks whole: at most a byte per primitive.)
    at(b, Scratch::CulledBlocks) =
        std::max<std::uint64_t>(in.pass ? chunk : chunk_blocks(static_cast<std::uint32_t>(chunk)), 4);
  }
  at(b, Scratch::Records) = chunk * in.setup_triangle_bytes;
  at(b, Scratch::BinBoxes) = chunk * sizeof(cl_uint2);
  at(b, Scratch::OverflowRecords) = overflow * in.setup_triangle_bytes;
  // Counts get one more entry, whose exclusive scan is the total.
  at(b, Scratch::ClippedCounts) = (chunk + 1) * sizeof(cl_uint);
  at(b, Scratch::PairCounts) = (chunk + 1) * sizeof(cl_uint);
  for (Scratch s : {Scratch::TileKeys0, Scratch::TileKeys1, Scratch::TriangleIds0, Scratch::TriangleIds1}) {
    at(b, s) = pairs * sizeof(cl_uint);
  }
  at(b, Scratch::TileRanges) = std::size_t{in.tile_count} * 2 * sizeof(cl_uint);
  at(b, Scratch::ScanBlockSums) =
      std::max(parallel::Scan::scratch_bytes(chunk + 1), parallel::RadixSort::scan_scratch_bytes(pairs));
  at(b, Scratch::RadixHistogram) = parallel::RadixSort::histogram_bytes(pairs);
  return b;
}

// The largest value in [lo, hi] that `fits`, which holds for lo and for every value below one that
// it holds for (a binary search).
template <typename Fits>
std::uint64_t largest_fitting(std::uint64_t lo, std::uint64_t hi, Fits fits) {
  while (lo < hi) {
    const std::uint64_t mid = lo + (hi - lo + 1) / 2;
    if (fits(mid)) lo = mid; else hi = mid - 1;
  }
  return lo;
}

std::size_t total(const runtime::ScratchSizes& sizes) {
  return std::accumulate(sizes.begin(), sizes.end(), std::size_t{0});
}

}  // namespace

StreamRange stream_range(int topology, std::uint32_t first_primitive, std::uint32_t primitive_count) {
  switch (topology) {
    case CLR_TOPOLOGY_LIST: return {3 * first_primitive, 3 * primitive_count, 3 * primitive_count};
    case CLR_TOPOLOGY_STRIP: return {first_primitive, primitive_count + 2, primitive_count + 2};
    default: return {first_primitive + 1, primitive_count + 1, primitive_count + 2};
  }
}

MemoryPlan plan_memory(const PlanInput& in) {
  MemoryPlan plan;
  const std::uint64_t all_vertices_bytes = in.vertex_count * in.shaded_vertex_bytes;
  plan.shade_all_vertices = !in.pass && in.indexed && all_vertices_bytes <= in.memory_cap / CLR_SHADE_ALL_CAP_DIVISOR &&
                            all_vertices_bytes <= in.buffer_bytes;
  // Room for the triangles of one primitive at least, however it is clipped.
  const auto overflow_for = [](std::uint64_t chunk) {
    return std::max<std::uint64_t>(chunk / CLR_OVERFLOW_DIVISOR, CLR_MAX_CLIP_TRIANGLES);
  };
  // A raster batch takes whole primitives (Pipeline::bin_and_rasterize), so it must hold the most
  // bin pairs one primitive makes: each of the triangles clipping leaves of it covering every tile.
  // Aim for two pairs per primitive.
  const auto min_pairs_for = [&](std::uint64_t chunk) {
    return std::max<std::uint64_t>(std::uint64_t{CLR_MAX_CLIP_TRIANGLES} * in.tile_count, 2 * chunk);
  };
  const auto sizes_for = [&](std::uint64_t chunk, std::uint64_t pairs) {
    return buffer_bytes(plan.shade_all_vertices, in, chunk, overflow_for(chunk), pairs);
  };
  const auto bytes_for = [&](std::uint64_t chunk, std::uint64_t pairs) { return total(sizes_for(chunk, pairs)); };
  const auto fits = [&](std::uint64_t chunk, std::uint64_t pairs) {
    const runtime::ScratchSizes sizes = sizes_for(chunk, pairs);
    return total(sizes) <= in.memory_cap && *std::max_element(sizes.begin(), sizes.end()) <= in.buffer_bytes;
  };

  const auto chunk_fits = [&](std::uint64_t chunk) { return fits(chunk, min_pairs_for(chunk)); };
  if (!chunk_fits(1)) {
    const runtime::ScratchSizes sizes = sizes_for(1, min_pairs_for(1));
    const std::size_t largest = *std::max_element(sizes.begin(), sizes.end());
    if (largest > in.buffer_bytes) {
      throw InvalidArgument("one primitive's " + std::to_string(min_pairs_for(1)) + " bin entries need a buffer of " +
                            std::to_string((largest >> 10) + 1) + " KiB; the device allocates at most " +
                            std::to_string(in.buffer_bytes >> 10) + " KiB at once: raise the tile size");
    }
    throw InvalidArgument("memory cap of " + std::to_string(in.memory_cap >> 10) + " KiB cannot hold one primitive's " +
                          std::to_string(min_pairs_for(1)) + " bin entries and the pipeline's buffers (needs " +
                          std::to_string((bytes_for(1, min_pairs_for(1)) >> 10) + 1) +
                          " KiB): raise the memory cap or the tile size");
  }
  const std::uint64_t chunk = largest_fitting(
      1, std::min<std::uint64_t>(std::max(in.primitive_count, 1u), CLR_MAX_CHUNK_PRIMITIVES), chunk_fits);
  plan.chunk_primitives = static_cast<std::uint32_t>(chunk);
  plan.overflow_capacity = static_cast<std::uint32_t>(overflow_for(chunk));

  // Whatever the chunk leaves goes to the bin pairs: the most that fit, at least min_pairs_for(chunk)
  // (chunk_fits).
  plan.pair_capacity =
      largest_fitting(min_pairs_for(chunk), 0xffffffffull, [&](std::uint64_t pairs) { return fits(chunk, pairs); });
  plan.buffer_bytes = buffer_bytes(plan.shade_all_vertices, in, chunk, plan.overflow_capacity, plan.pair_capacity);
  return plan;
}

}  // namespace clraster::pipeline
