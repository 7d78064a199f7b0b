/* interpolation.cl: what a span's fragments take from their triangle: barycentric weights and depth
 * (interpolation_weights), then, perspective-correct, the varyings (interpolate_span). */

#include "raster/span.cl"
#include "shared/clr_limits.h"
#include "shared/types.h"

/* What a span's fragments interpolate from: the barycentrics of the unsnapped triangle in screen
 * space, and depth, which the tests need for every lane. The perspective division waits for the
 * tests (interpolate_span). */
typedef struct {
  clr_span_float l[3];
  clr_span_float z; /* window depth, clamped to the depth range */
} span_weights;

/* Edge k's weight at grid points (X, Y), in subpixels, as the unsnapped triangle's: E for the vertices
 * before snapping, since barycentrics of the snapped triangle are off by up to 1/512 pixel over the
 * distance to an edge, which perspective magnifies (1e-3 of the texture coordinates near a horizon),
 * and llvmpipe interpolates with the unsnapped ones. A macro, for one grid point (scalars: a row
 * span's, which the compiler keeps scalar) and for one per lane (span vectors: a packed span's), in
 * the same operations, so the same bits. */
#define CLR_WEIGHT_AT_GRID(t, k, X, Y, unsnapped_x, unsnapped_y, convert_to_float)                          \
  ((convert_to_float((long)(t)->edge_a[k] * (X) + (long)(t)->edge_b[k] * (Y) + (t)->edge_c[k]) +             \
    ((t)->edge_correction[k][0] * (unsnapped_x) + (t)->edge_correction[k][1] * (unsnapped_y) +               \
     (t)->edge_correction[k][2])) *                                                                          \
   (t)->inv_double_area)
#define CLR_FLOAT_OF_LONG(value) ((float)(value))
#define CLR_SPAN_FLOAT_OF_LONG(value) CLR_SPAN_CONVERT(float, value)

/* The weights of triangle t for the span at `place`, into *w.
 *
 * Edge k's function E is evaluated exactly (in 64 bits) at every CLR_CPU_SPAN_PIXELS-th pixel centre
 * of a row only, a scalar, and the weights of the pixels after it step from there in floats, one
 * vector multiply-add a span, instead of a 64-bit edge function and its conversion per lane
 * (raster stage of model-50k 22.2 -> 20.4 ms, terrain-1m 46.6 -> 41.4). The grid is fixed, and the
 * step an explicit fma, so that a pixel gets the same weights from every span shape that shades it
 * (spans of one pixel on GPUs and in quad shading, of eight on CPUs, row or packed), and so the same
 * picture. A packed span's lanes each step from their own grid point. */
CLR_INLINE void interpolation_weights(const __local SetupTriangle* t, const clr_span_place* place, span_weights* w) {
  clr_span_float steps;
  clr_span_float at_grid[3];
  if (place->packed) {
    const clr_span_int grid_x = place->xs & ~(CLR_CPU_SPAN_PIXELS - 1);
    const clr_span_long X = CLR_SPAN_CONVERT(long, grid_x) << CLR_SUBPIXEL_BITS;
    const clr_span_long Y = CLR_SPAN_CONVERT(long, place->ys) << CLR_SUBPIXEL_BITS;
    const clr_span_float unsnapped_x = CLR_SPAN_CONVERT(float, grid_x << CLR_SUBPIXEL_BITS);
    const clr_span_float unsnapped_y = CLR_SPAN_CONVERT(float, place->ys << CLR_SUBPIXEL_BITS);
    steps = CLR_SPAN_CONVERT(float, place->xs - grid_x);
#pragma unroll
    for (int k = 0; k < 3; ++k) at_grid[k] = CLR_WEIGHT_AT_GRID(t, k, X, Y, unsnapped_x, unsnapped_y, CLR_SPAN_FLOAT_OF_LONG);
  } else {
    const int grid_x = place->x & ~(CLR_CPU_SPAN_PIXELS - 1);
    const long X = (long)grid_x << CLR_SUBPIXEL_BITS;
    const long Y = (long)place->y << CLR_SUBPIXEL_BITS;
    const float unsnapped_x = (float)(grid_x << CLR_SUBPIXEL_BITS);
    const float unsnapped_y = (float)(place->y << CLR_SUBPIXEL_BITS);
    steps = CLR_SPAN_CONVERT(float, (place->x - grid_x) + CLR_SPAN_LANES);
#pragma unroll
    for (int k = 0; k < 3; ++k) at_grid[k] = CLR_WEIGHT_AT_GRID(t, k, X, Y, unsnapped_x, unsnapped_y, CLR_FLOAT_OF_LONG);
  }
#pragma unroll
  for (int k = 0; k < 3; ++k) {
    const float per_pixel = ((float)t->edge_a[k] + t->edge_correction[k][0]) * (float)CLR_SUBPIXEL_ONE;
    const float step = per_pixel * t->inv_double_area;
    w->l[k] = fma(steps, (clr_span_float)(step), at_grid[k]);
  }
  /* Depth is linear in window space; OpenGL clamps it to the depth range. */
  w->z = clamp(w->l[0] * t->z[0] + w->l[1] * t->z[1] + w->l[2] * t->z[2], 0.0f, 1.0f);
}

/* The perspective-correct part of a span's fragments, for every lane at once: one vector division,
 * and the varyings interpolated in vectors, faster even when one lane of the span passes than the
 * same lane by lane (measured on terrain-1m, model-50k and fill-16). Flat varyings are not
 * interpolated: the generated clr_lane_varyings takes them from the triangle. */
typedef struct {
  clr_span_float pw[3]; /* screen-space weights divided by w */
  clr_span_float inv_w; /* their sum, 1 / w at the fragment */
  clr_span_float norm;  /* its reciprocal */
  clr_span_float varyings[CLR_NUM_VARYINGS];
} span_interpolants;

CLR_INLINE void interpolate_span(const __local SetupTriangle* t, span_weights w, span_interpolants* s) {
  /* Perspective-correct: interpolate value / w and 1 / w linearly, then divide. */
#pragma unroll
  for (int k = 0; k < 3; ++k) s->pw[k] = w.l[k] * t->inv_w[k];
  s->inv_w = s->pw[0] + s->pw[1] + s->pw[2];
  s->norm = 1.0f / s->inv_w;
#pragma unroll
  for (int j = 0; j < CLR_NUM_VARYINGS; ++j) {
    const int mode = clr_varying_interpolation[j];
    const clr_span_float* weights = mode == CLR_INTERPOLATE_NOPERSPECTIVE ? w.l : s->pw;
    const clr_span_float sum = weights[0] * t->varyings[0][j] + weights[1] * t->varyings[1][j] + weights[2] * t->varyings[2][j];
    s->varyings[j] = mode == CLR_INTERPOLATE_SMOOTH ? sum * s->norm : sum;
  }
}
