/* prelude.cl: what user programs call, besides OpenCL C's built-ins (docs/programs.md lists it all).
 * Compiled after the generated interface (clr_vertex, clr_fragment) and before the user's source. */

#include "program/library/blend_modes.cl"
#include "raster/span.cl"
#include "resources/texture.cl"
#include "resources/texture_span.cl"
#include "shared/types.h"

/* The declaration macros expand to nothing: the generator read them already. */
#define clr_attribute(type, name)
#define clr_varying(type, name)
#define clr_varying_flat(type, name)
#define clr_varying_noperspective(type, name)
#define clr_uniform(type, name)
#define clr_texture(name)
#define clr_buffer(type, name)
#define clr_output(type, name)

/* ---- Matrices: float16 holds a column-major 4x4 matrix (as glUniformMatrix4fv) ---------------- */
static inline float4 clr_mul(float16 m, float4 v) {
  return m.s0123 * v.x + m.s4567 * v.y + m.s89ab * v.z + m.scdef * v.w;
}
static inline float16 clr_mul_matrix(float16 a, float16 b) {
  return (float16)(clr_mul(a, b.s0123), clr_mul(a, b.s4567), clr_mul(a, b.s89ab), clr_mul(a, b.scdef));
}
/* The upper-left 3x3 of m times v (directions, or normals with the inverse-transpose). */
static inline float3 clr_mul3(float16 m, float3 v) { return m.s012 * v.x + m.s456 * v.y + m.s89a * v.z; }

/* ---- Fragments ---------------------------------------------------------------------------------- */
/* Discards the fragment: nothing of it is written. The program keeps running (its derivatives must
 * stay available to the rest of its quad), so return after it where that matters. */
static inline void clr_discard(clr_fragment* f) { f->discarded = true; }

/* Framebuffer fetch: colour attachment `target` at this pixel as it is before this fragment is
 * written (after every earlier fragment of the draw and of earlier draws). */
static inline float4 clr_framebuffer_fetch(const clr_fragment* f, uint target) {
  return target < CLR_NUM_OUTPUTS ? as_float4(clr_tile_pixel(f->clr_tile, target, f->clr_lane)) : (float4)(0.0f);
}
static inline int4 clr_framebuffer_fetch_int(const clr_fragment* f, uint target) {
  return target < CLR_NUM_OUTPUTS ? as_int4(clr_tile_pixel(f->clr_tile, target, f->clr_lane)) : (int4)(0);
}
static inline uint4 clr_framebuffer_fetch_uint(const clr_fragment* f, uint target) {
  return target < CLR_NUM_OUTPUTS ? clr_tile_pixel(f->clr_tile, target, f->clr_lane) : (uint4)(0);
}

/* ---- Derivatives -------------------------------------------------------------------------------------
 * Fragments are shaded in 2x2 quads aligned to even window coordinates. A derivative is the
 * difference between horizontal (x) or vertical (y) neighbours of the quad: "fine" uses this
 * fragment's own row or column, "coarse" the quad's first (lowest) row or column for all four.
 * Values are exchanged through local memory between the tile's work-items, so every fragment of
 * the tile must reach each derivative call (no derivatives inside branches that differ between
 * fragments, the same rule as GLSL's "uniform control flow"). */
/* dFdx and dFdy without a suffix: fine, as llvmpipe computes them. llvmpipe computes every variant
 * (dFdx, dFdxCoarse, dFdxFine) alike, from this fragment's own row or column of its quad: gallivm's
 * lp_build_ddx subtracts the quad's left pixel from its right one in each row (lp_bld_quad.c), and
 * tests/test_program_conformance.cpp (Derivatives) finds all three equal to clr_dfdx_fine. */
#define CLR_DEFAULT_DERIVATIVE_COARSE false
#define CLR_QUAD_X 0
#define CLR_QUAD_Y 1

/* Makes `value`, the value at the tile's pixel `lane`, visible to its quad through `quad`, the
 * tile's exchange; returns the difference along `axis`. */
