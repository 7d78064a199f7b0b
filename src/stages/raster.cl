/* raster.cl: rasterization, the fragment program and the per-fragment operations.
 *
 * One work-group per screen tile of CLR_TILE_SIZE^2 pixels. The tile's colour attachments, depth and
 * stencil live in local memory from the first triangle to the last, and the group walks its tile's
 * triangles in primitive order, staging CLR_RASTER_TRIANGLE_BATCH of them at a time in local memory
 * with each one's coverage of the tile as a bit mask (coverage_mask). Each pixel belongs to one
 * work-item, the only one to touch its attachments, so there are no atomics on them and every run
 * gives the same result. How many work-items a group has is the device's choice (CLR_RASTER_GROUP):
 * one per pixel on GPUs, few on CPUs, each then walking its pixels, visiting only the pixels each
 * triangle's mask has, a span of CLR_SPAN_PIXELS pixels of a row at a time (fragment_ops.cl), or,
 * where a triangle covers few pixels of many rows of the tile, of its pixels packed eight to a span
 * whatever their rows (packed spans, process_packed_span): the span's interpolation, tests, blending
 * and merge into the tile are vector operations, and only a per-fragment program runs per fragment.
 *
 * Per fragment, in OpenGL's order: the fragment program, the stencil test, the depth test (with
 * their stencil operations and depth write), then blending, the write mask and conversion to the
 * attachment's format, for each output. A program that neither discards nor writes depth, and is
 * not a per-fragment program taking derivatives, has its tests run first (early fragment tests), so
 * hidden fragments skip it (program/generator.hpp, early_fragment_tests).
 *
 * A pass that writes pending clears (`clears`, resources/pending_clear.hpp) starts each tile from the
 * clear values instead of loading it, runs the tiles without triangles too (they store the clear
 * values and nothing else), and writes its tiles back whole, also outside the clip rectangle.
 *
 * Tile storage: a colour attachment's pixel is four 32-bit words, kept channel by channel so that
 * a span of one channel is one vector (CLR_TILE_WORD), holding the decoded value exactly as the
 * attachment stores it (float bits for normalized and float formats, already quantized to the
 * format where the draw reads the tile back; int or uint for integer ones), except that an RGBA8
 * attachment the draw blends is held as its bytes (tile_holds_bytes). Programs that take
 * derivatives are shaded in 2x2 quads, the quad's uncovered pixels running the program as helpers
 * whose results are thrown away. A span program in spans of eight takes a triangle's quads two to a
 * span (quad spans, process_quad_span), its derivatives differences between lanes. Otherwise a
 * work-item per pixel of a quad (prelude.cl exchanges the values at barriers): on GPUs a work-item
 * per pixel of the tile, every one running the program for every triangle that covers any pixel of
 * the tile; on CPUs four work-items, which walk the quads each triangle covers together: PoCL runs a
 * group's work-items one after another between barriers, so the tile's 256 would each run the
 * program for every triangle of the tile (a textured 1080p frame of the demo scene took 2.7 s at
 * 16x16 tiles against llvmpipe's 59 ms). */

#define CLR_TILE_PIXELS (CLR_TILE_SIZE * CLR_TILE_SIZE)
#define CLR_TILE_TARGETS (CLR_NUM_OUTPUTS > 0 ? CLR_NUM_OUTPUTS : 1)
#define CLR_TILE_MASK_WORDS (CLR_TILE_PIXELS / 64) /* 64-bit words of one triangle's coverage of a tile */
/* Quad shading in spans of one pixel exchanges values between the pixels of a quad at barriers: one
 * work-item per pixel, of the tile where the context's shape has a work-item per pixel (GPUs), else
 * of one quad at a time. Other programs, quad spans included (fragment_ops.cl), take the context's
 * shape (clr_limits.h). */
#define CLR_QUAD_EXCHANGE (CLR_QUAD_SHADING && !CLR_QUAD_SPANS)
#if CLR_QUAD_EXCHANGE && CLR_RASTER_GROUP_SIZE >= CLR_TILE_PIXELS
#define CLR_RASTER_GROUP CLR_TILE_PIXELS
#elif CLR_QUAD_EXCHANGE
#define CLR_RASTER_GROUP CLR_QUAD_PIXELS
#else
#define CLR_RASTER_GROUP CLR_RASTER_GROUP_SIZE
#endif

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

/* Bit p of word w set where the tile's pixel 64 w + p is this work-item's: the pixels of span s (a
 * run of CLR_SPAN_PIXELS from pixel s * CLR_SPAN_PIXELS) belong to work-item s % CLR_RASTER_GROUP
 * (a power of two). Below 64 pixels between a work-item's spans, that is a run of CLR_SPAN_BITS every
 * CLR_OWNER_PERIOD bits, from the work-item's first span: ~0 / (2^period - 1) has a one every period
 * bits (all ones for a period of one). */
#define CLR_SPAN_BITS ((1ul << CLR_SPAN_PIXELS) - 1)
#define CLR_OWNER_PERIOD (CLR_RASTER_GROUP * CLR_SPAN_PIXELS)
static inline ulong own_pixels(uint word, uint item) {
  const uint first = item * CLR_SPAN_PIXELS;
#if CLR_OWNER_PERIOD >= 64
  return word == first / 64 ? CLR_SPAN_BITS << (first % 64) : 0ul;
#else
  return (~0ul / ((1ul << CLR_OWNER_PERIOD) - 1)) * CLR_SPAN_BITS << first;
#endif
}

static inline bool is_normalized_format(int format) { return format <= CLR_FORMAT_SRGB8_A8; }
static inline bool is_integer_format(int format) { return format >= CLR_FORMAT_R32I && format <= CLR_FORMAT_RGBA32UI; }
static inline bool is_signed_integer_format(int format) {
  return format == CLR_FORMAT_R32I || format == CLR_FORMAT_RGBA32I;
}

