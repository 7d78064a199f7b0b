// The buffers every stage of a draw reads, and the program's resources (the kernel parameters the
// generator adds after each stage kernel's own, program/generator.cpp).
#pragma once

#include "runtime/queue.hpp"

#include <CL/opencl.hpp>
#include <cstdint>
#include <vector>

namespace clraster::geometry {

// In kernel parameter order: uniform block, texture descriptions, texture data..., user buffers...
struct ProgramResources {
  cl::Buffer uniform_block;
  cl::Buffer texture_descs;
  std::vector<cl::Buffer> textures;
  std::vector<cl::Buffer> buffers;
};

struct DrawBuffers {
  cl::Buffer indices;   // a placeholder for non-indexed draws
  cl::Buffer uniforms;  // DrawUniforms of every draw of the pass ...
  std::uint32_t draw = 0;  // ... and this one's entry
  cl::Buffer counters;  // CLR_COUNTER_*
  const ProgramResources* resources = nullptr;
  cl::Buffer attribute_descs;              // AttributeDesc per declared attribute, per draw of the pass
  std::vector<cl::Buffer> attributes;      // per declared attribute
};

// Sets the resource parameters of `kernel` from argument index `first`; returns the next index.
cl_uint set_resource_args(cl::Kernel& kernel, cl_uint first, const ProgramResources& resources);

}  // namespace clraster::geometry
