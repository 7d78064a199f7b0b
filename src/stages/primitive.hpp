// Primitive assembly, clipping and culling (kernels in primitive.cl, clip.cl, fixed_point.cl):
// counts the triangles each primitive of a chunk leaves, for the scan that places them.
#pragma once

#include "stages/draw_buffers.hpp"
#include "stages/types.h"

#include <cstdint>

namespace clraster::stages {

struct PrimitiveParams {
  const DrawBuffers* draw = nullptr;
  SlotMap slots{};
  cl::Buffer shaded;
  std::uint32_t primitive_begin = 0;  // primitive index within the draw
  std::uint32_t primitive_count = 0;
  cl::Buffer triangle_counts;         // out: one count per primitive
};

class PrimitiveStage {
 public:
  explicit PrimitiveStage(const cl::Program& program) : kernel_(program, "primitive_count") {}
  void run(cl_host::Queue& queue, const PrimitiveParams& params);

 private:
  cl::Kernel kernel_;
};

}  // namespace clraster::stages
