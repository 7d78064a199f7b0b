/* texture.cl: sampling textures in software, by OpenGL 4.6's rules (sections 8.14 and 8.15).
 *
 * A texture is its buffer and its TextureDesc (types.h): every level in one buffer, and the sampler's
 * state. Reading buffers directly is about three times faster than read_imagef on PoCL, works on
 * every device, and lets every format and every wrap mode follow OpenGL to the texel.
 *
 *   level of detail   lambda = clamp(lambda_base + clamp(lod_bias, +-CLR_MAX_TEXTURE_LOD_BIAS), min_lod, max_lod),
 *                     lambda_base = log2(rho) from the gradients, or the explicit lod
 *   filter            lambda <= 0: magnification, mag_filter on level 0; else min_filter, on
 *                     level 0 (mip none), on the nearest level (ceil(lambda + 1/2) - 1, clamped), or
 *                     blended between levels floor(lambda) and floor(lambda) + 1 by frac(lambda)
 *   texel selection   nearest: i = wrap(floor(u)); linear: i0 = wrap(floor(u - 1/2)), i1 = wrap(i0 + 1)
 *                     weighted by frac(u - 1/2); u = s * level width (and likewise t, j)
 *
 * Texels are decoded before they are filtered, so sRGB textures are filtered in linear space and
 * depth textures sample as (depth, 0, 0, 1). Integer textures are only read with texel fetches.
 */

#include "resources/format.cl"
#include "shared/clr_limits.h"
#include "shared/types.h"

typedef struct {
  __global const uchar* data;          /* the texture's buffer */
  __constant const TextureDesc* desc;  /* its layout and the sampler's state */
} clr_texture;

static int clr_texture_levels(clr_texture t) { return t.desc->levels; }

/* Width and height of `level`; (0, 0) for a level the texture does not have. */
static int2 clr_texture_size(clr_texture t, int level) {
  if (level < 0 || level >= t.desc->levels) return (int2)(0, 0);
  return (int2)(max(1, t.desc->width >> level), max(1, t.desc->height >> level));
}

/* Index of texel (i, j) of `level` (whose size is `size`), in texels from the start of the buffer. */
static uint clr_texel_index(clr_texture t, int level, int2 size, int i, int j) {
  return t.desc->level_offset[level] + (uint)j * (uint)size.x + (uint)i;
}

/* ---- Texel fetches (texelFetch): exact texels, no filtering, no wrapping ------------------------------
 * OpenGL leaves a fetch outside the level, or of a level the texture does not have, undefined: here
 * it reads zeros, in every channel. */

static bool clr_fetch_index(clr_texture t, int2 texel, int level, uint* index) {
  const int2 size = clr_texture_size(t, level);
  if (texel.x < 0 || texel.y < 0 || texel.x >= size.x || texel.y >= size.y) return false;
  *index = clr_texel_index(t, level, size, texel.x, texel.y);
  return true;
}

static float4 clr_texel_fetch(clr_texture t, int2 texel, int level) {
  uint index;
  return clr_fetch_index(t, texel, level, &index) ? clr_load_texel_float(t.desc->format, t.data, index) : (float4)(0.0f);
}

static int4 clr_texel_fetch_int(clr_texture t, int2 texel, int level) {
  uint index;
  return clr_fetch_index(t, texel, level, &index) ? clr_load_texel_int(t.desc->format, t.data, index) : (int4)(0);
}

static uint4 clr_texel_fetch_uint(clr_texture t, int2 texel, int level) {
  uint index;
  return clr_fetch_index(t, texel, level, &index) ? clr_load_texel_uint(t.desc->format, t.data, index) : (uint4)(0u);
}

/* ---- Wrapping (section 8.14.2, table 8.20) ------------------------------------------------------------ */