/* An attachment's pixel in the tile's representation (see above). */
static inline uint4 load_attachment_pixel(int format, __global const uchar* data, uint pixel) {
  if (is_signed_integer_format(format)) return as_uint4(clr_load_texel_int(format, data, pixel));
  if (is_integer_format(format)) return clr_load_texel_uint(format, data, pixel);
  return as_uint4(clr_load_texel_float(format, data, pixel));
}
static inline void store_attachment_pixel(int format, __global uchar* data, uint pixel, uint4 value) {
  if (is_signed_integer_format(format)) clr_store_texel_int(format, data, pixel, as_int4(value));
  else if (is_integer_format(format)) clr_store_texel_uint(format, data, pixel, value);
  else clr_store_texel_float(format, data, pixel, as_float4(value));
}

/* Where the layer of triangle t's view starts in the attachments: fragment coordinates are within it. */
static inline float2 layer_origin(const __local SetupTriangle* t, __constant const DrawUniforms* u) {
  const int view = (int)(t->flags >> CLR_TRIANGLE_VIEW_SHIFT);
  return convert_float2((int2)(view % u->layer_columns * u->layer_size[0], view / u->layer_columns * u->layer_size[1]));
}

/* Whether the pixel (x, y) is inside the rectangle r (x0, y0, x1, y1, exclusive), and whether the
 * whole span of pixels from (x, y) is. */
static inline bool inside_rect(int x, int y, int4 r) { return x >= r.x && x < r.z && y >= r.y && y < r.w; }
static inline bool whole_span_inside(int x, int y, int4 r) {
  return inside_rect(x, y, r) && inside_rect(x + CLR_SPAN_PIXELS - 1, y, r);
}
/* Whether the pixel (x, y) is inside the draw's clip rectangle (scissor and framebuffer), and whether
 * the whole span of pixels from (x, y) is. */
static inline bool writable(int x, int y, __constant const DrawUniforms* u) {
  return inside_rect(x, y, vload4(0, u->clip_rect));
}
static inline bool whole_span_writable(int x, int y, __constant const DrawUniforms* u) {
  return whole_span_inside(x, y, vload4(0, u->clip_rect));
}

/* The pixels of an attachment that the tile loads and stores: those of the clip rectangle, or every
 * pixel of the framebuffer for an attachment whose pending clear the pass writes (`clearing`). */
static inline int4 moved_rect(bool clearing, __constant const DrawUniforms* u) {
  return clearing ? (int4)(0, 0, u->framebuffer_size[0], u->framebuffer_size[1]) : vload4(0, u->clip_rect);
}

/* Whether the tile holds colour attachment `target` as its bytes (0 to 255, in floats) rather than
 * decoded: an RGBA8 attachment the draw blends with OpenGL's equations, which llvmpipe computes on
 * bytes (fragment_ops.cl), so that the blend of each span needs no conversion of what it reads and no
 * division of what it writes. Framebuffer fetch and the program's blend function read decoded
 * colours, so their draws keep them. */
CLR_INLINE bool holds_bytes(int format, BlendUniforms b) {
  return !CLR_READS_FRAMEBUFFER && format == CLR_FORMAT_RGBA8 && b.enabled && b.rgb_equation != CLR_BLEND_PROGRAM &&
         b.alpha_equation != CLR_BLEND_PROGRAM;
}
static inline bool tile_holds_bytes(__constant const DrawUniforms* u, uint target) {
  return holds_bytes(u->target_format[target], u->blend[target]);
}

/* Colour attachment `target`'s pixels once its pending clear is written, as load_attachment_pixel
 * gives them: the clear value as storing it into the attachment and loading it back gives it. */
static inline uint4 cleared_pixel(__constant const DrawUniforms* u, uint target) {
  const int format = u->target_format[target];
  const uint4 value = vload4(0, u->clear_color[target]);
  if (is_integer_format(format)) return clr_quantize_uint(format, value);
  return as_uint4(clr_quantize_float(format, as_float4(value)));
}

/* A span of the tile written back to an attachment: streaming (non-temporal) where the draw's
 * uniforms say so (CLR_STREAMING_STORE_PIXELS), plain otherwise. */
#define CLR_WRITE_BACK_SPAN(value, pointer, streaming) \
  do {                                                 \
    if (streaming) CLR_SPAN_STREAM(value, pointer);    \
    else CLR_SPAN_STORE(value, pointer);               \
  } while (0)

/* RGBA8, the usual attachment, moves between the framebuffer and the tile a span at a time: one
 * vector of the span's 32-bit pixels, whose byte c is channel c on little-endian devices (all that
 * OpenCL runs on in practice; others take the pixel-by-pixel way). The conversions are
 * clr_decode_texel's and clr_float_to_unorm8's, so the results are the same bits. */
#ifdef __ENDIAN_LITTLE__
#define CLR_PACKED_RGBA8 1
#else
#define CLR_PACKED_RGBA8 0
#endif
CLR_INLINE void load_rgba8_span(__global const uint* pixels, bool bytes, __local uint* tile_channels) {
  const clr_span_uint packed = CLR_SPAN_LOAD(pixels);
#pragma unroll
  for (int c = 0; c < 4; ++c) {
    const clr_span_float byte = CLR_SPAN_CONVERT(float, (packed >> (8u * c)) & 0xffu);
    CLR_SPAN_STORE(CLR_SPAN_AS(uint, bytes ? byte : clr_unorm8_to_float(byte)), &tile_channels[CLR_TILE_WORD(0, c, 0)]);
  }
}
CLR_INLINE clr_span_uint pack_rgba8_span(__local const uint* tile_channels, bool bytes) {
  clr_span_uint packed = 0u;
#pragma unroll
  for (int c = 0; c < 4; ++c) {
    const clr_span_float value = CLR_SPAN_AS(float, CLR_SPAN_LOAD(&tile_channels[CLR_TILE_WORD(0, c, 0)]));
    const clr_span_float byte = bytes ? value : round_small(fmin(fmax(value, 0.0f), 1.0f) * 255.0f);
    packed |= CLR_SPAN_CONVERT(uint, byte) << (8u * c);
  }
  return packed;
}