static inline float4 clr_quad_difference(__local float4* quad, uint lane, float4 value, int axis, bool coarse) {
  barrier(CLK_LOCAL_MEM_FENCE); /* every earlier exchange has been read */
  quad[lane] = value;
  barrier(CLK_LOCAL_MEM_FENCE);
  const uint x = lane % CLR_TILE_SIZE;
  const uint y = lane / CLR_TILE_SIZE;
  if (axis == CLR_QUAD_X) {
    const uint row = coarse ? y & ~1u : y;
    const uint left = row * CLR_TILE_SIZE + (x & ~1u);
    return quad[left + 1] - quad[left];
  }
  const uint column = coarse ? x & ~1u : x;
  const uint bottom = (y & ~1u) * CLR_TILE_SIZE + column;
  return quad[bottom + CLR_TILE_SIZE] - quad[bottom];
}

/* A span program's derivatives: in quad spans (raster/span.cl: lanes 0, 1, 4, 5 one quad, 2, 3, 6, 7
 * another, lanes 0-3 their lower rows) the same differences between the lanes of the span, without
 * barriers; in spans of one pixel through the exchange. Four values at once, the components of a
 * span vector. (Spans of eight are quad spans wherever the program takes derivatives.) */
#if CLR_SPAN_PIXELS > 1
/* For each lane, the lanes whose difference is its derivative along `axis`, `coarse` or fine. */
static inline uint8 clr_quad_span_minuend(int axis, bool coarse) {
  if (axis == CLR_QUAD_X) return coarse ? (uint8)(1, 1, 3, 3, 1, 1, 3, 3) : (uint8)(1, 1, 3, 3, 5, 5, 7, 7);
  return coarse ? (uint8)(4, 4, 6, 6, 4, 4, 6, 6) : (uint8)(4, 5, 6, 7, 4, 5, 6, 7);
}
static inline uint8 clr_quad_span_subtrahend(int axis, bool coarse) {
  if (coarse) return (uint8)(0, 0, 2, 2, 0, 0, 2, 2);
  return axis == CLR_QUAD_X ? (uint8)(0, 0, 2, 2, 4, 4, 6, 6) : (uint8)(0, 1, 2, 3, 0, 1, 2, 3);
}
static inline clr_span_float clr_quad_span_difference(clr_span_float v, int axis, bool coarse) {
  return shuffle(v, clr_quad_span_minuend(axis, coarse)) - shuffle(v, clr_quad_span_subtrahend(axis, coarse));
}
/* *v becomes its difference along `axis` (an out-parameter, not a returned structure: LLVM's inliner
 * marks those with an intrinsic that Oclgrind cannot run). */
static inline void clr_span_quad_difference(clr_span_fragment* f, clr_span_float4* v, int axis, bool coarse) {
  v->x = clr_quad_span_difference(v->x, axis, coarse);
  v->y = clr_quad_span_difference(v->y, axis, coarse);
  v->z = clr_quad_span_difference(v->z, axis, coarse);
  v->w = clr_quad_span_difference(v->w, axis, coarse);
}
#else
static inline void clr_span_quad_difference(clr_span_fragment* f, clr_span_float4* v, int axis, bool coarse) {
  const float4 d = clr_quad_difference(f->clr_quad, f->clr_lane, (float4)(v->x, v->y, v->z, v->w), axis, coarse);
  v->x = d.x;
  v->y = d.y;
  v->z = d.z;
  v->w = d.w;
}
#endif

