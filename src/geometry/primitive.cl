/* primitive.cl: primitive assembly, clipping and culling.
 *
 * Primitive p of a draw takes its three vertices from stream positions (relative to the draw's
 * first element) in OpenGL's order:
 *   list   (3p, 3p + 1, 3p + 2)
 *   strip  (p, p + 1, p + 2) for even p, (p + 1, p, p + 2) for odd p, so every triangle keeps the
 *          strip's winding
 *   fan    (0, p + 1, p + 2)
 * Triangle set-up (setup.cl) then decides from the vertices' clip codes whether it is dropped,
 * rejected, clipped (clip.cl) or taken as the vertex stage projected and snapped it (fixed_point.cl),
 * and culls it. */

#include "geometry/clip.cl"
#include "geometry/fixed_point.cl"
#include "resources/index_range.cl"
#include "shared/types.h"

static inline uint3 primitive_stream_positions(int topology, uint p) {
  if (topology == CLR_TOPOLOGY_LIST) return (uint3)(3 * p, 3 * p + 1, 3 * p + 2);
  if (topology == CLR_TOPOLOGY_STRIP) return (p & 1) ? (uint3)(p + 1, p, p + 2) : (uint3)(p, p + 1, p + 2);
  return (uint3)(0, p + 1, p + 2);
}

/* Where the vertex stage put the vertex of a stream position (SlotMap, types.h; vertex.cl). */
static inline uint vertex_slot(uint position, const SlotMap* slots, __global const uchar* indices,
                               __constant const DrawUniforms* u) {
  if (slots->shade_all) {
    const uint element = u->first + position;
    return slots->slot_base + (u->index_size ? fetch_index(indices, u->index_size, element) : element) - slots->origin;
  }
  if (u->topology == CLR_TOPOLOGY_FAN && position == 0) return slots->slot_base + slots->fan_centre;
  return slots->slot_base + position - slots->origin;
}

/* The vertex slots of primitive p's three vertices, into slots[0..2]. Vertex slots travel between
 * set-up's functions as an array, not a uint3: Intel's CPU compiler, vectorizing set-up 16 work-items
 * wide (its choice on AVX-512 machines), passed a uint3 argument of a call that it did not inline
 * with its lanes mixed up, so that the varyings came from the wrong vertices or from addresses far
 * outside the buffer (a crash). */
static inline void primitive_slots(uint p, const SlotMap* map, __global const uchar* indices,
                                   __constant const DrawUniforms* u, uint* slots) {
  const uint3 positions = primitive_stream_positions(u->topology, p);
  slots[0] = vertex_slot(positions.x, map, indices, u);
  slots[1] = vertex_slot(positions.y, map, indices, u);
  slots[2] = vertex_slot(positions.z, map, indices, u);
}

static inline __global const float4* shaded_slot(__global const float4* shaded, uint slot) {
  return shaded + (size_t)slot * CLR_SHADED_VERTEX_FLOAT4S;
}

/* The union of the three vertices' clip codes (types.h) in .x, their intersection in .y. */
static inline uint2 primitive_codes(__global const float4* shaded, const uint* slots) {
  const uint c0 = as_uint(shaded_slot(shaded, slots[0])[CLR_SHADED_WINDOW + 1].z);
  const uint c1 = as_uint(shaded_slot(shaded, slots[1])[CLR_SHADED_WINDOW + 1].z);
  const uint c2 = as_uint(shaded_slot(shaded, slots[2])[CLR_SHADED_WINDOW + 1].z);
  return (uint2)(c0 | c1 | c2, c0 & c1 & c2);
}

/* Flat varyings take the provoking vertex's value: the last one (GL_LAST_VERTEX_CONVENTION). */
static inline void take_provoking_flat_varyings(float* v0, float* v1, const float* v2) {
#if CLR_HAS_FLAT_VARYINGS
#pragma unroll
  for (int k = 0; k < CLR_NUM_VARYINGS; ++k) {
    if (clr_varying_interpolation[k] == CLR_INTERPOLATE_FLAT) v0[k] = v1[k] = v2[k];
  }
#endif
}

static inline void load_varyings(__global const float4* slot, float* varyings) {
  __global const float* in = (__global const float*)(slot + CLR_SHADED_VARYINGS);
#pragma unroll
  for (int k = 0; k < CLR_NUM_VARYINGS; ++k) varyings[k] = in[k];
}

/* The three clip-space vertices of a primitive, for clipping. */
static void assemble_clip_triangle(__global const float4* shaded, const uint* slots, ClipVertex* triangle) {
#pragma unroll
  for (int i = 0; i < 3; ++i) {
    __global const float4* in = shaded_slot(shaded, slots[i]);
    triangle[i].position = in[0];
    load_varyings(in, triangle[i].varyings);
  }
  take_provoking_flat_varyings(triangle[0].varyings, triangle[1].varyings, triangle[2].varyings);
}

/* The window positions of a primitive inside every clip plane, as the vertex stage projected them;
 * their varyings wait for load_window_varyings, which culled triangles never need. */
static void assemble_window_triangle(__global const float4* shaded, const uint* slots, WindowVertex* triangle) {
#pragma unroll
  for (int i = 0; i < 3; ++i) {
    __global const float4* in = shaded_slot(shaded, slots[i]) + CLR_SHADED_WINDOW;
    const float4 position = in[0];
    const float4 depth = in[1];
    triangle[i].fixed = as_int2(position.xy);
    triangle[i].residual = position.zw;
    triangle[i].z = depth.x;
    triangle[i].inv_w = depth.y;
  }
}

static void load_window_varyings(__global const float4* shaded, const uint* slots, WindowVertex* triangle) {
  load_varyings(shaded_slot(shaded, slots[0]), triangle[0].varyings);
  load_varyings(shaded_slot(shaded, slots[1]), triangle[1].varyings);
  load_varyings(shaded_slot(shaded, slots[2]), triangle[2].varyings);
  take_provoking_flat_varyings(triangle[0].varyings, triangle[1].varyings, triangle[2].varyings);
}

/* Clips a triangle that crosses `planes` (poly holds CLR_MAX_CLIP_VERTICES) and projects what is left
 * into a convex window-space polygon; returns its vertex count (0: nothing left). */
static int clipped_window_polygon(ClipVertex* poly, uint planes, __constant const DrawUniforms* u,
                                  WindowVertex* polygon) {
  const int count = clip_polygon(poly, 3, planes, vload2(0, u->guard_min), vload2(0, u->guard_max));
  for (int i = 0; i < count; ++i) {
    if (!project_vertex(&poly[i], u, &polygon[i])) return 0;
  }
  return count;
}
