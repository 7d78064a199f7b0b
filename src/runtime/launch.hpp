// Small helpers for enqueueing kernels and reading single values back.
#pragma once

#include "runtime/queue.hpp"

#include <CL/opencl.hpp>

#include <array>
#include <cstddef>
#include <cstdint>

namespace clraster::runtime {

// The work-group size a kernel was compiled for (its reqd_work_group_size, x).
inline std::size_t compiled_group_size(const cl::Kernel& kernel) {
  const cl::Device device = kernel.getInfo<CL_KERNEL_PROGRAM>().getInfo<CL_PROGRAM_DEVICES>().front();
  return kernel.getWorkGroupInfo<CL_KERNEL_COMPILE_WORK_GROUP_SIZE>(device)[0];
}

// Sets the kernel's first arguments in order; returns the index of the next one.
template <typename... Args>
cl_uint set_args(cl::Kernel& kernel, const Args&... args) {
  cl_uint index = 0;
  (kernel.setArg(index++, args), ...);
  return index;
}

inline std::size_t round_up(std::size_t value, std::size_t multiple) { return (value + multiple - 1) / multiple * multiple; }
inline std::size_t divide_round_up(std::size_t value, std::size_t divisor) { return (value + divisor - 1) / divisor; }

// One work-item per element; the global size is rounded up to the work-group size because PoCL,
// like OpenCL 1.2, has no non-uniform work-groups. Kernels ignore the items past `count`.
inline void enqueue_items(Queue& queue, cl::Kernel& kernel, std::size_t count, std::size_t group_size) {
  if (count == 0) return;
  queue.get().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(round_up(count, group_size)),
                                   cl::NDRange(group_size), nullptr, queue.event());
}

// `count` work-items for each of `instances` (the second dimension), in groups of group_size.
inline void enqueue_instanced_items(Queue& queue, cl::Kernel& kernel, std::size_t count, std::size_t instances,
                                    std::size_t group_size) {
  if (count == 0 || instances == 0) return;
  queue.get().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(round_up(count, group_size), instances),
                                   cl::NDRange(group_size, 1), nullptr, queue.event());
}

// One work-group per `block` elements.
inline void enqueue_blocks(Queue& queue, cl::Kernel& kernel, std::size_t count, std::size_t block,
                           std::size_t group_size) {
  if (count == 0) return;
  queue.get().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(divide_round_up(count, block) * group_size),
                                   cl::NDRange(group_size), nullptr, queue.event());
}

// One work-group of `group_size` items.
inline void enqueue_group(Queue& queue, cl::Kernel& kernel, std::size_t group_size) {
  queue.get().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(group_size), cl::NDRange(group_size), nullptr,
                                   queue.event());
}

// Fills `bytes` bytes from `offset` with copies of `pattern`.
template <typename T>
void fill(Queue& queue, const cl::Buffer& buffer, T pattern, std::size_t offset, std::size_t bytes) {
  queue.get().enqueueFillBuffer(buffer, pattern, offset, bytes, nullptr, queue.event());
}

// Blocks until the value is read. Used only for the few totals the host needs to size the next step.
inline std::uint32_t read_uint(Queue& queue, const cl::Buffer& buffer, std::size_t index) {
  std::uint32_t value = 0;
  queue.get().enqueueReadBuffer(buffer, CL_TRUE, index * sizeof value, sizeof value, &value);
  return value;
}

// The same for values.size() consecutive values from `index` on, in one read.
template <std::size_t N>
void read_uints(Queue& queue, const cl::Buffer& buffer, std::size_t index, std::array<std::uint32_t, N>& values) {
  queue.get().enqueueReadBuffer(buffer, CL_TRUE, index * sizeof values[0], sizeof values, values.data());
}

}  // namespace clraster::runtime