/* Whether storing a span of colour needs what the tile holds there: a row span stores every lane,
 * what it held where not written; a packed span stores its written lanes only (CLR_TILE_UPDATE), and
 * needs it only for the channels the write mask keeps. */
static inline bool store_reads_tile(const clr_span_place* place, uint write_mask) {
  return !place->packed || (write_mask & 0xfu) != 0xfu;
}
/* A colour attachment's span in the tile, and the span written back where `written` is true. */
CLR_INLINE void load_tile_span(__local const uint* tile, uint target, const clr_span_place* place, clr_span_bits* bits) {
#pragma unroll
  for (int c = 0; c < 4; ++c) bits->c[c] = CLR_TILE_LOAD(&tile[CLR_TILE_WORD(target, c, 0)], *place);
}
CLR_INLINE void store_tile_span(__local uint* tile, uint target, const clr_span_place* place, clr_span_bits stored,
                                clr_span_bits value, clr_span_int written) {
#pragma unroll
  for (int c = 0; c < 4; ++c) {
    CLR_TILE_UPDATE(uint, stored.c[c], value.c[c], written, &tile[CLR_TILE_WORD(target, c, 0)], *place);
  }
}

/* Stencil test, then depth test, with their stencil operations and the depth write, for the covered
 * fragments of a span at `depth` and `stencil` in the tile; true where a fragment passes both. f:
 * the fragment, for the program's depth test (spans of one pixel, fragment_ops.cl). */
CLR_INLINE clr_span_int fragment_tests(clr_fragment* f, bool front_facing, clr_span_int covered,
                                       clr_span_float frag_depth, __constant const DrawUniforms* u, __local float* depth,
                                       __local uchar* stencil, const clr_span_place* place) {
  __constant const StencilUniforms* s = &u->stencil[front_facing ? 0 : 1];
  const clr_span_uint stored_stencil = CLR_SPAN_CONVERT(uint, CLR_TILE_LOAD(stencil, *place));
  const clr_span_int stencil_passes = u->stencil_test ? clr_stencil_test(*s, stored_stencil) : CLR_SPAN_TRUE;
  clr_span_int depth_passes = CLR_SPAN_TRUE;
  const clr_span_float stored_depth = CLR_TILE_LOAD(depth, *place);
  if (u->depth_test) {
#if CLR_PROGRAM_DEPTH_TEST
    if (u->depth_func == CLR_COMPARE_PROGRAM) {
      depth_passes = !stencil_passes || clr_program_depth_test(f, frag_depth, stored_depth);
    } else
#endif
      depth_passes = clr_compare(u->depth_func, frag_depth, stored_depth);
  }
  if (u->stencil_test) {
    const clr_span_uint updated = clr_stencil_after_tests(*s, stencil_passes, depth_passes, stored_stencil);
    CLR_TILE_UPDATE(uchar, stored_stencil, updated, covered, stencil, *place);
  }
  const clr_span_int passed = covered & stencil_passes & depth_passes;
  if (u->depth_test && u->depth_write) CLR_TILE_UPDATE(float, stored_depth, frag_depth, passed, depth, *place);
  return passed;
}

/* Output `target` of a span of fragments into a normalized or float attachment of format `format`
 * with blend state b, where `written`: blending (OpenGL's equations, or the program's blend function
 * for channels whose equation is CLR_BLEND_PROGRAM), the write mask, and quantization to the
 * attachment's format. */
CLR_INLINE void merge_float_output(clr_fragment* f, uint target, int format, BlendUniforms b, clr_span_color source,
                                   clr_span_int written, __local uint* tile, const clr_span_place* place,
                                   __constant const DrawUniforms* u) {
  clr_span_bits stored = {0}; /* what blending reads too */
  if (store_reads_tile(place, b.write_mask) || CLR_READS_FRAMEBUFFER || b.enabled) load_tile_span(tile, target, place, &stored);
  const clr_span_color destination = CLR_SPAN_BITS_COLOR(stored);
  clr_span_color result = source;
  /* The tile keeps what a store then a load of the attachment would give only where the draw reads
   * it back (blending, framebuffer fetch): otherwise the conversion when the tile is written out at
   * the end gives the same bytes. 8-bit blending's results are on the attachment's grid already. */
  bool quantize = CLR_READS_FRAMEBUFFER;
  if (b.enabled) {
    const bool program_rgb = b.rgb_equation == CLR_BLEND_PROGRAM;
    const bool program_alpha = b.alpha_equation == CLR_BLEND_PROGRAM;
    /* Without a blend function, the program's blending gives the source colour. */
    clr_span_color programmed = source;
#if CLR_PROGRAM_BLEND /* spans of one pixel (fragment_ops.cl) */
    if (program_rgb || program_alpha) {
      programmed = CLR_SPAN_COLOR_SPLAT(
          clr_program_blend(f, target, clr_span_color_lane(source, 0), clr_span_color_lane(destination, 0)));
    }
#endif
    if (program_rgb) b.rgb_equation = CLR_BLEND_ADD;
    if (program_alpha) b.alpha_equation = CLR_BLEND_ADD;
    const clr_span_color constant_color = CLR_SPAN_COLOR_SPLAT(vload4(0, u->blend_color));
    /* 8-bit linear attachments blend in 8-bit fixed point, as llvmpipe does (fragment_ops.cl). */
    const int channels = clr_texel_layout_of(format).channels;
    clr_span_color fixed;
    if (format <= CLR_FORMAT_RGBA8) {
      clr_blend_unorm8(b, source, destination, constant_color, channels, holds_bytes(format, b), &fixed);
    }
    else clr_blend(b, source, destination, constant_color, is_normalized_format(format), channels, &fixed);
#pragma unroll
    for (int c = 0; c < 4; ++c) result.c[c] = (c < 3 ? program_rgb : program_alpha) ? programmed.c[c] : fixed.c[c];
    quantize = quantize || program_rgb || program_alpha || format > CLR_FORMAT_RGBA8;
  }
  clr_span_bits masked = CLR_SPAN_COLOR_BITS(result);
  clr_apply_write_mask(b.write_mask, &masked, stored);
  result = CLR_SPAN_BITS_COLOR(masked);
  if (quantize) {
    for (int lane = 0; lane < CLR_SPAN_PIXELS; ++lane) {
      clr_span_set_color_lane(&result, lane, clr_quantize_float(format, clr_span_color_lane(result, lane)));
    }
  }
  store_tile_span(tile, target, place, stored, CLR_SPAN_COLOR_BITS(result), written);
}

