/* merge.cl: what a span's fragments do to the tile: the stencil and depth tests with their writes
 * (fragment_tests), then each colour output blended, masked and stored (clr_merge_float_output,
 * clr_merge_integer_output, which the generated glue calls per output). */

#include "raster/fragment_ops.cl"
#include "raster/span.cl"
#include "resources/format.cl"
#include "shared/types.h"

static inline bool is_normalized_format(int format) { return format <= CLR_FORMAT_SRGB8_A8; }

/* Whether the tile holds colour attachment `target` as its bytes (0 to 255, in floats) rather than
 * decoded: an RGBA8 attachment the draw blends with OpenGL's equations, which llvmpipe computes on
 * bytes (fragment_ops.cl), so that the blend of each span needs no conversion of what it reads and no
 * division of what it writes. Framebuffer fetch and the program's blend function read decoded
 * colours, so their draws keep them. */
CLR_INLINE bool holds_bytes(int format, BlendUniforms b) {
  return !CLR_READS_FRAMEBUFFER && format == CLR_FORMAT_RGBA8 && b.enabled && b.rgb_equation != CLR_BLEND_PROGRAM &&
         b.alpha_equation != CLR_BLEND_PROGRAM;
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
 * the fragment, for the program's depth test (spans of one pixel, span.cl). */
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
#if CLR_PROGRAM_BLEND /* spans of one pixel (span.cl) */
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
