#include "cl/device.hpp"

#include <cstdlib>
#include <string>

namespace clraster::cl_host {
namespace {

const char* type_name(cl_device_type type) {
  if (type & CL_DEVICE_TYPE_GPU) return "GPU";
  if (type & CL_DEVICE_TYPE_CPU) return "CPU";
  if (type & CL_DEVICE_TYPE_ACCELERATOR) return "accelerator";
  return "other";
}

std::vector<cl::Platform> platforms_or_throw() {
  std::vector<cl::Platform> platforms;
  try {
    cl::Platform::get(&platforms);
  } catch (const cl::Error&) {
    // The ICD loader reports "no platform" as CL_PLATFORM_NOT_FOUND_KHR; treat any failure alike.
    platforms.clear();
  }
  if (platforms.empty()) {
    throw DeviceError(
        "no OpenCL platform found: install an OpenCL driver, e.g. Debian's pocl-opencl-icd for the CPU");
  }
  return platforms;
}

int device_index_from_environment() {
  const char* text = std::getenv("CLRASTER_DEVICE");
  if (text == nullptr || *text == '\0') return 0;
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  if (*end != '\0' || value < 0 || value > 1 << 20) {
    throw DeviceError(std::string("CLRASTER_DEVICE='") + text + "' is not a device index (see `clraster devices`)");
  }
  return static_cast<int>(value);
}

}  // namespace

std::vector<Device> enumerate_devices() {
  std::vector<Device> result;
  for (const cl::Platform& platform : platforms_or_throw()) {
    std::vector<cl::Device> devices;
    try {
      platform.getDevices(CL_DEVICE_TYPE_ALL, &devices);
    } catch (const cl::Error&) {
      continue;  // a platform without devices reports CL_DEVICE_NOT_FOUND
    }
    for (const cl::Device& device : devices) {
      DeviceInfo info;
      info.index = static_cast<int>(result.size());
      info.name = device.getInfo<CL_DEVICE_NAME>();
      info.platform = platform.getInfo<CL_PLATFORM_NAME>();
      info.version = device.getInfo<CL_DEVICE_VERSION>();
      info.driver_version = device.getInfo<CL_DRIVER_VERSION>();
      info.type = type_name(device.getInfo<CL_DEVICE_TYPE>());
      info.compute_units = static_cast<int>(device.getInfo<CL_DEVICE_MAX_COMPUTE_UNITS>());
      result.push_back({device, info});
    }
  }
  if (result.empty()) throw DeviceError("OpenCL platforms exist but none has a device");
  return result;
}

Device select_device(int index) {
  std::vector<Device> devices = enumerate_devices();
  const int chosen = index >= 0 ? index : device_index_from_environment();
  if (chosen >= static_cast<int>(devices.size())) {
    throw DeviceError("no OpenCL device " + std::to_string(chosen) + ": this machine has " +
                      std::to_string(devices.size()) + " (see `clraster devices`)");
  }
  return devices[static_cast<std::size_t>(chosen)];
}

}  // namespace clraster::cl_host
