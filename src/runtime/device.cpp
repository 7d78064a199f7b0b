#include "runtime/device.hpp"

#include "shared/clr_limits.h"

#include <cstdlib>
#include <string>

namespace clraster::runtime {
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
      info.local_memory_bytes = device.getInfo<CL_DEVICE_LOCAL_MEM_SIZE>();
      info.work_group_items = device.getInfo<CL_DEVICE_MAX_WORK_GROUP_SIZE>();
      info.buffer_bytes = device.getInfo<CL_DEVICE_MAX_MEM_ALLOC_SIZE>();
      info.constant_buffer_bytes = device.getInfo<CL_DEVICE_MAX_CONSTANT_BUFFER_SIZE>();
      info.parameter_bytes = device.getInfo<CL_DEVICE_MAX_PARAMETER_SIZE>();
      info.address_bits = device.getInfo<CL_DEVICE_ADDRESS_BITS>();
      result.push_back({device, info});
    }
  }
  if (result.empty()) throw DeviceError("OpenCL platforms exist but none has a device");
  return result;
}

std::optional<KernelExcess> kernel_beyond_limits(const cl::Program& program, const Device& device) {
  std::vector<cl::Kernel> kernels;
  cl::Program(program).createKernels(&kernels);  // createKernels is not const, though it changes nothing
  const DeviceInfo& limits = device.info;
  const std::string on_device = "; device " + device.info.name + " has ";
  for (const cl::Kernel& kernel : kernels) {
    const std::string name = kernel.getInfo<CL_KERNEL_FUNCTION_NAME>();
    const bool raster = name == "raster_tiles";
    const std::size_t local = kernel.getWorkGroupInfo<CL_KERNEL_LOCAL_MEM_SIZE>(device.device);
    if (local > limits.local_memory_bytes) {
      return KernelExcess{"kernel " + name + " needs " + std::to_string(local) + " bytes of local memory" + on_device +
                              std::to_string(limits.local_memory_bytes),
                          raster};
    }
    const std::size_t compiled = kernel.getWorkGroupInfo<CL_KERNEL_COMPILE_WORK_GROUP_SIZE>(device.device)[0];
    const std::size_t items = compiled != 0 ? compiled : std::size_t{CLR_ITEM_GROUP_SIZE};
    const std::size_t runnable = kernel.getWorkGroupInfo<CL_KERNEL_WORK_GROUP_SIZE>(device.device);
    if (items > runnable) {
      return KernelExcess{"kernel " + name + " needs work-groups of " + std::to_string(items) + " work-items" +
                              on_device + "room for " + std::to_string(runnable),
                          raster};
    }
    const cl_uint arguments = kernel.getInfo<CL_KERNEL_NUM_ARGS>();
    if (std::size_t{16} * arguments > limits.parameter_bytes) {
      return KernelExcess{"kernel " + name + " takes " + std::to_string(arguments) + " arguments (up to " +
                              std::to_string(16 * arguments) + " bytes)" + on_device +
                              std::to_string(limits.parameter_bytes) + " bytes for them",
                          false};
    }
  }
  return std::nullopt;
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

}  // namespace clraster::runtime
