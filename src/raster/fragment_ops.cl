/* fragment_ops.cl: OpenGL's per-fragment operations after the fragment program (GL 4.6 section 17.3),
 * as functions the rasterizer calls per span of fragments and per colour attachment, in this order:
 *
 *   stencil test     clr_stencil_test
 *   depth test       clr_compare
 *   stencil update   clr_stencil_after_tests (clr_stencil_update with the op both outcomes pick)
 *   blending         clr_blend_unorm8 or clr_blend (fixed-function equations and factors)
 *   write mask       clr_apply_write_mask
 *
 * The state comes as the BlendUniforms and StencilUniforms of types.h, passed by value so the caller
 * may hold them in any address space. Everything here is pure arithmetic on fragments: the caller
 * reads and writes the framebuffer and converts between storage formats and floats. */

#include "raster/span.cl"
#include "shared/types.h"

/* ---- Comparisons (GL 4.6 17.3.3, 17.3.4) ---------------------------------------------------------
 * `fragment` func `stored`, in GL's operand order (LESS passes when fragment < stored). IEEE rules:
 * -0 equals +0, and every ordered comparison with a NaN fails, so only NOTEQUAL and ALWAYS pass a
 * NaN. CLR_COMPARE_PROGRAM is the caller's business; here it passes, like ALWAYS. */
CLR_INLINE clr_span_int clr_compare(int func, clr_span_float fragment, clr_span_float stored) {
  switch (func) {
    case CLR_COMPARE_NEVER: return (clr_span_int)(0);
    case CLR_COMPARE_LESS: return fragment < stored;
    case CLR_COMPARE_EQUAL: return fragment == stored;
    case CLR_COMPARE_LEQUAL: return fragment <= stored;
    case CLR_COMPARE_GREATER: return fragment > stored;
    case CLR_COMPARE_NOTEQUAL: return fragment != stored;
    case CLR_COMPARE_GEQUAL: return fragment >= stored;
    default: return CLR_SPAN_TRUE;
  }
}

/* ---- Stencil (GL 4.6 17.3.3), 8-bit stencil values ------------------------------------------------ */

/* (reference & read_mask) func (stored & read_mask). Values below 2^8 are exact in float, so the
 * depth test's comparison serves both. */
CLR_INLINE clr_span_int clr_stencil_test(StencilUniforms s, clr_span_uint stored) {
  return clr_compare(s.func, (clr_span_float)((float)(s.reference & s.read_mask)),
                     CLR_SPAN_CONVERT(float, stored & s.read_mask));
}

/* The stencil value after `op` (CLR_STENCIL_*), keeping the bits write_mask protects. INCR and DECR
 * saturate at 255 and 0; the _WRAP ops wrap modulo 256. */
CLR_INLINE clr_span_uint clr_stencil_update(StencilUniforms s, int op, clr_span_uint stored) {
  clr_span_uint value;
  switch (op) {
    case CLR_STENCIL_ZERO: value = 0u; break;
    case CLR_STENCIL_REPLACE: value = s.reference; break;
    case CLR_STENCIL_INCR: value = min(stored + 1u, (clr_span_uint)(255u)); break;
    case CLR_STENCIL_INCR_WRAP: value = stored + 1u; break;
    case CLR_STENCIL_DECR: value = select(stored - 1u, (clr_span_uint)(0u), stored == 0u); break;
    case CLR_STENCIL_DECR_WRAP: value = stored - 1u; break;
    case CLR_STENCIL_INVERT: value = ~stored; break;
    default: value = stored; break; /* CLR_STENCIL_KEEP */
  }
  return ((value & s.write_mask) | (stored & ~s.write_mask)) & 0xffu;
}

/* The stencil value after the tests, by the face's op for their outcomes: stencil_fail where the
 * stencil test failed (those fragments never reach the depth test), else depth_fail or depth_pass.
 * Pass depth_passed all true when there is no depth test (disabled or no depth buffer). */
CLR_INLINE clr_span_uint clr_stencil_after_tests(StencilUniforms s, clr_span_int stencil_passed,
                                                 clr_span_int depth_passed, clr_span_uint stored) {
  const clr_span_uint after_depth_test =
      select(clr_stencil_update(s, s.depth_fail, stored), clr_stencil_update(s, s.depth_pass, stored), depth_passed);
  return select(clr_stencil_update(s, s.stencil_fail, stored), after_depth_test, stencil_passed);
}

