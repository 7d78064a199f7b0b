#include "stages/primitive.hpp"

#include "cl/launch.hpp"
#include "clr_limits.h"

namespace clraster::stages {

void PrimitiveStage::run(cl_host::Queue& queue, const PrimitiveParams& p) {
  queue.set_stage(cl_host::Stage::Primitive);
  cl_host::set_args(kernel_, cl_uint{p.primitive_begin}, cl_uint{p.primitive_count}, p.slots, p.draw->indices,
                    p.shaded, p.draw->uniforms, p.triangle_counts, p.draw->counters);
  cl_host::enqueue_items(queue, kernel_, p.primitive_count, CLR_ITEM_GROUP_SIZE);
}

}  // namespace clraster::stages
