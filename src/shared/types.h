/* types.h: data layouts and constants shared by the host code and the kernels.
 *
 * Valid C++ and OpenCL C. Every struct holds only 4- and 8-byte scalars, ordered from the widest, so
 * both compilers lay them out identically (tests/test_kernels.cpp compares the device compiler's
 * sizes and offsets with the host's).
 */
#ifndef CLRASTER_TYPES_H
#define CLRASTER_TYPES_H

#include "shared/clr_limits.h"

#ifdef __OPENCL_VERSION__
/* Window coordinates must be computed exactly as written (no fused multiply-add), so that the same
 * input snaps to the same fixed-point position on every device and in every kernel. */
#pragma OPENCL FP_CONTRACT OFF
/* For the small functions that run per fragment (fragment operations, texel conversions) or per
 * vertex (clip codes, projection): inlined whatever the compiler's cost model says, since a call per
 * fragment and per operation costs more than the operation and keeps the draw's state from being
 * hoisted out of the pixel loops. Static, so that no standalone copy outlives the inlining: PoCL
 * parses a program's whole bitcode when it loads the program from the disk cache, and those copies
 * were a third of it (a stage program's load 35-60 -> 21-27 ms, of a first frame of about 100).
 * Every other helper function of the kernel sources (all but the kernels and a program's entry
 * points) is static for the same reason, but for two that Oclgrind cannot run inlined
 * (resources/texture_span.cl). */
#define CLR_INLINE static inline __attribute__((always_inline))
/* a##b after both are expanded: vector type names built from a width macro (float ## 8). */
#define CLR_PASTE(a, b) a##b
#define CLR_CAT(a, b) CLR_PASTE(a, b)
typedef long clr_long;
typedef int clr_int;
typedef uint clr_uint;
typedef float clr_float;
#else
#include <cstdint>

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

/* How a varying float is interpolated (program::Interpolation). */
#define CLR_INTERPOLATE_SMOOTH 0
#define CLR_INTERPOLATE_FLAT 1
#define CLR_INTERPOLATE_NOPERSPECTIVE 2

/* In the order of clraster::CompareFunc (and of GL_NEVER .. GL_ALWAYS). */
#define CLR_COMPARE_NEVER 0
#define CLR_COMPARE_LESS 1
#define CLR_COMPARE_EQUAL 2
#define CLR_COMPARE_LEQUAL 3
#define CLR_COMPARE_GREATER 4
#define CLR_COMPARE_NOTEQUAL 5
#define CLR_COMPARE_GEQUAL 6
#define CLR_COMPARE_ALWAYS 7
#define CLR_COMPARE_PROGRAM 8 /* the program's depth_test function */

/* In the order of clraster::Format. */
#define CLR_FORMAT_R8 0
#define CLR_FORMAT_RG8 1
#define CLR_FORMAT_RGBA8 2
#define CLR_FORMAT_SRGB8_A8 3
#define CLR_FORMAT_R32F 4
#define CLR_FORMAT_RG32F 5
#define CLR_FORMAT_RGBA16F 6
#define CLR_FORMAT_RGBA32F 7
#define CLR_FORMAT_R32I 8
#define CLR_FORMAT_R32UI 9
#define CLR_FORMAT_RGBA32I 10
#define CLR_FORMAT_RGBA32UI 11
#define CLR_FORMAT_DEPTH32F 12
#define CLR_FORMAT_DEPTH32F_STENCIL8 13
#define CLR_FORMAT_COUNT 14

/* How a format stores one channel. */
#define CLR_CHANNEL_UNORM8 0  /* byte c, read as c / 255 */
#define CLR_CHANNEL_SRGB8 1   /* as UNORM8, but the first three channels are sRGB-encoded (alpha is not) */
#define CLR_CHANNEL_FLOAT16 2 /* IEEE half */
#define CLR_CHANNEL_FLOAT32 3
#define CLR_CHANNEL_SINT32 4
#define CLR_CHANNEL_UINT32 5
#define CLR_CHANNEL_BYTES(type) ((type) <= CLR_CHANNEL_SRGB8 ? 1 : (type) == CLR_CHANNEL_FLOAT16 ? 2 : 4)

