/* fixed_point.cl: window coordinates, snapping and exact edge functions, shared by culling,
 * triangle set-up and rasterization.
 *
 * Window coordinates follow OpenGL (x_w = ndc * W/2 + X + W/2, y up, z_w = ndc_z / 2 + 1/2) and are
 * snapped to 1/256 pixel after subtracting the half pixel, as llvmpipe does, so that pixel centres
 * fall on integer multiples of CLR_SUBPIXEL_ONE. Every coverage decision is then integer
 * arithmetic in 64 bits: exact, watertight and the same on every device. */

#include "geometry/clip.cl"
#include "shared/clr_limits.h"
#include "shared/types.h"

typedef struct {
  int2 fixed;      /* snapped window position, pixel centres at multiples of CLR_SUBPIXEL_ONE */
  float2 residual; /* what snapping took away: the position before it is fixed + residual */
  float z;         /* window depth */
  float inv_w;
  float varyings[CLR_NUM_VARYINGS];
} WindowVertex;

/* Window positions of clip-space positions, one vertex per lane (clip.cl), projected and snapped. */
typedef struct {
  vertex_lanes_int fixed_x, fixed_y;            /* snapped, see WindowVertex */
  vertex_lanes_float residual_x, residual_y;    /* what snapping took away */
  vertex_lanes_float z, inv_w;                  /* window depth, 1 / clip w */
  vertex_lanes_int projectable;                 /* mask; where false (w = 0) the rest is 0 */
} ProjectedLanes;

/* Projects and snaps each lane's clip-space position. Only a vertex at the origin of clip space
 * survives clipping with w = 0; it cannot be projected. */
CLR_INLINE ProjectedLanes project_lanes(const PositionLanes* p, __constant const DrawUniforms* u) {
  const vertex_lanes_float inv_w = 1.0f / p->w;
  const vertex_lanes_float x = p->x * inv_w * u->viewport_scale[0] + u->viewport_offset[0];
  const vertex_lanes_float y = p->y * inv_w * u->viewport_scale[1] + u->viewport_offset[1];
  const vertex_lanes_float z = p->z * inv_w * 0.5f + 0.5f;
  const vertex_lanes_int projectable = isfinite(x) & isfinite(y) & isfinite(z);
  /* Where a lane cannot be projected, 0 instead of what the conversions make of infinities. */
  const vertex_lanes_float unsnapped_x = select((vertex_lanes_float)(0.0f), (x - 0.5f) * (float)CLR_SUBPIXEL_ONE, projectable);
  const vertex_lanes_float unsnapped_y = select((vertex_lanes_float)(0.0f), (y - 0.5f) * (float)CLR_SUBPIXEL_ONE, projectable);
  ProjectedLanes out;
  out.fixed_x = CLR_VERTEX_LANES_TO_INT_RTE(unsnapped_x);
  out.fixed_y = CLR_VERTEX_LANES_TO_INT_RTE(unsnapped_y);
  out.residual_x = unsnapped_x - CLR_VERTEX_LANES_TO_FLOAT(out.fixed_x);
  out.residual_y = unsnapped_y - CLR_VERTEX_LANES_TO_FLOAT(out.fixed_y);
  out.z = select((vertex_lanes_float)(0.0f), z, projectable);
  out.inv_w = select((vertex_lanes_float)(0.0f), inv_w, projectable);
  out.projectable = projectable;
  return out;
}

/* Projects and snaps one clip-space position into `out` (all but its varyings): project_lanes with
 * the position in every lane. Returns false when it cannot be projected. */
CLR_INLINE bool project_position(float4 position, __constant const DrawUniforms* u, WindowVertex* out) {
  const PositionLanes lanes = position_in_every_lane(position);
  const ProjectedLanes window = project_lanes(&lanes, u);
  out->fixed = (int2)(CLR_VERTEX_LANE(int, window.fixed_x, 0), CLR_VERTEX_LANE(int, window.fixed_y, 0));
  out->residual = (float2)(CLR_VERTEX_LANE(float, window.residual_x, 0), CLR_VERTEX_LANE(float, window.residual_y, 0));
  out->z = CLR_VERTEX_LANE(float, window.z, 0);
  out->inv_w = CLR_VERTEX_LANE(float, window.inv_w, 0);
  return CLR_VERTEX_LANE(int, window.projectable, 0) != 0;
}

/* project_position with the vertex's varyings. */
static inline bool project_vertex(const ClipVertex* v, __constant const DrawUniforms* u, WindowVertex* out) {
  if (!project_position(v->position, u, out)) return false;
#pragma unroll
  for (int k = 0; k < CLR_NUM_VARYINGS; ++k) out->varyings[k] = v->varyings[k];
  return true;
}

