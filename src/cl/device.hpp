// OpenCL platform and device discovery: the one place that talks to clGetPlatformIDs.
#pragma once

#include "clraster/clraster.hpp"

#include <CL/opencl.hpp>

namespace clraster::cl_host {

struct Device {
  cl::Device device;
  DeviceInfo info;
};

// Every device of every platform. Throws DeviceError when there is no OpenCL platform.
std::vector<Device> enumerate_devices();

// The device at `index`, or when index is -1 the one named by CLRASTER_DEVICE, else device 0.
// Throws DeviceError for an index that does not exist or a malformed CLRASTER_DEVICE.
Device select_device(int index);

}  // namespace clraster::cl_host