/* ---- Blending (GL 4.6 17.3.6) ----------------------------------------------------------------------
 * GL blends "as if in floating point", with at least the destination's precision, after clamping the
 * source, destination and constant colour to [0, 1] for normalized attachments; the result is clamped
 * only by the conversion to the attachment's format (17.3.7), which the caller does. Float arithmetic
 * here rounds each product and sum once (types.h turns FP_CONTRACT off); non-finite colours follow
 * IEEE arithmetic (a ZERO factor times an infinity is NaN).
 *
 * Which function for which attachment, to match llvmpipe (Mesa 22.3; measured on every equation and
 * factor pair, rgb and alpha state alike and apart, 4096 colour pairs each):
 *
 *   R8, RG8, RGBA8   clr_blend_unorm8, llvmpipe's 8-bit fixed-point blend. llvmpipe converts the
 *                    fragment and constant colours to 8 bits (round to nearest even), takes 1 - x as
 *                    255 - x, rounds each product with lp_build_mul_norm, (ab + (ab >> 8) + 128) >> 8
 *                    (round(ab / 255), except for 24 of the 65536 products, just above a half, which
 *                    it rounds down), and adds or subtracts with saturation. The same steps on 8-bit
 *                    values held in floats are exact (integers below 2^17): RGBA8 and RG8 match
 *                    llvmpipe bit for bit (0 of 55 million channels differ). On R8, ADD with
 *                    complementary factors (SRC_ALPHA and ONE_MINUS_SRC_ALPHA, ...) is llvmpipe's
 *                    8-bit lerp, d + round((f + (f >> 7)) * (s - d) / 256) (regrouped_blend), and
 *                    matches it bit for bit too. For comparison, blending the 8-bit inputs exactly
 *                    and rounding once is up to 1/255 off, and blending the unrounded fragment
 *                    colour up to 2/255 off.
 *   SRGB8_A8         clr_blend(normalized = true) on the destination with its rgb decoded to linear
 *                    (17.3.6.1), encoding the result afterwards (17.3.7). llvmpipe blends sRGB in
 *                    float from the unrounded fragment colour, as here: with exact sRGB conversions
 *                    the results are at most 1/255 apart, except where llvmpipe's polynomial sRGB
 *                    decoding shows, near black (up to 8/255 for SUBTRACT results close to 0).
 *   float formats    clr_blend(normalized = false): no clamping, and llvmpipe's order of operations
 *                    (regrouped_blend below): RGBA16F, RGBA32F, R32F and RG32F match it bit for bit. */

/* One blend factor (table 17.2) for channel `channel` (3 is alpha) of a span: the same function
 * serves the rgb factor on channels 0-2 and the alpha factor on channel 3. Colours are in units
 * where `one` is full intensity: 1, or 255 for 8-bit values. */
CLR_INLINE clr_span_float blend_factor(int factor, int channel, clr_span_color source, clr_span_color destination,
                                       clr_span_color constant_color, float one) {
  switch (factor) {
    case CLR_FACTOR_ZERO: return (clr_span_float)(0.0f);
    case CLR_FACTOR_SRC_COLOR: return source.c[channel];
    case CLR_FACTOR_ONE_MINUS_SRC_COLOR: return one - source.c[channel];
    case CLR_FACTOR_DST_COLOR: return destination.c[channel];
    case CLR_FACTOR_ONE_MINUS_DST_COLOR: return one - destination.c[channel];
    case CLR_FACTOR_SRC_ALPHA: return source.c[3];
    case CLR_FACTOR_ONE_MINUS_SRC_ALPHA: return one - source.c[3];
    case CLR_FACTOR_DST_ALPHA: return destination.c[3];
    case CLR_FACTOR_ONE_MINUS_DST_ALPHA: return one - destination.c[3];
    case CLR_FACTOR_CONSTANT_COLOR: return constant_color.c[channel];
    case CLR_FACTOR_ONE_MINUS_CONSTANT_COLOR: return one - constant_color.c[channel];
    case CLR_FACTOR_CONSTANT_ALPHA: return constant_color.c[3];
    case CLR_FACTOR_ONE_MINUS_CONSTANT_ALPHA: return one - constant_color.c[3];
    case CLR_FACTOR_SRC_ALPHA_SATURATE:
      return channel == 3 ? (clr_span_float)(one) : fmin(source.c[3], one - destination.c[3]);
    default: return (clr_span_float)(one); /* CLR_FACTOR_ONE */
  }
}

