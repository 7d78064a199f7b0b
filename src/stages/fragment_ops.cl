/* fragment_ops.cl: OpenGL's per-fragment operations after the fragment program (GL 4.6 section 17.3),
 * as functions the rasterizer calls per fragment and per colour attachment, in this order:
 *
 *   stencil test     clr_stencil_test, then clr_stencil_update with the op clr_stencil_op picks
 *   depth test       clr_compare
 *   blending         clr_blend (fixed-function equations and factors)
 *   write mask       clr_apply_write_mask
 *
 * The state comes as the BlendUniforms and StencilUniforms of types.h, passed by value so the caller
 * may hold them in any address space. Everything here is pure arithmetic on one fragment: the caller
 * reads and writes the framebuffer and converts between storage formats and floats. */

/* ---- Comparisons (GL 4.6 17.3.3, 17.3.4) ---------------------------------------------------------
 * `fragment` func `stored`, in GL's operand order (LESS passes when fragment < stored). IEEE rules:
 * -0 equals +0, and every ordered comparison with a NaN fails, so only NOTEQUAL and ALWAYS pass a
 * NaN. CLR_COMPARE_PROGRAM is the caller's business; here it passes, like ALWAYS. */
inline bool clr_compare(int func, float fragment, float stored) {
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
inline bool clr_stencil_test(StencilUniforms s, uint stored) {
  return clr_compare(s.func, (float)(s.reference & s.read_mask), (float)(stored & s.read_mask));
}

/* Which of the face's three ops applies. A fragment that fails the stencil test never reaches the
 * depth test; pass depth_passed = true when there is no depth test (disabled or no depth buffer). */
inline int clr_stencil_op(StencilUniforms s, bool stencil_passed, bool depth_passed) {
  if (!stencil_passed) return s.stencil_fail;
  return depth_passed ? s.depth_pass : s.depth_fail;
}

/* The stencil value after `op` (CLR_STENCIL_*), keeping the bits write_mask protects. INCR and DECR
 * saturate at 255 and 0; the _WRAP ops wrap modulo 256. */
inline uint clr_stencil_update(StencilUniforms s, int op, uint stored) {
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
 * Precision. All arithmetic is 32-bit float, each product and sum rounded once (types.h turns
 * FP_CONTRACT off), which is at least the destination's precision for every attachment format, as GL
 * requires. Non-finite colours follow IEEE arithmetic (a ZERO factor times an infinity is NaN).
 *
 * Normalized (RGBA8-family) attachments: GL clamps the source, the destination and the constant
 * colour to [0, 1] before blending; the result is not clamped here but by the conversion to fixed
 * point that follows (17.3.7), which the caller does.
 *
 * Matching llvmpipe on 8-bit attachments. llvmpipe does not blend RGBA8 in float: it converts the
 * fragment colour and the constant colour to 8 bits first (round to nearest), computes factors in
 * 8 bits (1 - x as 255 - x), rounds each product to 8 bits (lp_build_mul_norm: (ab + (ab >> 8) +
 * 0x80) >> 8, which is round(ab / 255)), and adds or subtracts with 8-bit saturation. Two cases
 * differ: MIN and MAX take no products, and ADD with complementary factors (SRC_ALPHA with
 * ONE_MINUS_SRC_ALPHA, ONE with ZERO, ...; the same for rgb and alpha) becomes a lerp d + f * (s - d)
 * whose weight is rescaled to f + (f >> 7) over 256 and whose product is rounded once (pmulhrsw).
 * Each of those steps is within half a unit of the exact value, and they round per term, so
 * llvmpipe's result stays within one unit of the exact sum rounded once. We compute the exact sum
 * in float from the same 8-bit inputs: pass the fragment and constant colours through
 * clr_round_unorm8 before clr_blend for linear 8-bit attachments, and round the result to nearest.
 * Blending unrounded inputs instead lets a factor built from the source (SRC_ALPHA, ...) drift by
 * half a unit before it multiplies, and the result by up to two units.
 * sRGB attachments are the exception: llvmpipe blends them in float, on the linearized destination
 * (17.3.6.1), so their source is not rounded; the caller decodes the destination's rgb before
 * clr_blend and encodes the result after. Float attachments are blended in float by llvmpipe too. */

/* A colour rounded to the nearest 8-bit unsigned normalized value, as llvmpipe converts fragment and
 * constant colours before blending 8-bit attachments (ties to even; NaN becomes 0). */
inline float4 clr_round_unorm8(float4 c) {
  return rint(clamp(c, 0.0f, 1.0f) * 255.0f) / 255.0f;
}

/* One blend factor (table 17.2) for all four channels: the rgb factor is its .xyz and the alpha
 * factor its .w, so the same function serves the rgb and the alpha factor of the state. */
inline float4 blend_factor(int factor, float4 source, float4 destination, float4 constant_color) {
  switch (factor) {
    case CLR_FACTOR_ZERO: return (float4)(0.0f);
    case CLR_FACTOR_SRC_COLOR: return source;
    case CLR_FACTOR_ONE_MINUS_SRC_COLOR: return 1.0f - source;
    case CLR_FACTOR_DST_COLOR: return destination;
    case CLR_FACTOR_ONE_MINUS_DST_COLOR: return 1.0f - destination;
    case CLR_FACTOR_SRC_ALPHA: return (float4)(source.w);
    case CLR_FACTOR_ONE_MINUS_SRC_ALPHA: return (float4)(1.0f - source.w);
    case CLR_FACTOR_DST_ALPHA: return (float4)(destination.w);
    case CLR_FACTOR_ONE_MINUS_DST_ALPHA: return (float4)(1.0f - destination.w);
    case CLR_FACTOR_CONSTANT_COLOR: return constant_color;
    case CLR_FACTOR_ONE_MINUS_CONSTANT_COLOR: return 1.0f - constant_color;
    case CLR_FACTOR_CONSTANT_ALPHA: return (float4)(constant_color.w);
    case CLR_FACTOR_ONE_MINUS_CONSTANT_ALPHA: return (float4)(1.0f - constant_color.w);
    case CLR_FACTOR_SRC_ALPHA_SATURATE: {
      const float f = fmin(source.w, 1.0f - destination.w);
      return (float4)(f, f, f, 1.0f);
    }
    default: return (float4)(1.0f); /* CLR_FACTOR_ONE */
  }
}

/* One blend equation (table 17.1) on all four channels. MIN and MAX ignore the factors. */
inline float4 blend_equation(int equation, float4 source, float4 destination, float4 source_factor,
                             float4 destination_factor) {
  switch (equation) {
    case CLR_BLEND_SUBTRACT: return source * source_factor - destination * destination_factor;
    case CLR_BLEND_REVERSE_SUBTRACT: return destination * destination_factor - source * source_factor;
    case CLR_BLEND_MIN: return fmin(source, destination);
    case CLR_BLEND_MAX: return fmax(source, destination);
    default: return source * source_factor + destination * destination_factor; /* CLR_BLEND_ADD */
  }
}

/* The blended colour of one attachment, before conversion to its format. `normalized`: the
 * attachment is unsigned normalized, so the inputs are clamped to [0, 1] first. */
inline float4 clr_blend(BlendUniforms b, float4 source, float4 destination, float4 constant_color,
                        bool normalized) {
  if (normalized) {
    source = clamp(source, 0.0f, 1.0f);
    destination = clamp(destination, 0.0f, 1.0f);
    constant_color = clamp(constant_color, 0.0f, 1.0f);
  }
  const float4 rgb = blend_equation(b.rgb_equation, source, destination,
                                    blend_factor(b.src_rgb, source, destination, constant_color),
                                    blend_factor(b.dst_rgb, source, destination, constant_color));
  const float4 alpha = blend_equation(b.alpha_equation, source, destination,
                                      blend_factor(b.src_alpha, source, destination, constant_color),
                                      blend_factor(b.dst_alpha, source, destination, constant_color));
  return (float4)(rgb.xyz, alpha.w);
}

/* ---- Colour write mask (GL 4.6 17.4.2) -------------------------------------------------------------- */

/* BlendUniforms::write_mask as a select() condition: lane c is all ones when channel c is written.
 * Integer attachments use it as select(stored, value, clr_write_mask_lanes(mask)) on their int4 or
 * uint4 values. */
inline int4 clr_write_mask_lanes(uint mask) {
  return -as_int4(((uint4)(mask) >> (uint4)(0u, 1u, 2u, 3u)) & 1u);
}

/* `value` in the written channels, `destination` in the others. */
inline float4 clr_apply_write_mask(uint mask, float4 value, float4 destination) {
  return select(destination, value, clr_write_mask_lanes(mask));
}
