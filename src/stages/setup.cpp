#include "stages/setup.hpp"

#include "cl/launch.hpp"
#include "clr_limits.h"

namespace clraster::stages {

void SetupStage::run(cl_host::Queue& queue, const SetupParams& p) {
  queue.set_stage(cl_host::Stage::Setup);
  cl_host::set_args(kernel_, cl_uint{p.primitive_begin}, cl_uint{p.primitive_count}, p.slots, p.draw->indices,
                    p.shaded, p.draw->uniforms, p.triangle_offsets, p.triangles, p.pair_counts);
  cl_host::enqueue_items(queue, kernel_, p.primitive_count, CLR_ITEM_GROUP_SIZE);
}

}  // namespace clraster::stages