/* floor(x) for |x| < 2^31, and x rounded to the nearest integer (ties to even) for 0 <= x < 2^22:
 * the 8-bit blend's roundings, on values that are small. PoCL's floor and rint are library code of a
 * dozen vector instructions each, which made them most of a blended span; these are two to four.
 * Adding 2^23 leaves x no fraction bits, so that addition rounds (to nearest even, the default mode)
 * and the subtraction is exact (OpenCL C compiles without reassociation unless told otherwise). */
CLR_INLINE clr_span_float floor_small(clr_span_float x) {
  const clr_span_float truncated = CLR_SPAN_CONVERT(float, CLR_SPAN_CONVERT(int, x));
  return truncated - select((clr_span_float)(0.0f), (clr_span_float)(1.0f), truncated > x);
}
CLR_INLINE clr_span_float round_small(clr_span_float x) { return (x + 8388608.0f) - 8388608.0f; }

/* llvmpipe's product of two 8-bit values, (ab + (ab >> 8) + 128) >> 8, on integers held in floats. */
CLR_INLINE clr_span_float mul_unorm8(clr_span_float a, clr_span_float b) {
  const clr_span_float ab = a * b;
  return floor_small((ab + floor_small(ab / 256.0f) + 128.0f) / 256.0f);
}

/* Whether f and g are one another's complement (ZERO and ONE, SRC_COLOR and ONE_MINUS_SRC_COLOR, ...),
 * and whether f is the plain one of its pair (ONE, SRC_COLOR, ...: what llvmpipe lists first). */
static inline bool complementary_factors(int f, int g) {
  return f != g && f / 2 == g / 2 && f < CLR_FACTOR_SRC_ALPHA_SATURATE;
}
static inline bool plain_factor(int f) { return f == CLR_FACTOR_ONE || (f % 2 == 0 && f != CLR_FACTOR_ZERO); }

/* llvmpipe (lp_build_blend) rewrites blends algebraically when the rgb and the alpha state each use
 * one factor on both sides, or the attachment has a single channel (`regroup`); the rewrites round
 * differently from s * sf op d * df, so they are reproduced here:
 *   equal factors f (float only)    ADD, SUBTRACT, REVERSE_SUBTRACT: (s op d) * f
 *   complementary factors, f the    ADD: the lerp d + f * (s - d), or s + f * (d - s) when f is the
 *   plain one's value (f and 1 - f       destination's: in float with a fused multiply-add (LLVM's
 *   on the side it is on)                fmuladd on a CPU with FMA); in 8 bits with the weight
 *                                        scaled to [0, 256] as f + (f >> 7) and the product divided
 *                                        by 256, rounded (pmulhrsw);
 *                                   SUBTRACT (float only): (s + d) * f - d, or s - (s + d) * f;
 *                                   REVERSE_SUBTRACT (float only): d - (s + d) * f, or (s + d) * f - s.
 * unorm8: colours and factors are 8-bit values (one = 255). Returns false, leaving *out alone, where
 * llvmpipe blends as written. */
CLR_INLINE bool regrouped_blend(int equation, int source_factor_id, int destination_factor_id, clr_span_float s,
                                clr_span_float d, clr_span_float source_factor, clr_span_float destination_factor,
                                bool unorm8, clr_span_float* out) {
  if (equation != CLR_BLEND_ADD && (unorm8 || (equation != CLR_BLEND_SUBTRACT &&
                                               equation != CLR_BLEND_REVERSE_SUBTRACT))) {
    return false;
  }
  if (complementary_factors(source_factor_id, destination_factor_id)) {
    const bool source_plain = plain_factor(source_factor_id);
    const clr_span_float f = source_plain ? source_factor : destination_factor;
    const clr_span_float from = source_plain ? d : s, to = source_plain ? s : d;
    if (unorm8) {
      *out = from + floor_small((f + floor_small(f / 128.0f)) * (to - from) / 256.0f + 0.5f);
    } else if (equation == CLR_BLEND_ADD) {
      *out = fma(f, to - from, from);
    } else {
      const clr_span_float sum = (s + d) * f;
      if (equation == CLR_BLEND_SUBTRACT) *out = source_plain ? sum - d : s - sum;
      else *out = source_plain ? d - sum : sum - s;
    }
    return true;
  }
  if (unorm8 || source_factor_id != destination_factor_id) return false;
  const clr_span_float combined = equation == CLR_BLEND_ADD ? s + d : equation == CLR_BLEND_SUBTRACT ? s - d : d - s;
  *out = combined * source_factor;
  return true;
}

