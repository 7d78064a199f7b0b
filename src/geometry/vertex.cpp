#include "geometry/vertex.hpp"

#include "runtime/launch.hpp"
#include "shared/clr_limits.h"

namespace clraster::geometry {

void VertexStage::run(runtime::Queue& queue, const VertexParams& p) {
  queue.set_stage(runtime::Stage::Vertex);
  cl_uint next = runtime::set_args(kernel_, p.draw->indices, p.slots, cl_uint{p.main_count}, cl_uint{p.slot_count},
                                   cl_uint{p.instance_slots}, p.draw->uniforms, cl_uint{p.draw->draw}, p.shaded,
                                   p.group_codes);
  next = set_resource_args(kernel_, next, *p.draw->resources);
  kernel_.setArg(next++, p.draw->attribute_descs);
  for (const cl::Buffer& attribute : p.draw->attributes) kernel_.setArg(next++, attribute);
  runtime::enqueue_instanced_items(queue, kernel_, runtime::divide_round_up(p.slot_count, lanes_), p.instances,
                                   CLR_ITEM_GROUP_SIZE);
}

}  // namespace clraster::geometry
