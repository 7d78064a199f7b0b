/* radix_sort.cl: stable least-significant-digit radix sort of (key, value) pairs, CLR_RADIX_BITS
 * bits per pass. Stability is what keeps primitive order: pairs enter in primitive order, so after
 * sorting by tile each tile's triangles are still in primitive order.
 *
 * One pass:
 *   radix_histogram  per block of CLR_RADIX_BLOCK pairs, how many have each digit, stored digit-major
 *                    (histogram[digit * block_count + block]) so that one exclusive scan of the whole
 *                    histogram gives every (digit, block) its first output position;
 *   (scan of the histogram, scan.cl)
 *   radix_scatter    per block, each pair's rank among the block's pairs with the same digit, in
 *                    input order, added to that position. */

#include "parallel/scan.cl"
#include "shared/clr_limits.h"
#include "shared/types.h"

static inline uint radix_digit(uint key, uint shift) { return (key >> shift) & (CLR_RADIX_BUCKETS - 1); }

__kernel __attribute__((reqd_work_group_size(CLR_SCAN_GROUP_SIZE, 1, 1)))
void radix_histogram(__global const uint* keys, uint count, uint shift, __global uint* histogram,
                     uint block_count) {
  __local uint buckets[CLR_RADIX_BUCKETS];
  const uint lid = get_local_id(0);
  for (uint d = lid; d < CLR_RADIX_BUCKETS; d += CLR_SCAN_GROUP_SIZE) buckets[d] = 0;
  barrier(CLK_LOCAL_MEM_FENCE);
  const uint begin = get_group_id(0) * CLR_RADIX_BLOCK;
  for (uint i = 0; i < CLR_RADIX_ITEMS; ++i) {
    const uint index = begin + i * CLR_SCAN_GROUP_SIZE + lid;
#if CLR_SCAN_GROUP_SIZE == 1 /* nobody to share the counts with: a locked increment costs many plain ones */
    if (index < count) ++buckets[radix_digit(keys[index], shift)];
#else
    if (index < count) atomic_inc(&buckets[radix_digit(keys[index], shift)]);
#endif
  }
  barrier(CLK_LOCAL_MEM_FENCE);
  for (uint d = lid; d < CLR_RADIX_BUCKETS; d += CLR_SCAN_GROUP_SIZE) {
    histogram[d * block_count + get_group_id(0)] = buckets[d];
  }
}

__kernel __attribute__((reqd_work_group_size(CLR_SCAN_GROUP_SIZE, 1, 1)))
void radix_scatter(__global const uint* keys_in, __global const uint* values_in, uint count, uint shift,
                   __global const uint* digit_offsets, uint block_count, __global uint* keys_out,
                   __global uint* values_out) {
  /* counts[digit * GROUP + item]: pairs of that digit among the item's consecutive pairs, then their
   * exclusive scan. 16 bits hold any count within a block, and keep the array within the 32 KiB of
   * local memory small GPUs have. */
#if CLR_RADIX_BLOCK > 65535
#error "a radix block's counts must fit 16 bits"
#endif
  __local ushort counts[CLR_RADIX_BUCKETS * CLR_SCAN_GROUP_SIZE];
  __local uint scratch[CLR_SCAN_GROUP_SIZE];
  const uint lid = get_local_id(0);
  const uint begin = get_group_id(0) * CLR_RADIX_BLOCK + lid * CLR_RADIX_ITEMS;

  uint own[CLR_RADIX_BUCKETS];
  for (uint d = 0; d < CLR_RADIX_BUCKETS; ++d) own[d] = 0;
  for (uint i = 0; i < CLR_RADIX_ITEMS; ++i) {
    if (begin + i < count) ++own[radix_digit(keys_in[begin + i], shift)];
  }
  for (uint d = 0; d < CLR_RADIX_BUCKETS; ++d) counts[d * CLR_SCAN_GROUP_SIZE + lid] = (ushort)own[d];
  barrier(CLK_LOCAL_MEM_FENCE);

  /* Exclusive scan of counts[] in digit-major order: item lid scans its run of
   * CLR_RADIX_BUCKETS entries serially, the runs' sums are scanned across the group. */
  const uint run = lid * CLR_RADIX_BUCKETS;
  uint run_sum = 0;
  for (uint i = 0; i < CLR_RADIX_BUCKETS; ++i) run_sum += counts[run + i];
  uint ignored_total;
  uint running = work_group_exclusive_scan(run_sum, scratch, &ignored_total);
  for (uint i = 0; i < CLR_RADIX_BUCKETS; ++i) {
    const uint value = counts[run + i];
    counts[run + i] = (ushort)running;
    running += value;
  }
  barrier(CLK_LOCAL_MEM_FENCE);

  /* counts[d * GROUP + lid] - counts[d * GROUP] is the number of the block's pairs with digit d
   * before this item's; the digit's block offset comes from the scanned histogram. */
  uint position[CLR_RADIX_BUCKETS];
  for (uint d = 0; d < CLR_RADIX_BUCKETS; ++d) {
    position[d] = digit_offsets[d * block_count + get_group_id(0)] + counts[d * CLR_SCAN_GROUP_SIZE + lid] -
                  counts[d * CLR_SCAN_GROUP_SIZE];
  }
  for (uint i = 0; i < CLR_RADIX_ITEMS; ++i) {
    if (begin + i < count) {
      const uint key = keys_in[begin + i];
      const uint destination = position[radix_digit(key, shift)]++;
      keys_out[destination] = key;
      values_out[destination] = values_in[begin + i];
    }
  }
}
