// Turns OpenCL failures into clraster errors at the API boundary, so users only ever catch
// clraster::Error, and checks allocations against the device's limits before making them.
#pragma once

#include "api/impl.hpp"

#include <string>

namespace clraster {

// The OpenCL name of an error code, e.g. "CL_OUT_OF_RESOURCES".
std::string cl_error_name(cl_int code);

// Throws InvalidArgument when `bytes` exceeds what the device can allocate in one buffer.
void check_allocation(const ContextState& state, std::size_t bytes, const char* what);

template <typename Function>
decltype(auto) translate_cl_errors(Function&& function) {
  try {
    return function();
  } catch (const cl::Error& error) {
    throw Error(std::string("OpenCL call ") + error.what() + " failed with " + cl_error_name(error.err()));
  }
}

}  // namespace clraster