/* The format table: one row per CLR_FORMAT_*, in order. A texel is `channels` channels of one type,
 * packed (bytes per texel = channels * CLR_CHANNEL_BYTES(type)); depth formats keep their depth in
 * the first channel, and a stencil format adds a stencil byte per texel in a second plane
 * (TextureDesc::stencil_offset). The host's format_info and the kernels' texel loads and stores
 * (resources/format.cl) both expand it, with X(id, name, channels, channel type, depth, stencil). */
#define CLR_FORMAT_TABLE(X)                                                   \
  X(CLR_FORMAT_R8, "R8", 1, CLR_CHANNEL_UNORM8, 0, 0)                         \
  X(CLR_FORMAT_RG8, "RG8", 2, CLR_CHANNEL_UNORM8, 0, 0)                       \
  X(CLR_FORMAT_RGBA8, "RGBA8", 4, CLR_CHANNEL_UNORM8, 0, 0)                   \
  X(CLR_FORMAT_SRGB8_A8, "SRGB8_A8", 4, CLR_CHANNEL_SRGB8, 0, 0)              \
  X(CLR_FORMAT_R32F, "R32F", 1, CLR_CHANNEL_FLOAT32, 0, 0)                    \
  X(CLR_FORMAT_RG32F, "RG32F", 2, CLR_CHANNEL_FLOAT32, 0, 0)                  \
  X(CLR_FORMAT_RGBA16F, "RGBA16F", 4, CLR_CHANNEL_FLOAT16, 0, 0)              \
  X(CLR_FORMAT_RGBA32F, "RGBA32F", 4, CLR_CHANNEL_FLOAT32, 0, 0)              \
  X(CLR_FORMAT_R32I, "R32I", 1, CLR_CHANNEL_SINT32, 0, 0)                     \
  X(CLR_FORMAT_R32UI, "R32UI", 1, CLR_CHANNEL_UINT32, 0, 0)                   \
  X(CLR_FORMAT_RGBA32I, "RGBA32I", 4, CLR_CHANNEL_SINT32, 0, 0)               \
  X(CLR_FORMAT_RGBA32UI, "RGBA32UI", 4, CLR_CHANNEL_UINT32, 0, 0)             \
  X(CLR_FORMAT_DEPTH32F, "Depth32F", 1, CLR_CHANNEL_FLOAT32, 1, 0)            \
  X(CLR_FORMAT_DEPTH32F_STENCIL8, "Depth32FStencil8", 1, CLR_CHANNEL_FLOAT32, 1, 1)

/* In the order of clraster::Filter, MipFilter and Wrap. */
#define CLR_FILTER_NEAREST 0
#define CLR_FILTER_LINEAR 1
#define CLR_MIP_NONE 0
#define CLR_MIP_NEAREST 1
#define CLR_MIP_LINEAR 2
#define CLR_WRAP_REPEAT 0
#define CLR_WRAP_CLAMP_TO_EDGE 1
#define CLR_WRAP_MIRRORED_REPEAT 2

/* In the order of clraster::StencilOp. */
#define CLR_STENCIL_KEEP 0
#define CLR_STENCIL_ZERO 1
#define CLR_STENCIL_REPLACE 2
#define CLR_STENCIL_INCR 3
#define CLR_STENCIL_INCR_WRAP 4
#define CLR_STENCIL_DECR 5
#define CLR_STENCIL_DECR_WRAP 6
#define CLR_STENCIL_INVERT 7

/* In the order of clraster::BlendEquation and BlendFactor. */
#define CLR_BLEND_ADD 0
#define CLR_BLEND_SUBTRACT 1
#define CLR_BLEND_REVERSE_SUBTRACT 2
#define CLR_BLEND_MIN 3
#define CLR_BLEND_MAX 4
#define CLR_BLEND_PROGRAM 5