/* merge_float_output with the attachment's format and blend state; a common blend (types.h) on
 * RGBA8 with the state as constants, so that the compiler leaves only its arithmetic. */
CLR_INLINE void clr_merge_float_output(clr_fragment* f, uint target, clr_span_color source, clr_span_int written,
                                       __local uint* tile, const clr_span_place* place, __constant const DrawUniforms* u) {
  const int format = u->target_format[target];
  if (format < 0) return;
  const BlendUniforms b = u->blend[target];
  switch (b.common) {
#define CLR_COMMON_BLEND_MERGE(index, equation, source_factor, destination_factor)                               \
  case index: {                                                                                                 \
    const BlendUniforms common = {1, equation, equation, source_factor, destination_factor, source_factor,        \
                                  destination_factor, b.write_mask, index};                                     \
    merge_float_output(f, target, CLR_FORMAT_RGBA8, common, source, written, tile, place, u);            \
    return;                                                                                                     \
  }
    CLR_COMMON_BLENDS(CLR_COMMON_BLEND_MERGE)
#undef CLR_COMMON_BLEND_MERGE
    default: merge_float_output(f, target, format, b, source, written, tile, place, u);
  }
}

/* Output `target` into an integer attachment: no blending (as in OpenGL), the write mask only. */
CLR_INLINE void clr_merge_integer_output(uint target, clr_span_bits value, clr_span_int written, __local uint* tile,
                                         const clr_span_place* place, __constant const DrawUniforms* u) {
  if (u->target_format[target] < 0) return;
  clr_span_bits stored = {0};
  if (store_reads_tile(place, u->blend[target].write_mask)) load_tile_span(tile, target, place, &stored);
  clr_apply_write_mask(u->blend[target].write_mask, &value, stored);
  store_tile_span(tile, target, place, stored, value, written);
}

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

/* The fragment of triangle t in lane `lane` of the span at `place`, from the span's interpolants.
 * helper: a helper invocation of quad shading. */
CLR_INLINE void start_fragment(clr_fragment* f, const __local SetupTriangle* t, span_weights w,
                               const span_interpolants* s, int lane, const clr_span_place* place, bool helper) {
  const float3 pw = (float3)(CLR_SPAN_LANE(float, s->pw[0], lane), CLR_SPAN_LANE(float, s->pw[1], lane),
                             CLR_SPAN_LANE(float, s->pw[2], lane));
  const float z = CLR_SPAN_LANE(float, w.z, lane);
  const float2 origin = layer_origin(t, f->clr_draw);
  f->frag_coord = (float4)((float)CLR_PLACE_LANE_X(*place, lane) + 0.5f - origin.x,
                           (float)CLR_PLACE_LANE_Y(*place, lane) + 0.5f - origin.y, z, CLR_SPAN_LANE(float, s->inv_w, lane));
  f->barycentric = pw * CLR_SPAN_LANE(float, s->norm, lane);
  f->frag_depth = z;
  f->primitive_id = t->primitive_id;
  f->view_id = t->flags >> CLR_TRIANGLE_VIEW_SHIFT;
  f->front_facing = (t->flags & CLR_TRIANGLE_FRONT_FACING) != 0;
  f->helper = helper;
  f->discarded = false;
  f->clr_lane = CLR_PLACE_LANE_PIXEL(*place, lane);
  const clr_outputs no_outputs = {0};
  f->out = no_outputs;
  clr_lane_varyings(t, s->varyings, lane, &f->in);
}

#if CLR_SPAN_PROGRAM
#if !CLR_EARLY_TESTS
#error "a span program runs after the early tests (program/interface.cpp rejects what would need late ones)"
#endif
/* Runs the span program for the span's fragments at once, `written` the lanes that passed the tests,
 * and takes its outputs. Its inputs are the per-fragment program's, lane by lane: the same
 * operations in vectors, so the same bits. The built-in normal shading as a span program: raster
 * stage of model-50k 34.6 -> 30.6 ms, terrain-1m 73.9 -> 63.0. f: the fragment whose resources
 * (uniforms, textures, buffers) it takes. */
