// Triangle set-up (kernels in setup.cl, with primitive.cl, clip.cl and fixed_point.cl): assembles,
// clips, projects, snaps and culls a chunk's primitives and writes their triangles with exact
// fixed-point edge functions, and how many tiles each primitive's triangles touch.
#pragma once

#include "stages/draw_buffers.hpp"
#include "stages/types.h"

#include <cstdint>

namespace clraster::stages {

struct SetupParams {
  const DrawBuffers* draw = nullptr;
  SlotMap slots{};
  cl::Buffer shaded;
  std::uint32_t primitive_begin = 0;  // primitive index within the draw
  std::uint32_t primitive_count = 0;
  cl::Buffer records;         // out: the SetupTriangle of each primitive that needs no clipping
  cl::Buffer bin_boxes;       // out: and its pixel box (uint2: pixel_min, pixel_max), for binning
  cl::Buffer pair_counts;     // out: tiles each primitive's triangles touch, clipped ones' included
  cl::Buffer clipped_counts;  // out: triangles clipping leaves of each primitive that crosses a plane
};

// For the primitives that cross a clip plane, once the clipped counts are scanned into offsets.
struct ClippedSetupParams {
  const DrawBuffers* draw = nullptr;
  SlotMap slots{};
  cl::Buffer shaded;
  std::uint32_t primitive_begin = 0;
  std::uint32_t primitive_count = 0;
  cl::Buffer clipped_offsets;  // primitive_count + 1 offsets into overflow
  cl::Buffer overflow;         // out: the clipped primitives' SetupTriangles
};

class SetupStage {
 public:
  explicit SetupStage(const cl::Program& program) : setup_(program, "triangle_setup"), clipped_(program, "clipped_setup") {}
  void run(cl_host::Queue& queue, const SetupParams& params);
  void run_clipped(cl_host::Queue& queue, const ClippedSetupParams& params);

 private:
  cl::Kernel setup_;
  cl::Kernel clipped_;
};

}  // namespace clraster::stages
