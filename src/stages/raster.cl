/* raster.cl: rasterization, the fragment program and the per-fragment operations.
 *
 * One work-group per screen tile of CLR_TILE_SIZE^2 pixels. The tile's colour attachments, depth and
 * stencil live in local memory from the first triangle to the last, and the group walks its tile's
 * triangles in primitive order, staging CLR_RASTER_TRIANGLE_BATCH of them at a time in local memory
 * with each one's coverage of the tile as a bit mask (coverage_mask). Each pixel belongs to one
 * work-item, the only one to touch its attachments, so there are no atomics on them and every run
 * gives the same result. How many work-items a group has is the device's choice (CLR_RASTER_GROUP):
 * one per pixel on GPUs, few on CPUs, each then shading its pixels one after the other, visiting
 * only the pixels each triangle's mask has.
 *
 * Per fragment, in OpenGL's order: the fragment program, the stencil test, the depth test (with
 * their stencil operations and depth write), then blending, the write mask and conversion to the
 * attachment's format, for each output. A program that neither discards nor writes depth nor takes
 * derivatives has its tests run first (early fragment tests), so hidden fragments skip it.
 *
 * Tile storage: a colour attachment's pixel is a uint4 holding the decoded value exactly as the
 * attachment stores it (float4 bits for normalized and float formats, already quantized to the
 * format; int4 or uint4 for integer ones). Programs that take derivatives are shaded in 2x2 quads,
 * one work-item per pixel: every work-item runs the program for every triangle that covers any
 * pixel of the tile, the uncovered ones as helpers whose results are thrown away (prelude.cl
 * exchanges the values). */

#define CLR_TILE_PIXELS (CLR_TILE_SIZE * CLR_TILE_SIZE)
#define CLR_TILE_TARGETS (CLR_NUM_OUTPUTS > 0 ? CLR_NUM_OUTPUTS : 1)
#define CLR_TILE_MASK_WORDS (CLR_TILE_PIXELS / 64) /* 64-bit words of one triangle's coverage of a tile */
/* Quad shading exchanges values between the pixels of a quad at barriers: one work-item per pixel.
 * Other programs take the context's shape (clr_limits.h). */
#if CLR_QUAD_SHADING
#define CLR_RASTER_GROUP CLR_TILE_PIXELS
#else
#define CLR_RASTER_GROUP CLR_RASTER_GROUP_SIZE
#endif

/* Edge functions of the pixel centre (x, y): e[k] = 2 * area * screen barycentric k. */
CLR_INLINE void edge_values(const __local SetupTriangle* t, int x, int y, long* e) {
  const long X = (long)x << CLR_SUBPIXEL_BITS;
  const long Y = (long)y << CLR_SUBPIXEL_BITS;
  for (int k = 0; k < 3; ++k) e[k] = (long)t->edge_a[k] * X + (long)t->edge_b[k] * Y + t->edge_c[k];
}

/* Lanes of `inside` (each 0 or -1) as the bits of a byte, lane 0 in bit 0. */
inline uint lanes_to_bits(long8 inside) {
  const ulong8 bits = as_ulong8(inside) & (ulong8)(1, 2, 4, 8, 16, 32, 64, 128);
  const ulong4 halves = bits.lo | bits.hi;
  const ulong2 quarters = halves.lo | halves.hi;
  return (uint)(quarters.lo | quarters.hi);
}

/* Which pixels of the tile whose first pixel is `origin` the triangle covers: bit p of the mask (word
 * p / 64) is the tile's pixel p, row-major. A pixel centre is covered when every edge function is
 * positive there, or zero on an edge that includes its centres (SetupTriangle's flags): E > 0 is
 * E - 1 >= 0 in integers, so subtracting 1 from the edges without the flag makes the test a sign
 * test, and one sign test of the three values OR-ed together tests them all. Eight pixels of a row
 * at a time, in 64-bit vectors: exact, and what vector units (and PoCL's compiler) do best. */
