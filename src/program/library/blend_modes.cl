/* blend_modes.cl: the advanced blend equations of KHR_blend_equation_advanced (the PDF and
 * Photoshop modes), for a program's blend function:
 *
 *   float4 blend(...) { return clr_blend_overlay(source, destination); }
 *
 * Every clr_blend_<mode>(source, destination) takes premultiplied colours and returns the
 * premultiplied result, exactly as the extension defines it:
 *
 *   Cs' = Cs / As (0 when As = 0), Cd' = Cd / Ad (0 when Ad = 0)
 *   p0 = As * Ad, p1 = As * (1 - Ad), p2 = Ad * (1 - As)
 *   RGB = f(Cs', Cd') * p0 + Y * Cs' * p1 + Z * Cd' * p2
 *   A   =           X * p0 + Y * p1      + Z * p2
 *
 * with (X, Y, Z) = (1, 1, 1) for all fifteen modes, which differ only in f. The extension blends
 * with at least half-float precision; these are float throughout. Against llvmpipe's
 * KHR_blend_equation_advanced on RGBA8 (premultiplied colours, alphas 0, partial and 1), the results
 * rounded to 8 bits were identical in all but one of 245760 channels, off by 1/255. */

#include "shared/types.h" /* FP_CONTRACT OFF, as in every kernel source */

/* The non-premultiplied colour of a premultiplied one, black when alpha is 0. */
static inline float3 clr_khr_unpremultiply(float4 c) {
  return c.w == 0.0f ? (float3)(0.0f) : c.xyz / c.w;
}

/* Combines f(Cs', Cd') with the uncorrelated coverages of source and destination. */
static inline float4 clr_khr_compose(float3 f, float3 cs, float3 cd, float as, float ad) {
  const float p0 = as * ad;
  const float p1 = as * (1.0f - ad);
  const float p2 = ad * (1.0f - as);
  return (float4)(f * p0 + cs * p1 + cd * p2, p0 + p1 + p2);
}

/* ---- f(Cs, Cd) of table X.1, per channel of non-premultiplied colours -------------------------- */

static inline float3 clr_khr_multiply(float3 cs, float3 cd) { return cs * cd; }

static inline float3 clr_khr_screen(float3 cs, float3 cd) { return cs + cd - cs * cd; }

static inline float3 clr_khr_overlay(float3 cs, float3 cd) {
  return select(1.0f - 2.0f * (1.0f - cs) * (1.0f - cd), 2.0f * cs * cd, cd <= 0.5f);
}

static inline float3 clr_khr_darken(float3 cs, float3 cd) { return fmin(cs, cd); }

static inline float3 clr_khr_lighten(float3 cs, float3 cd) { return fmax(cs, cd); }

static inline float3 clr_khr_colordodge(float3 cs, float3 cd) {
  const float3 dodged = select((float3)(1.0f), fmin(cd / (1.0f - cs), 1.0f), cs < 1.0f);
  return select((float3)(0.0f), dodged, cd > 0.0f);
}

static inline float3 clr_khr_colorburn(float3 cs, float3 cd) {
  const float3 burnt = select((float3)(0.0f), 1.0f - fmin((1.0f - cd) / cs, 1.0f), cs > 0.0f);
  return select((float3)(1.0f), burnt, cd < 1.0f);
}

/* HARDLIGHT is OVERLAY with the roles of source and destination swapped (both products are
 * symmetric; only the channel that picks the branch changes). */
static inline float3 clr_khr_hardlight(float3 cs, float3 cd) { return clr_khr_overlay(cd, cs); }

static inline float3 clr_khr_softlight(float3 cs, float3 cd) {
  const float3 darker = cd - (1.0f - 2.0f * cs) * cd * (1.0f - cd);
  const float3 lighter_dark = cd + (2.0f * cs - 1.0f) * cd * ((16.0f * cd - 12.0f) * cd + 3.0f);
  const float3 lighter_bright = cd + (2.0f * cs - 1.0f) * (sqrt(cd) - cd);
  return select(select(lighter_bright, lighter_dark, cd <= 0.25f), darker, cs <= 0.5f);
}

