/* raster.cl: rasterization, the fragment program and the per-fragment operations.
 *
 * One work-group per screen tile of CLR_TILE_SIZE^2 pixels, one work-item per pixel. The tile's
 * colour attachments, depth and stencil live in local memory from the first triangle to the last,
 * and the group walks its tile's triangles in primitive order, staging CLR_RASTER_TRIANGLE_BATCH of
 * them at a time in local memory too. Each work-item is the only one to touch its pixel's
 * attachments, so there are no atomics on them and every run gives the same result.
 *
 * Per fragment, in OpenGL's order: coverage, the fragment program, the stencil test, the depth test
 * (with their stencil operations and depth write), then blending, the write mask and conversion to
 * the attachment's format, for each output. A program that neither discards nor writes depth nor
 * takes derivatives has its tests run first (early fragment tests), so hidden fragments skip it.
 *
 * Tile storage: a colour attachment's pixel is a uint4 holding the decoded value exactly as the
 * attachment stores it (float4 bits for normalized and float formats, already quantized to the
 * format; int4 or uint4 for integer ones). Programs that take derivatives are shaded in 2x2 quads:
 * every work-item of the tile runs the program for every triangle that covers any pixel of the tile,
 * the uncovered ones as helpers whose results are thrown away (prelude.cl exchanges the values). */

#define CLR_TILE_PIXELS (CLR_TILE_SIZE * CLR_TILE_SIZE)
#define CLR_TILE_TARGETS (CLR_NUM_OUTPUTS > 0 ? CLR_NUM_OUTPUTS : 1)

/* Edge functions of the pixel centre (x, y): e[k] = 2 * area * screen barycentric k. */
inline void edge_values(const __local SetupTriangle* t, int x, int y, long* e) {
  const long X = (long)x << CLR_SUBPIXEL_BITS;
  const long Y = (long)y << CLR_SUBPIXEL_BITS;
  for (int k = 0; k < 3; ++k) e[k] = (long)t->edge_a[k] * X + (long)t->edge_b[k] * Y + t->edge_c[k];
}

inline bool triangle_covers(const __local SetupTriangle* t, int x, int y, long* e) {
  /* The bounding box rejects most pixels of a tile with a few 32-bit comparisons. */
  if (x < (int)(t->pixel_min & 0xffffu) || x > (int)(t->pixel_max & 0xffffu) || y < (int)(t->pixel_min >> 16) ||
      y > (int)(t->pixel_max >> 16)) {
    return false;
  }
  edge_values(t, x, y, e);
  bool covered = true;
  for (int k = 0; k < 3; ++k) covered = covered && (e[k] > 0 || (e[k] == 0 && (t->flags & (1u << k))));
  return covered;
}

/* Edge k's function at (X, Y) for the vertices before snapping, from its value e for the snapped ones. */
inline float unsnapped_edge(const __local SetupTriangle* t, int k, long e, float X, float Y) {
  return (float)e + (t->edge_correction[k][0] * X + t->edge_correction[k][1] * Y + t->edge_correction[k][2]);
}

/* Varying float j weighted by w (used by the generated clr_interpolate_varyings). */
inline float clr_weighted_varying(const __local SetupTriangle* t, int j, float3 w) {
  return w.x * t->varyings[0][j] + w.y * t->varyings[1][j] + w.z * t->varyings[2][j];
}

inline bool is_normalized_format(int format) { return format <= CLR_FORMAT_SRGB8_A8; }
inline bool is_integer_format(int format) { return format >= CLR_FORMAT_R32I && format <= CLR_FORMAT_RGBA32UI; }
inline bool is_signed_integer_format(int format) { return format == CLR_FORMAT_R32I || format == CLR_FORMAT_RGBA32I; }

/* An attachment's pixel in the tile's representation (see above). */
inline uint4 load_attachment_pixel(int format, __global const uchar* data, uint pixel) {
  if (is_signed_integer_format(format)) return as_uint4(clr_load_texel_int(format, data, pixel));
  if (is_integer_format(format)) return clr_load_texel_uint(format, data, pixel);
  return as_uint4(clr_load_texel_float(format, data, pixel));
}
inline void store_attachment_pixel(int format, __global uchar* data, uint pixel, uint4 value) {
  if (is_signed_integer_format(format)) clr_store_texel_int(format, data, pixel, as_int4(value));
  else if (is_integer_format(format)) clr_store_texel_uint(format, data, pixel, value);
  else clr_store_texel_float(format, data, pixel, as_float4(value));
}