inline void coverage_mask(const __local SetupTriangle* t, int2 origin, __local ulong* mask) {
  for (int w = 0; w < CLR_TILE_MASK_WORDS; ++w) mask[w] = 0;
  const int2 lo = max((int2)((int)(t->pixel_min & 0xffffu), (int)(t->pixel_min >> 16)), origin);
  const int2 hi = min((int2)((int)(t->pixel_max & 0xffffu), (int)(t->pixel_max >> 16)), origin + (CLR_TILE_SIZE - 1));
  if (lo.x > hi.x || lo.y > hi.y) return;
  long c[3];
  for (int k = 0; k < 3; ++k) c[k] = t->edge_c[k] - ((t->flags >> k) & 1u ? 0 : 1);
  for (int chunk = (lo.x - origin.x) / 8; chunk <= (hi.x - origin.x) / 8; ++chunk) {
    const int8 xs = (int8)(origin.x + chunk * 8) + (int8)(0, 1, 2, 3, 4, 5, 6, 7);
    const long8 X = convert_long8(xs) << CLR_SUBPIXEL_BITS;
    const long8 in_box = convert_long8(xs >= (int8)(lo.x) && xs <= (int8)(hi.x));
    const long8 ax0 = (long8)((long)t->edge_a[0]) * X;
    const long8 ax1 = (long8)((long)t->edge_a[1]) * X;
    const long8 ax2 = (long8)((long)t->edge_a[2]) * X;
    for (int y = lo.y; y <= hi.y; ++y) {
      const long Y = (long)y << CLR_SUBPIXEL_BITS;
      const long8 e0 = ax0 + ((long)t->edge_b[0] * Y + c[0]);
      const long8 e1 = ax1 + ((long)t->edge_b[1] * Y + c[1]);
      const long8 e2 = ax2 + ((long)t->edge_b[2] * Y + c[2]);
      const uint bits = lanes_to_bits(((e0 | e1 | e2) >= (long8)(0)) & in_box);
      const int first = (y - origin.y) * CLR_TILE_SIZE + chunk * 8;
      mask[first / 64] |= (ulong)bits << (first % 64);
    }
  }
}

/* Bit p of word w set where the tile's pixel 64 w + p is this work-item's: pixel p belongs to
 * work-item p % CLR_RASTER_GROUP (a power of two). Below 64 that is every CLR_RASTER_GROUP-th bit
 * from bit `item`: ~0 / (2^GROUP - 1) has a one every GROUP bits (all ones for a group of one). */
inline ulong own_pixels(uint word, uint item) {
#if CLR_RASTER_GROUP >= 64
  return word == item / 64 ? 1ul << (item % 64) : 0ul;
#else
  return (~0ul / ((1ul << CLR_RASTER_GROUP) - 1)) << item;
#endif
}

/* Edge k's function at (X, Y) for the vertices before snapping, from its value e for the snapped ones. */
CLR_INLINE float unsnapped_edge(const __local SetupTriangle* t, int k, long e, float X, float Y) {
  return (float)e + (t->edge_correction[k][0] * X + t->edge_correction[k][1] * Y + t->edge_correction[k][2]);
}

/* Varying float j weighted by w (used by the generated clr_interpolate_varyings). */
CLR_INLINE float clr_weighted_varying(const __local SetupTriangle* t, int j, float3 w) {
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
CLR_INLINE bool fragment_tests(clr_fragment* f, __constant const DrawUniforms* u, __local float* depth,
                               __local uchar* stencil) {
  __constant const StencilUniforms* s = &u->stencil[f->front_facing ? 0 : 1];
  const bool stencil_passes = !u->stencil_test || clr_stencil_test(*s, *stencil);
  bool depth_passes = true;
  if (stencil_passes && u->depth_test) {
    depth_passes = u->depth_func == CLR_COMPARE_PROGRAM ? clr_program_depth_test(f, f->frag_depth, *depth)
                                                        : clr_compare(u->depth_func, f->frag_depth, *depth);
  }
  if (u->stencil_test) {
    *stencil = (uchar)clr_stencil_update(*s, clr_stencil_op(*s, stencil_passes, depth_passes), *stencil);
  }
  if (!stencil_passes || !depth_passes) return false;
  if (u->depth_test && u->depth_write) *depth = f->frag_depth;
  return true;
}

/* Output `target` of a fragment into a normalized or float attachment: blending (OpenGL's
 * equations, or the program's blend function for channels whose equation is CLR_BLEND_PROGRAM),
 * the write mask, and quantization to the attachment's format. */
CLR_INLINE void clr_merge_float_output(clr_fragment* f, uint target, float4 source, __local uint4* tile, uint lane,
                                       __constant const DrawUniforms* u) {
  const int format = u->target_format[target];
  if (format < 0) return;
  __local uint4* pixel = &tile[target * CLR_TILE_PIXELS + lane];
  const float4 destination = as_float4(*pixel);
  BlendUniforms b = u->blend[target];
  float4 result = source;
  /* The tile keeps what a store then a load of the attachment would give only where the draw reads
   * it back (blending, framebuffer fetch): otherwise the conversion when the tile is written out at
   * the end gives the same bytes. 8-bit blending's results are on the attachment's grid already. */
  bool quantize = CLR_READS_FRAMEBUFFER;
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
    quantize = quantize || program_rgb || program_alpha || format > CLR_FORMAT_RGBA8;
  }
  result = clr_apply_write_mask(b.write_mask, result, destination);
  *pixel = as_uint4(quantize ? clr_quantize_float(format, result) : result);
}

