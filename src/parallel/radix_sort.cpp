#include "parallel/radix_sort.hpp"

#include "runtime/launch.hpp"
#include "shared/clr_limits.h"

#include <algorithm>

namespace clraster::parallel {

using runtime::divide_round_up;

RadixSort::RadixSort(const cl::Program& program, Scan& scan)
    : scan_(scan),
      histogram_(program, "radix_histogram"),
      scatter_(program, "radix_scatter"),
      group_size_(runtime::compiled_group_size(histogram_)),
      digit_bits_(CLR_RADIX_BITS_FOR(group_size_)),
      block_(CLR_RADIX_BLOCK_FOR(group_size_)) {}

std::size_t RadixSort::histogram_bytes(std::size_t count) {
  const auto entries = [count](std::size_t block, int bits) {
    return std::max<std::size_t>(1, divide_round_up(count, block)) << bits;
  };
  return std::max(entries(CLR_RADIX_CPU_BLOCK, CLR_RADIX_CPU_BITS), entries(CLR_RADIX_GPU_BLOCK, CLR_RADIX_GPU_BITS)) *
         sizeof(cl_uint);
}

std::size_t RadixSort::scan_scratch_bytes(std::size_t count) {
  return Scan::scratch_bytes(histogram_bytes(count) / sizeof(cl_uint));
}

int RadixSort::sort(runtime::Queue& queue, const cl::Buffer (&keys)[2], const cl::Buffer (&values)[2],
                    std::size_t count, int key_bits, const cl::Buffer& histogram, const cl::Buffer& block_sums,
                    const cl::Buffer& counters) {
  const auto n = static_cast<cl_uint>(count);
  const auto blocks = static_cast<cl_uint>(divide_round_up(count, block_));
  int source = 0;
  for (int shift = 0; shift < key_bits && count > 1; shift += digit_bits_) {
    const auto shift_arg = static_cast<cl_uint>(shift);
    runtime::set_args(histogram_, keys[source], n, shift_arg, histogram, blocks);
    runtime::enqueue_blocks(queue, histogram_, count, block_, group_size_);
    scan_.exclusive(queue, histogram, std::size_t{blocks} << digit_bits_, block_sums, counters);
    runtime::set_args(scatter_, keys[source], values[source], n, shift_arg, histogram, blocks, keys[1 - source],
                      values[1 - source]);
    runtime::enqueue_blocks(queue, scatter_, count, block_, group_size_);
    source = 1 - source;
  }
  return source;
}

}  // namespace clraster::parallel
