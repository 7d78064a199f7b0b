#include "geometry/setup.hpp"

#include "runtime/launch.hpp"
#include "shared/clr_limits.h"

namespace clraster::geometry {

void SetupStage::run(runtime::Queue& queue, const SetupParams& p) {
  queue.set_stage(runtime::Stage::Setup);
  runtime::set_args(setup_, cl_uint{p.primitive_begin}, cl_uint{p.primitive_count}, p.slots, cl_uint{p.instance_slots},
                    p.draw->indices,
                    p.shaded, cl_int{p.block_culling}, p.culled_blocks, p.draw->uniforms, cl_uint{p.draw->draw},
                    cl_uint{p.record_base}, p.records, p.bin_boxes, p.pair_counts, p.clipped_counts, p.draw->counters);
  runtime::enqueue_instanced_items(queue, setup_, p.primitive_count, p.instances, CLR_ITEM_GROUP_SIZE);
}

void SetupStage::run_cull(runtime::Queue& queue, const CullParams& p) {
  queue.set_stage(runtime::Stage::Setup);
  runtime::set_args(cull_, cl_uint{p.first_block}, cl_uint{p.block_count}, p.index_ranges, cl_uint{p.slot_offset},
                    cl_uint{p.instance_slots}, p.group_codes, p.culled);
  runtime::enqueue_instanced_items(queue, cull_, p.block_count, p.instances, CLR_ITEM_GROUP_SIZE);
}

void SetupStage::run_clipped(runtime::Queue& queue, const ClippedSetupParams& p) {
  queue.set_stage(runtime::Stage::Setup);
  runtime::set_args(clipped_, cl_uint{p.primitive_begin}, cl_uint{p.primitive_count}, p.slots, cl_uint{p.instance_slots},
                    p.draw->indices,
                    p.shaded, p.draw->uniforms, cl_uint{p.draw->draw}, cl_uint{p.record_base}, p.clipped_offsets,
                    p.overflow);
  runtime::enqueue_instanced_items(queue, clipped_, p.primitive_count, p.instances, CLR_ITEM_GROUP_SIZE);
}

}  // namespace clraster::geometry