/* a mod b, in [0, b) also for negative a. */
static int clr_floor_mod(int a, int b) {
  /* Without a division where it can (a division was a fifth of a bilinear sample): inside already,
   * or a power of two, whose mask is the floor modulo in two's complement. The power of two found
   * with clz: LLVM makes a population count of b & (b - 1), which Oclgrind cannot run. */
  if ((uint)a < (uint)b) return a;
  if (((uint)b << clz(b)) == 0x80000000u) return a & (b - 1);
  const int r = a % b;
  return r < 0 ? r + b : r;
}

/* The texel that integer coordinate i (any integer) selects in a row or column of `size` texels. */
static int clr_wrap(int mode, int i, int size) {
  switch (mode) {
    case CLR_WRAP_CLAMP_TO_EDGE: return clamp(i, 0, size - 1);
    case CLR_WRAP_MIRRORED_REPEAT: {
      const int m = clr_floor_mod(i, 2 * size) - size;
      return (size - 1) - (m >= 0 ? m : -(1 + m)); /* (size - 1) - mirror(m) */
    }
    default: return clr_floor_mod(i, size); /* CLR_WRAP_REPEAT */
  }
}

/* floor(u) as an integer. Coordinates beyond +-2^30 texels (where floats no longer tell texels apart)
 * are clamped there, so i + 1 and the wrap arithmetic cannot overflow; NaN becomes -2^30. */
#define CLR_TEXEL_COORDINATE_LIMIT 1073741824.0f
static int clr_floor_to_int(float u) {
  return convert_int(fmin(fmax(floor(u), -CLR_TEXEL_COORDINATE_LIMIT), CLR_TEXEL_COORDINATE_LIMIT));
}

/* ---- Filtering one level -------------------------------------------------------------------------------- */

/* The linear blend a + (b - a) * w, written out rather than mix(): OpenCL leaves mix()'s precision
 * to the implementation, and Intel's CPU runtime rounds its scalar and vector mix differently, so
 * that a span program's samples (texture_span.cl) differed from its per-fragment twin's in the last
 * bit. Plain operations round the same everywhere (FP_CONTRACT is off, types.h). For scalars, vectors
 * and span vectors alike. */
#define CLR_LERP(a, b, w) ((a) + ((b) - (a)) * (w))

static float4 clr_filter_level(clr_texture t, float2 uv, int level, int filter) {
  __constant const TextureDesc* desc = t.desc;
  const int2 size = clr_texture_size(t, level);
  const float2 texel = uv * convert_float2(size); /* (u, v) */
  if (filter == CLR_FILTER_NEAREST) {
    const int i = clr_wrap(desc->wrap_s, clr_floor_to_int(texel.x), size.x);
    const int j = clr_wrap(desc->wrap_t, clr_floor_to_int(texel.y), size.y);
    return clr_load_texel_float(desc->format, t.data, clr_texel_index(t, level, size, i, j));
  }
  const float2 corner = texel - 0.5f;
  const float2 base = floor(corner);
  /* fmax turns the NaN that infinite coordinates give into 0. */
  const float alpha = fmax(corner.x - base.x, 0.0f);
  const float beta = fmax(corner.y - base.y, 0.0f);
  const int i = clr_floor_to_int(base.x);
  const int j = clr_floor_to_int(base.y);
  const int i0 = clr_wrap(desc->wrap_s, i, size.x);
  const int i1 = clr_wrap(desc->wrap_s, i + 1, size.x);
  const int j0 = clr_wrap(desc->wrap_t, j, size.y);
  const int j1 = clr_wrap(desc->wrap_t, j + 1, size.y);
  const float4 t00 = clr_load_texel_float(desc->format, t.data, clr_texel_index(t, level, size, i0, j0));
  const float4 t10 = clr_load_texel_float(desc->format, t.data, clr_texel_index(t, level, size, i1, j0));
  const float4 t01 = clr_load_texel_float(desc->format, t.data, clr_texel_index(t, level, size, i0, j1));
  const float4 t11 = clr_load_texel_float(desc->format, t.data, clr_texel_index(t, level, size, i1, j1));
  /* OpenGL's weighted sum, as lerps: equal texels give exactly their value. */
  return CLR_LERP(CLR_LERP(t00, t10, alpha), CLR_LERP(t01, t11, alpha), beta);
}