/* Output `target` into an integer attachment: no blending (as in OpenGL), the write mask only. */
CLR_INLINE void clr_merge_integer_output(uint target, uint4 value, __local uint4* tile, uint lane,
                                         __constant const DrawUniforms* u) {
  if (u->target_format[target] < 0) return;
  __local uint4* pixel = &tile[target * CLR_TILE_PIXELS + lane];
  *pixel = select(*pixel, value, clr_write_mask_lanes(u->blend[target].write_mask));
}

/* One fragment of triangle t at pixel (x, y), the tile's pixel `lane`. `live`: the triangle covers
 * the pixel (a writable one); otherwise this is a helper invocation (quad shading only). */
CLR_INLINE void process_fragment(const __local SetupTriangle* t, int x, int y, uint lane, bool live, clr_fragment* f,
                                 __local uint4* tile_color, __local float* depth, __local uchar* stencil,
                                 __constant const DrawUniforms* u) {
  long e[3];
  edge_values(t, x, y, e);
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
  f->clr_lane = lane;
  const clr_outputs no_outputs = {0};
  f->out = no_outputs;
#if CLR_EARLY_TESTS
  /* Hidden fragments skip the interpolation too, unless the program's depth test may read it. */
  const bool program_depth_test = u->depth_test && u->depth_func == CLR_COMPARE_PROGRAM;
  if (program_depth_test) clr_interpolate_varyings(t, pw, norm, l, &f->in);
  if (!fragment_tests(f, u, depth, stencil)) return;
  if (!program_depth_test) clr_interpolate_varyings(t, pw, norm, l, &f->in);
  fragment(f);
#else
  clr_interpolate_varyings(t, pw, norm, l, &f->in);
  fragment(f);
  if (!live || f->discarded) return;
  f->frag_depth = clamp(f->frag_depth, 0.0f, 1.0f);
  if (!fragment_tests(f, u, depth, stencil)) return;
#endif
  clr_write_outputs(f, tile_color, lane, u);
}

