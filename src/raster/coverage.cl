/* coverage.cl: which pixels of a tile a triangle covers, as a bit mask of the tile (coverage_mask),
 * and the walk of such a mask in quads (take_lowest_quad). */

#include "raster/group.cl"
#include "raster/span.cl"
#include "shared/clr_limits.h"
#include "shared/types.h"

#define CLR_TILE_MASK_WORDS (CLR_TILE_PIXELS / 64) /* 64-bit words of one triangle's coverage of a tile */

/* Lanes of `inside` (each 0 or -1) as the bits of a byte, lane 0 in bit 0. */
static inline uint lanes_to_bits(long8 inside) {
  const ulong8 bits = as_ulong8(inside) & (ulong8)(1, 2, 4, 8, 16, 32, 64, 128);
  const ulong4 halves = bits.lo | bits.hi;
  const ulong2 quarters = halves.lo | halves.hi;
  return (uint)(quarters.lo | quarters.hi);
}

/* What coverage_mask found of a triangle in a tile besides its mask: the words of the mask that can
 * have bits, [first_word, end_word), which are the only ones the shading loops visit (a small
 * triangle's are one or two of a 32x32 tile's 16), and whether its pixels are shaded in packed spans
 * (process_packed_span), which they are where that takes fewer spans than rows. */
typedef struct {
  uchar first_word;
  uchar end_word;
  bool packed;
} TileCoverage;

/* Which pixels of the tile whose first pixel is `origin` the triangle covers: bit p of the mask (word
 * p / 64) is the tile's pixel p, row-major. A pixel centre is covered when every edge function is
 * positive there, or zero on an edge that includes its centres (SetupTriangle's flags): E > 0 is
 * E - 1 >= 0 in integers, so subtracting 1 from the edges without the flag makes the test a sign
 * test, and one sign test of the three values OR-ed together tests them all. Eight pixels of a row
 * at a time, in 64-bit vectors: exact, and what vector units (and PoCL's compiler) do best. *summary:
 * which words of the mask can have bits, and how to shade them. */
static inline void coverage_mask(const __local SetupTriangle* t, int2 origin, __local ulong* mask,
                                 __local TileCoverage* summary) {
  for (int w = 0; w < CLR_TILE_MASK_WORDS; ++w) mask[w] = 0;
  summary->first_word = summary->end_word = 0;
  summary->packed = false;
  const int2 lo = max((int2)((int)(t->pixel_min & 0xffffu), (int)(t->pixel_min >> 16)), origin);
  const int2 hi = min((int2)((int)(t->pixel_max & 0xffffu), (int)(t->pixel_max >> 16)), origin + (CLR_TILE_SIZE - 1));
  if (lo.x > hi.x || lo.y > hi.y) return;
  summary->first_word = (uchar)((lo.y - origin.y) * CLR_TILE_SIZE / 64);
  summary->end_word = (uchar)(((hi.y - origin.y) * CLR_TILE_SIZE + CLR_TILE_SIZE - 1) / 64 + 1);
  long c[3];
#pragma unroll
  for (int k = 0; k < 3; ++k) c[k] = t->edge_c[k] - ((t->flags >> k) & 1u ? 0 : 1);
  /* An edge function is linear, so over the rectangle [lo, hi] its extremes are at the corners:
   * where every corner centre is outside one edge, nothing is covered, and where the rectangle is
   * the whole tile and every corner is inside every edge, all of it is. The triangles of large
   * primitives are mostly one or the other in each tile they are binned to, and skip the rows; small
   * ones, with few rows, go straight to them. */
  if (hi.y - lo.y >= CLR_TILE_SIZE / 2) {
    const long4 X = convert_long4((int4)(lo.x, hi.x, lo.x, hi.x)) << CLR_SUBPIXEL_BITS;
    const long4 Y = convert_long4((int4)(lo.y, lo.y, hi.y, hi.y)) << CLR_SUBPIXEL_BITS;
    const long4 e0 = (long)t->edge_a[0] * X + (long)t->edge_b[0] * Y + c[0];
    const long4 e1 = (long)t->edge_a[1] * X + (long)t->edge_b[1] * Y + c[1];
    const long4 e2 = (long)t->edge_a[2] * X + (long)t->edge_b[2] * Y + c[2];
    if (all(e0 < (long4)(0)) || all(e1 < (long4)(0)) || all(e2 < (long4)(0))) return;
    if (all(lo == origin) && all(hi == origin + (CLR_TILE_SIZE - 1)) && all((e0 | e1 | e2) >= (long4)(0))) {
      for (int w = 0; w < CLR_TILE_MASK_WORDS; ++w) mask[w] = ~0ul;
      return;
    }
  }
  uint pixels = 0, row_spans = 0;
  for (int chunk = (lo.x - origin.x) / 8; chunk <= (hi.x - origin.x) / 8; ++chunk) {
    const int8 xs = (int8)(origin.x + chunk * 8) + (int8)(0, 1, 2, 3, 4, 5, 6, 7);
    const long8 X = convert_long8(xs) << CLR_SUBPIXEL_BITS;
    const long8 in_box = convert_long8((xs >= (int8)(lo.x)) & (xs <= (int8)(hi.x)));
    const long8 ax0 = (long8)((long)t->edge_a[0]) * X;
    const long8 ax1 = (long8)((long)t->edge_a[1]) * X;
    const long8 ax2 = (long8)((long)t->edge_a[2]) * X;
    for (int y = lo.y; y <= hi.y; ++y) {
      const long Y = (long)y << CLR_SUBPIXEL_BITS;
      const long8 e0 = ax0 + ((long)t->edge_b[0] * Y + c[0]);
      const long8 e1 = ax1 + ((long)t->edge_b[1] * Y + c[1]);
      const long8 e2 = ax2 + ((long)t->edge_b[2] * Y + c[2]);
      const uint bits = lanes_to_bits(((e0 | e1 | e2) >= (long8)(0)) & in_box);
      const int first = (y - origin.y) * CLR_TILE_SIZE + chunk * 8;
      mask[first / 64] |= (ulong)bits << (first % 64);
      pixels += popcount(bits);
      row_spans += bits != 0;
    }
  }
  summary->packed = CLR_SPAN_PIXELS > 1 && (pixels + CLR_SPAN_PIXELS - 1) / CLR_SPAN_PIXELS < row_spans;
}

/* The first pixel, within its mask word, of the quad of the lowest pixel left in `*left` (a word of a
 * coverage mask, which holds whole rows, an even number of them, so the quad is in it); the quad's
 * pixels are taken out of `*left`. The quad walks of quad shading take a triangle's quads in this
 * order. */
static inline uint take_lowest_quad(ulong* left) {
  const uint bit = (63 - clz(*left & (0 - *left))) & 63;
  const uint corner = (bit / CLR_TILE_SIZE & ~1u) * CLR_TILE_SIZE + (bit % CLR_TILE_SIZE & ~1u);
  *left &= ~((3ul | 3ul << CLR_TILE_SIZE) << corner);
  return corner;
}