/* Stencil test, then depth test, with their stencil operations and the depth write; true when the
 * fragment passes both. */
inline bool fragment_tests(clr_fragment* f, __constant const DrawUniforms* u, __local float* depth,
                           __local uchar* stencil) {
  const StencilUniforms s = u->stencil[f->front_facing ? 0 : 1];
  const bool stencil_passes = !u->stencil_test || clr_stencil_test(s, *stencil);
  bool depth_passes = true;
  if (stencil_passes && u->depth_test) {
    depth_passes = u->depth_func == CLR_COMPARE_PROGRAM ? clr_program_depth_test(f, f->frag_depth, *depth)
                                                        : clr_compare(u->depth_func, f->frag_depth, *depth);
  }
  if (u->stencil_test) *stencil = (uchar)clr_stencil_update(s, clr_stencil_op(s, stencil_passes, depth_passes), *stencil);
  if (!stencil_passes || !depth_passes) return false;
  if (u->depth_test && u->depth_write) *depth = f->frag_depth;
  return true;
}

/* Output `target` of a fragment into a normalized or float attachment: blending (OpenGL's
 * equations, or the program's blend function for channels whose equation is CLR_BLEND_PROGRAM),
 * the write mask, and quantization to the attachment's format. */
void clr_merge_float_output(clr_fragment* f, uint target, float4 source, __local uint4* tile, uint lane,
                            __constant const DrawUniforms* u) {
  const int format = u->target_format[target];
  if (format < 0) return;
  __local uint4* pixel = &tile[target * CLR_TILE_PIXELS + lane];
  const float4 destination = as_float4(*pixel);
  BlendUniforms b = u->blend[target];
  float4 result = source;
  if (b.enabled) {
    const bool program_rgb = b.rgb_equation == CLR_BLEND_PROGRAM;
    const bool program_alpha = b.alpha_equation == CLR_BLEND_PROGRAM;
    const float4 programmed =
        program_rgb || program_alpha ? clr_program_blend(f, target, source, destination) : (float4)(0.0f);
    if (program_rgb) b.rgb_equation = CLR_BLEND_ADD;
    if (program_alpha) b.alpha_equation = CLR_BLEND_ADD;
    const float4 constant_color = vload4(0, u->blend_color);
    /* 8-bit linear attachments blend in 8-bit fixed point, as llvmpipe does (fragment_ops.cl). */
    const int channels = clr_texel_layout_of(format).channels;
    const float4 fixed =
        format <= CLR_FORMAT_RGBA8
            ? clr_blend_unorm8(b, source, destination, constant_color, channels)
            : clr_blend(b, source, destination, constant_color, is_normalized_format(format), channels);
    result = (float4)(program_rgb ? programmed.xyz : fixed.xyz, program_alpha ? programmed.w : fixed.w);
  }
  *pixel = as_uint4(clr_quantize_float(format, clr_apply_write_mask(b.write_mask, result, destination)));
}

/* Output `target` into an integer attachment: no blending (as in OpenGL), the write mask only. */
void clr_merge_integer_output(uint target, uint4 value, __local uint4* tile, uint lane,
                              __constant const DrawUniforms* u) {
  if (u->target_format[target] < 0) return;
  __local uint4* pixel = &tile[target * CLR_TILE_PIXELS + lane];
  *pixel = select(*pixel, value, clr_write_mask_lanes(u->blend[target].write_mask));
}

/* One fragment of triangle t at this work-item's pixel (x, y) with edge values e. `live`: the
 * triangle covers the pixel and the pixel is writable; otherwise this is a helper invocation
 * (quad shading only). */