#define CLR_FACTOR_ZERO 0
#define CLR_FACTOR_ONE 1
#define CLR_FACTOR_SRC_COLOR 2
#define CLR_FACTOR_ONE_MINUS_SRC_COLOR 3
#define CLR_FACTOR_DST_COLOR 4
#define CLR_FACTOR_ONE_MINUS_DST_COLOR 5
#define CLR_FACTOR_SRC_ALPHA 6
#define CLR_FACTOR_ONE_MINUS_SRC_ALPHA 7
#define CLR_FACTOR_DST_ALPHA 8
#define CLR_FACTOR_ONE_MINUS_DST_ALPHA 9
#define CLR_FACTOR_CONSTANT_COLOR 10
#define CLR_FACTOR_ONE_MINUS_CONSTANT_COLOR 11
#define CLR_FACTOR_CONSTANT_ALPHA 12
#define CLR_FACTOR_ONE_MINUS_CONSTANT_ALPHA 13
#define CLR_FACTOR_SRC_ALPHA_SATURATE 14

/* ---- Textures ----------------------------------------------------------------------------------
 * A texture is one device buffer holding every mip level, level after level, each tightly packed
 * rows from t = 0. A Depth32FStencil8 texture has one level: the depth plane, then a stencil byte per
 * texel at stencil_offset. The sampler's state travels with the texture's description. */
typedef struct {
  clr_uint level_offset[CLR_MAX_TEXTURE_LEVELS]; /* in texels from the start of the buffer */
  clr_uint stencil_offset;                       /* in bytes (Depth32FStencil8) */
  clr_int format;
  clr_int width;                                 /* of level 0; level l is max(1, width >> l) */
  clr_int height;
  clr_int levels;
  clr_int mag_filter;
  clr_int min_filter;
  clr_int mip_filter;
  clr_int wrap_s;
  clr_int wrap_t;
  clr_float lod_bias;
  clr_float min_lod;
  clr_float max_lod;
} TextureDesc;

/* ---- Per-fragment operations ---------------------------------------------------------------------- */
/* Blend states common enough for code of their own on RGBA8 attachments: the rasterizer runs the
 * same blend as for any other state, compiled with these as constants, where the draw's state is
 * one of them (BlendUniforms::common). X(index, equation, source factor, destination factor), the
 * same for rgb and alpha. */
#define CLR_COMMON_BLENDS(X)                                                        \
  X(0, CLR_BLEND_ADD, CLR_FACTOR_ONE, CLR_FACTOR_ONE)                 /* additive */ \
  X(1, CLR_BLEND_ADD, CLR_FACTOR_SRC_ALPHA, CLR_FACTOR_ONE_MINUS_SRC_ALPHA) /* alpha */ \
  X(2, CLR_BLEND_ADD, CLR_FACTOR_ONE, CLR_FACTOR_ONE_MINUS_SRC_ALPHA) /* premultiplied alpha */
#define CLR_NOT_COMMON_BLEND (-1)

typedef struct {
  clr_int enabled;
  clr_int rgb_equation;
  clr_int alpha_equation;
  clr_int src_rgb;
  clr_int dst_rgb;
  clr_int src_alpha;
  clr_int dst_alpha;
  clr_uint write_mask; /* bit c: channel c (r, g, b, a) is written */
  clr_int common;      /* the index in CLR_COMMON_BLENDS of an enabled blend on RGBA8, or CLR_NOT_COMMON_BLEND */
} BlendUniforms;

typedef struct {
  clr_int func;        /* CLR_COMPARE_* */
  clr_uint reference;
  clr_uint read_mask;
  clr_uint write_mask;
  clr_int stencil_fail; /* CLR_STENCIL_* */
  clr_int depth_fail;
  clr_int depth_pass;
} StencilUniforms;

