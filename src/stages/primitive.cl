/* primitive.cl: primitive assembly, clipping and culling.
 *
 * Primitive p of a draw takes its three vertices from stream positions (relative to the draw's
 * first element) in OpenGL's order:
 *   list   (3p, 3p + 1, 3p + 2)
 *   strip  (p, p + 1, p + 2) for even p, (p + 1, p, p + 2) for odd p, so every triangle keeps the
 *          strip's winding
 *   fan    (0, p + 1, p + 2)
 * It is clipped (clip.cl), projected and snapped (fixed_point.cl), fanned into triangles and culled.
 * primitive_count counts the triangles each primitive leaves; triangle_setup (setup.cl) repeats the
 * same steps to write them at the offsets the scan of those counts gives. */

inline uint3 primitive_stream_positions(int topology, uint p) {
  if (topology == CLR_TOPOLOGY_LIST) return (uint3)(3 * p, 3 * p + 1, 3 * p + 2);
  if (topology == CLR_TOPOLOGY_STRIP) return (p & 1) ? (uint3)(p + 1, p, p + 2) : (uint3)(p, p + 1, p + 2);
  return (uint3)(0, p + 1, p + 2);
}

/* Where the vertex stage put the vertex of a stream position (SlotMap, types.h; vertex.cl). */
inline uint vertex_slot(uint position, const SlotMap* slots, __global const uchar* indices,
                        __constant const DrawUniforms* u) {
  if (slots->shade_all) {
    const uint element = u->first + position;
    return u->index_size ? fetch_index(indices, u->index_size, element) : element;
  }
  if (u->topology == CLR_TOPOLOGY_FAN && position == 0) return slots->fan_centre;
  return position - slots->stream_begin;
}

inline bool load_clip_vertex(__global const float4* shaded, uint slot, ClipVertex* v) {
  v->position = shaded[slot * CLR_SHADED_VERTEX_FLOAT4S];
  const float4 varyings = shaded[slot * CLR_SHADED_VERTEX_FLOAT4S + 1];
  v->varyings[0] = varyings.x;
  v->varyings[1] = varyings.y;
  v->varyings[2] = varyings.z;
  return all(isfinite(v->position));
}

/* Assembles, clips and projects primitive p into a convex polygon in window space. Returns its
 * vertex count: 0 when nothing is visible, -1 when a vertex has a non-finite clip position (the
 * primitive is dropped and counted). */
int primitive_window_polygon(uint p, const SlotMap* slots, __global const uchar* indices,
                             __global const float4* shaded, __constant const DrawUniforms* u,
                             WindowVertex* polygon) {
  const uint3 positions = primitive_stream_positions(u->topology, p);
  ClipVertex clip[CLR_MAX_CLIP_VERTICES];
  bool finite = load_clip_vertex(shaded, vertex_slot(positions.x, slots, indices, u), &clip[0]);
  finite &= load_clip_vertex(shaded, vertex_slot(positions.y, slots, indices, u), &clip[1]);
  finite &= load_clip_vertex(shaded, vertex_slot(positions.z, slots, indices, u), &clip[2]);
  if (!finite) return -1;
  const int count = clip_triangle(clip, vload2(0, u->guard_min), vload2(0, u->guard_max));
  for (int i = 0; i < count; ++i) {
    if (!project_vertex(&clip[i], u, &polygon[i])) return 0;
  }
  return count;
}

__kernel void primitive_count(uint primitive_begin, uint primitive_count, SlotMap slots,
                              __global const uchar* indices, __global const float4* shaded,
                              __constant const DrawUniforms* u, __global uint* triangle_counts,
                              __global uint* counters) {
  const uint i = get_global_id(0);
  if (i >= primitive_count) return;
  WindowVertex polygon[CLR_MAX_CLIP_VERTICES];
  const int n = primitive_window_polygon(primitive_begin + i, &slots, indices, shaded, u, polygon);
  if (n < 0) atomic_inc(&counters[CLR_COUNTER_DROPPED]);
  uint surviving = 0;
  for (int k = 1; k + 1 < n; ++k) surviving += triangle_survives(&polygon[0], &polygon[k], &polygon[k + 1], u);
  triangle_counts[i] = surviving;
}