/* One blend equation (table 17.1) on one channel; MIN and MAX ignore the factors.
 * unorm8: the colours and factors are 8-bit values (one = 255), multiplied as llvmpipe does.
 * regroup: llvmpipe's rewrites apply (regrouped_blend). */
CLR_INLINE clr_span_float blend_equation(int equation, int source_factor_id, int destination_factor_id,
                                         clr_span_float source, clr_span_float destination,
                                         clr_span_float source_factor, clr_span_float destination_factor, bool unorm8,
                                         bool regroup) {
  if (equation == CLR_BLEND_MIN) return fmin(source, destination);
  if (equation == CLR_BLEND_MAX) return fmax(source, destination);
  clr_span_float regrouped;
  if (regroup && regrouped_blend(equation, source_factor_id, destination_factor_id, source, destination,
                                 source_factor, destination_factor, unorm8, &regrouped)) {
    return regrouped;
  }
  /* A factor of ONE leaves its term as it is: x * 1 is x in float, NaN and infinities included, and
   * llvmpipe's 8-bit product by 255 is x for every byte x (255 x + (x - 1) + 128 is 256 x + 127). */
  const clr_span_float source_term = source_factor_id == CLR_FACTOR_ONE ? source
                                     : unorm8                           ? mul_unorm8(source, source_factor)
                                                                        : source * source_factor;
  const clr_span_float destination_term = destination_factor_id == CLR_FACTOR_ONE ? destination
                                          : unorm8 ? mul_unorm8(destination, destination_factor)
                                                   : destination * destination_factor;
  switch (equation) {
    case CLR_BLEND_SUBTRACT: return source_term - destination_term;
    case CLR_BLEND_REVERSE_SUBTRACT: return destination_term - source_term;
    default: return source_term + destination_term; /* CLR_BLEND_ADD */
  }
}

/* For attachments without alpha, llvmpipe hard-wires the destination alpha to 1 by replacing
 * factors (force_dst_alpha_one in lp_state_fs.c): DST_ALPHA becomes ONE and ONE_MINUS_DST_ALPHA
 * ZERO (SRC_ALPHA_SATURATE becomes ZERO for 8-bit formats only, where every rewrite it enables
 * gives the same result), and gives alpha the rgb equation and factors. The values do not change,
 * but the new factors decide llvmpipe's rewrites (regrouped_blend). */
static inline int factor_without_destination_alpha(int factor) {
  switch (factor) {
    case CLR_FACTOR_DST_ALPHA: return CLR_FACTOR_ONE;
    case CLR_FACTOR_ONE_MINUS_DST_ALPHA: return CLR_FACTOR_ZERO;
    default: return factor;
  }
}

static inline bool ignores_factors(int equation) { return equation == CLR_BLEND_MIN || equation == CLR_BLEND_MAX; }

/* The rgb equation and factors on channels 0-2, the alpha ones on channel 3, for an attachment of
 * `channels` channels, into *blended. */
