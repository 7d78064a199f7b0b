/* types.h: data layouts and constants shared by the host code and the kernels.
 *
 * Valid C++ and OpenCL C. Every struct holds only 4- and 8-byte scalars, ordered from the widest, so
 * both compilers lay them out identically (checked by static_asserts on the host side).
 */
#ifndef CLRASTER_TYPES_H
#define CLRASTER_TYPES_H

#ifdef __OPENCL_VERSION__
/* Window coordinates must be computed exactly as written (no fused multiply-add), so that the same
 * input snaps to the same fixed-point position on every device and in every kernel. */
#pragma OPENCL FP_CONTRACT OFF
typedef long clr_long;
typedef int clr_int;
typedef uint clr_uint;
typedef float clr_float;
#else
#include <cstdint>

#include "clr_limits.h" /* the kernels get it prepended instead */
typedef std::int64_t clr_long;
typedef std::int32_t clr_int;
typedef std::uint32_t clr_uint;
typedef float clr_float;
#endif

/* ---- Enumerations (the host maps the public enums onto these) ------------------------------- */
#define CLR_TOPOLOGY_LIST 0
#define CLR_TOPOLOGY_STRIP 1
#define CLR_TOPOLOGY_FAN 2

#define CLR_CULL_NONE 0
#define CLR_CULL_BACK 1
#define CLR_CULL_FRONT 2

#define CLR_SHADING_NORMAL 0
#define CLR_SHADING_LAMBERT 1
#define CLR_SHADING_DEPTH 2
#define CLR_SHADING_CONSTANT 3

/* In the order of clraster::CompareFunc (and of GL_NEVER .. GL_ALWAYS). */
#define CLR_COMPARE_NEVER 0
#define CLR_COMPARE_LESS 1
#define CLR_COMPARE_EQUAL 2
#define CLR_COMPARE_LEQUAL 3
#define CLR_COMPARE_GREATER 4
#define CLR_COMPARE_NOTEQUAL 5
#define CLR_COMPARE_GEQUAL 6
#define CLR_COMPARE_ALWAYS 7

#define CLR_BLEND_REPLACE 0
#define CLR_BLEND_ADDITIVE 1

/* ---- Per-draw constants --------------------------------------------------------------------- */
typedef struct {
  clr_float mvp[16];            /* projection * model_view, column-major */
  clr_float model_view[16];
  clr_float normal_matrix[9];   /* inverse transpose of model_view's upper 3x3, column-major */
  clr_float base_color[4];
  clr_float depth_shading_range[2];
  clr_float viewport_scale[2];  /* window = ndc * scale + offset */
  clr_float viewport_offset[2];
  clr_float guard_min[2];       /* guard-band clip planes, in NDC: guard_min * w <= x, y <= guard_max * w */
  clr_float guard_max[2];
  clr_int clip_rect[4];         /* x0, y0, x1, y1 (exclusive): pixels in viewport, scissor and framebuffer */
  clr_int topology;
  clr_int index_size;           /* 0 (non-indexed), 2 or 4 */
  clr_uint first;               /* first element (index or vertex) of the draw */
  clr_int cull;
  clr_int front_face_ccw;
  clr_int shading;
  clr_int depth_test;
  clr_int depth_func;
  clr_int depth_write;
  clr_int blend;
} DrawUniforms;

/* ---- Transformed vertices ------------------------------------------------------------------------
 * Two float4 per vertex slot: the clip-space position, then the varyings (w unused). */
#define CLR_SHADED_VERTEX_FLOAT4S 2

/* Where the vertex stage put the vertex of each stream position, for one chunk (see vertex.cl). */
typedef struct {
  clr_int shade_all;     /* slot = vertex index */
  clr_uint stream_begin; /* else slot = stream position - stream_begin ... */
  clr_uint fan_centre;   /* ... except a fan's centre (position 0), in this slot */
} SlotMap;

/* ---- Set-up triangles ------------------------------------------------------------------------------
 * Counter-clockwise in window space (y up) after set-up. Edge k is opposite vertex k. Its function
 * E_k(X, Y) = edge_a[k] * X + edge_b[k] * Y + edge_c[k], with X, Y a pixel centre in fixed point
 * (pixel index << CLR_SUBPIXEL_BITS: snapping subtracted the half-pixel), is positive inside and
 * equals 2 * area * barycentric_k. A centre exactly on edge k is covered when bit k of
 * `flags` is set (a left or bottom edge, the rule llvmpipe applies). */
#define CLR_TRIANGLE_FRONT_FACING (1u << 3)

/* Bin pair triangle ids with this bit set index the overflow records of clipped primitives; the
 * others index the chunk's per-primitive records (see setup.cl). */
#define CLR_OVERFLOW_TRIANGLE 0x80000000u

typedef struct {
  clr_long edge_c[3];
  clr_int edge_a[3];
  clr_int edge_b[3];
  clr_float z[3];                          /* window depth of each vertex */
  clr_float inv_w[3];                      /* 1 / clip w of each vertex */
  clr_float varyings[3][CLR_NUM_VARYINGS];
  clr_float inv_double_area;               /* 1 / (2 * area), area in fixed-point units squared */
  clr_uint primitive_id;
  clr_uint flags;                          /* bits 0-2: edge includes centres on it; bit 3: front */
  clr_uint pixel_min;                      /* writable pixels in the bounding box: x | y << 16 ... */
  clr_uint pixel_max;                      /* ... to x | y << 16, inclusive */
} SetupTriangle;

/* ---- Counters the host reads back (one small buffer per context) -------------------------------- */
#define CLR_COUNTER_SCAN_TOTAL 0     /* total of the last scan */
#define CLR_COUNTER_DROPPED 1        /* primitives dropped for non-finite coordinates, this draw */
#define CLR_COUNTER_MAX_INDEX 2      /* largest index in a range (index validation) */
#define CLR_COUNTER_COUNT 4

#endif /* CLRASTER_TYPES_H */
