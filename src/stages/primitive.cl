/* primitive.cl: primitive assembly, clipping and culling.
 *
 * Primitive p of a draw takes its three vertices from stream positions (relative to the draw's
 * first element) in OpenGL's order:
 *   list   (3p, 3p + 1, 3p + 2)
 *   strip  (p, p + 1, p + 2) for even p, (p + 1, p, p + 2) for odd p, so every triangle keeps the
 *          strip's winding
 *   fan    (0, p + 1, p + 2)
 * Triangle set-up (setup.cl) then clips it when it crosses a plane (clip.cl), projects and snaps it
 * (fixed_point.cl), and culls it. */

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
  __global const float4* in = shaded + (size_t)slot * CLR_SHADED_VERTEX_FLOAT4S;
  v->position = in[0];
  __global const float* varyings = (__global const float*)(in + 1);
  for (int k = 0; k < CLR_NUM_VARYINGS; ++k) v->varyings[k] = varyings[k];
  return all(isfinite(v->position));
}

/* The three clip-space vertices of primitive p. False when one has a non-finite position: the
 * primitive is dropped (and counted). */
bool assemble_primitive(uint p, const SlotMap* slots, __global const uchar* indices, __global const float4* shaded,
                        __constant const DrawUniforms* u, ClipVertex* triangle) {
  const uint3 positions = primitive_stream_positions(u->topology, p);
  bool finite = load_clip_vertex(shaded, vertex_slot(positions.x, slots, indices, u), &triangle[0]);
  finite &= load_clip_vertex(shaded, vertex_slot(positions.y, slots, indices, u), &triangle[1]);
  finite &= load_clip_vertex(shaded, vertex_slot(positions.z, slots, indices, u), &triangle[2]);
#if CLR_HAS_FLAT_VARYINGS
  /* Flat varyings take the provoking vertex's value: the last one (GL_LAST_VERTEX_CONVENTION). */
  for (int k = 0; k < CLR_NUM_VARYINGS; ++k) {
    if (clr_varying_interpolation[k] == CLR_INTERPOLATE_FLAT) {
      triangle[0].varyings[k] = triangle[1].varyings[k] = triangle[2].varyings[k];
    }
  }
#endif
  return finite;
}

/* Clips a triangle that crosses `planes` (poly holds CLR_MAX_CLIP_VERTICES) and projects what is left
 * into a convex window-space polygon; returns its vertex count (0: nothing left). */
int clipped_window_polygon(ClipVertex* poly, uint planes, __constant const DrawUniforms* u, WindowVertex* polygon) {
  const int count = clip_polygon(poly, 3, planes, vload2(0, u->guard_min), vload2(0, u->guard_max));
  for (int i = 0; i < count; ++i) {
    if (!project_vertex(&poly[i], u, &polygon[i])) return 0;
  }
  return count;
}
