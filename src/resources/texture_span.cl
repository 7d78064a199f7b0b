/* texture_span.cl: texture sampling for span programs (docs/programs.md): clr_sample_grad and
 * clr_sample_lod of a span of coordinates, a sample per lane, each the bits that texture.cl's sample
 * of that lane's coordinates gives (tests/test_program_draws.cpp, SpanPrograms).
 *
 * In spans of eight the sample is vector code, texture.cl's steps on the eight lanes at once: level
 * of detail, the level(s) each lane takes, texel coordinates and wrapping, then the texels, gathered a
 * lane at a time (RGBA8 and sRGB8 ones as one 32-bit word each, decoded in vectors; other formats by
 * texture.cl's load), and their weighted sums. Per lane, as a loop over texture.cl's sample, it took
 * about half of a textured frame (the demo scene with --shading material, docs/performance.md). A
 * lane's level, filter and wrap arithmetic can differ from its neighbours': each step computes what
 * any lane needs and selects. */

#include "raster/span.cl"
#include "resources/format.cl"
#include "resources/texture.cl"
#include "shared/clr_limits.h"
#include "shared/types.h"

#if CLR_SPAN_PIXELS > 1

/* clr_floor_mod and clr_wrap (texture.cl) lane by lane, each lane with its own size. */
static inline clr_span_int clr_span_floor_mod(clr_span_int a, clr_span_int b) {
  const clr_span_int outside = CLR_SPAN_AS(uint, a) >= CLR_SPAN_AS(uint, b);
  const clr_span_int not_power_of_two = (CLR_SPAN_AS(uint, b) << CLR_SPAN_AS(uint, clz(b))) != 0x80000000u;
  clr_span_int result = select(a, a & (b - 1), outside);
  const clr_span_int divided = outside & not_power_of_two;
  if (clr_span_any(divided)) { /* a division per lane: only where some lane is outside a side not a power of two */
    const clr_span_int r = a % select((clr_span_int)(1), b, divided);
    result = select(result, select(r, r + b, r < 0), divided);
  }
  return result;
}

static inline clr_span_int clr_span_wrap(int mode, clr_span_int i, clr_span_int size) {
  switch (mode) {
    case CLR_WRAP_CLAMP_TO_EDGE: return clamp(i, (clr_span_int)(0), size - 1);
    case CLR_WRAP_MIRRORED_REPEAT: {
      const clr_span_int m = clr_span_floor_mod(i, 2 * size) - size;
      return (size - 1) - select(-(1 + m), m, m >= 0);
    }
    default: return clr_span_floor_mod(i, size);
  }
}

static inline clr_span_int clr_span_floor_to_int(clr_span_float u) {
  return CLR_SPAN_CONVERT(int, fmin(fmax(floor(u), -CLR_TEXEL_COORDINATE_LIMIT), CLR_TEXEL_COORDINATE_LIMIT));
}

/* The texels at `index` (texels from the start of the buffer), decoded as clr_load_texel_float does,
 * into *texel. (Out-parameters here, not returned structures: LLVM's inliner marks a returned
 * structure with an intrinsic that Oclgrind cannot run.) */
