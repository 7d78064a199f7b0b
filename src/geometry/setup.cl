/* setup.cl: triangle set-up, one pass over a chunk's primitives.
 *
 * Almost every primitive is a triangle inside all clip planes: triangle_setup takes its vertices as
 * the vertex stage projected and snapped them, culls it and writes it straight into the primitive's
 * own record, with the number of tiles its bounding box touches (0 when culled). A primitive that
 * crosses a plane (rare) keeps no record there: it counts the triangles clipping leaves of it and
 * the tiles they touch, and the draw's CLR_COUNTER_CLIPPED; only when that counter moved does the
 * host scan the triangle counts and run clipped_setup, which clips those primitives again and writes
 * their triangles into the overflow records. The pair counts are all known after triangle_setup, so
 * their scan needs no host decision before it, and they stay per primitive either way, so the bin
 * pairs come out in primitive order.
 *
 * Each record's pixel box is also written apart, 8 bytes a primitive (bin_boxes), which is all that
 * binning reads of an unclipped triangle: its 168-byte records, one cache line each, read a second
 * time, cost binning more than its sort (bin_emit of terrain-1m 4.3 -> 1.3 ms without them).
 *
 * The loops over a triangle's vertices and varyings here and in primitive.cl are unrolled, so that
 * the record and the vertices being assembled stay in registers (raster/span.cl says why; set-up
 * of terrain-4m 63 -> 48 ms). */

#include "geometry/clip.cl"
#include "geometry/fixed_point.cl"
#include "geometry/primitive.cl"
#include "shared/clr_limits.h"
#include "shared/types.h"

/* A triangle's writable pixels within its bounding box, the corners packed as x | y << 16. */
static inline uint2 packed_pixel_box(const TriangleExtent* extent) {
  return (uint2)((uint)extent->pixel_min.x | (uint)extent->pixel_min.y << 16,
                 (uint)extent->pixel_max.x | (uint)extent->pixel_max.y << 16);
}

/* The number of tiles a triangle's pixel box touches: its bin pairs. */
static inline uint tiles_touched(const TriangleExtent* extent) {
  const int2 tile_lo = extent->pixel_min / CLR_TILE_SIZE;
  const int2 tile_hi = extent->pixel_max / CLR_TILE_SIZE;
  return (uint)((tile_hi.x - tile_lo.x + 1) * (tile_hi.y - tile_lo.y + 1));
}

/* Writes the record of a triangle that survived culling (which measured `extent`). Always inlined:
 * PoCL's compiler kept it a call, with the vertices passed through the stack (set-up of terrain-4m
 * 38 -> 34 ms inlined). */
CLR_INLINE void write_setup_triangle(const WindowVertex* v0, const WindowVertex* v1, const WindowVertex* v2,
                                     const TriangleExtent* extent, uint primitive_id,
                                     __constant const DrawUniforms* u, __global SetupTriangle* out) {
  long area = extent->double_area;
  const bool front = (area > 0) == (u->front_face_ccw != 0);
  /* Rasterization wants counter-clockwise vertices: swap the last two of a clockwise triangle. */
  const WindowVertex* v[3] = {v0, area > 0 ? v1 : v2, area > 0 ? v2 : v1};
  area = area > 0 ? area : -area;

  SetupTriangle t;
  t.flags = (front ? CLR_TRIANGLE_FRONT_FACING : 0u) | u->batch_draw << CLR_TRIANGLE_DRAW_SHIFT |
            u->view << CLR_TRIANGLE_VIEW_SHIFT;
#pragma unroll
  for (int k = 0; k < 3; ++k) {
    /* Edge k runs from vertex k+1 to vertex k+2, opposite vertex k. */
    const int2 a = v[(k + 1) % 3]->fixed;
    const int2 b = v[(k + 2) % 3]->fixed;
    const int dx = b.x - a.x;
    const int dy = b.y - a.y;
    t.edge_a[k] = -dy;
    t.edge_b[k] = dx;
    t.edge_c[k] = (long)dy * a.x - (long)dx * a.y;
    if (edge_includes_centres(a, b)) t.flags |= 1u << k;
    /* The unsnapped edge, a + ra to b + rb, has the function cross(d + dr, X - a - ra) with
     * d = b - a and dr = rb - ra: E_k plus cross(dr, X - a) - cross(d + dr, ra), a plane. */
    const float2 ra = v[(k + 1) % 3]->residual;
    const float2 dr = v[(k + 2) % 3]->residual - ra;
    const float2 d_true = convert_float2(b - a) + dr;
    t.edge_correction[k][0] = -dr.y;
    t.edge_correction[k][1] = dr.x;
    t.edge_correction[k][2] = dr.y * (float)a.x - dr.x * (float)a.y - (d_true.x * ra.y - d_true.y * ra.x);
    t.z[k] = v[k]->z;
    t.inv_w[k] = v[k]->inv_w;
#pragma unroll
    for (int j = 0; j < CLR_NUM_VARYINGS; ++j) t.varyings[k][j] = v[k]->varyings[j];
  }
  /* Twice the unsnapped area: cross(e1 + r1 - r0, e2 + r2 - r0) with e1, e2 the snapped sides from
   * vertex 0; the snapped part is exact in `area`, the rest small. */
  const float2 e1 = convert_float2(v[1]->fixed - v[0]->fixed);
  const float2 e2 = convert_float2(v[2]->fixed - v[0]->fixed);
  const float2 r1 = v[1]->residual - v[0]->residual;
  const float2 r2 = v[2]->residual - v[0]->residual;
  const float area_correction = (e1.x * r2.y - e1.y * r2.x) + (r1.x * e2.y - r1.y * e2.x) + (r1.x * r2.y - r1.y * r2.x);
  t.inv_double_area = 1.0f / ((float)area + area_correction);
  t.primitive_id = primitive_id;

  const uint2 box = packed_pixel_box(extent);
  t.pixel_min = box.x;
  t.pixel_max = box.y;
  *out = t;
}

