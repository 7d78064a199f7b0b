// The vertex stage (kernel in vertex.cl): the program's vertex function, one work-item per
// CLR_VERTEX_LANES slots.
#pragma once

#include "geometry/draw_buffers.hpp"
#include "shared/clr_limits.h"
#include "shared/types.h"

#include <cstddef>
#include <cstdint>

namespace clraster::geometry {

struct VertexParams {
  const DrawBuffers* draw = nullptr;
  SlotMap slots{};                // where the draw's vertices go (types.h, vertex.cl)
  std::uint32_t main_count = 0;   // stream slots: the fan's centre is in slot main_count when slot_count exceeds it
  std::uint32_t slot_count = 0;   // from slots.slot_base
  std::uint32_t instances = 1;    // from the draw's DrawUniforms::instance on, ...
  std::uint32_t instance_slots = 0;  // ... each this many slots after the one before
  cl::Buffer shaded;
  cl::Buffer group_codes;  // when shade_all: each group of slots' clip codes (see ands_group_codes)
};

class VertexStage {
 public:
  // `lanes`: the slots each work-item shades, the CLR_VERTEX_LANES the program was built with.
  VertexStage(const cl::Program& program, std::size_t lanes) : kernel_(program, "vertex_shade"), lanes_(lanes) {}
  void run(runtime::Queue& queue, const VertexParams& params);
  // Whether work-items share groups of slots and AND their codes into them (vertex.cl), so that
  // group_codes must hold all ones before the stage runs. Otherwise (CPU shapes) each work-item
  // stores its own group's codes whole.
  bool ands_group_codes() const { return lanes_ < CLR_CODE_GROUP_SLOTS; }

 private:
  cl::Kernel kernel_;
  std::size_t lanes_;
};

}  // namespace clraster::geometry
