/* bin.cl: binning. Every set-up triangle emits one (tile, triangle) pair per tile its bounding box
 * touches, at its primitive's offset from a scan of the per-primitive pair counts, so pairs come out
 * in primitive order. An unclipped triangle's box comes from bin_boxes (setup.cl), not its record.
 * A stable radix sort by tile (radix_sort.cl) then groups them per tile without disturbing that
 * order, and tile_ranges finds where each tile's run starts and ends.
 *
 * Triangle ids: a primitive's own record (setup.cl) is id = primitive index in the chunk; triangles
 * left by clipping are CLR_OVERFLOW_TRIANGLE | their index in the overflow records. */

#include "shared/types.h"

/* The pairs of the triangle `id` whose pixel box has the corners pixel_min and pixel_max (x | y << 16),
 * from pair `out` on; returns the pair after them. */
static inline uint emit_tiles(uint pixel_min, uint pixel_max, uint id, uint tiles_x, uint out, __global uint* tile_keys,
                              __global uint* triangle_ids) {
  for (uint ty = (pixel_min >> 16) / CLR_TILE_SIZE; ty <= (pixel_max >> 16) / CLR_TILE_SIZE; ++ty) {
    for (uint tx = (pixel_min & 0xffffu) / CLR_TILE_SIZE; tx <= (pixel_max & 0xffffu) / CLR_TILE_SIZE; ++tx) {
      tile_keys[out] = ty * tiles_x + tx;
      triangle_ids[out] = id;
      ++out;
    }
  }
  return out;
}

__kernel void bin_emit(uint primitive_begin, uint primitive_count, __global const uint2* bin_boxes,
                       __global const SetupTriangle* overflow, __global const uint* clipped_offsets,
                       __global const uint* pair_offsets, uint pair_base, uint tiles_x, __global uint* tile_keys,
                       __global uint* triangle_ids) {
  if (get_global_id(0) >= primitive_count) return;
  const uint i = primitive_begin + get_global_id(0);
  if (pair_offsets[i] == pair_offsets[i + 1]) return; /* culled, or nothing left after clipping */
  uint out = pair_offsets[i] - pair_base;
  if (clipped_offsets[i] == clipped_offsets[i + 1]) {
    const uint2 box = bin_boxes[i];
    emit_tiles(box.x, box.y, i, tiles_x, out, tile_keys, triangle_ids);
  } else {
    for (uint t = clipped_offsets[i]; t < clipped_offsets[i + 1]; ++t) {
      out = emit_tiles(overflow[t].pixel_min, overflow[t].pixel_max, CLR_OVERFLOW_TRIANGLE | t, tiles_x, out, tile_keys,
                       triangle_ids);
    }
  }
}

/* ranges[2 tile], ranges[2 tile + 1] = first, end of the tile's run in the sorted pairs; tiles without pairs keep the
 * (0, 0) the host filled in. */
__kernel void tile_ranges(__global const uint* sorted_keys, uint pair_count, __global uint* ranges) {
  const uint i = get_global_id(0);
  if (i >= pair_count) return;
  const uint key = sorted_keys[i];
  if (i == 0 || sorted_keys[i - 1] != key) ranges[2 * key] = i;
  if (i + 1 == pair_count || sorted_keys[i + 1] != key) ranges[2 * key + 1] = i + 1;
}
