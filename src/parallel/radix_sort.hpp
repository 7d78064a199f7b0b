// Stable radix sort of (key, value) uint pairs on the device (kernels in radix_sort.cl).
#pragma once

#include "parallel/scan.hpp"

namespace clraster::parallel {

class RadixSort {
 public:
  RadixSort(const cl::Program& program, Scan& scan);

  // Bytes of histogram scratch for sorting `count` pairs in either shape, and of block-sum
  // scratch for scanning it.
  static std::size_t histogram_bytes(std::size_t count);
  static std::size_t scan_scratch_bytes(std::size_t count);

  // Sorts keys[0][0 .. count) with values[0] alongside by the low `key_bits` bits of the keys,
  // ping-ponging between buffer 0 and 1. Returns the index (0 or 1) of the buffers holding the result.
  int sort(runtime::Queue& queue, const cl::Buffer (&keys)[2], const cl::Buffer (&values)[2], std::size_t count,
           int key_bits, const cl::Buffer& histogram, const cl::Buffer& block_sums, const cl::Buffer& counters);

 private:
  Scan& scan_;
  cl::Kernel histogram_;
  cl::Kernel scatter_;
  std::size_t group_size_;  // work-items per block (CLR_SCAN_GROUP_SIZE)
  int digit_bits_;          // bits sorted per pass (CLR_RADIX_BITS in the kernels)
  std::size_t block_;       // pairs per block (CLR_RADIX_BLOCK in the kernels)
};

}  // namespace clraster::parallel
