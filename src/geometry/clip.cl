/* clip.cl: clipping in homogeneous clip space (Sutherland-Hodgman, one plane at a time).
 *
 * Planes: near (z >= -w) and far (z <= w), as OpenGL clips without depth clamping, and four
 * guard-band planes far outside the viewport (guard_min * w <= x, y <= guard_max * w) that keep
 * window coordinates small enough for exact fixed-point edge functions. Clipping x and y at the
 * viewport instead would move triangle edges by the snapping of the new vertices; the guard band
 * leaves every visible edge where the vertices put it, as llvmpipe does. Together the guard planes
 * also imply w >= 0, so clipped polygons never cross w = 0. */

#include "shared/clr_limits.h"
#include "shared/types.h"

typedef struct {
  float4 position; /* clip space */
  float varyings[CLR_NUM_VARYINGS];
} ClipVertex;

/* ---- Vertex lanes ----------------------------------------------------------------------------------
 * The vertex stage classifies and projects CLR_VERTEX_LANES vertices at a time, one vector lane each
 * (clr_limits.h: 8 on CPUs, where it took 60% of the vertex stage as scalar code; 1 on GPUs). The
 * clip codes here and the projection in fixed_point.cl are written once, for lanes; clipping (in
 * set-up), which takes one vertex at a time, puts it in every lane and reads lane 0. So a vertex made
 * by clipping is projected and snapped by the same code as the vertices the vertex stage projected,
 * and the two sides of a shared edge agree to the bit. */
#if CLR_VERTEX_LANES == 1
#define CLR_VERTEX_LANE_SUFFIX
#define CLR_VERTEX_LANE(type, value, lane) (value)
#define CLR_VERTEX_LANE_INDICES 0
#elif CLR_VERTEX_LANES == 8
#define CLR_VERTEX_LANE_SUFFIX 8
#define CLR_VERTEX_LANE(type, value, lane) (((const type*)&(value))[lane])
#define CLR_VERTEX_LANE_INDICES (int8)(0, 1, 2, 3, 4, 5, 6, 7)
#else
#error "CLR_VERTEX_LANES must be 1 or 8"
#endif
typedef CLR_CAT(float, CLR_VERTEX_LANE_SUFFIX) vertex_lanes_float;
typedef CLR_CAT(int, CLR_VERTEX_LANE_SUFFIX) vertex_lanes_int; /* also masks: -1 true in vectors, 1 in scalars */
#define CLR_VERTEX_LANES_TO_INT_RTE(value) CLR_CAT(CLR_CAT(convert_int, CLR_VERTEX_LANE_SUFFIX), _rte)(value)
#define CLR_VERTEX_LANES_TO_FLOAT(value) CLR_CAT(convert_float, CLR_VERTEX_LANE_SUFFIX)(value)

/* Clip-space positions, one vertex per lane. */
typedef struct {
  vertex_lanes_float x, y, z, w;
} PositionLanes;

/* `lanes` with lane `lane` set to `value`, by a select in registers: lanes stored one by one into an
 * array and loaded back as a vector stall the load, which waits for the stores to reach the cache
 * (a third of the vertex stage's samples did). */
static inline vertex_lanes_float with_lane(vertex_lanes_float lanes, uint lane, float value) {
  return select(lanes, (vertex_lanes_float)(value), CLR_VERTEX_LANE_INDICES == (vertex_lanes_int)((int)lane));
}

static inline PositionLanes position_in_every_lane(float4 p) {
  return (PositionLanes){(vertex_lanes_float)(p.x), (vertex_lanes_float)(p.y), (vertex_lanes_float)(p.z),
                         (vertex_lanes_float)(p.w)};
}

/* Signed distance of each lane's position to plane `plane`: >= 0 inside. */
static inline vertex_lanes_float clip_distance_lanes(const PositionLanes* p, int plane, float2 guard_min,
                                                     float2 guard_max) {
  switch (plane) {
    case 0: return p->z + p->w;                  /* near */
    case 1: return p->w - p->z;                  /* far */
    case 2: return p->x - guard_min.x * p->w;    /* left guard band */
    case 3: return guard_max.x * p->w - p->x;    /* right */
    case 4: return p->y - guard_min.y * p->w;    /* bottom */
    default: return guard_max.y * p->w - p->y;   /* top */
  }
}