static inline void clr_span_load_texels(clr_texture t, clr_span_uint index, clr_span_float4* texel) {
  const int format = t.desc->format;
#ifdef __ENDIAN_LITTLE__
  /* Gathers with int indices, which x86 gathers take as they are, where uint ones are widened to 64
   * bits and gathered four at a time (CesiumMilkTruck's textured frame 19.5 -> 17.4 ms). */
  if (format == CLR_FORMAT_RGBA8 || format == CLR_FORMAT_SRGB8_A8) { /* byte c of the word is channel c */
    const clr_span_uint bits = CLR_SPAN_GATHER((__global const uint*)t.data, CLR_SPAN_AS(int, index));
    const clr_span_int r = CLR_SPAN_AS(int, bits & 0xffu), g = CLR_SPAN_AS(int, bits >> 8 & 0xffu),
                       b = CLR_SPAN_AS(int, bits >> 16 & 0xffu);
    if (format == CLR_FORMAT_SRGB8_A8) {
      texel->x = CLR_SPAN_GATHER(clr_srgb_to_linear_table, r);
      texel->y = CLR_SPAN_GATHER(clr_srgb_to_linear_table, g);
      texel->z = CLR_SPAN_GATHER(clr_srgb_to_linear_table, b);
    } else {
      texel->x = clr_unorm8_to_float(CLR_SPAN_CONVERT(float, r));
      texel->y = clr_unorm8_to_float(CLR_SPAN_CONVERT(float, g));
      texel->z = clr_unorm8_to_float(CLR_SPAN_CONVERT(float, b));
    }
    texel->w = clr_unorm8_to_float(CLR_SPAN_CONVERT(float, bits >> 24));
    return;
  }
#endif
#pragma unroll
  for (int lane = 0; lane < CLR_SPAN_PIXELS; ++lane) {
    const float4 value = clr_load_texel_float(format, t.data, CLR_SPAN_LANE(uint, index, lane));
    CLR_SPAN_SET_LANE(texel->x, lane, value.x);
    CLR_SPAN_SET_LANE(texel->y, lane, value.y);
    CLR_SPAN_SET_LANE(texel->z, lane, value.z);
    CLR_SPAN_SET_LANE(texel->w, lane, value.w);
  }
}

/* *a = CLR_LERP(*a, b, w) per channel, as texture.cl blends float4s. */
static inline void clr_span_mix_into(clr_span_float4* a, clr_span_float4 b, clr_span_float w) {
  a->x = CLR_LERP(a->x, b.x, w);
  a->y = CLR_LERP(a->y, b.y, w);
  a->z = CLR_LERP(a->z, b.z, w);
  a->w = CLR_LERP(a->w, b.w, w);
}

/* *a = b where `take_b`. */
static inline void clr_span_select_into(clr_span_float4* a, clr_span_float4 b, clr_span_int take_b) {
  a->x = select(a->x, b.x, take_b);
  a->y = select(a->y, b.y, take_b);
  a->z = select(a->z, b.z, take_b);
  a->w = select(a->w, b.w, take_b);
}

/* clr_filter_level, each lane at its own level (one the texture has), into *result. */
static void clr_span_filter_level(clr_texture t, clr_span_float2 uv, clr_span_int level, int filter,
                                  clr_span_float4* result) {
  __constant const TextureDesc* desc = t.desc;
  const clr_span_int width = max((clr_span_int)(desc->width) >> level, (clr_span_int)(1));
  const clr_span_int height = max((clr_span_int)(desc->height) >> level, (clr_span_int)(1));
  const clr_span_uint offset = CLR_SPAN_GATHER(desc->level_offset, level);
  const clr_span_float u = uv.x * CLR_SPAN_CONVERT(float, width);
  const clr_span_float v = uv.y * CLR_SPAN_CONVERT(float, height);
#define CLR_SPAN_TEXEL_INDEX(i, j) (offset + CLR_SPAN_AS(uint, j) * CLR_SPAN_AS(uint, width) + CLR_SPAN_AS(uint, i))
  if (filter == CLR_FILTER_NEAREST) {
    const clr_span_int i = clr_span_wrap(desc->wrap_s, clr_span_floor_to_int(u), width);
    const clr_span_int j = clr_span_wrap(desc->wrap_t, clr_span_floor_to_int(v), height);
    clr_span_load_texels(t, CLR_SPAN_TEXEL_INDEX(i, j), result);
    return;
  }
  const clr_span_float corner_u = u - 0.5f, corner_v = v - 0.5f;
  const clr_span_float base_u = floor(corner_u), base_v = floor(corner_v);
  const clr_span_float alpha = fmax(corner_u - base_u, 0.0f);
  const clr_span_float beta = fmax(corner_v - base_v, 0.0f);
  const clr_span_int i = clr_span_floor_to_int(base_u);
  const clr_span_int j = clr_span_floor_to_int(base_v);
  const clr_span_int i0 = clr_span_wrap(desc->wrap_s, i, width);
  const clr_span_int i1 = clr_span_wrap(desc->wrap_s, i + 1, width);
  const clr_span_int j0 = clr_span_wrap(desc->wrap_t, j, height);
  const clr_span_int j1 = clr_span_wrap(desc->wrap_t, j + 1, height);
  clr_span_float4 t00, t10, t01, t11;
  clr_span_load_texels(t, CLR_SPAN_TEXEL_INDEX(i0, j0), &t00);
  clr_span_load_texels(t, CLR_SPAN_TEXEL_INDEX(i1, j0), &t10);
  clr_span_load_texels(t, CLR_SPAN_TEXEL_INDEX(i0, j1), &t01);
  clr_span_load_texels(t, CLR_SPAN_TEXEL_INDEX(i1, j1), &t11);
#undef CLR_SPAN_TEXEL_INDEX
  /* CLR_LERP(CLR_LERP(t00, t10, alpha), CLR_LERP(t01, t11, alpha), beta) */
  clr_span_mix_into(&t00, t10, alpha);
  clr_span_mix_into(&t01, t11, alpha);
  clr_span_mix_into(&t00, t01, beta);
  *result = t00;
}

