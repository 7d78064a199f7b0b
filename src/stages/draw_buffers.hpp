// The buffers every geometry stage of a draw reads.
#pragma once

#include "cl/queue.hpp"

#include <CL/opencl.hpp>

namespace clraster::stages {

struct DrawBuffers {
  cl::Buffer positions;
  cl::Buffer normals;   // a placeholder when has_normals is false
  bool has_normals = false;
  cl::Buffer indices;   // a placeholder for non-indexed draws
  cl::Buffer uniforms;  // DrawUniforms
  cl::Buffer counters;  // CLR_COUNTER_*
};

}  // namespace clraster::stages
