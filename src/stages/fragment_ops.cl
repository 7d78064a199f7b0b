/* fragment_ops.cl: OpenGL's per-fragment operations after the fragment program (GL 4.6 section 17.3),
 * as functions the rasterizer calls per fragment and per colour attachment, in this order:
 *
 *   stencil test     clr_stencil_test
 *   depth test       clr_compare
 *   stencil update   clr_stencil_update, with the op clr_stencil_op picks from both outcomes
 *   blending         clr_blend_unorm8 or clr_blend (fixed-function equations and factors)
 *   write mask       clr_apply_write_mask
 *
 * The state comes as the BlendUniforms and StencilUniforms of types.h, passed by value so the caller
 * may hold them in any address space. Everything here is pure arithmetic on one fragment: the caller
 * reads and writes the framebuffer and converts between storage formats and floats. */

/* ---- Comparisons (GL 4.6 17.3.3, 17.3.4) ---------------------------------------------------------
 * `fragment` func `stored`, in GL's operand order (LESS passes when fragment < stored). IEEE rules:
 * -0 equals +0, and every ordered comparison with a NaN fails, so only NOTEQUAL and ALWAYS pass a
 * NaN. CLR_COMPARE_PROGRAM is the caller's business; here it passes, like ALWAYS. */
CLR_INLINE bool clr_compare(int func, float fragment, float stored) {
  switch (func) {
    case CLR_COMPARE_NEVER: return false;
    case CLR_COMPARE_LESS: return fragment < stored;
    case CLR_COMPARE_EQUAL: return fragment == stored;
    case CLR_COMPARE_LEQUAL: return fragment <= stored;
    case CLR_COMPARE_GREATER: return fragment > stored;
    case CLR_COMPARE_NOTEQUAL: return fragment != stored;
    case CLR_COMPARE_GEQUAL: return fragment >= stored;
    default: return true;
  }
}

/* ---- Stencil (GL 4.6 17.3.3), 8-bit stencil values ------------------------------------------------ */

/* (reference & read_mask) func (stored & read_mask). Values below 2^8 are exact in float, so the
 * depth test's comparison serves both. */
CLR_INLINE bool clr_stencil_test(StencilUniforms s, uint stored) {
  return clr_compare(s.func, (float)(s.reference & s.read_mask), (float)(stored & s.read_mask));
}

/* Which of the face's three ops applies. A fragment that fails the stencil test never reaches the
 * depth test; pass depth_passed = true when there is no depth test (disabled or no depth buffer). */
CLR_INLINE int clr_stencil_op(StencilUniforms s, bool stencil_passed, bool depth_passed) {
  if (!stencil_passed) return s.stencil_fail;
  return depth_passed ? s.depth_pass : s.depth_fail;
}

/* The stencil value after `op` (CLR_STENCIL_*), keeping the bits write_mask protects. INCR and DECR
 * saturate at 255 and 0; the _WRAP ops wrap modulo 256. */