CLR_INLINE void shade_span(const clr_fragment* f, const __local SetupTriangle* t, span_weights w,
                           const span_interpolants* s, const clr_span_place* place, clr_span_int written,
                           clr_span_outputs* outputs) {
  clr_span_fragment g;
  clr_span_program_inputs(t, s->varyings, &g.in);
  const float2 origin = layer_origin(t, f->clr_draw);
  g.frag_coord.x = CLR_SPAN_CONVERT(float, CLR_PLACE_X(*place)) + (0.5f - origin.x);
  g.frag_coord.y = CLR_SPAN_CONVERT(float, CLR_PLACE_Y(*place)) + (0.5f - origin.y);
  g.frag_coord.z = w.z;
  g.frag_coord.w = s->inv_w;
  g.barycentric.x = s->pw[0] * s->norm;
  g.barycentric.y = s->pw[1] * s->norm;
  g.barycentric.z = s->pw[2] * s->norm;
  g.written = written;
  g.primitive_id = t->primitive_id;
  g.view_id = t->flags >> CLR_TRIANGLE_VIEW_SHIFT;
  g.front_facing = (t->flags & CLR_TRIANGLE_FRONT_FACING) != 0;
  const clr_span_program_outputs no_outputs = {0};
  g.out = no_outputs;
  g.uniforms = f->uniforms;
  g.textures = f->textures;
  g.buffers = f->buffers;
  g.clr_quad = f->clr_quad;
  g.clr_lane = CLR_PLACE_LANE_PIXEL(*place, 0);
  fragment_span(&g);
  clr_span_program_results(&g.out, outputs);
}
#elif CLR_EARLY_TESTS
/* Runs the program for lane `lane` of a span whose tests passed there, and gathers its outputs. */
CLR_INLINE void shade_lane(clr_fragment* f, const __local SetupTriangle* t, span_weights w, const span_interpolants* s,
                           int lane, const clr_span_place* place, bool program_depth_test,
                           clr_span_outputs* outputs) {
  if (!program_depth_test) start_fragment(f, t, w, s, lane, place, false);
  fragment(f);
  clr_gather_outputs(f, lane, outputs);
}
#endif

/* The fragments of triangle t in the span of the tile at `place`, where `covered` (writable pixels the
 * triangle covers). In quad shading (spans of one pixel), an uncovered pixel runs the program as a
 * helper. */
