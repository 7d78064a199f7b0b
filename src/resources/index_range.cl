/* index_range.cl: the smallest and largest index in a range of an index buffer, so that a draw can
 * be refused before it renders anything when it references a vertex that does not exist, and shades
 * only the vertices it uses; and the range of the indices of each block of primitives, for block
 * culling (clr_limits.h). */

#include "shared/clr_limits.h"
#include "shared/types.h"

static inline uint fetch_index(__global const uchar* indices, int index_size, uint position) {
  if (index_size == 2) return ((__global const ushort*)indices)[position];
  return ((__global const uint*)indices)[position];
}

/* Into counters[CLR_COUNTER_MIN_INDEX] and [CLR_COUNTER_MAX_INDEX], which hold ~0 and 0 before. */
__kernel __attribute__((reqd_work_group_size(CLR_SCAN_GROUP_SIZE, 1, 1)))
void index_bounds(__global const uchar* indices, int index_size, uint first, uint count, __global uint* counters) {
  __local uint smallest[CLR_SCAN_GROUP_SIZE];
  __local uint largest[CLR_SCAN_GROUP_SIZE];
  const uint lid = get_local_id(0);
  const uint begin = get_group_id(0) * CLR_SCAN_BLOCK;
  uint low = 0xffffffffu;
  uint high = 0;
  for (uint i = 0; i < CLR_SCAN_ITEMS; ++i) {
    const uint position = begin + i * CLR_SCAN_GROUP_SIZE + lid;
    if (position < count) {
      const uint index = fetch_index(indices, index_size, first + position);
      low = min(low, index);
      high = max(high, index);
    }
  }
  smallest[lid] = low;
  largest[lid] = high;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint stride = CLR_SCAN_GROUP_SIZE / 2; stride > 0; stride >>= 1) {
    if (lid < stride) {
      smallest[lid] = min(smallest[lid], smallest[lid + stride]);
      largest[lid] = max(largest[lid], largest[lid + stride]);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (lid == 0) {
    atomic_min(&counters[CLR_COUNTER_MIN_INDEX], smallest[0]);
    atomic_max(&counters[CLR_COUNTER_MAX_INDEX], largest[0]);
  }
}

/* Where the indices of each block of CLR_CULL_BLOCK_PRIMITIVES primitives of an indexed draw of
 * `primitive_count` primitives from element `first` are, one work-item per block: two ranges, (x, y)
 * and (z, w), that hold them all, the block's smallest to largest index split at their midpoint and
 * each side shrunk to the indices it has. A block of a grid mesh's cells takes vertices from two
 * rows, each a run of the grid's vertex order: two ranges find both, where one would hold the whole
 * row between them. The elements of a list's primitives p are 3p to 3p + 2, of a strip's p to
 * p + 2, and of a fan's 0 and p + 1 to p + 2 (geometry/primitive.cl). */
__kernel void block_index_ranges(__global const uchar* indices, int index_size, uint first, uint primitive_count,
                                 int topology, __global uint4* ranges) {
  const uint block = get_global_id(0);
  const uint begin = block * CLR_CULL_BLOCK_PRIMITIVES;
  if (begin >= primitive_count) return;
  const uint end = min(begin + CLR_CULL_BLOCK_PRIMITIVES, primitive_count);
  uint element_begin = begin, element_end = end + 2;
  if (topology == CLR_TOPOLOGY_LIST) {
    element_begin = 3 * begin;
    element_end = 3 * end;
  } else if (topology == CLR_TOPOLOGY_FAN) {
    element_begin = begin + 1;
  }
  const bool fan = topology == CLR_TOPOLOGY_FAN;
  const uint centre = fetch_index(indices, index_size, first); /* a fan's, in every primitive */
  uint2 range = fan ? (uint2)(centre) : (uint2)(0xffffffffu, 0u);
  for (uint e = element_begin; e < element_end; ++e) {
    const uint index = fetch_index(indices, index_size, first + e);
    range = (uint2)(min(range.x, index), max(range.y, index));
  }
  /* The largest index is above the midpoint unless all are equal, so the upper range has one. */
  const uint middle = range.x + (range.y - range.x) / 2;
  uint4 split = (uint4)(range.x, range.x, range.y, range.y); /* lower's first and last, upper's */
  if (fan && centre <= middle) split.y = max(split.y, centre);
  if (fan && centre > middle) split.z = min(split.z, centre);
  for (uint e = element_begin; e < element_end; ++e) {
    const uint index = fetch_index(indices, index_size, first + e);
    if (index <= middle) split.y = max(split.y, index);
    else split.z = min(split.z, index);
  }
  ranges[block] = split;
}
