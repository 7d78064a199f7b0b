// Exclusive prefix sum of a uint buffer on the device (kernels in scan.cl).
#pragma once

#include "runtime/queue.hpp"

#include <CL/opencl.hpp>

#include <cstddef>

namespace clraster::parallel {

class Scan {
 public:
  explicit Scan(const cl::Program& program);

  // Bytes of block-sum scratch a scan of `count` elements needs.
  static std::size_t scratch_bytes(std::size_t count);

  // Replaces data[0 .. count) by its exclusive prefix sums and writes the total to
  // counters[CLR_COUNTER_SCAN_TOTAL]. block_sums holds at least scratch_bytes(count).
  void exclusive(runtime::Queue& queue, const cl::Buffer& data, std::size_t count, const cl::Buffer& block_sums,
                 const cl::Buffer& counters);

 private:
  cl::Kernel reduce_;
  cl::Kernel scan_block_sums_;
  cl::Kernel apply_;
  std::size_t group_size_;  // work-items per block (CLR_SCAN_GROUP_SIZE)
};

}  // namespace clraster::parallel