#define CLR_DERIVATIVE(name, axis, coarse)                                                                      \
  static __attribute__((overloadable)) inline float name(clr_fragment* f, float v) {                            \
    return clr_quad_difference(f->clr_quad, f->clr_lane, (float4)(v, 0.0f, 0.0f, 0.0f), axis, coarse).x;       \
  }                                                                                                              \
  static __attribute__((overloadable)) inline float2 name(clr_fragment* f, float2 v) {                          \
    return clr_quad_difference(f->clr_quad, f->clr_lane, (float4)(v, 0.0f, 0.0f), axis, coarse).xy;            \
  }                                                                                                              \
  static __attribute__((overloadable)) inline float3 name(clr_fragment* f, float3 v) {                          \
    return clr_quad_difference(f->clr_quad, f->clr_lane, (float4)(v, 0.0f), axis, coarse).xyz;                 \
  }                                                                                                              \
  static __attribute__((overloadable)) inline float4 name(clr_fragment* f, float4 v) {                          \
    return clr_quad_difference(f->clr_quad, f->clr_lane, v, axis, coarse);                                      \
  }                                                                                                              \
  static __attribute__((overloadable)) inline clr_span_float name(clr_span_fragment* f, clr_span_float v) {     \
    clr_span_float4 d = {v, 0.0f, 0.0f, 0.0f};                                                                  \
    clr_span_quad_difference(f, &d, axis, coarse);                                                              \
    return d.x;                                                                                                 \
  }                                                                                                              \
  static __attribute__((overloadable)) inline clr_span_float2 name(clr_span_fragment* f, clr_span_float2 v) {   \
    clr_span_float4 d = {v.x, v.y, 0.0f, 0.0f};                                                                 \
    clr_span_quad_difference(f, &d, axis, coarse);                                                              \
    const clr_span_float2 result = {d.x, d.y};                                                                  \
    return result;                                                                                              \
  }                                                                                                              \
  static __attribute__((overloadable)) inline clr_span_float3 name(clr_span_fragment* f, clr_span_float3 v) {   \
    clr_span_float4 d = {v.x, v.y, v.z, 0.0f};                                                                  \
    clr_span_quad_difference(f, &d, axis, coarse);                                                              \
    const clr_span_float3 result = {d.x, d.y, d.z};                                                             \
    return result;                                                                                              \
  }                                                                                                              \
  static __attribute__((overloadable)) inline clr_span_float4 name(clr_span_fragment* f, clr_span_float4 v) {   \
    clr_span_quad_difference(f, &v, axis, coarse);                                                              \
    return v;                                                                                                   \
  }
CLR_DERIVATIVE(clr_dfdx_fine, CLR_QUAD_X, false)
CLR_DERIVATIVE(clr_dfdy_fine, CLR_QUAD_Y, false)
CLR_DERIVATIVE(clr_dfdx_coarse, CLR_QUAD_X, true)
CLR_DERIVATIVE(clr_dfdy_coarse, CLR_QUAD_Y, true)
CLR_DERIVATIVE(clr_dfdx, CLR_QUAD_X, CLR_DEFAULT_DERIVATIVE_COARSE)
CLR_DERIVATIVE(clr_dfdy, CLR_QUAD_Y, CLR_DEFAULT_DERIVATIVE_COARSE)
#undef CLR_DERIVATIVE

static __attribute__((overloadable)) inline float clr_fwidth(clr_fragment* f, float v) {
  return fabs(clr_dfdx(f, v)) + fabs(clr_dfdy(f, v));
}
static __attribute__((overloadable)) inline float2 clr_fwidth(clr_fragment* f, float2 v) {
  return fabs(clr_dfdx(f, v)) + fabs(clr_dfdy(f, v));
}
static __attribute__((overloadable)) inline float3 clr_fwidth(clr_fragment* f, float3 v) {
  return fabs(clr_dfdx(f, v)) + fabs(clr_dfdy(f, v));
}
static __attribute__((overloadable)) inline float4 clr_fwidth(clr_fragment* f, float4 v) {
  return fabs(clr_dfdx(f, v)) + fabs(clr_dfdy(f, v));
}
static __attribute__((overloadable)) inline clr_span_float clr_fwidth(clr_span_fragment* f, clr_span_float v) {
  return fabs(clr_dfdx(f, v)) + fabs(clr_dfdy(f, v));
}
static __attribute__((overloadable)) inline clr_span_float2 clr_fwidth(clr_span_fragment* f, clr_span_float2 v) {
  const clr_span_float2 dx = clr_dfdx(f, v), dy = clr_dfdy(f, v);
  const clr_span_float2 result = {fabs(dx.x) + fabs(dy.x), fabs(dx.y) + fabs(dy.y)};
  return result;
}
static __attribute__((overloadable)) inline clr_span_float3 clr_fwidth(clr_span_fragment* f, clr_span_float3 v) {
  const clr_span_float3 dx = clr_dfdx(f, v), dy = clr_dfdy(f, v);
  const clr_span_float3 result = {fabs(dx.x) + fabs(dy.x), fabs(dx.y) + fabs(dy.y), fabs(dx.z) + fabs(dy.z)};
  return result;
}
static __attribute__((overloadable)) inline clr_span_float4 clr_fwidth(clr_span_fragment* f, clr_span_float4 v) {
  const clr_span_float4 dx = clr_dfdx(f, v), dy = clr_dfdy(f, v);
  const clr_span_float4 result = {fabs(dx.x) + fabs(dy.x), fabs(dx.y) + fabs(dy.y), fabs(dx.z) + fabs(dy.z),
                                  fabs(dx.w) + fabs(dy.w)};
  return result;
}