CLR_INLINE void process_span(const __local SetupTriangle* t, const clr_span_place* place, clr_span_int covered,
                             clr_fragment* f, __local uint* tile_color, __local float* tile_depth,
                             __local uchar* tile_stencil, __constant const DrawUniforms* u) {
  f->uniforms = f->clr_uniform_table + ((t->flags >> CLR_TRIANGLE_DRAW_SHIFT) & CLR_TRIANGLE_DRAW_MASK); /* its draw's */
  span_weights w = {0};
  const bool front_facing = (t->flags & CLR_TRIANGLE_FRONT_FACING) != 0;
  clr_span_outputs outputs = {0};
  span_interpolants s;
#if CLR_EARLY_TESTS
  /* The tests need the weights (for depth) only with the depth test on. Without it they wait for a
   * fragment to pass, and the compiler drops them as dead code where the program reads neither
   * varyings nor its fragment's coordinates (a constant colour: fill-16's raster stage 93 -> 53 ms).
   * Hidden fragments skip the program and the interpolation, unless the program's depth test may
   * read them (spans of one pixel). */
  const bool weighed_before_tests = u->depth_test;
  if (weighed_before_tests) interpolation_weights(t, place, &w);
#if CLR_PROGRAM_DEPTH_TEST
  const bool program_depth_test = u->depth_test && u->depth_func == CLR_COMPARE_PROGRAM;
  if (program_depth_test) {
    interpolate_span(t, w, &s);
    start_fragment(f, t, w, &s, 0, place, false);
  }
#else
  const bool program_depth_test = false;
#endif
  const clr_span_int written = fragment_tests(f, front_facing, covered, w.z, u, tile_depth, tile_stencil, place);
  const uint passed = clr_span_bits_of_lanes(written);
#if CLR_QUAD_EXCHANGE
  /* A span program in spans of one pixel that takes derivatives: every pixel runs it, helpers and
   * hidden fragments too, so that its quad has values to exchange at the barriers. */
  const bool shaded = true;
#else
  const bool shaded = passed != 0;
#endif
  /* Two ifs, not one &&: program_depth_test is a constant in most programs, and clang warns about
   * && with a constant operand on stderr, which the examples require to be empty. */
  if (shaded) {
    if (!weighed_before_tests) interpolation_weights(t, place, &w);
    if (!program_depth_test) interpolate_span(t, w, &s); /* a program's depth test had it done first */
  }
#if CLR_SPAN_PROGRAM
  if (shaded) shade_span(f, t, w, &s, place, written, &outputs);
#else
  /* A per-fragment program runs for the lanes that passed only, in order: a span of a small
   * triangle has one or two. A span that passed whole takes the lanes in an unrolled loop instead:
   * no search for the next lane, and each lane's outputs go to a constant place in the span, where
   * what does not vary between lanes folds (a constant colour is one vector). Unrolled, not left to
   * the compiler, which kept the loop (fill-16 raster 48 -> 38 ms; a program's first build ~5%
   * longer). */
  if (passed == (uint)CLR_SPAN_BITS) {
#pragma unroll
    for (int lane = 0; lane < CLR_SPAN_PIXELS; ++lane) {
      shade_lane(f, t, w, &s, lane, place, program_depth_test, &outputs);
    }
  } else {
    for (uint lanes = passed; lanes != 0; lanes &= lanes - 1) {
      shade_lane(f, t, w, &s, 31 - clz(lanes & (0 - lanes)), place, program_depth_test, &outputs);
    }
  }
#endif
#else
  interpolation_weights(t, place, &w);
  clr_span_int kept = covered;
  clr_span_float frag_depth = w.z;
  interpolate_span(t, w, &s);
  for (int lane = 0; lane < CLR_SPAN_PIXELS; ++lane) {
    const bool live = CLR_SPAN_LANE(int, covered, lane) != 0;
#if !CLR_QUAD_SHADING /* quad shading runs the program for uncovered pixels too, as helpers */
    if (!live) continue;
#endif
    start_fragment(f, t, w, &s, lane, place, !live);
    fragment(f);
    if (!live || f->discarded) {
      CLR_SPAN_SET_LANE(kept, lane, 0);
      continue;
    }
    CLR_SPAN_SET_LANE(frag_depth, lane, clamp(f->frag_depth, 0.0f, 1.0f));
    clr_gather_outputs(f, lane, &outputs);
  }
  const clr_span_int written = fragment_tests(f, front_facing, kept, frag_depth, u, tile_depth, tile_stencil, place);
#endif
  if (clr_span_any(written)) clr_merge_outputs(f, &outputs, written, tile_color, place, u);
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

#if CLR_QUAD_SPANS
/* The fragments of triangle t in the quads whose first pixels are the tile's pixels `first` and
 * `second`, where `covered` (lane bits; fragment_ops.cl: lanes 0, 1, 4, 5 the first quad's, 2, 3,
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
#endif

/* Where a tile's work-group has fewer work-items than a vector has lanes (one walking the tile in
 * spans, CPU shapes), the kernel says that its work is as wide as a span already (OpenCL's
 * vec_type_hint): a compiler that vectorizes across work-items (Intel's CPU runtime) otherwise built
 * a version for eight work-items at once, that a group of one never runs, in most of a program's
 * build time (88 -> 13 s for the built-in normal shading). */
#if CLR_RASTER_GROUP < CLR_CPU_SPAN_PIXELS
#define CLR_RASTER_WIDTH_HINT __attribute__((vec_type_hint(CLR_SPAN_CAT(float, CLR_CPU_SPAN_PIXELS))))
#else
#define CLR_RASTER_WIDTH_HINT
#endif

__kernel __attribute__((reqd_work_group_size(CLR_RASTER_GROUP, 1, 1))) CLR_RASTER_WIDTH_HINT
void raster_tiles(__global const SetupTriangle* records, __global const SetupTriangle* overflow,
                  __global const uint* sorted_triangles, __global const uint* tile_ranges, uint tiles_x,
                  uint tile_count, uint run_count, uint run_stride,
                  uint framebuffer_width, __constant const DrawUniforms* u, __global uchar* depth_stencil,
                  uint stencil_offset, uint clears CLR_TARGET_PARAMS CLR_RESOURCE_PARAMS) {
  __local SetupTriangle batch[CLR_RASTER_TRIANGLE_BATCH];
  __local ulong masks[CLR_RASTER_TRIANGLE_BATCH][CLR_TILE_MASK_WORDS]; /* coverage_mask of each */
  __local TileCoverage coverage[CLR_RASTER_TRIANGLE_BATCH];           /* and what else it found */
  /* Each array with room for packed spans' spare pixel (CLR_TILE_SPARE_PIXEL). */
  __local uint tile_color[CLR_TILE_TARGETS * 4 * CLR_TILE_CHANNEL_WORDS]; /* CLR_TILE_WORD */
  __local float tile_depth[CLR_TILE_CHANNEL_WORDS];
  __local uchar tile_stencil[CLR_TILE_CHANNEL_WORDS];
#if CLR_QUAD_EXCHANGE
  __local float4 quad_exchange[CLR_TILE_PIXELS];
#endif
  /* Work-groups take the tiles in runs of CLR_RASTER_TILE_RUN, the runs in an order that strides
   * across the picture (run_stride, coprime with run_count, near run_count / golden ratio). A CPU
   * driver deals a kernel's work-groups out to its threads in ranges of consecutive ones (PoCL's, of
   * up to 512), while a chunk's triangles, a mesh's primitives being ordered in space, can cover a
   * band of the picture only: in tile order one range could hold all its work. A run's tiles, side
   * by side, share triangles. */
  const uint group = get_group_id(0);
  const uint run = (uint)((ulong)(group / CLR_RASTER_TILE_RUN) * run_stride % run_count);
  const uint tile = run * CLR_RASTER_TILE_RUN + group % CLR_RASTER_TILE_RUN;
  if (tile >= tile_count) return; /* past the last tile, in the last run */
  const uint begin = tile_ranges[2 * tile];
  const uint end = tile_ranges[2 * tile + 1];
  /* A tile without triangles has nothing to do but the pass's pending clears (below). The same for the
   * whole group: no barrier is skipped by only some items. */
  if (begin == end && clears == 0) return;

  const int2 origin = (int2)((int)(tile % tiles_x), (int)(tile / tiles_x)) * CLR_TILE_SIZE;
  const uint item = get_local_id(0);
  __global float* depth = (__global float*)depth_stencil;
  __global uchar* stencil = depth_stencil + stencil_offset;
#if CLR_NUM_OUTPUTS > 0 /* a program without outputs (a depth-only pass) has no colour targets */
  __global uchar* const targets[CLR_NUM_OUTPUTS] = CLR_TARGETS;
#endif
  const bool clear_depth = (clears & CLR_CLEAR_DEPTH) != 0;
  const bool clear_stencil = (clears & CLR_CLEAR_STENCIL) != 0;
#if CLR_NUM_OUTPUTS > 0
  uint4 cleared[CLR_NUM_OUTPUTS]; /* once per tile: the conversions are not cheap */
  for (int k = 0; k < CLR_NUM_OUTPUTS; ++k) cleared[k] = (clears >> k) & 1u ? cleared_pixel(u, k) : (uint4)(0u);
#endif
  /* A tile without triangles only writes the clears, straight from their values. */
  const bool empty = begin == end;
  for (uint first = item * CLR_SPAN_PIXELS; first < CLR_TILE_PIXELS && !empty; first += CLR_RASTER_GROUP * CLR_SPAN_PIXELS) {
    const int x = origin.x + (int)(first % CLR_TILE_SIZE);
    const int y = origin.y + (int)(first / CLR_TILE_SIZE);
    const uint pixel = (uint)y * framebuffer_width + (uint)x;
    const bool whole = whole_span_writable(x, y, u);
#if CLR_NUM_OUTPUTS > 0
    for (int k = 0; k < CLR_NUM_OUTPUTS; ++k) {
      const int format = u->target_format[k];
      if ((clears >> k) & 1u) { /* the clear value, instead of what the clear would have stored */
        const uint4 value = tile_holds_bytes(u, k) ? as_uint4(rint(as_float4(cleared[k]) * 255.0f)) : cleared[k];
        CLR_SPAN_STORE((clr_span_uint)(value.x), &tile_color[CLR_TILE_WORD(k, 0, first)]);
        CLR_SPAN_STORE((clr_span_uint)(value.y), &tile_color[CLR_TILE_WORD(k, 1, first)]);
        CLR_SPAN_STORE((clr_span_uint)(value.z), &tile_color[CLR_TILE_WORD(k, 2, first)]);
        CLR_SPAN_STORE((clr_span_uint)(value.w), &tile_color[CLR_TILE_WORD(k, 3, first)]);
        continue;
      }
      if (whole && format == CLR_FORMAT_RGBA8 && CLR_PACKED_RGBA8) {
        load_rgba8_span((__global const uint*)targets[k] + pixel, tile_holds_bytes(u, k),
                        &tile_color[CLR_TILE_WORD(k, 0, first)]);
        continue;
      }
      for (int i = 0; i < CLR_SPAN_PIXELS; ++i) {
        uint4 value = writable(x + i, y, u) && format >= 0 ? load_attachment_pixel(format, targets[k], pixel + i)
                                                            : (uint4)(0);
        if (tile_holds_bytes(u, k)) value = as_uint4(rint(as_float4(value) * 255.0f)); /* c / 255 back to c */
        tile_color[CLR_TILE_WORD(k, 0, first + i)] = value.x;
        tile_color[CLR_TILE_WORD(k, 1, first + i)] = value.y;
        tile_color[CLR_TILE_WORD(k, 2, first + i)] = value.z;
        tile_color[CLR_TILE_WORD(k, 3, first + i)] = value.w;
      }
    }
#endif
    if (clear_depth) CLR_SPAN_STORE((clr_span_float)(u->clear_depth), &tile_depth[first]);
    else if (whole) CLR_SPAN_STORE(u->depth_test ? CLR_SPAN_LOAD(&depth[pixel]) : (clr_span_float)(0.0f), &tile_depth[first]);
    else {
      for (int i = 0; i < CLR_SPAN_PIXELS; ++i) {
        tile_depth[first + i] = writable(x + i, y, u) && u->depth_test ? depth[pixel + i] : 0.0f;
      }
    }
    if (clear_stencil) CLR_SPAN_STORE((CLR_SPAN(uchar))((uchar)u->clear_stencil), &tile_stencil[first]);
    else if (whole) CLR_SPAN_STORE(u->stencil_test ? CLR_SPAN_LOAD(&stencil[pixel]) : (CLR_SPAN(uchar))(0), &tile_stencil[first]);
    else {
      for (int i = 0; i < CLR_SPAN_PIXELS; ++i) {
        tile_stencil[first + i] = writable(x + i, y, u) && u->stencil_test ? stencil[pixel + i] : 0;
      }
    }
  }

  clr_fragment f = {0};
  f.clr_tile = tile_color;
  f.clr_draw = u;
#if CLR_QUAD_EXCHANGE
  f.clr_quad = quad_exchange;
#endif
  CLR_BIND_RESOURCES(f, 0);
  f.clr_uniform_table = f.uniforms;

  for (uint base = begin; base < end; base += CLR_RASTER_TRIANGLE_BATCH) {
    const uint n = min((uint)CLR_RASTER_TRIANGLE_BATCH, end - base);
    barrier(CLK_LOCAL_MEM_FENCE); /* everyone is done with the previous batch */
    /* All the batch's records first, then their coverage: the records are scattered over the
     * chunk, and loads with nothing in between wait for memory together, not one after another. */
    for (uint i = item; i < n; i += CLR_RASTER_GROUP) {
      const uint id = sorted_triangles[base + i];
      batch[i] = (id & CLR_OVERFLOW_TRIANGLE) ? overflow[id & ~CLR_OVERFLOW_TRIANGLE] : records[id];
    }
    for (uint i = item; i < n; i += CLR_RASTER_GROUP) coverage_mask(&batch[i], origin, masks[i], &coverage[i]);
    barrier(CLK_LOCAL_MEM_FENCE);
#if CLR_QUAD_SPANS
    /* The quads that have a pixel of the triangle, two to a span (fragment_ops.cl), in mask order
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
          process_quad_span(&batch[i], origin, first_quad, pixel, covered, &f, tile_color, tile_depth, tile_stencil, u);
          waiting = false;
        }
      }
      /* A last quad alone: its lanes again in the second quad's, which cover nothing. */
      if (waiting) {
        process_quad_span(&batch[i], origin, first_quad, first_quad, covered, &f, tile_color, tile_depth, tile_stencil,
                          u);
      }
    }
#elif CLR_QUAD_EXCHANGE && CLR_RASTER_GROUP == CLR_QUAD_PIXELS
    /* One work-item per pixel of a quad: the four walk the quads each triangle covers together,
     * every one deciding from the same masks, so all of them reach the program's barriers. A quad's
     * pixels are in one word of a mask: a word holds whole rows, an even number of them. */
    for (uint i = 0; i < n; ++i) {
      for (int w = coverage[i].first_word; w < coverage[i].end_word; ++w) {
        for (ulong left = masks[i][w]; left != 0;) {
          const uint corner = take_lowest_quad(&left);
          const uint pixel = (uint)w * 64 + corner + (item & 1u) + (item >> 1) * CLR_TILE_SIZE;
          const clr_span_place place = {origin.x + (int)(pixel % CLR_TILE_SIZE), origin.y + (int)(pixel / CLR_TILE_SIZE),
                                        pixel, 0, 0, 0, false};
          process_span(&batch[i], &place, clr_span_lanes_from_bits((uint)(masks[i][w] >> (pixel % 64))), &f,
                       tile_color, tile_depth, tile_stencil, u);
          barrier(CLK_LOCAL_MEM_FENCE); /* as below */
        }
      }
    }
#elif CLR_QUAD_EXCHANGE
    /* One work-item per pixel: every one runs the program for each triangle that covers any pixel
     * of the tile, the uncovered ones as helpers. */
    const int x = origin.x + (int)(item % CLR_TILE_SIZE);
    const int y = origin.y + (int)(item / CLR_TILE_SIZE);
    for (uint i = 0; i < n; ++i) {
      ulong any = 0;
      for (int w = 0; w < CLR_TILE_MASK_WORDS; ++w) any |= masks[i][w];
      /* The same decision in every work-item, so all of them reach the program's barriers. */
      if (!any) continue;
      const clr_span_place place = {x, y, item, 0, 0, 0, false};
      process_span(&batch[i], &place, clr_span_lanes_from_bits((uint)(masks[i][item / 64] >> (item % 64))), &f,
                   tile_color, tile_depth, tile_stencil, u);
      /* What follows the program's last barrier branches per pixel (helper or not, discard, the
       * tests, blending, the program's own code). Those branches must meet again at a barrier before
       * the loop goes on: PoCL otherwise takes a branch that leads on toward the next iteration's
       * barriers as uniform and follows work-item 0's way for the whole group, so every pixel of the
       * tile was written, or left, as its first pixel was. */
      barrier(CLK_LOCAL_MEM_FENCE);
    }
#else
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
              process_packed_span(&batch[i], origin, lanes, filled, &f, tile_color, tile_depth, tile_stencil, u);
              lanes = (clr_span_uint)(CLR_TILE_SPARE_PIXEL);
              filled = 0;
            }
          }
        }
        if (filled > 0) process_packed_span(&batch[i], origin, lanes, filled, &f, tile_color, tile_depth, tile_stencil, u);
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
          process_span(&batch[i], &place, clr_span_lanes_from_bits(covered), &f, tile_color, tile_depth, tile_stencil, u);
        }
      }
    }