/* ---- Per-draw constants --------------------------------------------------------------------- */
typedef struct {
  clr_float viewport_scale[2];  /* window = ndc * scale + offset */
  clr_float viewport_offset[2];
  clr_float guard_min[2];       /* guard-band clip planes, in NDC: guard_min * w <= x, y <= guard_max * w */
  clr_float guard_max[2];
  clr_float blend_color[4];
  clr_int clip_rect[4];         /* x0, y0, x1, y1 (exclusive): pixels in viewport, scissor and framebuffer */
  clr_int topology;
  clr_int index_size;           /* 0 (non-indexed), 2 or 4 */
  clr_uint first;               /* first element (index or vertex) of the draw */
  clr_uint instance;            /* the instance being drawn */
  clr_uint batch_draw;          /* this draw's entry in its pass's table of draws (raster_tiles' triangles carry it) */
  clr_uint view;                /* the view drawn, view_id: into layer `view` of a layered framebuffer */
  clr_int layer_size[2];        /* width, height of a layer (the framebuffer's, unlayered) */
  clr_int layer_columns;        /* layers per row of the attachments: layer l starts at column l % layer_columns */
  clr_int cull;
  clr_int front_face_ccw;
  clr_int depth_test;           /* enabled and there is a depth attachment */
  clr_int depth_func;           /* CLR_COMPARE_* */
  clr_int depth_write;
  clr_int stencil_test;         /* enabled and there is a stencil attachment */
  clr_int target_format[CLR_MAX_COLOR_ATTACHMENTS]; /* CLR_FORMAT_* of each colour attachment, -1: none */
  BlendUniforms blend[CLR_MAX_COLOR_ATTACHMENTS];
  StencilUniforms stencil[2];   /* for front-facing, then back-facing triangles */
  /* Clears the raster pass may write with its tiles (raster_tiles' `clears`): each colour
   * attachment's value as the bits of its float, int or uint channels, the depth and the stencil. */
  clr_uint clear_color[CLR_MAX_COLOR_ATTACHMENTS][4];
  clr_float clear_depth;
  clr_uint clear_stencil;
  clr_int framebuffer_size[2];  /* width, height: where a clear is written */
  clr_int streaming_stores;     /* the tile's write-back bypasses the caches (CLR_STREAMING_STORE_PIXELS) */
} DrawUniforms;

/* raster_tiles' `clears`: bit k for colour attachment k, then these two. */
#define CLR_CLEAR_DEPTH (1u << CLR_MAX_COLOR_ATTACHMENTS)
#define CLR_CLEAR_STENCIL (1u << (CLR_MAX_COLOR_ATTACHMENTS + 1))

/* Where a vertex attribute's element i (vertex, or instance when per_instance) is: at byte
 * offset + i * stride of its buffer. components 0: not supplied, the attribute reads (0, 0, 0, 1). */
typedef struct {
  clr_uint offset;
  clr_uint stride;
  clr_uint components;
  clr_uint per_instance;
} AttributeDesc;

/* ---- Transformed vertices ------------------------------------------------------------------------
 * CLR_SHADED_VERTEX_FLOAT4S (generated per program) float4 per vertex slot:
 *   [0]                     the clip-space position;
 *   [CLR_SHADED_WINDOW]     the snapped window position (x, y, as int bits) and its residual (x, y);
 *   [CLR_SHADED_WINDOW + 1] window depth, 1 / clip w, the clip codes (uint bits), unused;
 *   [CLR_SHADED_VARYINGS..] the varyings as floats.
 * The vertex stage projects and snaps each vertex once (vertex.cl), so that set-up does not do it
 * again for every triangle that shares the vertex; only clipping goes back to the clip position. */
#define CLR_SHADED_WINDOW 1
#define CLR_SHADED_VARYINGS 3
/* Clip codes: bit k (k < CLR_CLIP_PLANES) set when the position is outside clip plane k (clip.cl),
 * and the two flags below. The window part means something only when the codes are 0. */
#define CLR_VERTEX_OUTSIDE_PLANES ((1u << CLR_CLIP_PLANES) - 1u)
#define CLR_VERTEX_NOT_FINITE (1u << CLR_CLIP_PLANES)           /* the position has an infinity or NaN */
#define CLR_VERTEX_NOT_PROJECTABLE (1u << (CLR_CLIP_PLANES + 1)) /* inside every plane, but w = 0 */
/* Outside the viewport's left, right, bottom or top side (x < -w, x > w, y < -w, y > w): not a
 * clip plane (the guard band is), but a primitive whose vertices are all outside one side has no
 * pixel, and is rejected as one outside a clip plane is. */