/* The same at each lane's level, with the magnification filter where `magnified`, else the
 * minification one: one filter for the span where they agree. */
static void clr_span_filter_levels(clr_texture t, clr_span_float2 uv, clr_span_int level, clr_span_int magnified,
                                   clr_span_float4* result) {
  __constant const TextureDesc* desc = t.desc;
  if (desc->mag_filter == desc->min_filter || !clr_span_any(magnified)) {
    clr_span_filter_level(t, uv, level, desc->min_filter, result);
  } else if (all(magnified)) {
    clr_span_filter_level(t, uv, level, desc->mag_filter, result);
  } else {
    clr_span_float4 magnification;
    clr_span_filter_level(t, uv, level, desc->min_filter, result);
    clr_span_filter_level(t, uv, level, desc->mag_filter, &magnification);
    clr_span_select_into(result, magnification, magnified);
  }
}

/* clr_sample_lambda: each lane's level(s) and weight as texture.cl picks them, then the filter. */
static void clr_span_sample_lambda(clr_texture t, clr_span_float2 uv, clr_span_float lambda_base,
                                   clr_span_float4* result) {
  __constant const TextureDesc* desc = t.desc;
  if (clr_texture_is_one_texel(t)) {
    clr_span_load_texels(t, (clr_span_uint)(desc->level_offset[0]), result);
    return;
  }
  const float bias = clamp(desc->lod_bias, -CLR_MAX_TEXTURE_LOD_BIAS, CLR_MAX_TEXTURE_LOD_BIAS);
  const clr_span_float lambda = fmin(fmax(lambda_base + bias, desc->min_lod), desc->max_lod);
  const clr_span_int magnified = lambda <= 0.0f; /* level 0, the magnification filter */
  const int q = desc->levels - 1;
  switch (desc->mip_filter) {
    case CLR_MIP_NEAREST: {
      const clr_span_int nearest = CLR_SPAN_CONVERT(int, ceil(lambda + 0.5f)) - 1;
      clr_span_int level = select((clr_span_int)(q), nearest, lambda <= (float)q + 0.5f);
      level = select(level, (clr_span_int)(0), lambda <= 0.5f);
      clr_span_filter_levels(t, uv, level, magnified, result);
      return;
    }
    case CLR_MIP_LINEAR: {
      /* Lanes at or past the last level (or NaN) take it alone, and magnified lanes level 0. */
      const clr_span_int last = (lambda >= (float)q) | isnan(lambda);
      const clr_span_float d1 = floor(lambda);
      const clr_span_int alone = last | magnified;
      const clr_span_int finer_level =
          select(select(CLR_SPAN_CONVERT(int, d1), (clr_span_int)(q), last), (clr_span_int)(0), magnified);
      const clr_span_float weight = select(lambda - d1, (clr_span_float)(0.0f), alone);
      clr_span_filter_levels(t, uv, finer_level, magnified, result); /* the finer level */
      /* A whole lambda takes level d1 alone (and saves filtering the coarser one). */
      const clr_span_int blended = weight != 0.0f;
      if (!clr_span_any(blended)) return;
      clr_span_float4 coarser;
      clr_span_filter_level(t, uv, select(finer_level, finer_level + 1, blended), desc->min_filter, &coarser);
      clr_span_float4 mixed = *result;
      clr_span_mix_into(&mixed, coarser, weight);
      clr_span_select_into(result, mixed, blended);
      return;
    }
    default: clr_span_filter_levels(t, uv, (clr_span_int)(0), magnified, result); /* CLR_MIP_NONE */
  }
}