#endif
  }
  barrier(CLK_LOCAL_MEM_FENCE); /* every pixel's last fragment is in the tile */
  const int4 depth_rect = moved_rect(clear_depth, u);
  const int4 stencil_rect = moved_rect(clear_stencil, u);
  const bool store_depth = empty ? clear_depth : (u->depth_test && u->depth_write) || clear_depth;
  const bool store_stencil = empty ? clear_stencil : u->stencil_test || clear_stencil;
  for (uint first = item * CLR_SPAN_PIXELS; first < CLR_TILE_PIXELS; first += CLR_RASTER_GROUP * CLR_SPAN_PIXELS) {
    const int x = origin.x + (int)(first % CLR_TILE_SIZE);
    const int y = origin.y + (int)(first / CLR_TILE_SIZE);
    const uint pixel = (uint)y * framebuffer_width + (uint)x;
#if CLR_NUM_OUTPUTS > 0
    for (int k = 0; k < CLR_NUM_OUTPUTS; ++k) {
      const int format = u->target_format[k];
      const bool clearing = (clears >> k) & 1u;
      if (empty && !clearing) continue;
      const int4 rect = moved_rect(clearing, u);
      if (whole_span_inside(x, y, rect) && format == CLR_FORMAT_RGBA8 && CLR_PACKED_RGBA8) {
        if (empty) {
          const uint4 bytes = clr_float_to_unorm8(as_float4(cleared[k]));
          CLR_WRITE_BACK_SPAN((clr_span_uint)(bytes.x | bytes.y << 8 | bytes.z << 16 | bytes.w << 24),
                              (__global uint*)targets[k] + pixel, u->streaming_stores);
        } else {
          CLR_WRITE_BACK_SPAN(pack_rgba8_span(&tile_color[CLR_TILE_WORD(k, 0, first)], tile_holds_bytes(u, k)),
                              (__global uint*)targets[k] + pixel, u->streaming_stores);
        }
        continue;
      }
      for (int i = 0; i < CLR_SPAN_PIXELS; ++i) {
        if (inside_rect(x + i, y, rect) && format >= 0) {
          uint4 value = empty ? cleared[k] : clr_tile_pixel(tile_color, k, first + i);
          /* A tile that holds bytes has c where the attachment stores c / 255. */
          if (!empty && tile_holds_bytes(u, k)) value = as_uint4(clr_unorm8_to_float(as_float4(value)));
          store_attachment_pixel(format, targets[k], pixel + i, value);
        }
      }
    }
#endif
    const clr_span_float depths = empty ? (clr_span_float)(u->clear_depth) : CLR_SPAN_LOAD(&tile_depth[first]);
    if (store_depth && whole_span_inside(x, y, depth_rect)) {
      CLR_WRITE_BACK_SPAN(depths, &depth[pixel], u->streaming_stores);
    } else if (store_depth) {
      for (int i = 0; i < CLR_SPAN_PIXELS; ++i) {
        if (inside_rect(x + i, y, depth_rect)) depth[pixel + i] = CLR_SPAN_LANE(float, depths, i);
      }
    }
    const CLR_SPAN(uchar) stencils = empty ? (CLR_SPAN(uchar))((uchar)u->clear_stencil) : CLR_SPAN_LOAD(&tile_stencil[first]);
    if (store_stencil && whole_span_inside(x, y, stencil_rect)) {
      CLR_SPAN_STORE(stencils, &stencil[pixel]);
    } else if (store_stencil) {
      for (int i = 0; i < CLR_SPAN_PIXELS; ++i) {
        if (inside_rect(x + i, y, stencil_rect)) stencil[pixel + i] = CLR_SPAN_LANE(uchar, stencils, i);
      }
    }
  }
  /* The pixels outside the clip rectangle meet the others here, not at the kernel's end, which the
   * groups of empty tiles reach from their early return: PoCL (3.1) took a branch joining that
   * path as uniform, so in a group of many work-items every pixel followed work-item 0 and the
   * rows below a partial tile were written outside the framebuffer. */
  barrier(CLK_LOCAL_MEM_FENCE);
}