inline void process_fragment(const __local SetupTriangle* t, int x, int y, const long* e, bool live, clr_fragment* f,
                             __local uint4* tile_color, __local float* depth, __local uchar* stencil,
                             __constant const DrawUniforms* u) {
  /* Barycentrics of the unsnapped triangle (see SetupTriangle), as llvmpipe interpolates: those of
   * the snapped one are off by up to 1/512 pixel over the distance to an edge, which perspective
   * magnifies (1e-3 of the texture coordinates near a horizon). */
  const float X = (float)(x << CLR_SUBPIXEL_BITS);
  const float Y = (float)(y << CLR_SUBPIXEL_BITS);
  const float3 unsnapped = (float3)(unsnapped_edge(t, 0, e[0], X, Y), unsnapped_edge(t, 1, e[1], X, Y),
                                    unsnapped_edge(t, 2, e[2], X, Y));
  const float3 l = unsnapped * t->inv_double_area;
  /* Depth is linear in window space; OpenGL clamps it to the depth range. */
  const float z = clamp(l.x * t->z[0] + l.y * t->z[1] + l.z * t->z[2], 0.0f, 1.0f);
  /* Perspective-correct: interpolate value / w and 1 / w linearly, then divide. */
  const float3 pw = l * (float3)(t->inv_w[0], t->inv_w[1], t->inv_w[2]);
  const float norm = 1.0f / (pw.x + pw.y + pw.z);
  f->frag_coord = (float4)((float)x + 0.5f, (float)y + 0.5f, z, pw.x + pw.y + pw.z);
  f->barycentric = pw * norm;
  f->frag_depth = z;
  f->primitive_id = t->primitive_id;
  f->front_facing = (t->flags & CLR_TRIANGLE_FRONT_FACING) != 0;
  f->helper = !live;
  f->discarded = false;
  const clr_outputs no_outputs = {0};
  f->out = no_outputs;
  clr_interpolate_varyings(t, pw, norm, l, &f->in);
#if CLR_EARLY_TESTS
  if (!fragment_tests(f, u, depth, stencil)) return;
  fragment(f);
#else
  fragment(f);
  if (!live || f->discarded) return;
  f->frag_depth = clamp(f->frag_depth, 0.0f, 1.0f);
  if (!fragment_tests(f, u, depth, stencil)) return;
#endif
  clr_write_outputs(f, tile_color, f->clr_lane, u);
}

