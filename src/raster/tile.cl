/* tile.cl: rasterization, the kernel raster_tiles.
 *
 * One work-group per screen tile of CLR_TILE_SIZE^2 pixels. The tile's colour attachments, depth and
 * stencil live in local memory from the first triangle to the last, and the group walks its tile's
 * triangles in primitive order, staging CLR_RASTER_TRIANGLE_BATCH of them at a time in local memory
 * with each one's coverage of the tile as a bit mask (coverage.cl). Each pixel belongs to one
 * work-item, the only one to touch its attachments, so there are no atomics on them and every run
 * gives the same result. How many work-items a group has, and how they shade a batch of triangles,
 * is the strategy group.cl picks (strategy/).
 *
 * A pass that writes pending clears (`clears`, resources/pending_clear.hpp) starts each tile from the
 * clear values instead of loading it, runs the tiles without triangles too (they store the clear
 * values and nothing else), and writes its tiles back whole, also outside the clip rectangle.
 *
 * Tile storage: a colour attachment's pixel is four 32-bit words, kept channel by channel so that
 * a span of one channel is one vector (CLR_TILE_WORD), holding the decoded value exactly as the
 * attachment stores it (float bits for normalized and float formats, already quantized to the
 * format where the draw reads the tile back; int or uint for integer ones), except that an RGBA8
 * attachment the draw blends is held as its bytes (tile_holds_bytes). */

#include "raster/coverage.cl"
#include "raster/fragment_ops.cl"
#include "raster/group.cl"
#include "raster/merge.cl"
#include "raster/span.cl"
#include "raster/strategy/quad_spans.cl"
#include "raster/strategy/quad_walk.cl"
#include "raster/strategy/spans.cl"
#include "raster/strategy/tile_quads.cl"
#include "resources/format.cl"
#include "shared/clr_limits.h"
#include "shared/types.h"

#define CLR_TILE_TARGETS (CLR_NUM_OUTPUTS > 0 ? CLR_NUM_OUTPUTS : 1)

static inline bool is_integer_format(int format) { return format >= CLR_FORMAT_R32I && format <= CLR_FORMAT_RGBA32UI; }
static inline bool is_signed_integer_format(int format) {
  return format == CLR_FORMAT_R32I || format == CLR_FORMAT_RGBA32I;
}

/* An attachment's pixel in the tile's representation (see above). */
static inline uint4 load_attachment_pixel(int format, __global const uchar* data, uint pixel) {
  if (is_signed_integer_format(format)) return as_uint4(clr_load_texel_int(format, data, pixel));
  if (is_integer_format(format)) return clr_load_texel_uint(format, data, pixel);
  return as_uint4(clr_load_texel_float(format, data, pixel));
}
static inline void store_attachment_pixel(int format, __global uchar* data, uint pixel, uint4 value) {
  if (is_signed_integer_format(format)) clr_store_texel_int(format, data, pixel, as_int4(value));
  else if (is_integer_format(format)) clr_store_texel_uint(format, data, pixel, value);
  else clr_store_texel_float(format, data, pixel, as_float4(value));
}

/* Whether the pixel (x, y) is inside the rectangle r (x0, y0, x1, y1, exclusive), and whether the
 * whole span of pixels from (x, y) is. */
static inline bool inside_rect(int x, int y, int4 r) { return x >= r.x && x < r.z && y >= r.y && y < r.w; }
static inline bool whole_span_inside(int x, int y, int4 r) {
  return inside_rect(x, y, r) && inside_rect(x + CLR_SPAN_PIXELS - 1, y, r);
}
/* Whether the pixel (x, y) is inside the draw's clip rectangle (scissor and framebuffer), and whether
 * the whole span of pixels from (x, y) is. */
static inline bool writable(int x, int y, __constant const DrawUniforms* u) {
  return inside_rect(x, y, vload4(0, u->clip_rect));
}
static inline bool whole_span_writable(int x, int y, __constant const DrawUniforms* u) {
  return whole_span_inside(x, y, vload4(0, u->clip_rect));
}

/* The pixels of an attachment that the tile loads and stores: those of the clip rectangle, or every
 * pixel of the framebuffer for an attachment whose pending clear the pass writes (`clearing`). */