CLR_INLINE uint clr_stencil_update(StencilUniforms s, int op, uint stored) {
  uint value;
  switch (op) {
    case CLR_STENCIL_ZERO: value = 0u; break;
    case CLR_STENCIL_REPLACE: value = s.reference; break;
    case CLR_STENCIL_INCR: value = min(stored + 1u, 255u); break;
    case CLR_STENCIL_INCR_WRAP: value = stored + 1u; break;
    case CLR_STENCIL_DECR: value = stored > 0u ? stored - 1u : 0u; break;
    case CLR_STENCIL_DECR_WRAP: value = stored - 1u; break;
    case CLR_STENCIL_INVERT: value = ~stored; break;
    default: value = stored; break; /* CLR_STENCIL_KEEP */
  }
  return ((value & s.write_mask) | (stored & ~s.write_mask)) & 0xffu;
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

/* One blend factor (table 17.2) for all four channels: the rgb factor is its .xyz and the alpha
 * factor its .w, so the same function serves the rgb and the alpha factor of the state. Colours are
 * in units where `one` is full intensity: 1, or 255 for 8-bit values. */
CLR_INLINE float4 blend_factor(int factor, float4 source, float4 destination, float4 constant_color, float one) {
  switch (factor) {
    case CLR_FACTOR_ZERO: return (float4)(0.0f);
    case CLR_FACTOR_SRC_COLOR: return source;
    case CLR_FACTOR_ONE_MINUS_SRC_COLOR: return one - source;
    case CLR_FACTOR_DST_COLOR: return destination;
    case CLR_FACTOR_ONE_MINUS_DST_COLOR: return one - destination;
    case CLR_FACTOR_SRC_ALPHA: return (float4)(source.w);
    case CLR_FACTOR_ONE_MINUS_SRC_ALPHA: return (float4)(one - source.w);
    case CLR_FACTOR_DST_ALPHA: return (float4)(destination.w);
    case CLR_FACTOR_ONE_MINUS_DST_ALPHA: return (float4)(one - destination.w);
    case CLR_FACTOR_CONSTANT_COLOR: return constant_color;
    case CLR_FACTOR_ONE_MINUS_CONSTANT_COLOR: return one - constant_color;
    case CLR_FACTOR_CONSTANT_ALPHA: return (float4)(constant_color.w);
    case CLR_FACTOR_ONE_MINUS_CONSTANT_ALPHA: return (float4)(one - constant_color.w);
    case CLR_FACTOR_SRC_ALPHA_SATURATE: {
      const float f = fmin(source.w, one - destination.w);
      return (float4)(f, f, f, one);
    }
    default: return (float4)(one); /* CLR_FACTOR_ONE */
  }
}

/* llvmpipe's product of two 8-bit values, (ab + (ab >> 8) + 128) >> 8, on integers held in floats. */
CLR_INLINE float4 mul_unorm8(float4 a, float4 b) {
  const float4 ab = a * b;
  return floor((ab + floor(ab / 256.0f) + 128.0f) / 256.0f);
}

/* Whether f and g are one another's complement (ZERO and ONE, SRC_COLOR and ONE_MINUS_SRC_COLOR, ...),
 * and whether f is the plain one of its pair (ONE, SRC_COLOR, ...: what llvmpipe lists first). */
inline bool complementary_factors(int f, int g) {
  return f != g && f / 2 == g / 2 && f < CLR_FACTOR_SRC_ALPHA_SATURATE;
}
inline bool plain_factor(int f) { return f == CLR_FACTOR_ONE || (f % 2 == 0 && f != CLR_FACTOR_ZERO); }

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
CLR_INLINE bool regrouped_blend(int equation, int source_factor_id, int destination_factor_id, float4 s, float4 d,
                                float4 source_factor, float4 destination_factor, bool unorm8, float4* out) {
  if (equation != CLR_BLEND_ADD && (unorm8 || (equation != CLR_BLEND_SUBTRACT &&
                                               equation != CLR_BLEND_REVERSE_SUBTRACT))) {
    return false;
  }
  if (complementary_factors(source_factor_id, destination_factor_id)) {
    const bool source_plain = plain_factor(source_factor_id);
    const float4 f = source_plain ? source_factor : destination_factor;
    const float4 from = source_plain ? d : s, to = source_plain ? s : d;
    if (unorm8) {
      *out = from + floor((f + floor(f / 128.0f)) * (to - from) / 256.0f + 0.5f);
    } else if (equation == CLR_BLEND_ADD) {
      *out = fma(f, to - from, from);
    } else {
      const float4 sum = (s + d) * f;
      if (equation == CLR_BLEND_SUBTRACT) *out = source_plain ? sum - d : s - sum;
      else *out = source_plain ? d - sum : sum - s;
    }
    return true;
  }
  if (unorm8 || source_factor_id != destination_factor_id) return false;
  const float4 combined = equation == CLR_BLEND_ADD ? s + d : equation == CLR_BLEND_SUBTRACT ? s - d : d - s;
  *out = combined * source_factor;
  return true;
}

/* One blend equation (table 17.1) on all four channels; MIN and MAX ignore the factors.
 * unorm8: the colours and factors are 8-bit values (one = 255), multiplied as llvmpipe does.
 * regroup: llvmpipe's rewrites apply (regrouped_blend). */
CLR_INLINE float4 blend_equation(int equation, int source_factor_id, int destination_factor_id, float4 source,
                                 float4 destination, float4 source_factor, float4 destination_factor, bool unorm8,
                                 bool regroup) {
  if (equation == CLR_BLEND_MIN) return fmin(source, destination);
  if (equation == CLR_BLEND_MAX) return fmax(source, destination);
  float4 regrouped;
  if (regroup && regrouped_blend(equation, source_factor_id, destination_factor_id, source, destination,
                                 source_factor, destination_factor, unorm8, &regrouped)) {
    return regrouped;
  }
  const float4 source_term = unorm8 ? mul_unorm8(source, source_factor) : source * source_factor;
  const float4 destination_term = unorm8 ? mul_unorm8(destination, destination_factor) : destination * destination_factor;
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
inline int factor_without_destination_alpha(int factor) {
  switch (factor) {
    case CLR_FACTOR_DST_ALPHA: return CLR_FACTOR_ONE;
    case CLR_FACTOR_ONE_MINUS_DST_ALPHA: return CLR_FACTOR_ZERO;
    default: return factor;
  }
}

inline bool ignores_factors(int equation) { return equation == CLR_BLEND_MIN || equation == CLR_BLEND_MAX; }

/* The rgb equation and factors on .xyz, the alpha ones on .w, for an attachment of `channels` channels. */
CLR_INLINE float4 blend_colors(BlendUniforms b, float4 source, float4 destination, float4 constant_color, bool unorm8,
                               int channels) {
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
  const float4 rgb = blend_equation(b.rgb_equation, b.src_rgb, b.dst_rgb, source, destination,
                                    blend_factor(b.src_rgb, source, destination, constant_color, one),
                                    blend_factor(b.dst_rgb, source, destination, constant_color, one), unorm8, regroup);
  const float4 alpha =
      blend_equation(b.alpha_equation, b.src_alpha, b.dst_alpha, source, destination,
                     blend_factor(b.src_alpha, source, destination, constant_color, one),
                     blend_factor(b.dst_alpha, source, destination, constant_color, one), unorm8, regroup);
  return (float4)(rgb.xyz, alpha.w);
}

/* The blended colour of a float attachment (normalized = false) or an sRGB one (normalized = true,
 * destination rgb decoded to linear) of `channels` channels, before conversion to its format. */
CLR_INLINE float4 clr_blend(BlendUniforms b, float4 source, float4 destination, float4 constant_color, bool normalized,
                            int channels) {
  if (normalized) {
    source = clamp(source, 0.0f, 1.0f);
    destination = clamp(destination, 0.0f, 1.0f);
    constant_color = clamp(constant_color, 0.0f, 1.0f);
  }
  return blend_colors(b, source, destination, constant_color, false, channels);
}

/* A colour in [0, 1] as an 8-bit value, rounded to nearest even as llvmpipe converts (NaN becomes 0). */
CLR_INLINE float4 to_unorm8(float4 c) {
  return rint(clamp(c, 0.0f, 1.0f) * 255.0f);
}

/* The blended colour of a linear 8-bit unsigned normalized attachment, as llvmpipe blends it: a
 * multiple of 1/255 in [0, 1] (so any conversion that rounds to nearest gives the byte).
 * destination: the stored colour, with the channels the format lacks as GL reads them (green and
 * blue 0, alpha 1). */
CLR_INLINE float4 clr_blend_unorm8(BlendUniforms b, float4 source, float4 destination, float4 constant_color,
                                   int channels) {
  const float4 blended =
      blend_colors(b, to_unorm8(source), to_unorm8(destination), to_unorm8(constant_color), true, channels);
  return clamp(blended, 0.0f, 255.0f) / 255.0f;
}

/* ---- Colour write mask (GL 4.6 17.4.2) -------------------------------------------------------------- */

/* BlendUniforms::write_mask as a select() condition: lane c is all ones when channel c is written.
 * Integer attachments use it as select(stored, value, clr_write_mask_lanes(mask)) on their int4 or
 * uint4 values. */
CLR_INLINE int4 clr_write_mask_lanes(uint mask) {
  return -as_int4(((uint4)(mask) >> (uint4)(0u, 1u, 2u, 3u)) & 1u);
}

/* `value` in the written channels, `destination` in the others. */
CLR_INLINE float4 clr_apply_write_mask(uint mask, float4 value, float4 destination) {
  return select(destination, value, clr_write_mask_lanes(mask));
}
