// OpenCL platform and device discovery: the one place that talks to clGetPlatformIDs.
#pragma once

#include "clraster/clraster.hpp"

#include <CL/opencl.hpp>

#include <optional>
#include <string>

namespace clraster::runtime {

struct Device {
  cl::Device device;
  DeviceInfo info;  // with the device's limits
  bool cpu() const { return info.type == "CPU"; }  // the work-group shapes are the CPU's (clr_limits.h)
};

// Every device of every platform. Throws DeviceError when there is no OpenCL platform.
std::vector<Device> enumerate_devices();

// What of a program the device cannot run as built: the first kernel beyond its local memory, its
// work-group (the reqd_work_group_size the kernel was compiled with, else CLR_ITEM_GROUP_SIZE) or
// its argument bytes (16 a kernel argument at most: pointers and scalars take 8, set-up's SlotMap
// 12), described ("kernel raster_tiles needs 40808 bytes of local memory; device D has 32768").
struct KernelExcess {
  std::string description;
  bool tile_bound = false;  // the raster stage's local memory or work-group: smaller tiles need less
};
std::optional<KernelExcess> kernel_beyond_limits(const cl::Program& program, const Device& device);

// The device at `index`, or when index is -1 the one named by CLRASTER_DEVICE, else device 0.
// Throws DeviceError for an index that does not exist or a malformed CLRASTER_DEVICE.
Device select_device(int index);

}  // namespace clraster::runtime
