/* raster.cl: rasterization, depth test, perspective-correct interpolation, shading and blending.
 *
 * One work-group per screen tile of CLR_TILE_SIZE^2 pixels, one work-item per pixel. The tile's
 * colour and depth live in local memory from the first triangle to the last, and the group walks its
 * tile's triangles in primitive order, staging CLR_RASTER_TRIANGLE_BATCH of them at a time in local
 * memory too. Each work-item tests only its own pixel and is the only one to touch that pixel's
 * colour and depth, so there are no atomics and no races, and every run gives the same result. */

inline bool triangle_covers(const __local SetupTriangle* t, int x, int y, long* e) {
  /* The bounding box rejects most pixels of a tile with a few 32-bit comparisons. */
  if (x < (int)(t->pixel_min & 0xffffu) || x > (int)(t->pixel_max & 0xffffu) || y < (int)(t->pixel_min >> 16) ||
      y > (int)(t->pixel_max >> 16)) {
    return false;
  }
  const long X = (long)x << CLR_SUBPIXEL_BITS;
  const long Y = (long)y << CLR_SUBPIXEL_BITS;
  bool covered = true;
  for (int k = 0; k < 3; ++k) {
    e[k] = (long)t->edge_a[k] * X + (long)t->edge_b[k] * Y + t->edge_c[k];
    covered = covered && (e[k] > 0 || (e[k] == 0 && (t->flags & (1u << k))));
  }
  return covered;
}

inline bool depth_passes(int func, float fragment, float stored) {
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

/* The built-in fragment program (see clraster::Shading). */
inline float4 shade(__constant const DrawUniforms* u, float3 v) {
  const float4 base = vload4(0, u->base_color);
  switch (u->shading) {
    case CLR_SHADING_NORMAL: {
      const float len = length(v);
      return (float4)(len > 0.0f ? v / len * 0.5f + 0.5f : (float3)(0.5f), 1.0f);
    }
    case CLR_SHADING_LAMBERT: {
      const float len = length(v);
      const float k = 0.1f + 0.9f * (len > 0.0f ? fabs(v.z / len) : 0.0f);
      return (float4)(base.xyz * k, base.w);
    }
    case CLR_SHADING_DEPTH: {
      const float g = clamp(1.0f - (v.x - u->depth_shading_range[0]) /
                                       (u->depth_shading_range[1] - u->depth_shading_range[0]),
                            0.0f, 1.0f);
      return (float4)(g, g, g, 1.0f);
    }
    default: return base;
  }
}

/* Float to unsigned normalized 8 bits, round to nearest (NaN becomes 0). */
inline uint pack_unorm8(float4 c) {
  const uint4 b = convert_uint4(clamp(c, 0.0f, 1.0f) * 255.0f + 0.5f);
  return b.x | b.y << 8 | b.z << 16 | b.w << 24;
}

inline uint blend(int mode, uint source, uint destination) {
  if (mode == CLR_BLEND_ADDITIVE) {
    return as_uint(add_sat(as_uchar4(source), as_uchar4(destination)));
  }
  return source;
}

inline void rasterize_pixel(const __local SetupTriangle* t, int x, int y, __constant const DrawUniforms* u,
                            __local uint* color, __local float* depth) {
  long e[3];
  if (!triangle_covers(t, x, y, e)) return;
  const float3 l = (float3)((float)e[0], (float)e[1], (float)e[2]) * t->inv_double_area;
  /* Depth is linear in window space; OpenGL clamps it to the depth range. */
  const float z = clamp(l.x * t->z[0] + l.y * t->z[1] + l.z * t->z[2], 0.0f, 1.0f);
  if (u->depth_test) {
    if (!depth_passes(u->depth_func, z, *depth)) return;
    if (u->depth_write) *depth = z;
  }
  /* Perspective-correct: interpolate varying / w and 1 / w linearly, then divide. */
  const float3 pw = l * (float3)(t->inv_w[0], t->inv_w[1], t->inv_w[2]);
  const float norm = 1.0f / (pw.x + pw.y + pw.z);
  float3 v;
  v.x = (pw.x * t->varyings[0][0] + pw.y * t->varyings[1][0] + pw.z * t->varyings[2][0]) * norm;
  v.y = (pw.x * t->varyings[0][1] + pw.y * t->varyings[1][1] + pw.z * t->varyings[2][1]) * norm;
  v.z = (pw.x * t->varyings[0][2] + pw.y * t->varyings[1][2] + pw.z * t->varyings[2][2]) * norm;
  *color = blend(u->blend, pack_unorm8(shade(u, v)), *color);
}

__kernel __attribute__((reqd_work_group_size(CLR_TILE_SIZE, CLR_TILE_SIZE, 1)))
void raster_tiles(__global const SetupTriangle* records, __global const SetupTriangle* overflow,
                  __global const uint* sorted_triangles,
                  __global const uint* tile_ranges, uint tiles_x, __global uint* color, __global float* depth,
                  uint framebuffer_width, __constant const DrawUniforms* u) {
  __local SetupTriangle batch[CLR_RASTER_TRIANGLE_BATCH];
  __local uint tile_color[CLR_TILE_SIZE * CLR_TILE_SIZE];
  __local float tile_depth[CLR_TILE_SIZE * CLR_TILE_SIZE];
  const uint tile = get_group_id(1) * tiles_x + get_group_id(0);
  const uint begin = tile_ranges[2 * tile];
  const uint end = tile_ranges[2 * tile + 1];
  if (begin == end) return; /* the same for the whole group: no barrier is skipped by only some items */

  const int x = get_global_id(0);
  const int y = get_global_id(1);
  const bool writable = x >= u->clip_rect[0] && x < u->clip_rect[2] && y >= u->clip_rect[1] && y < u->clip_rect[3];
  const uint pixel = (uint)y * framebuffer_width + (uint)x;
  const uint lid = get_local_id(1) * CLR_TILE_SIZE + get_local_id(0);
  tile_color[lid] = writable ? color[pixel] : 0u;
  tile_depth[lid] = writable ? depth[pixel] : 0.0f;

  for (uint base = begin; base < end; base += CLR_RASTER_TRIANGLE_BATCH) {
    const uint n = min((uint)CLR_RASTER_TRIANGLE_BATCH, end - base);
    barrier(CLK_LOCAL_MEM_FENCE); /* everyone is done with the previous batch */
    for (uint i = lid; i < n; i += CLR_TILE_SIZE * CLR_TILE_SIZE) {
      const uint id = sorted_triangles[base + i];
      batch[i] = (id & CLR_OVERFLOW_TRIANGLE) ? overflow[id & ~CLR_OVERFLOW_TRIANGLE] : records[id];
    }
    barrier(CLK_LOCAL_MEM_FENCE);
    if (writable) {
      for (uint i = 0; i < n; ++i) rasterize_pixel(&batch[i], x, y, u, &tile_color[lid], &tile_depth[lid]);
    }
  }
  if (writable) {
    color[pixel] = tile_color[lid];
    depth[pixel] = tile_depth[lid];
  }
}
