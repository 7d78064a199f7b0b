// OpenCL platform and device discovery: the one place that talks to clGetPlatformIDs.
#pragma once

#include "clraster/clraster.hpp"

#include <CL/opencl.hpp>

#include <optional>
#include <string>

namespace clraster::cl_host {

// What the pipeline must respect of a device, read once when the device is found. OpenCL 1.2
// promises little (32 KiB of local memory, 64 KiB of constant memory, 1 KiB of kernel arguments,
// work-groups of 1 work-item, buffers of a quarter of the memory): every size the pipeline
// chooses is checked against these, so that what a device cannot run is a clear error, not a
// driver failure.
struct DeviceLimits {
  bool cpu = false;                      // CL_DEVICE_TYPE_CPU: the device's work-group shapes are the CPU's
  std::size_t local_memory_bytes = 0;    // CL_DEVICE_LOCAL_MEM_SIZE
  std::size_t work_group_items = 0;      // CL_DEVICE_MAX_WORK_GROUP_SIZE
  std::size_t buffer_bytes = 0;          // CL_DEVICE_MAX_MEM_ALLOC_SIZE: one buffer at most
  std::size_t constant_buffer_bytes = 0; // CL_DEVICE_MAX_CONSTANT_BUFFER_SIZE: one __constant argument
  std::size_t parameter_bytes = 0;       // CL_DEVICE_MAX_PARAMETER_SIZE: all of a kernel's arguments
  unsigned address_bits = 0;             // CL_DEVICE_ADDRESS_BITS: the size of a kernel's pointers
};

struct Device {
  cl::Device device;
  DeviceInfo info;
  DeviceLimits limits;
};

// Every device of every platform. Throws DeviceError when there is no OpenCL platform.
std::vector<Device> enumerate_devices();

// The first of the program's kernels that the device cannot run as built, described ("kernel
// raster_tiles needs 40808 bytes of local memory; device D has 32768"), or nothing: its local
// memory, its work-group (the reqd_work_group_size it was compiled with, else CLR_ITEM_GROUP_SIZE)
// and its arguments (16 bytes each at most: pointers and scalars take 8, set-up's SlotMap 12).
std::optional<std::string> kernel_beyond_limits(const cl::Program& program, const Device& device);

// The device at `index`, or when index is -1 the one named by CLRASTER_DEVICE, else device 0.
// Throws DeviceError for an index that does not exist or a malformed CLRASTER_DEVICE.
Device select_device(int index);

}  // namespace clraster::cl_host
