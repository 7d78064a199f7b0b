/* clip.cl: clipping in homogeneous clip space (Sutherland-Hodgman, one plane at a time).
 *
 * Planes: near (z >= -w) and far (z <= w), as OpenGL clips without depth clamping, and four
 * guard-band planes far outside the viewport (guard_min * w <= x, y <= guard_max * w) that keep
 * window coordinates small enough for exact fixed-point edge functions. Clipping x and y at the
 * viewport instead would move triangle edges by the snapping of the new vertices; the guard band
 * leaves every visible edge where the vertices put it, as llvmpipe does. Together the guard planes
 * also imply w >= 0, so clipped polygons never cross w = 0. */

typedef struct {
  float4 position; /* clip space */
  float varyings[CLR_NUM_VARYINGS];
} ClipVertex;

/* Signed distance of a clip-space position to plane `plane`: >= 0 inside. */
static inline float clip_distance(float4 p, int plane, float2 guard_min, float2 guard_max) {
  switch (plane) {
    case 0: return p.z + p.w;                 /* near */
    case 1: return p.w - p.z;                 /* far */
    case 2: return p.x - guard_min.x * p.w;   /* left guard band */
    case 3: return guard_max.x * p.w - p.x;   /* right */
    case 4: return p.y - guard_min.y * p.w;   /* bottom */
    default: return guard_max.y * p.w - p.y;  /* top */
  }
}

/* Bit k set: the position is outside plane k. Unrolled, so that each plane's distance is its own
 * expression instead of a switch taken in a loop (this runs for every vertex). */
CLR_INLINE uint clip_outcode(float4 p, float2 guard_min, float2 guard_max) {
  uint code = 0;
#pragma unroll
  for (int plane = 0; plane < CLR_CLIP_PLANES; ++plane) {
    if (clip_distance(p, plane, guard_min, guard_max) < 0.0f) code |= 1u << plane;
  }
  return code;
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
int clip_polygon(ClipVertex* poly, int count, uint planes, float2 guard_min, float2 guard_max) {
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