static inline float clip_distance(float4 p, int plane, float2 guard_min, float2 guard_max) {
  const PositionLanes lanes = position_in_every_lane(p);
  const vertex_lanes_float distance = clip_distance_lanes(&lanes, plane, guard_min, guard_max);
  return CLR_VERTEX_LANE(float, distance, 0);
}

/* Bit k set: the lane's position is outside plane k. Unrolled, so that each plane's distance is its
 * own expression instead of a switch taken in a loop (this runs for every vertex). */
CLR_INLINE vertex_lanes_int clip_outcode_lanes(const PositionLanes* p, float2 guard_min, float2 guard_max) {
  vertex_lanes_int code = 0;
#pragma unroll
  for (int plane = 0; plane < CLR_CLIP_PLANES; ++plane) {
    code |= select((vertex_lanes_int)(0), (vertex_lanes_int)(1 << plane),
                   clip_distance_lanes(p, plane, guard_min, guard_max) < 0.0f);
  }
  return code;
}

/* The viewport sides each lane's position is outside, as CLR_VERTEX_OUTSIDE_VIEW bits (types.h). */
CLR_INLINE vertex_lanes_int view_outcode_lanes(const PositionLanes* p) {
  const int first = CLR_CLIP_PLANES + 2;
  return select((vertex_lanes_int)(0), (vertex_lanes_int)(1 << first), p->x < -p->w) |
         select((vertex_lanes_int)(0), (vertex_lanes_int)(1 << (first + 1)), p->x > p->w) |
         select((vertex_lanes_int)(0), (vertex_lanes_int)(1 << (first + 2)), p->y < -p->w) |
         select((vertex_lanes_int)(0), (vertex_lanes_int)(1 << (first + 3)), p->y > p->w);
}

/* The point where segment inside -> outside crosses the plane. Always interpolated from the inside
 * end, so the two triangles that share an edge compute bit-identical points on it. */
static inline ClipVertex clip_intersect(const ClipVertex* inside, const ClipVertex* outside, float d_inside,
                                        float d_outside) {
  const float t = d_inside / (d_inside - d_outside);
  ClipVertex v;
  v.position = inside->position + t * (outside->position - inside->position);
  /* Varyings interpolated without perspective are linear in window space: there the new vertex
   * sits at t * w_outside / w_new of the way. */
  const float t_window = t * outside->position.w / v.position.w;
  for (int k = 0; k < CLR_NUM_VARYINGS; ++k) {
    const int mode = clr_varying_interpolation[k];
    const float s = mode == CLR_INTERPOLATE_NOPERSPECTIVE ? t_window : t;
    /* Flat varyings (every vertex holds the provoking vertex's value) are copied, not computed,
     * so that integers travelling as float bits keep their bits even when those read as NaN. */
    v.varyings[k] = mode == CLR_INTERPOLATE_FLAT ? inside->varyings[k]
                                                 : inside->varyings[k] + s * (outside->varyings[k] - inside->varyings[k]);
  }
  return v;
}

/* Clips the convex polygon poly[0 .. count) against every plane in `planes` (a bit mask) and returns
 * the new vertex count (0 when nothing is left). poly must hold CLR_MAX_CLIP_VERTICES. */
static int clip_polygon(ClipVertex* poly, int count, uint planes, float2 guard_min, float2 guard_max) {
  ClipVertex scratch[CLR_MAX_CLIP_VERTICES];
  for (int plane = 0; plane < CLR_CLIP_PLANES && count > 0; ++plane) {
    if (!(planes & (1u << plane))) continue;
    int out_count = 0;
    for (int i = 0; i < count; ++i) {
      const ClipVertex* a = &poly[i];
      const ClipVertex* b = &poly[i + 1 == count ? 0 : i + 1];
      const float da = clip_distance(a->position, plane, guard_min, guard_max);
      const float db = clip_distance(b->position, plane, guard_min, guard_max);
      if (da >= 0.0f) scratch[out_count++] = *a;
      if ((da >= 0.0f) != (db >= 0.0f)) {
        scratch[out_count++] = da >= 0.0f ? clip_intersect(a, b, da, db) : clip_intersect(b, a, db, da);
      }
    }
    count = out_count;
    for (int i = 0; i < count; ++i) poly[i] = scratch[i];
  }
  return count;
}
