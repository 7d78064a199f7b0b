/* index_range.cl: the largest index in a range of an index buffer, so that a draw can be refused
 * before it renders anything when it references a vertex that does not exist. */

static inline uint fetch_index(__global const uchar* indices, int index_size, uint position) {
  if (index_size == 2) return ((__global const ushort*)indices)[position];
  return ((__global const uint*)indices)[position];
}

__kernel __attribute__((reqd_work_group_size(CLR_SCAN_GROUP_SIZE, 1, 1)))
void index_max(__global const uchar* indices, int index_size, uint first, uint count, __global uint* counters) {
  __local uint scratch[CLR_SCAN_GROUP_SIZE];
  const uint lid = get_local_id(0);
  const uint begin = get_group_id(0) * CLR_SCAN_BLOCK;
  uint largest = 0;
  for (uint i = 0; i < CLR_SCAN_ITEMS; ++i) {
    const uint position = begin + i * CLR_SCAN_GROUP_SIZE + lid;
    if (position < count) largest = max(largest, fetch_index(indices, index_size, first + position));
  }
  scratch[lid] = largest;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint stride = CLR_SCAN_GROUP_SIZE / 2; stride > 0; stride >>= 1) {
    if (lid < stride) scratch[lid] = max(scratch[lid], scratch[lid + stride]);
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (lid == 0) atomic_max(&counters[CLR_COUNTER_MAX_INDEX], scratch[0]);
}
