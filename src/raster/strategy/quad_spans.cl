/* quad_spans.cl: the strategy of span programs that take derivatives in spans of eight (group.cl):
 * a triangle's quads two to a span. */

#include "raster/coverage.cl"
#include "raster/group.cl"
#include "raster/shade.cl"
#include "raster/span.cl"
#include "shared/types.h"

#if CLR_SHADE_QUAD_SPANS
/* The fragments of triangle t in the quads whose first pixels are the tile's pixels `first` and
 * `second`, where `covered` (lane bits; span.cl: lanes 0, 1, 4, 5 the first quad's, 2, 3,
 * 6, 7 the second's), as a packed span of per-lane places. */
CLR_INLINE void process_quad_span(const __local SetupTriangle* t, int2 origin, uint first, uint second, uint covered,
                                  clr_fragment* f, __local uint* tile_color, __local float* tile_depth,
                                  __local uchar* tile_stencil, __constant const DrawUniforms* u) {
  const clr_span_uint corners = select((clr_span_uint)(first), (clr_span_uint)(second), CLR_QUAD_SPAN_SECOND);
  clr_span_place place;
  place.x = 0;
  place.y = 0;
  place.first = 0;
  place.pixels = corners + CLR_SPAN_AS(uint, CLR_QUAD_SPAN_X + CLR_QUAD_SPAN_Y * CLR_TILE_SIZE);
  place.xs = origin.x + CLR_SPAN_AS(int, place.pixels % CLR_TILE_SIZE);
  place.ys = origin.y + CLR_SPAN_AS(int, place.pixels / CLR_TILE_SIZE);
  place.packed = true;
  process_span(t, &place, clr_span_lanes_from_bits(covered), f, tile_color, tile_depth, tile_stencil, u);
}

CLR_INLINE void shade_batch(const __local SetupTriangle* batch, __local ulong (*masks)[CLR_TILE_MASK_WORDS],
                            const __local TileCoverage* coverage, uint n, int2 origin, uint item, clr_fragment* f,
                            __local uint* tile_color, __local float* tile_depth, __local uchar* tile_stencil,
                            __constant const DrawUniforms* u) {
  /* The quads that have a pixel of the triangle, two to a span (span.cl), in mask order
   * wherever they are in the tile, as packed spans take pixels: a thin triangle crosses many
   * blocks of 4x2 pixels in one quad of the two. */
  for (uint i = 0; i < n; ++i) {
    uint first_quad = 0; /* the span's first quad's first pixel, while it waits for a second */
    uint covered = 0;    /* the span's covered lanes */
    bool waiting = false;
    for (int w = coverage[i].first_word; w < coverage[i].end_word; ++w) {
      for (ulong left = masks[i][w]; left != 0;) {
        const uint corner = take_lowest_quad(&left);
        /* The quad's pixels (x, y), (x + 1, y), (x, y + 1), (x + 1, y + 1) in bits 0-3. */
        const uint quad =
            (uint)(masks[i][w] >> corner) & 3u | ((uint)(masks[i][w] >> (corner + CLR_TILE_SIZE)) & 3u) << 2;
        const uint pixel = (uint)w * 64 + corner;
        if (!waiting) {
          first_quad = pixel;
          covered = (quad & 3u) | (quad & 0xcu) << 2; /* lanes 0, 1, 4, 5 */
          waiting = true;
          continue;
        }
        covered |= (quad & 3u) << 2 | (quad & 0xcu) << 4; /* lanes 2, 3, 6, 7 */
        process_quad_span(&batch[i], origin, first_quad, pixel, covered, f, tile_color, tile_depth, tile_stencil, u);
        waiting = false;
      }
    }
    /* A last quad alone: its lanes again in the second quad's, which cover nothing. */
    if (waiting) {
      process_quad_span(&batch[i], origin, first_quad, first_quad, covered, f, tile_color, tile_depth, tile_stencil,
                        u);
    }
  }
}
#endif