/* clr_fast_log2, lane by lane. */
static inline clr_span_float clr_span_fast_log2(clr_span_float x) {
  clr_span_int exponent;
  const clr_span_float mantissa = frexp(x, &exponent);
  const clr_span_float approximation = CLR_SPAN_CONVERT(float, exponent - 1) + (2.0f * mantissa - 1.0f);
  return select(log2(x), approximation, (x > 0.0f) & (x < INFINITY));
}

static __attribute__((overloadable)) clr_span_float4 clr_sample_grad(clr_texture t, clr_span_float2 uv,
                                                                     clr_span_float2 duv_dx, clr_span_float2 duv_dy) {
  const float width = (float)t.desc->width, height = (float)t.desc->height;
  const clr_span_float dx_u = duv_dx.x * width, dx_v = duv_dx.y * height;
  const clr_span_float dy_u = duv_dy.x * width, dy_v = duv_dy.y * height;
  const clr_span_float rho_squared = fmax(dx_u * dx_u + dx_v * dx_v, dy_u * dy_u + dy_v * dy_v);
  clr_span_float4 result;
  clr_span_sample_lambda(t, uv, 0.5f * clr_span_fast_log2(rho_squared), &result);
  return result;
}

static __attribute__((overloadable)) clr_span_float4 clr_sample_lod(clr_texture t, clr_span_float2 uv,
                                                                    clr_span_float lod) {
  clr_span_float4 result;
  clr_span_sample_lambda(t, uv, lod, &result);
  return result;
}

#else /* spans of one pixel: texture.cl's sample */

/* Not static, unlike the other helpers (types.h): inlined, these two mark the structure they return
 * with llvm.experimental.noalias.scope.decl, which Oclgrind 21.10 cannot run (the GPU shapes' check,
 * oclgrind_kernels_wide). */
__attribute__((overloadable)) clr_span_float4 clr_sample_grad(clr_texture t, clr_span_float2 uv,
                                                              clr_span_float2 duv_dx, clr_span_float2 duv_dy) {
  const float4 s = clr_sample_grad(t, (float2)(uv.x, uv.y), (float2)(duv_dx.x, duv_dx.y), (float2)(duv_dy.x, duv_dy.y));
  const clr_span_float4 result = {s.x, s.y, s.z, s.w};
  return result;
}

__attribute__((overloadable)) clr_span_float4 clr_sample_lod(clr_texture t, clr_span_float2 uv,
                                                             clr_span_float lod) {
  const float4 s = clr_sample_lod(t, (float2)(uv.x, uv.y), lod);
  const clr_span_float4 result = {s.x, s.y, s.z, s.w};
  return result;
}

#endif