__kernel __attribute__((reqd_work_group_size(CLR_TILE_SIZE, CLR_TILE_SIZE, 1)))
void raster_tiles(__global const SetupTriangle* records, __global const SetupTriangle* overflow,
                  __global const uint* sorted_triangles, __global const uint* tile_ranges, uint tiles_x,
                  uint framebuffer_width, __constant const DrawUniforms* u, __global uchar* depth_stencil,
                  uint stencil_offset CLR_TARGET_PARAMS CLR_RESOURCE_PARAMS) {
  __local SetupTriangle batch[CLR_RASTER_TRIANGLE_BATCH];
  __local uint4 tile_color[CLR_TILE_TARGETS * CLR_TILE_PIXELS];
  __local float tile_depth[CLR_TILE_PIXELS];
  __local uchar tile_stencil[CLR_TILE_PIXELS];
#if CLR_QUAD_SHADING
  __local float4 quad_exchange[CLR_TILE_PIXELS];
  __local uint group_coverage[CLR_RASTER_TRIANGLE_BATCH / 32]; /* bit i: triangle i covers a pixel */
  /* Bit i: triangle i covers this pixel. In local memory, not in a private array: PoCL 3.1 keeps one
   * copy for the whole group of a private array that lives across the fragment program's barriers,
   * and with the coverage bits (or the edge values) in one, every pixel of a tile was shaded as live,
   * or as a helper, as one of them was. Private arrays here live between two barriers only. */
  __local uint pixel_coverage[CLR_TILE_PIXELS][CLR_RASTER_TRIANGLE_BATCH / 32];
#endif
  const uint tile = get_group_id(1) * tiles_x + get_group_id(0);
  const uint begin = tile_ranges[2 * tile];
  const uint end = tile_ranges[2 * tile + 1];
  if (begin == end) return; /* the same for the whole group: no barrier is skipped by only some items */

  const int x = get_global_id(0);
  const int y = get_global_id(1);
  const bool writable = x >= u->clip_rect[0] && x < u->clip_rect[2] && y >= u->clip_rect[1] && y < u->clip_rect[3];
  const uint pixel = (uint)y * framebuffer_width + (uint)x;
  const uint lane = get_local_id(1) * CLR_TILE_SIZE + get_local_id(0);
  __global float* depth = (__global float*)depth_stencil;
  __global uchar* stencil = depth_stencil + stencil_offset;
#if CLR_NUM_OUTPUTS > 0 /* a program without outputs (a depth-only pass) has no colour targets */
  __global uchar* const targets[CLR_NUM_OUTPUTS] = CLR_TARGETS;
  for (int k = 0; k < CLR_NUM_OUTPUTS; ++k) {
    const int format = u->target_format[k];
    tile_color[k * CLR_TILE_PIXELS + lane] =
        writable && format >= 0 ? load_attachment_pixel(format, targets[k], pixel) : (uint4)(0);
  }
#endif
  tile_depth[lane] = writable && u->depth_test ? depth[pixel] : 0.0f;
  tile_stencil[lane] = writable && u->stencil_test ? stencil[pixel] : 0;

  clr_fragment f = {0};
  f.clr_tile = tile_color;
  f.clr_draw = u;
  f.clr_lane = lane;
#if CLR_QUAD_SHADING
  f.clr_quad = quad_exchange;
#endif
  CLR_BIND_RESOURCES(f);

  for (uint base = begin; base < end; base += CLR_RASTER_TRIANGLE_BATCH) {
    const uint n = min((uint)CLR_RASTER_TRIANGLE_BATCH, end - base);
    barrier(CLK_LOCAL_MEM_FENCE); /* everyone is done with the previous batch */
    for (uint i = lane; i < n; i += CLR_TILE_PIXELS) {
      const uint id = sorted_triangles[base + i];
      batch[i] = (id & CLR_OVERFLOW_TRIANGLE) ? overflow[id & ~CLR_OVERFLOW_TRIANGLE] : records[id];
    }
#if CLR_QUAD_SHADING
    if (lane < CLR_RASTER_TRIANGLE_BATCH / 32) group_coverage[lane] = 0;
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint w = 0; w < CLR_RASTER_TRIANGLE_BATCH / 32; ++w) {
      uint covered = 0;
      long e[3];
      for (uint i = w * 32; i < min(n, w * 32 + 32); ++i) {
        if (writable && triangle_covers(&batch[i], x, y, e)) covered |= 1u << (i % 32);
      }
      pixel_coverage[lane][w] = covered;
      if (covered) atomic_or(&group_coverage[w], covered);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    for (uint i = 0; i < n; ++i) {
      /* The same decision in every work-item, so all of them reach the program's barriers. */
      if (!(group_coverage[i / 32] & (1u << (i % 32)))) continue;
      long e[3];
      edge_values(&batch[i], x, y, e);
      process_fragment(&batch[i], x, y, e, (pixel_coverage[lane][i / 32] >> (i % 32)) & 1u, &f, tile_color,
                       &tile_depth[lane], &tile_stencil[lane], u);
      /* What follows the program's last barrier branches per pixel (helper or not, discard, the
       * tests, blending, the program's own code). Those branches must meet again at a barrier before
       * the loop goes on: PoCL otherwise takes a branch that leads on toward the next iteration's
       * barriers as uniform and follows work-item 0's way for the whole group, so every pixel of the
       * tile was written, or left, as its first pixel was. */
      barrier(CLK_LOCAL_MEM_FENCE);
    }
#else
    barrier(CLK_LOCAL_MEM_FENCE);
    if (writable) {
      long e[3];
      for (uint i = 0; i < n; ++i) {
        if (triangle_covers(&batch[i], x, y, e)) {
          process_fragment(&batch[i], x, y, e, true, &f, tile_color, &tile_depth[lane], &tile_stencil[lane], u);
        }
      }
    }
#endif
  }
  if (!writable) return;
#if CLR_NUM_OUTPUTS > 0
  for (int k = 0; k < CLR_NUM_OUTPUTS; ++k) {
    const int format = u->target_format[k];
    if (format >= 0) store_attachment_pixel(format, targets[k], pixel, tile_color[k * CLR_TILE_PIXELS + lane]);
  }
#endif
  if (u->depth_test && u->depth_write) depth[pixel] = tile_depth[lane];
  if (u->stencil_test) stencil[pixel] = tile_stencil[lane];
}
