/* scan.cl: exclusive prefix sums of uint arrays, in place, in three passes:
 *   scan_reduce      one work-group per block of CLR_SCAN_BLOCK elements writes the block's sum;
 *   scan_block_sums  one work-group scans the block sums (any number of them, in rounds);
 *   scan_apply       one work-group per block scans its block and adds the block's offset.
 * Sums saturate at UINT_MAX instead of wrapping: saturating addition of non-negative values is still
 * associative, so the result does not depend on the order of the additions, and a scan whose true
 * total does not fit in 32 bits stays monotone, with a total of UINT_MAX the host can recognize. */

#include "shared/clr_limits.h"
#include "shared/types.h"

/* A block's elements add up exactly in 64 bits; their saturated sum is that, clamped. */
static inline uint saturated(ulong sum) { return (uint)min(sum, (ulong)UINT_MAX); }

#if CLR_SCAN_ITEMS % 8 != 0
#error "scan_apply scans a work-item's elements eight at a time"
#endif

/* Lane k: the sum of lanes 0 to k (three shifted additions). */
static inline ulong8 inclusive_scan8(ulong8 v) {
  const ulong8 zero = (ulong8)(0);
  v += shuffle2(zero, v, (ulong8)(0, 8, 9, 10, 11, 12, 13, 14));
  v += shuffle2(zero, v, (ulong8)(0, 1, 8, 9, 10, 11, 12, 13));
  v += shuffle2(zero, v, (ulong8)(0, 1, 2, 3, 8, 9, 10, 11));
  return v;
}

/* Exclusive scan of one value per work-item across the work-group (CLR_SCAN_GROUP_SIZE items).
 * Returns the item's prefix; *total receives the sum over the group. Hillis-Steele in local memory:
 * log2(group) rounds, every item active, no divergent barriers. */
static uint work_group_exclusive_scan(uint value, __local uint* scratch, uint* total) {
  const uint lid = get_local_id(0);
  scratch[lid] = value;
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint offset = 1; offset < CLR_SCAN_GROUP_SIZE; offset <<= 1) {
    const uint add = lid >= offset ? scratch[lid - offset] : 0u;
    barrier(CLK_LOCAL_MEM_FENCE);
    scratch[lid] = add_sat(scratch[lid], add);
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  /* The item's prefix is the inclusive sum of the items before it. */
  const uint exclusive = lid > 0 ? scratch[lid - 1] : 0u;
  *total = scratch[CLR_SCAN_GROUP_SIZE - 1];
  barrier(CLK_LOCAL_MEM_FENCE); /* scratch may be reused right after */
  return exclusive;
}

__kernel __attribute__((reqd_work_group_size(CLR_SCAN_GROUP_SIZE, 1, 1)))
void scan_reduce(__global const uint* data, uint count, __global uint* block_sums) {
  __local uint scratch[CLR_SCAN_GROUP_SIZE];
  const uint begin = get_group_id(0) * CLR_SCAN_BLOCK;
  ulong sum = 0;
  /* Strided so that neighbouring work-items read neighbouring elements. */
  for (uint i = 0; i < CLR_SCAN_ITEMS; ++i) {
    const uint index = begin + i * CLR_SCAN_GROUP_SIZE + get_local_id(0);
    if (index < count) sum += data[index];
  }
  uint total;
  work_group_exclusive_scan(saturated(sum), scratch, &total);
  if (get_local_id(0) == 0) block_sums[get_group_id(0)] = total;
}

/* Scans block_sums[0 .. block_count) in place and writes the grand total for the host to read. */
__kernel __attribute__((reqd_work_group_size(CLR_SCAN_GROUP_SIZE, 1, 1)))
void scan_block_sums(__global uint* block_sums, uint block_count, __global uint* counters) {
  __local uint scratch[CLR_SCAN_GROUP_SIZE];
  const uint lid = get_local_id(0);
  uint carry = 0;
  for (uint base = 0; base < block_count; base += CLR_SCAN_GROUP_SIZE) {
    const uint index = base + lid;
    const uint value = index < block_count ? block_sums[index] : 0u;
    uint round_total;
    const uint prefix = work_group_exclusive_scan(value, scratch, &round_total);
    if (index < block_count) block_sums[index] = add_sat(carry, prefix);
    carry = add_sat(carry, round_total);
  }
  if (lid == 0) counters[CLR_COUNTER_SCAN_TOTAL] = carry;
}

__kernel __attribute__((reqd_work_group_size(CLR_SCAN_GROUP_SIZE, 1, 1)))
void scan_apply(__global uint* data, uint count, __global const uint* block_offsets) {
  __local uint scratch[CLR_SCAN_GROUP_SIZE];
  /* Each work-item sums CLR_SCAN_ITEMS consecutive elements (a multiple of 8), the items' sums are
   * scanned across the group, then each item scans its elements. */
  const uint begin = get_group_id(0) * CLR_SCAN_BLOCK + get_local_id(0) * CLR_SCAN_ITEMS;
  ulong sum = 0;
  for (uint i = 0; i < CLR_SCAN_ITEMS; ++i) {
    if (begin + i < count) sum += data[begin + i];
  }
  uint group_total;
  ulong running =
      add_sat(block_offsets[get_group_id(0)], work_group_exclusive_scan(saturated(sum), scratch, &group_total));
  /* Eight elements at a time, scanned in a vector; the last block's tail one by one. */
  for (uint i = 0; i < CLR_SCAN_ITEMS; i += 8) {
    if (begin + i + 8 <= count) {
      const ulong8 values = convert_ulong8(vload8(0, data + begin + i));
      const ulong8 inclusive = inclusive_scan8(values);
      vstore8(convert_uint8(min((ulong8)(running) + inclusive - values, (ulong8)(UINT_MAX))), 0, data + begin + i);
      running += inclusive.s7;
    } else {
      for (uint j = i; j < i + 8 && begin + j < count; ++j) {
        const uint value = data[begin + j];
        data[begin + j] = saturated(running);
        running += value;
      }
    }
  }
}