static inline int4 moved_rect(bool clearing, __constant const DrawUniforms* u) {
  return clearing ? (int4)(0, 0, u->framebuffer_size[0], u->framebuffer_size[1]) : vload4(0, u->clip_rect);
}
/* Whether the tile holds colour attachment `target` as its bytes (merge.cl). */
static inline bool tile_holds_bytes(__constant const DrawUniforms* u, uint target) {
  return holds_bytes(u->target_format[target], u->blend[target]);
}

/* Colour attachment `target`'s pixels once its pending clear is written, as load_attachment_pixel
 * gives them: the clear value as storing it into the attachment and loading it back gives it. */
static inline uint4 cleared_pixel(__constant const DrawUniforms* u, uint target) {
  const int format = u->target_format[target];
  const uint4 value = vload4(0, u->clear_color[target]);
  if (is_integer_format(format)) return clr_quantize_uint(format, value);
  return as_uint4(clr_quantize_float(format, as_float4(value)));
}

/* A span of the tile written back to an attachment: streaming (non-temporal) where the draw's
 * uniforms say so (CLR_STREAMING_STORE_PIXELS), plain otherwise. */
#define CLR_WRITE_BACK_SPAN(value, pointer, streaming) \
  do {                                                 \
    if (streaming) CLR_SPAN_STREAM(value, pointer);    \
    else CLR_SPAN_STORE(value, pointer);               \
  } while (0)

/* RGBA8, the usual attachment, moves between the framebuffer and the tile a span at a time: one
 * vector of the span's 32-bit pixels, whose byte c is channel c on little-endian devices (all that
 * OpenCL runs on in practice; others take the pixel-by-pixel way). The conversions are
 * clr_decode_texel's and clr_float_to_unorm8's, so the results are the same bits. */
#ifdef __ENDIAN_LITTLE__
#define CLR_PACKED_RGBA8 1
#else
#define CLR_PACKED_RGBA8 0
#endif
CLR_INLINE void load_rgba8_span(__global const uint* pixels, bool bytes, __local uint* tile_channels) {
  const clr_span_uint packed = CLR_SPAN_LOAD(pixels);
#pragma unroll
  for (int c = 0; c < 4; ++c) {
    const clr_span_float byte = CLR_SPAN_CONVERT(float, (packed >> (8u * c)) & 0xffu);
    CLR_SPAN_STORE(CLR_SPAN_AS(uint, bytes ? byte : clr_unorm8_to_float(byte)), &tile_channels[CLR_TILE_WORD(0, c, 0)]);
  }
}
CLR_INLINE clr_span_uint pack_rgba8_span(__local const uint* tile_channels, bool bytes) {
  clr_span_uint packed = 0u;
#pragma unroll
  for (int c = 0; c < 4; ++c) {
    const clr_span_float value = CLR_SPAN_AS(float, CLR_SPAN_LOAD(&tile_channels[CLR_TILE_WORD(0, c, 0)]));
    const clr_span_float byte = bytes ? value : round_small(fmin(fmax(value, 0.0f), 1.0f) * 255.0f);
    packed |= CLR_SPAN_CONVERT(uint, byte) << (8u * c);
  }
  return packed;
}

/* Where a tile's work-group has fewer work-items than a vector has lanes (one walking the tile in
 * spans, CPU shapes), the kernel says that its work is as wide as a span already (OpenCL's
 * vec_type_hint): a compiler that vectorizes across work-items (Intel's CPU runtime) otherwise built
 * a version for eight work-items at once, that a group of one never runs, in most of a program's
 * build time (88 -> 13 s for the built-in normal shading). */
#if CLR_RASTER_GROUP < CLR_CPU_SPAN_PIXELS
#define CLR_RASTER_WIDTH_HINT __attribute__((vec_type_hint(CLR_CAT(float, CLR_CPU_SPAN_PIXELS))))
#else
#define CLR_RASTER_WIDTH_HINT
#endif

