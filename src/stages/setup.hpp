// Triangle set-up (kernel in setup.cl): writes each chunk's surviving triangles with their exact
// fixed-point edge functions and the number of tiles each touches.
#pragma once

#include "stages/draw_buffers.hpp"
#include "stages/types.h"

#include <cstdint>

namespace clraster::stages {

struct SetupParams {
  const DrawBuffers* draw = nullptr;
  SlotMap slots{};
  cl::Buffer shaded;
  std::uint32_t primitive_begin = 0;
  std::uint32_t primitive_count = 0;
  cl::Buffer triangle_offsets;  // exclusive scan of the primitive stage's counts
  cl::Buffer triangles;         // out: SetupTriangle per surviving triangle
  cl::Buffer pair_counts;       // out: tiles each triangle touches
};

class SetupStage {
 public:
  explicit SetupStage(const cl::Program& program) : kernel_(program, "triangle_setup") {}
  void run(cl_host::Queue& queue, const SetupParams& params);

 private:
  cl::Kernel kernel_;
};

}  // namespace clraster::stages