__kernel __attribute__((reqd_work_group_size(CLR_RASTER_GROUP, 1, 1)))
void raster_tiles(__global const SetupTriangle* records, __global const SetupTriangle* overflow,
                  __global const uint* sorted_triangles, __global const uint* tile_ranges, uint tiles_x,
                  uint framebuffer_width, __constant const DrawUniforms* u, __global uchar* depth_stencil,
                  uint stencil_offset CLR_TARGET_PARAMS CLR_RESOURCE_PARAMS) {
  __local SetupTriangle batch[CLR_RASTER_TRIANGLE_BATCH];
  __local ulong masks[CLR_RASTER_TRIANGLE_BATCH][CLR_TILE_MASK_WORDS]; /* coverage_mask of each */
  __local uint4 tile_color[CLR_TILE_TARGETS * CLR_TILE_PIXELS];
  __local float tile_depth[CLR_TILE_PIXELS];
  __local uchar tile_stencil[CLR_TILE_PIXELS];
#if CLR_QUAD_SHADING
  __local float4 quad_exchange[CLR_TILE_PIXELS];
#endif
  const uint tile = get_group_id(0);
  const uint begin = tile_ranges[2 * tile];
  const uint end = tile_ranges[2 * tile + 1];
  if (begin == end) return; /* the same for the whole group: no barrier is skipped by only some items */

  const int2 origin = (int2)((int)(tile % tiles_x), (int)(tile / tiles_x)) * CLR_TILE_SIZE;
  const uint item = get_local_id(0);
  __global float* depth = (__global float*)depth_stencil;
  __global uchar* stencil = depth_stencil + stencil_offset;
#if CLR_NUM_OUTPUTS > 0 /* a program without outputs (a depth-only pass) has no colour targets */
  __global uchar* const targets[CLR_NUM_OUTPUTS] = CLR_TARGETS;
#endif
  for (uint lane = item; lane < CLR_TILE_PIXELS; lane += CLR_RASTER_GROUP) {
    const int x = origin.x + (int)(lane % CLR_TILE_SIZE);
    const int y = origin.y + (int)(lane / CLR_TILE_SIZE);
    const bool writable = x >= u->clip_rect[0] && x < u->clip_rect[2] && y >= u->clip_rect[1] && y < u->clip_rect[3];
    const uint pixel = (uint)y * framebuffer_width + (uint)x;
#if CLR_NUM_OUTPUTS > 0
    for (int k = 0; k < CLR_NUM_OUTPUTS; ++k) {
      const int format = u->target_format[k];
      tile_color[k * CLR_TILE_PIXELS + lane] =
          writable && format >= 0 ? load_attachment_pixel(format, targets[k], pixel) : (uint4)(0);
    }
#endif
    tile_depth[lane] = writable && u->depth_test ? depth[pixel] : 0.0f;
    tile_stencil[lane] = writable && u->stencil_test ? stencil[pixel] : 0;
  }

  clr_fragment f = {0};
  f.clr_tile = tile_color;
  f.clr_draw = u;
#if CLR_QUAD_SHADING
  f.clr_quad = quad_exchange;
#endif
  CLR_BIND_RESOURCES(f);

  for (uint base = begin; base < end; base += CLR_RASTER_TRIANGLE_BATCH) {
    const uint n = min((uint)CLR_RASTER_TRIANGLE_BATCH, end - base);
    barrier(CLK_LOCAL_MEM_FENCE); /* everyone is done with the previous batch */
    for (uint i = item; i < n; i += CLR_RASTER_GROUP) {
      const uint id = sorted_triangles[base + i];
      batch[i] = (id & CLR_OVERFLOW_TRIANGLE) ? overflow[id & ~CLR_OVERFLOW_TRIANGLE] : records[id];
      coverage_mask(&batch[i], origin, masks[i]);
    }
    barrier(CLK_LOCAL_MEM_FENCE);
#if CLR_QUAD_SHADING
    /* One work-item per pixel: every one runs the program for each triangle that covers any pixel
     * of the tile, the uncovered ones as helpers. */
    const int x = origin.x + (int)(item % CLR_TILE_SIZE);
    const int y = origin.y + (int)(item / CLR_TILE_SIZE);
    for (uint i = 0; i < n; ++i) {
      ulong any = 0;
      for (int w = 0; w < CLR_TILE_MASK_WORDS; ++w) any |= masks[i][w];
      /* The same decision in every work-item, so all of them reach the program's barriers. */
      if (!any) continue;
      process_fragment(&batch[i], x, y, item, (masks[i][item / 64] >> (item % 64)) & 1u, &f, tile_color,
                       &tile_depth[item], &tile_stencil[item], u);
      /* What follows the program's last barrier branches per pixel (helper or not, discard, the
       * tests, blending, the program's own code). Those branches must meet again at a barrier before
       * the loop goes on: PoCL otherwise takes a branch that leads on toward the next iteration's
       * barriers as uniform and follows work-item 0's way for the whole group, so every pixel of the
       * tile was written, or left, as its first pixel was. */
      barrier(CLK_LOCAL_MEM_FENCE);
    }
#else
    /* Each work-item shades the fragments of its own pixels, triangle by triangle in primitive
     * order, visiting only the pixels each triangle covers. */
    for (uint i = 0; i < n; ++i) {
      for (int w = 0; w < CLR_TILE_MASK_WORDS; ++w) {
        for (ulong bits = masks[i][w] & own_pixels(w, item); bits != 0; bits &= bits - 1) {
          const uint lane = (uint)w * 64 + (63 - clz(bits & (0 - bits)));
          process_fragment(&batch[i], origin.x + (int)(lane % CLR_TILE_SIZE), origin.y + (int)(lane / CLR_TILE_SIZE),
                           lane, true, &f, tile_color, &tile_depth[lane], &tile_stencil[lane], u);
        }
      }
    }
#endif
  }
  barrier(CLK_LOCAL_MEM_FENCE); /* every pixel's last fragment is in the tile */
  for (uint lane = item; lane < CLR_TILE_PIXELS; lane += CLR_RASTER_GROUP) {
    const int x = origin.x + (int)(lane % CLR_TILE_SIZE);
    const int y = origin.y + (int)(lane / CLR_TILE_SIZE);
    if (!(x >= u->clip_rect[0] && x < u->clip_rect[2] && y >= u->clip_rect[1] && y < u->clip_rect[3])) continue;
    const uint pixel = (uint)y * framebuffer_width + (uint)x;
#if CLR_NUM_OUTPUTS > 0
    for (int k = 0; k < CLR_NUM_OUTPUTS; ++k) {
      const int format = u->target_format[k];
      if (format >= 0) store_attachment_pixel(format, targets[k], pixel, tile_color[k * CLR_TILE_PIXELS + lane]);
    }
#endif
    if (u->depth_test && u->depth_write) depth[pixel] = tile_depth[lane];
    if (u->stencil_test) stencil[pixel] = tile_stencil[lane];
  }
}