/* `outside` ANDed with the codes of the groups that hold vertex slots first to last. */
static inline uint outside_of_groups(__global const uint* group_codes, uint first, uint last, uint outside) {
  for (uint group = first / CLR_CODE_GROUP_SLOTS; group <= last / CLR_CODE_GROUP_SLOTS && outside != 0; ++group) {
    outside &= group_codes[group];
  }
  return outside;
}

/* Block culling (clr_limits.h): block first_block + j of the draw's primitives is outside a clip
 * plane or viewport side where every group of vertex slots in its index ranges is (the vertex
 * stage's group_codes, the ranges from block_index_ranges, index i in slot i + slot_offset), and
 * culled[j] is then 1, else 0. One work-item per block of a chunk, for each instance (the second
 * dimension: instance k's slots instance_slots further on, its verdicts block_count further). */
__kernel void cull_blocks(uint first_block, uint block_count, __global const uint4* index_ranges, uint slot_offset,
                          uint instance_slots, __global const uint* group_codes, __global uchar* culled) {
  const uint j = get_global_id(0);
  if (j >= block_count) return;
  const uint instance = get_global_id(1);
  culled += instance * block_count;
  slot_offset += instance * instance_slots;
  const uint4 ranges = index_ranges[first_block + j] + slot_offset; /* two, (x, y) and (z, w) */
  const uint outside = outside_of_groups(group_codes, ranges.z, ranges.w,
                                         outside_of_groups(group_codes, ranges.x, ranges.y, CLR_VERTEX_OUTSIDE));
  culled[j] = outside != 0;
}

/* The place of instance get_global_id(1) of a draw's chunk in a pass: its vertex slots
 * instance_slots after the previous instance's, its primitives' entries primitive_count after. */
static inline uint instance_record_base(uint record_base, uint primitive_count) {
  return record_base + (uint)get_global_id(1) * primitive_count;
}
/* Changes a copy of the SlotMap argument, never the argument: PoCL passes a structure argument by
 * reference to one copy that all work-items share, so that their changes added up (a crash). */
static inline void move_to_instance(SlotMap* map, uint instance_slots) {
  map->slot_base += (uint)get_global_id(1) * instance_slots;
}

/* culled_blocks: cull_blocks' verdicts for the chunk's blocks, where `block_culling`; a primitive of a
 * culled block is rejected without a look at its indices or vertices. The draws of a pass write
 * side by side: primitive i of this one at entry record_base + i of records, bin_boxes and the
 * counts. The second dimension counts the instances (their slots, verdicts and entries one after
 * the other). */