/* ---- Level of detail and mipmapping (sections 8.14.1, 8.14.3) --------------------------------------------- */

/* A texture of one texel (a material's white texture, a constant colour) samples as that texel
 * whatever the coordinates, filters and level of detail: every tap is it, and the lerps of equal
 * texels give exactly their value (weights that are NaN are made 0 first). Samplers return it at
 * once, without filtering. (The derivatives before are still taken: skipping the quad exchange's
 * barriers in some calls blew PoCL's build of a program sampling in every shape up past 5 GB.) */
static inline bool clr_texture_is_one_texel(clr_texture t) { return t.desc->width == 1 && t.desc->height == 1; }

/* Samples with lambda_base, the unbiased, unclamped level of detail. NaN anywhere picks a level the
 * texture has, never an out-of-range one. */
static float4 clr_sample_lambda(clr_texture t, float2 uv, float lambda_base) {
  __constant const TextureDesc* desc = t.desc;
  if (clr_texture_is_one_texel(t)) return clr_load_texel_float(desc->format, t.data, desc->level_offset[0]);
  const float bias = clamp(desc->lod_bias, -CLR_MAX_TEXTURE_LOD_BIAS, CLR_MAX_TEXTURE_LOD_BIAS);
  const float lambda = fmin(fmax(lambda_base + bias, desc->min_lod), desc->max_lod);
  if (lambda <= 0.0f) return clr_filter_level(t, uv, 0, desc->mag_filter);

  const int q = desc->levels - 1; /* the last level */
  switch (desc->mip_filter) {
    case CLR_MIP_NEAREST: {
      int level = q;
      if (lambda <= 0.5f) level = 0;
      else if (lambda <= (float)q + 0.5f) level = (int)ceil(lambda + 0.5f) - 1;
      return clr_filter_level(t, uv, level, desc->min_filter);
    }
    case CLR_MIP_LINEAR: {
      if (!(lambda < (float)q)) return clr_filter_level(t, uv, q, desc->min_filter);
      const float d1 = floor(lambda);
      const float weight = lambda - d1;
      const float4 finer = clr_filter_level(t, uv, (int)d1, desc->min_filter);
      /* A whole lambda takes level d1 alone (and saves filtering the coarser one). */
      if (weight == 0.0f) return finer;
      const float4 coarser = clr_filter_level(t, uv, (int)d1 + 1, desc->min_filter);
      return CLR_LERP(finer, coarser, weight);
    }
    default: return clr_filter_level(t, uv, 0, desc->min_filter); /* CLR_MIP_NONE */
  }
}

/* textureLod: an explicit level of detail, to which the sampler's bias and lod range still apply. */
static __attribute__((overloadable)) float4 clr_sample_lod(clr_texture t, float2 uv, float lod) {
  return clr_sample_lambda(t, uv, lod);
}

/* log2(x) approximated as llvmpipe's lp_build_fast_log2 does: exact at powers of two and linear in
 * between, floor(log2(x)) + x / 2^floor(log2(x)) - 1, at most 0.086 below log2(x). Zero, infinities
 * and NaN go to log2 (-inf, inf, NaN), where the approximation has nothing to add. */
static float clr_fast_log2(float x) {
  if (!(x > 0.0f) || isinf(x)) return log2(x);
  int exponent;
  const float mantissa = frexp(x, &exponent); /* x = mantissa * 2^exponent, mantissa in [0.5, 1) */
  return (float)(exponent - 1) + (2.0f * mantissa - 1.0f);
}

