#include "geometry/bin.hpp"

#include "runtime/launch.hpp"
#include "shared/clr_limits.h"

#include <bit>

namespace clraster::geometry {

int BinStage::run(runtime::Queue& queue, const BinParams& p) {
  queue.set_stage(runtime::Stage::Binning);
  runtime::set_args(emit_, cl_uint{p.primitive_begin}, cl_uint{p.primitive_count}, p.bin_boxes, p.overflow,
                    p.clipped_offsets, p.pair_offsets, cl_uint{p.pair_base}, cl_uint{p.tiles_x}, p.tile_keys[0],
                    p.triangle_ids[0]);
  runtime::enqueue_items(queue, emit_, p.primitive_count, CLR_ITEM_GROUP_SIZE);

  // Only the bits a tile index can have are sorted.
  const int key_bits = std::bit_width(p.tile_count - 1);
  const int sorted = sort_.sort(queue, p.tile_keys, p.triangle_ids, p.pair_count, key_bits, p.histogram,
                                p.block_sums, p.counters);

  runtime::fill(queue, p.tile_ranges, cl_uint{0}, 0, std::size_t{p.tile_count} * 2 * sizeof(cl_uint));
  runtime::set_args(ranges_, p.tile_keys[sorted], cl_uint{p.pair_count}, p.tile_ranges);
  runtime::enqueue_items(queue, ranges_, p.pair_count, CLR_ITEM_GROUP_SIZE);
  return sorted;
}

}  // namespace clraster::geometry
