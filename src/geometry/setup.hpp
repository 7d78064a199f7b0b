// Triangle set-up (kernels in setup.cl, with primitive.cl, clip.cl and fixed_point.cl): assembles,
// clips, projects, snaps and culls a chunk's primitives and writes their triangles with exact
// fixed-point edge functions, and how many tiles each primitive's triangles touch.
#pragma once

#include "geometry/draw_buffers.hpp"
#include "shared/types.h"

#include <cstdint>

namespace clraster::geometry {

struct SetupParams {
  const DrawBuffers* draw = nullptr;
  SlotMap slots{};
  cl::Buffer shaded;
  std::uint32_t primitive_begin = 0;  // primitive index within the draw
  std::uint32_t primitive_count = 0;
  // Instances set up at once (whole draws only: primitive_begin 0), each instance_slots vertex slots,
  // primitive_count entries and the draw's blocks of culled_blocks after the one before.
  std::uint32_t instances = 1;
  std::uint32_t instance_slots = 0;
  bool block_culling = false;
  cl::Buffer culled_blocks;   // cull_blocks' verdicts for the chunk's blocks (any buffer without block_culling)
  std::uint32_t record_base = 0;  // where primitive_begin's entries are in the four outputs
  cl::Buffer records;         // out: the SetupTriangle of each primitive that needs no clipping
  cl::Buffer bin_boxes;       // out: and its pixel box (uint2: pixel_min, pixel_max), for binning
  cl::Buffer pair_counts;     // out: tiles each primitive's triangles touch, clipped ones' included
  cl::Buffer clipped_counts;  // out: triangles clipping leaves of each primitive that crosses a plane
};

// Block culling (clr_limits.h): which of the blocks of primitives a chunk overlaps are culled whole.
struct CullParams {
  std::uint32_t first_block = 0;  // the block of the chunk's first primitive (of the draw's blocks)
  std::uint32_t block_count = 0;
  cl::Buffer index_ranges;        // per block of the draw: its smallest and largest index
  std::uint32_t slot_offset = 0;  // index i is in vertex slot i + slot_offset
  std::uint32_t instances = 1;    // as SetupParams'
  std::uint32_t instance_slots = 0;
  cl::Buffer group_codes;         // per group of vertex slots: the clip planes all its vertices are outside
  cl::Buffer culled;              // out: per block of the chunk, 1 where culled
};

// For the primitives that cross a clip plane, once the clipped counts are scanned into offsets.
struct ClippedSetupParams {
  const DrawBuffers* draw = nullptr;
  SlotMap slots{};
  cl::Buffer shaded;
  std::uint32_t primitive_begin = 0;
  std::uint32_t primitive_count = 0;
  std::uint32_t instances = 1;  // as SetupParams'
  std::uint32_t instance_slots = 0;
  std::uint32_t record_base = 0;  // where primitive_begin's offset is in clipped_offsets
  cl::Buffer clipped_offsets;  // primitive_count + 1 offsets into overflow
  cl::Buffer overflow;         // out: the clipped primitives' SetupTriangles
};

class SetupStage {
 public:
  explicit SetupStage(const cl::Program& program)
      : setup_(program, "triangle_setup"), clipped_(program, "clipped_setup"), cull_(program, "cull_blocks") {}
  void run(runtime::Queue& queue, const SetupParams& params);
  void run_clipped(runtime::Queue& queue, const ClippedSetupParams& params);
  void run_cull(runtime::Queue& queue, const CullParams& params);

 private:
  cl::Kernel setup_;
  cl::Kernel clipped_;
  cl::Kernel cull_;
};

}  // namespace clraster::geometry
