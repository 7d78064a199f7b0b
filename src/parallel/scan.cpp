#include "parallel/scan.hpp"

#include "runtime/launch.hpp"
#include "shared/clr_limits.h"
#include "shared/types.h"

#include <algorithm>

namespace clraster::parallel {

using runtime::divide_round_up;

Scan::Scan(const cl::Program& program)
    : reduce_(program, "scan_reduce"),
      scan_block_sums_(program, "scan_block_sums"),
      apply_(program, "scan_apply"),
      group_size_(runtime::compiled_group_size(reduce_)) {}

std::size_t Scan::scratch_bytes(std::size_t count) {
  return std::max<std::size_t>(1, divide_round_up(count, CLR_SCAN_BLOCK)) * sizeof(cl_uint);
}

void Scan::exclusive(runtime::Queue& queue, const cl::Buffer& data, std::size_t count, const cl::Buffer& block_sums,
                     const cl::Buffer& counters) {
  const auto n = static_cast<cl_uint>(count);
  const auto blocks = static_cast<cl_uint>(divide_round_up(count, CLR_SCAN_BLOCK));
  runtime::set_args(reduce_, data, n, block_sums);
  runtime::enqueue_blocks(queue, reduce_, count, CLR_SCAN_BLOCK, group_size_);
  runtime::set_args(scan_block_sums_, block_sums, blocks, counters);
  runtime::enqueue_group(queue, scan_block_sums_, group_size_);
  runtime::set_args(apply_, data, n, block_sums);
  runtime::enqueue_blocks(queue, apply_, count, CLR_SCAN_BLOCK, group_size_);
}

}  // namespace clraster::parallel
