/* vertex.cl: the vertex stage. Each work-item takes CLR_VERTEX_LANES consecutive vertex slots: it
 * runs the program's vertex function on each one's attributes, storing the clip-space position and
 * the varyings, then classifies, projects and snaps the positions together, one vector lane each
 * (clip.cl).
 *
 * Slots (SlotMap, types.h): a draw's slots start at slots.slot_base, so that the draws of one pass
 * keep their vertices side by side until set-up has read them. The second dimension of the range
 * counts the instances from u->instance: instance i's slots are instance_slots further on. When the draw's index range is shaded
 * once, its slot slot_base + s holds vertex slots.origin + s. Otherwise (the range would take more
 * slots than the draw's stream positions, or the draw is not indexed) slot slot_base + s holds the
 * element at stream position origin + s, and for fans one extra slot, main_count, the fan's centre
 * (stream position 0).
 *
 * Besides the program's outputs a slot keeps the vertex's clip codes and its window position
 * (types.h): computed here once per vertex, not by set-up once per triangle using it. When the index
 * range is shaded once, the codes of each group of CLR_CODE_GROUP_SLOTS slots are also ANDed into
 * group_codes, for block culling (setup.cl; slot_base is a multiple of the group size): on CPUs a
 * work-item's slots are one group, whose codes it stores; on GPUs the group's work-items AND theirs
 * in (group_codes filled with ones before). */

#include "geometry/clip.cl"
#include "geometry/fixed_point.cl"
#include "resources/index_range.cl"
#include "shared/clr_limits.h"
#include "shared/types.h"

__kernel void vertex_shade(__global const uchar* indices, SlotMap slots, uint main_count, uint slot_count,
                           uint instance_slots, __constant const DrawUniforms* draws, uint draw,
                           __global float4* shaded, __global uint* group_codes CLR_RESOURCE_PARAMS CLR_ATTRIBUTE_PARAMS) {
  __constant const DrawUniforms* const u = draws + draw;
  const uint first_local = get_global_id(0) * CLR_VERTEX_LANES;
  if (first_local >= slot_count) return;
  const uint lane_count = min((uint)CLR_VERTEX_LANES, slot_count - first_local);
  const uint instance = u->instance + (uint)get_global_id(1);
  const uint first_slot = slots.slot_base + (uint)get_global_id(1) * instance_slots + first_local;
  __global float4* const first_out = shaded + (size_t)first_slot * CLR_SHADED_VERTEX_FLOAT4S;

  /* Lanes past the last slot keep (0, 0, 0, 1) and store nothing. */
  PositionLanes p = position_in_every_lane((float4)(0.0f, 0.0f, 0.0f, 1.0f));
  for (uint lane = 0; lane < lane_count; ++lane) {
    const uint draw_slot = first_local + lane;
    uint vertex_index = slots.origin + draw_slot;
    if (!slots.shade_all) {
      const uint stream_position = u->first + (draw_slot < main_count ? slots.origin + draw_slot : 0u);
      vertex_index = u->index_size ? fetch_index(indices, u->index_size, stream_position) : stream_position;
    }
    clr_vertex v = {0};
    v.vertex_id = vertex_index;
    v.instance_id = instance;
    v.view_id = u->view;
    CLR_FETCH_ATTRIBUTES(v.in, vertex_index, instance, draw);
    v.position = (float4)(0.0f, 0.0f, 0.0f, 1.0f);
    CLR_BIND_RESOURCES(v, draw);
    vertex(&v);
    __global float4* const out = first_out + lane * CLR_SHADED_VERTEX_FLOAT4S;
    out[0] = v.position;
    clr_store_varyings(&v.out, (__global float*)(out + CLR_SHADED_VARYINGS));
    p.x = with_lane(p.x, lane, v.position.x);
    p.y = with_lane(p.y, lane, v.position.y);
    p.z = with_lane(p.z, lane, v.position.z);
    p.w = with_lane(p.w, lane, v.position.w);
  }

  /* The window part of the slots (CLR_SHADED_WINDOW, two float4s). */
  const ProjectedLanes window = project_lanes(&p, u);
  const vertex_lanes_int finite = isfinite(p.x) & isfinite(p.y) & isfinite(p.z) & isfinite(p.w);
  const vertex_lanes_int codes = clip_outcode_lanes(&p, vload2(0, u->guard_min), vload2(0, u->guard_max)) |
                                 view_outcode_lanes(&p) |
                                 select((vertex_lanes_int)(CLR_VERTEX_NOT_FINITE),
                                        select((vertex_lanes_int)(CLR_VERTEX_NOT_PROJECTABLE), (vertex_lanes_int)(0),
                                               window.projectable),
                                        finite);
  /* The planes and viewport sides that all of this work-item's vertices are outside: none if one is
   * not finite (such a vertex's primitives are dropped and counted, not culled). Lanes past the last
   * slot count as outside all of them. CLR_VERTEX_LANES divides CLR_CODE_GROUP_SLOTS, so the slots
   * are in one group. */
  if (slots.shade_all) {
    const vertex_lanes_int outside =
        select((vertex_lanes_int)(0), codes & (vertex_lanes_int)(CLR_VERTEX_OUTSIDE), finite);
    uint all_outside = CLR_VERTEX_OUTSIDE;
#pragma unroll
    for (uint lane = 0; lane < CLR_VERTEX_LANES; ++lane) {
      if (lane < lane_count) all_outside &= (uint)CLR_VERTEX_LANE(int, outside, lane);
    }
#if CLR_VERTEX_LANES == CLR_CODE_GROUP_SLOTS
    group_codes[first_slot / CLR_CODE_GROUP_SLOTS] = all_outside; /* the work-item's own group */
#else
    atomic_and(&group_codes[first_slot / CLR_CODE_GROUP_SLOTS], all_outside);
#endif
  }
#pragma unroll
  for (uint lane = 0; lane < CLR_VERTEX_LANES; ++lane) {
    if (lane < lane_count) {
      __global float4* const out = first_out + lane * CLR_SHADED_VERTEX_FLOAT4S + CLR_SHADED_WINDOW;
      out[0] = (float4)(as_float(CLR_VERTEX_LANE(int, window.fixed_x, lane)),
                        as_float(CLR_VERTEX_LANE(int, window.fixed_y, lane)),
                        CLR_VERTEX_LANE(float, window.residual_x, lane), CLR_VERTEX_LANE(float, window.residual_y, lane));
      out[1] = (float4)(CLR_VERTEX_LANE(float, window.z, lane), CLR_VERTEX_LANE(float, window.inv_w, lane),
                        as_float(CLR_VERTEX_LANE(int, codes, lane)), 0.0f);
    }
  }
}
