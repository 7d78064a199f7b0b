#include "geometry/vertex.hpp"

#include "runtime/launch.hpp"
#include "shared/clr_limits.h"

namespace clraster::stages {

void VertexStage::run(cl_host::Queue& queue, const VertexParams& p) {
  queue.set_stage(cl_host::Stage::Vertex);
  cl_uint next = cl_host::set_args(kernel_, p.draw->indices, p.slots, cl_uint{p.main_count}, cl_uint{p.slot_count},
                                   cl_uint{p.instance_slots}, p.draw->uniforms, cl_uint{p.draw->draw}, p.shaded,
                                   p.group_codes);
  next = set_resource_args(kernel_, next, *p.draw->resources);
  kernel_.setArg(next++, p.draw->attribute_descs);
  for (const cl::Buffer& attribute : p.draw->attributes) kernel_.setArg(next++, attribute);
  cl_host::enqueue_instanced_items(queue, kernel_, cl_host::divide_round_up(p.slot_count, lanes_), p.instances,
                                   CLR_ITEM_GROUP_SIZE);
}

}  // namespace clraster::stages
