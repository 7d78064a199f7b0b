// The vertex stage (kernel in vertex.cl): the program's vertex function, one work-item per slot.
#pragma once

#include "stages/draw_buffers.hpp"

#include <cstdint>

namespace clraster::stages {

struct VertexParams {
  const DrawBuffers* draw = nullptr;
  bool shade_all = false;          // slot s = vertex s, for s < slot_count
  std::uint32_t stream_begin = 0;  // else slot s = stream position stream_begin + s, for s < main_count,
  std::uint32_t main_count = 0;    // and slot main_count = the fan's centre when slot_count exceeds it
  std::uint32_t slot_count = 0;
  cl::Buffer shaded;
};

class VertexStage {
 public:
  explicit VertexStage(const cl::Program& program) : kernel_(program, "vertex_shade") {}
  void run(cl_host::Queue& queue, const VertexParams& params);

 private:
  cl::Kernel kernel_;
};

}  // namespace clraster::stages