CLR_INLINE void blend_colors(BlendUniforms b, clr_span_color source, clr_span_color destination,
                             clr_span_color constant_color, bool unorm8, int channels, clr_span_color* blended) {
  /* Mesa's state tracker gives MIN and MAX the factors ONE and ONE, first (st_update_blend). */
  if (ignores_factors(b.rgb_equation)) b.src_rgb = b.dst_rgb = CLR_FACTOR_ONE;
  if (ignores_factors(b.alpha_equation)) b.src_alpha = b.dst_alpha = CLR_FACTOR_ONE;
  if (channels < 4) {
    b.src_rgb = b.src_alpha = factor_without_destination_alpha(b.src_rgb);
    b.dst_rgb = b.dst_alpha = factor_without_destination_alpha(b.dst_rgb);
    b.alpha_equation = b.rgb_equation;
  }
  const float one = unorm8 ? 255.0f : 1.0f;
  const bool regroup = (b.src_rgb == b.dst_rgb && b.src_alpha == b.dst_alpha) || channels == 1;
#pragma unroll
  for (int c = 0; c < 4; ++c) {
    const int equation = c < 3 ? b.rgb_equation : b.alpha_equation;
    const int source_factor = c < 3 ? b.src_rgb : b.src_alpha;
    const int destination_factor = c < 3 ? b.dst_rgb : b.dst_alpha;
    blended->c[c] = blend_equation(equation, source_factor, destination_factor, source.c[c], destination.c[c],
                                   blend_factor(source_factor, c, source, destination, constant_color, one),
                                   blend_factor(destination_factor, c, source, destination, constant_color, one),
                                   unorm8, regroup);
  }
}

/* The blended colour of a float attachment (normalized = false) or an sRGB one (normalized = true,
 * destination rgb decoded to linear) of `channels` channels, before conversion to its format. */
CLR_INLINE void clr_blend(BlendUniforms b, clr_span_color source, clr_span_color destination,
                          clr_span_color constant_color, bool normalized, int channels, clr_span_color* blended) {
  if (normalized) {
#pragma unroll
    for (int c = 0; c < 4; ++c) {
      source.c[c] = clamp(source.c[c], 0.0f, 1.0f);
      destination.c[c] = clamp(destination.c[c], 0.0f, 1.0f);
      constant_color.c[c] = clamp(constant_color.c[c], 0.0f, 1.0f);
    }
  }
  blend_colors(b, source, destination, constant_color, false, channels, blended);
}

static inline bool is_constant_factor(int factor) {
  return factor >= CLR_FACTOR_CONSTANT_COLOR && factor <= CLR_FACTOR_ONE_MINUS_CONSTANT_ALPHA;
}
static inline bool uses_constant_color(BlendUniforms b) {
  return is_constant_factor(b.src_rgb) || is_constant_factor(b.dst_rgb) || is_constant_factor(b.src_alpha) ||
         is_constant_factor(b.dst_alpha);
}

/* Colours in [0, 1] as 8-bit values, rounded to nearest even as llvmpipe converts (NaN becomes 0). */
CLR_INLINE void to_unorm8(clr_span_color* color) {
#pragma unroll
  for (int c = 0; c < 4; ++c) color->c[c] = round_small(clamp(color->c[c], 0.0f, 1.0f) * 255.0f);
}

/* The blended colour of a linear 8-bit unsigned normalized attachment, as llvmpipe blends it: a
 * multiple of 1/255 in [0, 1] (so any conversion that rounds to nearest gives the byte).
 * destination: the stored colour, with the channels the format lacks as GL reads them (green and
 * blue 0, alpha 1). in_bytes: the destination comes, and the result goes, as the byte values
 * themselves (0 to 255, in floats), as the rasterizer's tile holds a blended RGBA8 attachment. */
CLR_INLINE void clr_blend_unorm8(BlendUniforms b, clr_span_color source, clr_span_color destination,
                                 clr_span_color constant_color, int channels, bool in_bytes, clr_span_color* blended) {
  to_unorm8(&source);
  if (!in_bytes) to_unorm8(&destination);
  if (uses_constant_color(b)) to_unorm8(&constant_color);
  blend_colors(b, source, destination, constant_color, true, channels, blended);
#pragma unroll
  for (int c = 0; c < 4; ++c) {
    blended->c[c] = clamp(blended->c[c], 0.0f, 255.0f);
    if (!in_bytes) blended->c[c] = clr_unorm8_to_float(blended->c[c]);
  }
}

/* ---- Colour write mask (GL 4.6 17.4.2) -------------------------------------------------------------- */

/* *value keeps the channels BlendUniforms::write_mask writes (bit c for channel c) and takes
 * `destination` in the others: on the bits the tile holds, so integer and float attachments alike. */
CLR_INLINE void clr_apply_write_mask(uint mask, clr_span_bits* value, clr_span_bits destination) {
#pragma unroll
  for (int c = 0; c < 4; ++c) {
    if (!((mask >> c) & 1u)) value->c[c] = destination.c[c];
  }
}