/* ---- Textures ------------------------------------------------------------------------------------
 * clr_sample_lod, clr_sample_grad, clr_texel_fetch(_int, _uint), clr_texture_size and
 * clr_texture_levels work in any program (resources/texture.cl). In fragment programs clr_sample
 * picks the level of detail from the quad's derivatives of uv, as GLSL's texture() does. */
static __attribute__((overloadable)) inline float4 clr_sample(clr_fragment* f, clr_texture texture, float2 uv) {
  barrier(CLK_LOCAL_MEM_FENCE);
  f->clr_quad[f->clr_lane] = (float4)(uv, 0.0f, 0.0f);
  barrier(CLK_LOCAL_MEM_FENCE);
  /* One level of detail per quad, from its first row and column. */
  const uint x = f->clr_lane % CLR_TILE_SIZE;
  const uint y = f->clr_lane / CLR_TILE_SIZE;
  const uint corner = (y & ~1u) * CLR_TILE_SIZE + (x & ~1u);
  const float2 duv_dx = f->clr_quad[corner + 1].xy - f->clr_quad[corner].xy;
  const float2 duv_dy = f->clr_quad[corner + CLR_TILE_SIZE].xy - f->clr_quad[corner].xy;
  return clr_sample_grad(texture, uv, duv_dx, duv_dy);
}
/* The same for a span: the quad's differences along its first row and column are its coarse
 * derivatives. */
static __attribute__((overloadable)) inline clr_span_float4 clr_sample(clr_span_fragment* f, clr_texture texture,
                                                                       clr_span_float2 uv) {
  clr_span_float4 dx = {uv.x, uv.y, 0.0f, 0.0f}, dy = dx;
  clr_span_quad_difference(f, &dx, CLR_QUAD_X, true);
  clr_span_quad_difference(f, &dy, CLR_QUAD_Y, true);
  const clr_span_float2 duv_dx = {dx.x, dx.y}, duv_dy = {dy.x, dy.y};
  return clr_sample_grad(texture, uv, duv_dx, duv_dy);
}

/* ---- Vertex attributes (used by the generated fetch) ----------------------------------------------- */
static inline __global const uchar* clr_attribute_element(__constant const AttributeDesc* d, __global const uchar* data,
                                                          uint vertex, uint instance) {
  return data + d->offset + (ulong)(d->per_instance ? instance : vertex) * d->stride;
}
static inline float4 clr_fetch_float(__constant const AttributeDesc* d, __global const uchar* data, uint vertex,
                                     uint instance) {
  float4 v = (float4)(0.0f, 0.0f, 0.0f, 1.0f);
  __global const float* p = (__global const float*)clr_attribute_element(d, data, vertex, instance);
  if (d->components > 0) v.x = p[0];
  if (d->components > 1) v.y = p[1];
  if (d->components > 2) v.z = p[2];
  if (d->components > 3) v.w = p[3];
  return v;
}
static inline int4 clr_fetch_int(__constant const AttributeDesc* d, __global const uchar* data, uint vertex,
                                 uint instance) {
  int4 v = (int4)(0, 0, 0, 1);
  __global const int* p = (__global const int*)clr_attribute_element(d, data, vertex, instance);
  if (d->components > 0) v.x = p[0];
  if (d->components > 1) v.y = p[1];
  if (d->components > 2) v.z = p[2];
  if (d->components > 3) v.w = p[3];
  return v;
}
static inline uint4 clr_fetch_uint(__constant const AttributeDesc* d, __global const uchar* data, uint vertex,
                                   uint instance) {
  return as_uint4(clr_fetch_int(d, data, vertex, instance));
}