/* textureGrad: the level of detail from the derivatives of (s, t) along window x and y:
 * rho = max(|d(u, v)/dx|, |d(u, v)/dy|) in level-0 texels, lambda_base = log2(rho).
 * OpenGL lets implementations approximate this function (section 8.14.1). clraster computes it as
 * llvmpipe does (gallivm's lp_build_lod_selector: lambda_base = 0.5 * fast_log2(rho^2)), so that its
 * mip selection and trilinear weights agree with the oracle's: exact log2 chose levels up to 0.043
 * higher than llvmpipe across a receding plane, enough to move trilinear results by several 1/255. */
static __attribute__((overloadable)) float4 clr_sample_grad(clr_texture t, float2 uv, float2 duv_dx, float2 duv_dy) {
  const float2 size = (float2)((float)t.desc->width, (float)t.desc->height);
  const float2 dx = duv_dx * size;
  const float2 dy = duv_dy * size;
  /* Written out rather than dot(), whose rounding is the implementation's, as the span sampler does. */
  const float rho_squared = fmax(dx.x * dx.x + dx.y * dx.y, dy.x * dy.x + dy.y * dy.y);
  return clr_sample_lambda(t, uv, 0.5f * clr_fast_log2(rho_squared));
}

/* ---- Mipmap generation ------------------------------------------------------------------------------------ */

/* Level source_level + 1 from source_level, one work-item per destination texel: the source level
 * sampled bilinearly at the destination texel's centre, so `desc` must describe the texture with a
 * linear, clamp-to-edge sampler. This is what Mesa's glGenerateMipmap does (a linear blit from level
 * to level): where a side halves exactly, it is a 2x2 box filter; where it is odd (5 -> 2), the
 * source texels are weighted by how far each destination centre falls between them (1.25 -> texels 0
 * and 1, weighted 1/4 and 3/4). Texels are filtered decoded, so sRGB levels are filtered in linear
 * space and encoded again. Not for integer formats. */
__kernel void texture_downsample(__global uchar* data, __constant const TextureDesc* desc, int source_level) {
  const clr_texture t = {data, desc};
  const int2 target = clr_texture_size(t, source_level + 1);
  const uint id = get_global_id(0);
  if (id >= (uint)target.x * (uint)target.y) return;
  const int x = id % target.x;
  const int y = id / target.x;
  const float2 centre = ((float2)((float)x, (float)y) + 0.5f) / convert_float2(target);
  float4 value = clr_filter_level(t, centre, source_level, CLR_FILTER_LINEAR);
  const int2 source = clr_texture_size(t, source_level);
  const int format = desc->format;
  if ((format == CLR_FORMAT_R8 || format == CLR_FORMAT_RG8 || format == CLR_FORMAT_RGBA8) && all(source == 2 * target)) {
    /* llvmpipe's glGenerateMipmap blends 8-bit texels in 8-bit arithmetic, each of its two linear
     * steps (along x, then along y) rounding halves up; its levels are what OpenGL users see, so
     * halving sides get the same bytes here. */
    const uint4 t00 = convert_uint4_rte(clr_texel_fetch(t, (int2)(2 * x, 2 * y), source_level) * 255.0f);
    const uint4 t10 = convert_uint4_rte(clr_texel_fetch(t, (int2)(2 * x + 1, 2 * y), source_level) * 255.0f);
    const uint4 t01 = convert_uint4_rte(clr_texel_fetch(t, (int2)(2 * x, 2 * y + 1), source_level) * 255.0f);
    const uint4 t11 = convert_uint4_rte(clr_texel_fetch(t, (int2)(2 * x + 1, 2 * y + 1), source_level) * 255.0f);
    const uint4 bottom = (t00 + t10 + 1u) >> 1;
    const uint4 top = (t01 + t11 + 1u) >> 1;
    value = clr_unorm8_to_float(convert_float4((bottom + top + 1u) >> 1));
  }
  clr_store_texel_float(desc->format, data, clr_texel_index(t, source_level + 1, target, x, y), value);
}