__kernel void triangle_setup(uint primitive_begin, uint primitive_count, SlotMap slots, uint instance_slots,
                             __global const uchar* indices, __global const float4* shaded, int block_culling,
                             __global const uchar* culled_blocks, __constant const DrawUniforms* draws, uint draw,
                             uint record_base, __global SetupTriangle* records, __global uint2* bin_boxes,
                             __global uint* pair_counts, __global uint* clipped_counts, __global uint* counters) {
  const uint i = get_global_id(0);
  if (i >= primitive_count) return;
  __constant const DrawUniforms* const u = draws + draw;
  SlotMap map = slots;
  move_to_instance(&map, instance_slots);
  record_base = instance_record_base(record_base, primitive_count);
  /* Instances come in whole draws (primitive_begin 0): block_count of cull_blocks is the draw's blocks. */
  culled_blocks += get_global_id(1) * ((primitive_count + CLR_CULL_BLOCK_PRIMITIVES - 1) / CLR_CULL_BLOCK_PRIMITIVES);
  records += record_base;
  bin_boxes += record_base;
  pair_counts += record_base;
  clipped_counts += record_base;
  /* The extra entries after the last instance's, whose exclusive scans are the totals (an earlier
   * instance's would be the next one's first). */
  if (i == primitive_count - 1 && get_global_id(1) == get_global_size(1) - 1) {
    pair_counts[primitive_count] = 0;
    clipped_counts[primitive_count] = 0;
  }
  uint pairs = 0;
  uint clipped = 0;
  if (block_culling && culled_blocks[(primitive_begin + i) / CLR_CULL_BLOCK_PRIMITIVES -
                                     primitive_begin / CLR_CULL_BLOCK_PRIMITIVES]) {
    pair_counts[i] = 0;
    clipped_counts[i] = 0;
    return;
  }
  uint vertex_slots[3];
  primitive_slots(primitive_begin + i, &map, indices, u, vertex_slots);
  const uint2 codes = primitive_codes(shaded, vertex_slots);
  const uint planes = codes.x & CLR_VERTEX_OUTSIDE_PLANES;
  if (codes.x & CLR_VERTEX_NOT_FINITE) {
    atomic_inc(&counters[CLR_COUNTER_DROPPED]);
  } else if (codes.y & CLR_VERTEX_OUTSIDE) {
    /* All three vertices outside one plane, or one side of the viewport: nothing of it is left. */
  } else if (planes == 0) {
    WindowVertex triangle[3];
    TriangleExtent extent;
    assemble_window_triangle(shaded, vertex_slots, triangle);
    if (!(codes.x & CLR_VERTEX_NOT_PROJECTABLE) && triangle_survives(&triangle[0], &triangle[1], &triangle[2], u, &extent)) {
      load_window_varyings(shaded, vertex_slots, triangle);
      write_setup_triangle(&triangle[0], &triangle[1], &triangle[2], &extent, primitive_begin + i, u, &records[i]);
      bin_boxes[i] = packed_pixel_box(&extent);
      pairs = tiles_touched(&extent);
    }
  } else {
    ClipVertex triangle[CLR_MAX_CLIP_VERTICES];
    WindowVertex polygon[CLR_MAX_CLIP_VERTICES];
    TriangleExtent extent;
    assemble_clip_triangle(shaded, vertex_slots, triangle);
    const int n = clipped_window_polygon(triangle, planes, u, polygon);
    for (int k = 1; k + 1 < n; ++k) {
      if (triangle_survives(&polygon[0], &polygon[k], &polygon[k + 1], u, &extent)) {
        ++clipped;
        pairs += tiles_touched(&extent);
      }
    }
    atomic_inc(&counters[CLR_COUNTER_CLIPPED]);
  }
  pair_counts[i] = pairs;
  clipped_counts[i] = clipped;
}

/* For the primitives triangle_setup counted clipped triangles for: the same clipping again, writing
 * them at the primitive's overflow offset. */
__kernel void clipped_setup(uint primitive_begin, uint primitive_count, SlotMap slots, uint instance_slots,
                            __global const uchar* indices, __global const float4* shaded,
                            __constant const DrawUniforms* draws, uint draw, uint record_base,
                            __global const uint* clipped_offsets, __global SetupTriangle* overflow) {
  const uint i = get_global_id(0);
  SlotMap map = slots;
  move_to_instance(&map, instance_slots);
  clipped_offsets += instance_record_base(record_base, primitive_count);
  if (i >= primitive_count || clipped_offsets[i] == clipped_offsets[i + 1]) return;
  __constant const DrawUniforms* const u = draws + draw;
  uint vertex_slots[3];
  primitive_slots(primitive_begin + i, &map, indices, u, vertex_slots);
  const uint planes = primitive_codes(shaded, vertex_slots).x & CLR_VERTEX_OUTSIDE_PLANES;
  ClipVertex triangle[CLR_MAX_CLIP_VERTICES];
  WindowVertex polygon[CLR_MAX_CLIP_VERTICES];
  assemble_clip_triangle(shaded, vertex_slots, triangle);
  const int n = clipped_window_polygon(triangle, planes, u, polygon);
  uint out = clipped_offsets[i];
  TriangleExtent extent;
  for (int k = 1; k + 1 < n; ++k) {
    if (triangle_survives(&polygon[0], &polygon[k], &polygon[k + 1], u, &extent)) {
      write_setup_triangle(&polygon[0], &polygon[k], &polygon[k + 1], &extent, primitive_begin + i, u,
                           &overflow[out++]);
    }
  }
}