#define CLR_VERTEX_OUTSIDE_VIEW (0xfu << (CLR_CLIP_PLANES + 2))
#define CLR_VERTEX_OUTSIDE (CLR_VERTEX_OUTSIDE_PLANES | CLR_VERTEX_OUTSIDE_VIEW)

/* Where the vertex stage put the vertex of each stream position, for one draw or chunk (see
 * vertex.cl). The draws of a pass share the shaded vertices, each from its own slot_base. */
typedef struct {
  clr_int shade_all;   /* slot = slot_base + vertex index - origin (origin: the draw's smallest index) */
  clr_uint origin;     /* else slot = slot_base + stream position - origin ... */
  clr_uint fan_centre; /* ... except a fan's centre (position 0), in slot slot_base + fan_centre */
  clr_uint slot_base;
} SlotMap;

/* ---- Set-up triangles ------------------------------------------------------------------------------
 * Counter-clockwise in window space (y up) after set-up. Edge k is opposite vertex k. Its function
 * E_k(X, Y) = edge_a[k] * X + edge_b[k] * Y + edge_c[k], with X, Y a pixel centre in fixed point
 * (pixel index << CLR_SUBPIXEL_BITS: snapping subtracted the half-pixel), is positive inside and
 * equals 2 * area * barycentric_k. A centre exactly on edge k is covered when bit k of
 * `flags` is set (a left or bottom edge, the rule llvmpipe applies). */
#define CLR_TRIANGLE_FRONT_FACING (1u << 3)
/* (flags >> CLR_TRIANGLE_DRAW_SHIFT) & CLR_TRIANGLE_DRAW_MASK: the triangle's draw in its pass
 * (DrawUniforms::batch_draw, below CLR_MAX_PASS_DRAWS), whose uniform block its fragments read;
 * flags >> CLR_TRIANGLE_VIEW_SHIFT: its view (below CLR_MAX_LAYERS). */
#define CLR_TRIANGLE_DRAW_SHIFT 8
#define CLR_TRIANGLE_DRAW_MASK 0xfffu
#define CLR_TRIANGLE_VIEW_SHIFT 20

/* Bin pair triangle ids with this bit set index the overflow records of clipped primitives; the
 * others index the chunk's per-primitive records (see setup.cl). */
#define CLR_OVERFLOW_TRIANGLE 0x80000000u

#ifdef CLR_NUM_VARYINGS /* kernel programs generated for a user program (program/generator.cpp) */
typedef struct {
  clr_long edge_c[3];
  clr_int edge_a[3];
  clr_int edge_b[3];
  clr_float z[3];                          /* window depth of each vertex */
  clr_float inv_w[3];                      /* 1 / clip w of each vertex */
  /* Interpolation weights come from the unsnapped triangle, as in llvmpipe: E_k(X, Y) plus
   * edge_correction[k][0] * X + [k][1] * Y + [k][2] is edge k's function for the vertices where
   * they were before snapping (setup.cl), and 2 * its area the sum of the three. */
  clr_float edge_correction[3][3];
  clr_float varyings[3][CLR_NUM_VARYINGS];
  clr_float inv_double_area;               /* 1 / (2 * unsnapped area), in fixed-point units squared */
  clr_uint primitive_id;
  clr_uint flags;                          /* bits 0-2: edge includes centres on it; bit 3: front; 8-31: draw */
  clr_uint pixel_min;                      /* writable pixels in the bounding box: x | y << 16 ... */
  clr_uint pixel_max;                      /* ... to x | y << 16, inclusive */
} SetupTriangle;
#endif

/* ---- Counters the host reads back (one small buffer per context) -------------------------------- */
#define CLR_COUNTER_SCAN_TOTAL 0     /* total of the last scan */
#define CLR_COUNTER_DROPPED 1        /* primitives dropped for non-finite coordinates, since the host last read it */
#define CLR_COUNTER_MAX_INDEX 2      /* largest index in a range (index validation) */
#define CLR_COUNTER_CLIPPED 3        /* primitives that needed clipping, this draw (a chunk cut short counts twice) */
#define CLR_COUNTER_MIN_INDEX 4      /* smallest index in a range */
#define CLR_COUNTER_COUNT 5

#endif /* CLRASTER_TYPES_H */
