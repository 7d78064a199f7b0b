/* vertex.cl: the vertex stage. One work-item per vertex slot fetches the vertex's attributes and
 * runs the program's vertex function; the slot keeps the clip-space position and the varyings.
 *
 * Slots: when the whole vertex range is shaded once per draw, slot s holds vertex s. Otherwise
 * (the draw's transformed vertices would not fit the memory cap) each chunk shades its own stream
 * positions: slot s holds the element at stream position stream_begin + s, and for fans one extra
 * slot, main_count, holds the fan's centre (stream position 0).
 *
 * Besides the program's outputs a slot keeps the vertex's clip codes and its window position
 * (types.h): computed here once per vertex, not by set-up once per triangle using it. */

/* The window part of a slot (CLR_SHADED_WINDOW, two float4s) for a clip-space position. */
CLR_INLINE void store_window_part(float4 position, __constant const DrawUniforms* u, __global float4* out) {
  uint codes = clip_outcode(position, vload2(0, u->guard_min), vload2(0, u->guard_max));
  WindowVertex w = {0};
  if (!all(isfinite(position))) {
    codes |= CLR_VERTEX_NOT_FINITE;
  } else if (!project_position(position, u, &w)) {
    codes |= CLR_VERTEX_NOT_PROJECTABLE;
  }
  out[0] = (float4)(as_float2(w.fixed), w.residual);
  out[1] = (float4)(w.z, w.inv_w, as_float(codes), 0.0f);
}

__kernel void vertex_shade(__global const uchar* indices, int shade_all, uint stream_begin, uint main_count,
                           uint slot_count, __constant const DrawUniforms* u,
                           __global float4* shaded CLR_RESOURCE_PARAMS CLR_ATTRIBUTE_PARAMS) {
  const uint slot = get_global_id(0);
  if (slot >= slot_count) return;
  uint vertex_index = slot;
  if (!shade_all) {
    const uint position = u->first + (slot < main_count ? stream_begin + slot : 0u);
    vertex_index = u->index_size ? fetch_index(indices, u->index_size, position) : position;
  }
  clr_vertex v = {0};
  v.vertex_id = vertex_index;
  v.instance_id = u->instance;
  CLR_FETCH_ATTRIBUTES(v.in, vertex_index, u->instance);
  v.position = (float4)(0.0f, 0.0f, 0.0f, 1.0f);
  CLR_BIND_RESOURCES(v);
  vertex(&v);
  __global float4* out = shaded + (size_t)slot * CLR_SHADED_VERTEX_FLOAT4S;
  out[0] = v.position;
  store_window_part(v.position, u, out + CLR_SHADED_WINDOW);
  clr_store_varyings(&v.out, (__global float*)(out + CLR_SHADED_VARYINGS));
}
