/* bin.cl: binning. Every set-up triangle emits one (tile, triangle) pair per tile its bounding box
 * touches, at offsets from a scan of the pair counts, so pairs come out in triangle order. A stable
 * radix sort by tile (radix_sort.cl) then groups them per tile without disturbing that order, and
 * tile_ranges finds where each tile's run starts and ends. */

__kernel void bin_emit(uint triangle_begin, uint triangle_count, __global const SetupTriangle* triangles,
                       __global const uint* pair_offsets, uint pair_base, uint tiles_x,
                       __global uint* tile_keys, __global uint* triangle_ids) {
  const uint i = get_global_id(0);
  if (i >= triangle_count) return;
  const uint triangle = triangle_begin + i;
  const uint pixel_min = triangles[triangle].pixel_min;
  const uint pixel_max = triangles[triangle].pixel_max;
  uint out = pair_offsets[triangle] - pair_base;
  for (uint ty = (pixel_min >> 16) / CLR_TILE_SIZE; ty <= (pixel_max >> 16) / CLR_TILE_SIZE; ++ty) {
    for (uint tx = (pixel_min & 0xffffu) / CLR_TILE_SIZE; tx <= (pixel_max & 0xffffu) / CLR_TILE_SIZE; ++tx) {
      tile_keys[out] = ty * tiles_x + tx;
      triangle_ids[out] = triangle;
      ++out;
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
