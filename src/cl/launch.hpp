// Small helpers for enqueueing kernels and reading single values back.
#pragma once

#include <CL/opencl.hpp>

#include <cstddef>
#include <cstdint>

namespace clraster::cl_host {

// Sets every kernel argument in order.
template <typename... Args>
void set_args(cl::Kernel& kernel, const Args&... args) {
  cl_uint index = 0;
  (kernel.setArg(index++, args), ...);
}

inline std::size_t round_up(std::size_t value, std::size_t multiple) { return (value + multiple - 1) / multiple * multiple; }
inline std::size_t divide_round_up(std::size_t value, std::size_t divisor) { return (value + divisor - 1) / divisor; }

// One work-item per element; the global size is rounded up to the work-group size because PoCL,
// like OpenCL 1.2, has no non-uniform work-groups. Kernels ignore the items past `count`.
inline void enqueue_items(cl::CommandQueue& queue, cl::Kernel& kernel, std::size_t count, std::size_t group_size) {
  if (count == 0) return;
  queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(round_up(count, group_size)), cl::NDRange(group_size));
}

// One work-group per `block` elements.
inline void enqueue_blocks(cl::CommandQueue& queue, cl::Kernel& kernel, std::size_t count, std::size_t block,
                           std::size_t group_size) {
  if (count == 0) return;
  queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(divide_round_up(count, block) * group_size),
                             cl::NDRange(group_size));
}

// Blocks until the value is read. Used only for the few totals the host needs to size the next step.
inline std::uint32_t read_uint(cl::CommandQueue& queue, const cl::Buffer& buffer, std::size_t index) {
  std::uint32_t value = 0;
  queue.enqueueReadBuffer(buffer, CL_TRUE, index * sizeof value, sizeof value, &value);
  return value;
}

}  // namespace clraster::cl_host