__kernel __attribute__((reqd_work_group_size(CLR_RASTER_GROUP, 1, 1))) CLR_RASTER_WIDTH_HINT
void raster_tiles(__global const SetupTriangle* records, __global const SetupTriangle* overflow,
                  __global const uint* sorted_triangles, __global const uint* tile_ranges, uint tiles_x,
                  uint tile_count, uint run_count, uint run_stride,
                  uint framebuffer_width, __constant const DrawUniforms* u, __global uchar* depth_stencil,
                  uint stencil_offset, uint clears CLR_TARGET_PARAMS CLR_RESOURCE_PARAMS) {
  __local SetupTriangle batch[CLR_RASTER_TRIANGLE_BATCH];
  __local ulong masks[CLR_RASTER_TRIANGLE_BATCH][CLR_TILE_MASK_WORDS]; /* coverage_mask of each */
  __local TileCoverage coverage[CLR_RASTER_TRIANGLE_BATCH];           /* and what else it found */
  /* Each array with room for packed spans' spare pixel (CLR_TILE_SPARE_PIXEL). */
  __local uint tile_color[CLR_TILE_TARGETS * 4 * CLR_TILE_CHANNEL_WORDS]; /* CLR_TILE_WORD */
  __local float tile_depth[CLR_TILE_CHANNEL_WORDS];
  __local uchar tile_stencil[CLR_TILE_CHANNEL_WORDS];
#if CLR_QUAD_EXCHANGE
  __local float4 quad_exchange[CLR_TILE_PIXELS];
#endif
  /* Work-groups take the tiles in runs of CLR_RASTER_TILE_RUN, the runs in an order that strides
   * across the picture (run_stride, coprime with run_count, near run_count / golden ratio). A CPU
   * driver deals a kernel's work-groups out to its threads in ranges of consecutive ones (PoCL's, of
   * up to 512), while a chunk's triangles, a mesh's primitives being ordered in space, can cover a
   * band of the picture only: in tile order one range could hold all its work. A run's tiles, side
   * by side, share triangles. */
  const uint group = get_group_id(0);
  const uint run = (uint)((ulong)(group / CLR_RASTER_TILE_RUN) * run_stride % run_count);
  const uint tile = run * CLR_RASTER_TILE_RUN + group % CLR_RASTER_TILE_RUN;
  if (tile >= tile_count) return; /* past the last tile, in the last run */
  const uint begin = tile_ranges[2 * tile];
  const uint end = tile_ranges[2 * tile + 1];
  /* A tile without triangles has nothing to do but the pass's pending clears (below). The same for the
   * whole group: no barrier is skipped by only some items. */
  if (begin == end && clears == 0) return;

  const int2 origin = (int2)((int)(tile % tiles_x), (int)(tile / tiles_x)) * CLR_TILE_SIZE;
  const uint item = get_local_id(0);
  __global float* depth = (__global float*)depth_stencil;
  __global uchar* stencil = depth_stencil + stencil_offset;
#if CLR_NUM_OUTPUTS > 0 /* a program without outputs (a depth-only pass) has no colour targets */
  __global uchar* const targets[CLR_NUM_OUTPUTS] = CLR_TARGETS;
#endif
  const bool clear_depth = (clears & CLR_CLEAR_DEPTH) != 0;
  const bool clear_stencil = (clears & CLR_CLEAR_STENCIL) != 0;
#if CLR_NUM_OUTPUTS > 0
  uint4 cleared[CLR_NUM_OUTPUTS]; /* once per tile: the conversions are not cheap */
  for (int k = 0; k < CLR_NUM_OUTPUTS; ++k) cleared[k] = (clears >> k) & 1u ? cleared_pixel(u, k) : (uint4)(0u);
#endif
  /* A tile without triangles only writes the clears, straight from their values. */
  const bool empty = begin == end;
  for (uint first = item * CLR_SPAN_PIXELS; first < CLR_TILE_PIXELS && !empty; first += CLR_RASTER_GROUP * CLR_SPAN_PIXELS) {
    const int x = origin.x + (int)(first % CLR_TILE_SIZE);
    const int y = origin.y + (int)(first / CLR_TILE_SIZE);
    const uint pixel = (uint)y * framebuffer_width + (uint)x;
    const bool whole = whole_span_writable(x, y, u);
#if CLR_NUM_OUTPUTS > 0
    for (int k = 0; k < CLR_NUM_OUTPUTS; ++k) {
      const int format = u->target_format[k];
      if ((clears >> k) & 1u) { /* the clear value, instead of what the clear would have stored */
        const uint4 value = tile_holds_bytes(u, k) ? as_uint4(rint(as_float4(cleared[k]) * 255.0f)) : cleared[k];
        CLR_SPAN_STORE((clr_span_uint)(value.x), &tile_color[CLR_TILE_WORD(k, 0, first)]);
        CLR_SPAN_STORE((clr_span_uint)(value.y), &tile_color[CLR_TILE_WORD(k, 1, first)]);
        CLR_SPAN_STORE((clr_span_uint)(value.z), &tile_color[CLR_TILE_WORD(k, 2, first)]);
        CLR_SPAN_STORE((clr_span_uint)(value.w), &tile_color[CLR_TILE_WORD(k, 3, first)]);
        continue;
      }
      if (whole && format == CLR_FORMAT_RGBA8 && CLR_PACKED_RGBA8) {
        load_rgba8_span((__global const uint*)targets[k] + pixel, tile_holds_bytes(u, k),
                        &tile_color[CLR_TILE_WORD(k, 0, first)]);
        continue;
      }
      for (int i = 0; i < CLR_SPAN_PIXELS; ++i) {
        uint4 value = writable(x + i, y, u) && format >= 0 ? load_attachment_pixel(format, targets[k], pixel + i)
                                                            : (uint4)(0);
        if (tile_holds_bytes(u, k)) value = as_uint4(rint(as_float4(value) * 255.0f)); /* c / 255 back to c */
        tile_color[CLR_TILE_WORD(k, 0, first + i)] = value.x;
        tile_color[CLR_TILE_WORD(k, 1, first + i)] = value.y;
        tile_color[CLR_TILE_WORD(k, 2, first + i)] = value.z;
        tile_color[CLR_TILE_WORD(k, 3, first + i)] = value.w;
      }
    }
#endif
    if (clear_depth) CLR_SPAN_STORE((clr_span_float)(u->clear_depth), &tile_depth[first]);
    else if (whole) CLR_SPAN_STORE(u->depth_test ? CLR_SPAN_LOAD(&depth[pixel]) : (clr_span_float)(0.0f), &tile_depth[first]);
    else {
      for (int i = 0; i < CLR_SPAN_PIXELS; ++i) {
        tile_depth[first + i] = writable(x + i, y, u) && u->depth_test ? depth[pixel + i] : 0.0f;
      }
    }
    if (clear_stencil) CLR_SPAN_STORE((CLR_SPAN(uchar))((uchar)u->clear_stencil), &tile_stencil[first]);
    else if (whole) CLR_SPAN_STORE(u->stencil_test ? CLR_SPAN_LOAD(&stencil[pixel]) : (CLR_SPAN(uchar))(0), &tile_stencil[first]);
    else {
      for (int i = 0; i < CLR_SPAN_PIXELS; ++i) {
        tile_stencil[first + i] = writable(x + i, y, u) && u->stencil_test ? stencil[pixel + i] : 0;
      }
    }
  }

  clr_fragment f = {0};
  f.clr_tile = tile_color;
  f.clr_draw = u;
#if CLR_QUAD_EXCHANGE
  f.clr_quad = quad_exchange;
#endif
  CLR_BIND_RESOURCES(f, 0);
  f.clr_uniform_table = f.uniforms;

  for (uint base = begin; base < end; base += CLR_RASTER_TRIANGLE_BATCH) {
    const uint n = min((uint)CLR_RASTER_TRIANGLE_BATCH, end - base);
    barrier(CLK_LOCAL_MEM_FENCE); /* everyone is done with the previous batch */
    /* All the batch's records first, then their coverage: the records are scattered over the
     * chunk, and loads with nothing in between wait for memory together, not one after another. */
    for (uint i = item; i < n; i += CLR_RASTER_GROUP) {
      const uint id = sorted_triangles[base + i];
      batch[i] = (id & CLR_OVERFLOW_TRIANGLE) ? overflow[id & ~CLR_OVERFLOW_TRIANGLE] : records[id];
    }
    for (uint i = item; i < n; i += CLR_RASTER_GROUP) coverage_mask(&batch[i], origin, masks[i], &coverage[i]);
    barrier(CLK_LOCAL_MEM_FENCE);
    shade_batch(batch, masks, coverage, n, origin, item, &f, tile_color, tile_depth, tile_stencil, u);
  }
  barrier(CLK_LOCAL_MEM_FENCE); /* every pixel's last fragment is in the tile */
  const int4 depth_rect = moved_rect(clear_depth, u);
  const int4 stencil_rect = moved_rect(clear_stencil, u);
  const bool store_depth = empty ? clear_depth : (u->depth_test && u->depth_write) || clear_depth;
  const bool store_stencil = empty ? clear_stencil : u->stencil_test || clear_stencil;
  for (uint first = item * CLR_SPAN_PIXELS; first < CLR_TILE_PIXELS; first += CLR_RASTER_GROUP * CLR_SPAN_PIXELS) {
    const int x = origin.x + (int)(first % CLR_TILE_SIZE);
    const int y = origin.y + (int)(first / CLR_TILE_SIZE);
    const uint pixel = (uint)y * framebuffer_width + (uint)x;
#if CLR_NUM_OUTPUTS > 0
    for (int k = 0; k < CLR_NUM_OUTPUTS; ++k) {
      const int format = u->target_format[k];
      const bool clearing = (clears >> k) & 1u;
      if (empty && !clearing) continue;
      const int4 rect = moved_rect(clearing, u);
      if (whole_span_inside(x, y, rect) && format == CLR_FORMAT_RGBA8 && CLR_PACKED_RGBA8) {
        if (empty) {
          const uint4 bytes = clr_float_to_unorm8(as_float4(cleared[k]));
          CLR_WRITE_BACK_SPAN((clr_span_uint)(bytes.x | bytes.y << 8 | bytes.z << 16 | bytes.w << 24),
                              (__global uint*)targets[k] + pixel, u->streaming_stores);
        } else {
          CLR_WRITE_BACK_SPAN(pack_rgba8_span(&tile_color[CLR_TILE_WORD(k, 0, first)], tile_holds_bytes(u, k)),
                              (__global uint*)targets[k] + pixel, u->streaming_stores);
        }
        continue;
      }
      for (int i = 0; i < CLR_SPAN_PIXELS; ++i) {
        if (inside_rect(x + i, y, rect) && format >= 0) {
          uint4 value = empty ? cleared[k] : clr_tile_pixel(tile_color, k, first + i);
          /* A tile that holds bytes has c where the attachment stores c / 255. */
          if (!empty && tile_holds_bytes(u, k)) value = as_uint4(clr_unorm8_to_float(as_float4(value)));
          store_attachment_pixel(format, targets[k], pixel + i, value);
        }
      }
    }
#endif
    const clr_span_float depths = empty ? (clr_span_float)(u->clear_depth) : CLR_SPAN_LOAD(&tile_depth[first]);
    if (store_depth && whole_span_inside(x, y, depth_rect)) {
      CLR_WRITE_BACK_SPAN(depths, &depth[pixel], u->streaming_stores);
    } else if (store_depth) {
      for (int i = 0; i < CLR_SPAN_PIXELS; ++i) {
        if (inside_rect(x + i, y, depth_rect)) depth[pixel + i] = CLR_SPAN_LANE(float, depths, i);
      }
    }
    const CLR_SPAN(uchar) stencils = empty ? (CLR_SPAN(uchar))((uchar)u->clear_stencil) : CLR_SPAN_LOAD(&tile_stencil[first]);
    if (store_stencil && whole_span_inside(x, y, stencil_rect)) {
      CLR_SPAN_STORE(stencils, &stencil[pixel]);
    } else if (store_stencil) {
      for (int i = 0; i < CLR_SPAN_PIXELS; ++i) {
        if (inside_rect(x + i, y, stencil_rect)) stencil[pixel + i] = CLR_SPAN_LANE(uchar, stencils, i);
      }
    }
  }
  /* The pixels outside the clip rectangle meet the others here, not at the kernel's end, which the
   * groups of empty tiles reach from their early return: PoCL (3.1) took a branch joining that
   * path as uniform, so in a group of many work-items every pixel followed work-item 0 and the
   * rows below a partial tile were written outside the framebuffer. */
  barrier(CLK_LOCAL_MEM_FENCE);
}
