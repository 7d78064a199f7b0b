// Binning (kernels in bin.cl, sorting in parallel/radix_sort.cl): the (tile, triangle) pairs of a
// batch of primitives' set-up triangles, sorted by tile with primitive order kept, and each tile's
// run of them.
#pragma once

#include "parallel/radix_sort.hpp"

#include <cstdint>

namespace clraster::geometry {

struct BinParams {
  cl::Buffer bin_boxes;            // the pixel boxes of the chunk's per-primitive SetupTriangles
  cl::Buffer overflow;             // and those of its clipped primitives
  cl::Buffer clipped_offsets;      // where each primitive's clipped triangles are in overflow
  cl::Buffer pair_offsets;         // exclusive scan of the per-primitive pair counts
  std::uint32_t primitive_begin = 0;  // the batch: primitives of the chunk
  std::uint32_t primitive_count = 0;
  std::uint32_t pair_base = 0;     // pair offset of primitive_begin
  std::uint32_t pair_count = 0;    // pairs of the batch
  std::uint32_t tiles_x = 0;
  std::uint32_t tile_count = 0;
  cl::Buffer tile_keys[2];         // scratch, pair_count each
  cl::Buffer triangle_ids[2];
  cl::Buffer histogram;            // radix sort scratch
  cl::Buffer block_sums;           // scan scratch
  cl::Buffer counters;
  cl::Buffer tile_ranges;          // out: (first, end) per tile into the sorted triangle ids
};

class BinStage {
 public:
  BinStage(const cl::Program& program, parallel::RadixSort& sort)
      : sort_(sort), emit_(program, "bin_emit"), ranges_(program, "tile_ranges") {}

  // Returns the index (0 or 1) of the triangle_ids buffer that holds the sorted ids.
  int run(runtime::Queue& queue, const BinParams& params);

 private:
  parallel::RadixSort& sort_;
  cl::Kernel emit_;
  cl::Kernel ranges_;
};

}  // namespace clraster::geometry