static inline float3 clr_khr_difference(float3 cs, float3 cd) { return fabs(cd - cs); }

static inline float3 clr_khr_exclusion(float3 cs, float3 cd) { return cs + cd - 2.0f * cs * cd; }

/* ---- f(Cs, Cd) of table X.2: hue, saturation and luminosity, with the extension's helpers -------- */

static inline float clr_khr_min3(float3 c) { return fmin(fmin(c.x, c.y), c.z); }
static inline float clr_khr_max3(float3 c) { return fmax(fmax(c.x, c.y), c.z); }
static inline float clr_khr_lum(float3 c) { return dot(c, (float3)(0.30f, 0.59f, 0.11f)); }
static inline float clr_khr_sat(float3 c) { return clr_khr_max3(c) - clr_khr_min3(c); }

/* Pulls a colour with components outside [0, 1] back in range, keeping its luminosity. */
static inline float3 clr_khr_clip_color(float3 color) {
  const float lum = clr_khr_lum(color);
  const float mincol = clr_khr_min3(color);
  const float maxcol = clr_khr_max3(color);
  if (mincol < 0.0f) color = lum + ((color - lum) * lum) / (lum - mincol);
  if (maxcol > 1.0f) color = lum + ((color - lum) * (1.0f - lum)) / (maxcol - lum);
  return color;
}

/* `cbase` with the luminosity of `clum`. */
static inline float3 clr_khr_set_lum(float3 cbase, float3 clum) {
  return clr_khr_clip_color(cbase + (clr_khr_lum(clum) - clr_khr_lum(cbase)));
}

/* `cbase` with the saturation of `csat`, then the luminosity of `clum`. */
static inline float3 clr_khr_set_lum_sat(float3 cbase, float3 csat, float3 clum) {
  const float sbase = clr_khr_sat(cbase);
  const float3 color = sbase > 0.0f ? (cbase - clr_khr_min3(cbase)) * clr_khr_sat(csat) / sbase : (float3)(0.0f);
  return clr_khr_set_lum(color, clum);
}

static inline float3 clr_khr_hsl_hue(float3 cs, float3 cd) { return clr_khr_set_lum_sat(cs, cd, cd); }
static inline float3 clr_khr_hsl_saturation(float3 cs, float3 cd) { return clr_khr_set_lum_sat(cd, cs, cd); }
static inline float3 clr_khr_hsl_color(float3 cs, float3 cd) { return clr_khr_set_lum(cs, cd); }
static inline float3 clr_khr_hsl_luminosity(float3 cs, float3 cd) { return clr_khr_set_lum(cd, cs); }

/* ---- The blend functions programs call -------------------------------------------------------------- */

#define CLR_KHR_BLEND_MODE(mode)                                                     \
  static inline float4 clr_blend_##mode(float4 source, float4 destination) {        \
    const float3 cs = clr_khr_unpremultiply(source);                                 \
    const float3 cd = clr_khr_unpremultiply(destination);                            \
    return clr_khr_compose(clr_khr_##mode(cs, cd), cs, cd, source.w, destination.w); \
  }

CLR_KHR_BLEND_MODE(multiply)
CLR_KHR_BLEND_MODE(screen)
CLR_KHR_BLEND_MODE(overlay)
CLR_KHR_BLEND_MODE(darken)
CLR_KHR_BLEND_MODE(lighten)
CLR_KHR_BLEND_MODE(colordodge)
CLR_KHR_BLEND_MODE(colorburn)
CLR_KHR_BLEND_MODE(hardlight)
CLR_KHR_BLEND_MODE(softlight)
CLR_KHR_BLEND_MODE(difference)
CLR_KHR_BLEND_MODE(exclusion)
CLR_KHR_BLEND_MODE(hsl_hue)
CLR_KHR_BLEND_MODE(hsl_saturation)
CLR_KHR_BLEND_MODE(hsl_color)
CLR_KHR_BLEND_MODE(hsl_luminosity)

#undef CLR_KHR_BLEND_MODE
