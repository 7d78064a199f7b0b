/* spans.cl: the strategy of programs without derivatives (group.cl). Each work-item walks its own
 * pixels, visiting only the pixels each triangle's mask has, a span of CLR_SPAN_PIXELS pixels of a
 * row at a time (span.cl), or, where a triangle covers few pixels of many rows of the tile, of its
 * pixels packed eight to a span whatever their rows (packed spans, process_packed_span): the span's
 * interpolation, tests, blending and merge into the tile are vector operations, and only a
 * per-fragment program runs per fragment. */

#include "raster/coverage.cl"
#include "raster/group.cl"
#include "raster/shade.cl"
#include "raster/span.cl"
#include "shared/types.h"

#if CLR_SHADE_SPANS
/* Bit p of word w set where the tile's pixel 64 w + p is this work-item's: the pixels of span s (a
 * run of CLR_SPAN_PIXELS from pixel s * CLR_SPAN_PIXELS) belong to work-item s % CLR_RASTER_GROUP
 * (a power of two). Below 64 pixels between a work-item's spans, that is a run of CLR_SPAN_BITS every
 * CLR_OWNER_PERIOD bits, from the work-item's first span: ~0 / (2^period - 1) has a one every period
 * bits (all ones for a period of one). */
#define CLR_OWNER_PERIOD (CLR_RASTER_GROUP * CLR_SPAN_PIXELS)
static inline ulong own_pixels(uint word, uint item) {
  const uint first = item * CLR_SPAN_PIXELS;
#if CLR_OWNER_PERIOD >= 64
  return word == first / 64 ? CLR_SPAN_BITS << (first % 64) : 0ul;
#else
  return (~0ul / ((1ul << CLR_OWNER_PERIOD) - 1)) * CLR_SPAN_BITS << first;
#endif
}

#if CLR_SPAN_PIXELS > 1
/* The fragments of triangle t at the tile's pixels `lanes`, its first `filled` lanes (a packed span:
 * the triangle's pixels of the tile in mask order, eight at a time, instead of a row span for each
 * row, which for a long thin triangle has a lane or two covered). The lanes past `filled` are at the
 * spare pixel. */
CLR_INLINE void process_packed_span(const __local SetupTriangle* t, int2 origin, clr_span_uint lanes, int filled,
                                    clr_fragment* f, __local uint* tile_color, __local float* tile_depth,
                                    __local uchar* tile_stencil, __constant const DrawUniforms* u) {
  clr_span_place place;
  place.x = 0;
  place.y = 0;
  place.first = 0;
  place.xs = origin.x + CLR_SPAN_AS(int, lanes % CLR_TILE_SIZE);
  place.ys = origin.y + CLR_SPAN_AS(int, lanes / CLR_TILE_SIZE);
  place.pixels = lanes;
  place.packed = true;
  process_span(t, &place, CLR_SPAN_LANES < filled, f, tile_color, tile_depth, tile_stencil, u);
}
#endif

CLR_INLINE void shade_batch(const __local SetupTriangle* batch, __local ulong (*masks)[CLR_TILE_MASK_WORDS],
                            const __local TileCoverage* coverage, uint n, int2 origin, uint item, clr_fragment* f,
                            __local uint* tile_color, __local float* tile_depth, __local uchar* tile_stencil,
                            __constant const DrawUniforms* u) {
  /* Each work-item shades the fragments of its own pixels, triangle by triangle in primitive
   * order, visiting only the spans each triangle covers. */
  for (uint i = 0; i < n; ++i) {
    const int first_word = coverage[i].first_word;
    const int end_word = coverage[i].end_word;
#if CLR_SPAN_PIXELS > 1
    if (coverage[i].packed) {
      clr_span_uint lanes = (clr_span_uint)(CLR_TILE_SPARE_PIXEL);
      int filled = 0;
      for (int w = first_word; w < end_word; ++w) {
        for (ulong bits = masks[i][w] & own_pixels(w, item); bits != 0; bits &= bits - 1) {
          const uint pixel = (uint)w * 64 + ((63 - clz(bits & (0 - bits))) & 63);
          lanes = select(lanes, (clr_span_uint)(pixel), CLR_SPAN_LANES == filled);
          if (++filled == CLR_SPAN_PIXELS) {
            process_packed_span(&batch[i], origin, lanes, filled, f, tile_color, tile_depth, tile_stencil, u);
            lanes = (clr_span_uint)(CLR_TILE_SPARE_PIXEL);
            filled = 0;
          }
        }
      }
      if (filled > 0) process_packed_span(&batch[i], origin, lanes, filled, f, tile_color, tile_depth, tile_stencil, u);
      continue;
    }
#endif
    for (int w = first_word; w < end_word; ++w) {
      ulong bits = masks[i][w] & own_pixels(w, item);
      while (bits != 0) {
        /* The span of the lowest pixel left: span-aligned, within one row of the tile. */
        const uint first = ((63 - clz(bits & (0 - bits))) & 63) / CLR_SPAN_PIXELS * CLR_SPAN_PIXELS;
        const uint covered = (uint)((bits >> first) & CLR_SPAN_BITS);
        bits &= ~(CLR_SPAN_BITS << first);
        const uint first_pixel = (uint)w * 64 + first;
        const clr_span_place place = {origin.x + (int)(first_pixel % CLR_TILE_SIZE),
                                      origin.y + (int)(first_pixel / CLR_TILE_SIZE), first_pixel, 0, 0, 0, false};
        process_span(&batch[i], &place, clr_span_lanes_from_bits(covered), f, tile_color, tile_depth, tile_stencil, u);
      }
    }
  }
}
#endif