/* Twice the signed area of the snapped triangle: positive when counter-clockwise (y up). */
static inline long double_area(int2 a, int2 b, int2 c) {
  return (long)(b.x - a.x) * (long)(c.y - a.y) - (long)(c.x - a.x) * (long)(b.y - a.y);
}

/* Pixels whose centres the snapped triangle's bounding box contains, clipped to the draw's
 * writable rectangle: [min.x, max.x] x [min.y, max.y], empty when min > max. */
static inline void pixel_bounds(int2 a, int2 b, int2 c, __constant const DrawUniforms* u, int2* lo, int2* hi) {
  const int2 fixed_min = min(a, min(b, c));
  const int2 fixed_max = max(a, max(b, c));
  /* Centre of pixel i is at i * ONE: the first centre >= min is ceil(min / ONE). */
  *lo = max((fixed_min + (CLR_SUBPIXEL_ONE - 1)) >> CLR_SUBPIXEL_BITS, (int2)(u->clip_rect[0], u->clip_rect[1]));
  *hi = min(fixed_max >> CLR_SUBPIXEL_BITS, (int2)(u->clip_rect[2] - 1, u->clip_rect[3] - 1));
}

/* Whether a pixel centre exactly on the edge from a to b (counter-clockwise triangle, y up) belongs
 * to the triangle: yes for left edges (going down) and bottom edges (horizontal, going right). This
 * is llvmpipe's top-left rule seen in OpenGL's y-up window coordinates. */
static inline bool edge_includes_centres(int2 a, int2 b) {
  const int dx = b.x - a.x;
  const int dy = b.y - a.y;
  return dy < 0 || (dy == 0 && dx > 0);
}

/* E(p) for the edge a -> b, positive left of it (inside a counter-clockwise triangle). */
static inline long edge_function(int2 a, int2 b, long px, long py) {
  return (long)(b.x - a.x) * (py - a.y) - (long)(b.y - a.y) * (px - a.x);
}

/* Whether the centre (px, py) is on the inner side of the edge from a to b of a counter-clockwise
 * triangle: E > 0, or E = 0 on an edge that includes its centres. */
static inline bool edge_covers_centre(int2 a, int2 b, long px, long py) {
  const long e = edge_function(a, b, px, py);
  return e > 0 || (e == 0 && edge_includes_centres(a, b));
}

/* Where the box [lo, hi] holds a single pixel centre, as it does for many of a dense mesh's smallest
 * triangles, tests that centre with the rasterizer's own test (exact edge functions and the top-left
 * rule) and empties the box when the triangle misses it: a triangle that falls between the centres
 * is then culled instead of being set up, binned and rasterized for nothing. The picture cannot
 * change: the rasterizer never writes a pixel outside its triangle's coverage. */
CLR_INLINE void cull_missed_centre(int2 a, int2 b, int2 c, long signed_double_area, int2* lo, int2* hi) {
  if (any(*lo != *hi)) return;
  if (signed_double_area < 0) {
    const int2 swap = b;
    b = c;
    c = swap;
  }
  const long px = (long)lo->x << CLR_SUBPIXEL_BITS;
  const long py = (long)lo->y << CLR_SUBPIXEL_BITS;
  const bool covered = edge_covers_centre(b, c, px, py) && edge_covers_centre(c, a, px, py) &&
                       edge_covers_centre(a, b, px, py);
  if (!covered) *hi = *lo - 1;
}

/* What culling measured of a snapped triangle; set-up reuses it. */
typedef struct {
  long double_area;     /* signed, see double_area */
  int2 pixel_min;       /* writable pixels of the bounding box, see pixel_bounds */
  int2 pixel_max;
} TriangleExtent;

/* Face culling and emptiness: a triangle survives when it has non-zero snapped area, is not culled
 * by its facing, and its bounding box contains a writable pixel centre that, where it is the only
 * one, the triangle covers (cull_missed_centre). */
CLR_INLINE bool triangle_survives(const WindowVertex* a, const WindowVertex* b, const WindowVertex* c,
                                  __constant const DrawUniforms* u, TriangleExtent* extent) {
  extent->double_area = double_area(a->fixed, b->fixed, c->fixed);
  if (extent->double_area == 0) return false;
  const bool front = (extent->double_area > 0) == (u->front_face_ccw != 0);
  if ((u->cull == CLR_CULL_BACK && !front) || (u->cull == CLR_CULL_FRONT && front)) return false;
  pixel_bounds(a->fixed, b->fixed, c->fixed, u, &extent->pixel_min, &extent->pixel_max);
  cull_missed_centre(a->fixed, b->fixed, c->fixed, extent->double_area, &extent->pixel_min, &extent->pixel_max);
  /* all() of a vector comparison, not two scalar ones: clang combines those into a vector
   * comparison whose true lane Oclgrind 21.10 then keeps as 255, which counted as 255 clipped
   * triangles. */
  return all(extent->pixel_min <= extent->pixel_max);
}
