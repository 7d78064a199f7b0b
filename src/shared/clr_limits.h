/* clr_limits.h: every hard limit and tunable of the clraster pipeline, in one place.
 *
 * Included by the host C++ code and prepended to every OpenCL program, so both sides agree on
 * sizes and layouts. Plain preprocessor constants only: this file must stay valid C++ and OpenCL C.
 */
#ifndef CLRASTER_LIMITS_H
#define CLRASTER_LIMITS_H

/* ---- Framebuffers and viewports ------------------------------------------------------------ */
#define CLR_MAX_FRAMEBUFFER_SIZE 16384 /* pixels per side */
#define CLR_MAX_LAYERS 4096 /* layers of a layered framebuffer: views of a draw (4096 fit 12 bits of a triangle's flags) */
#define CLR_MAX_VIEWPORT_OFFSET 32768  /* |viewport x|, |viewport y| (GL_VIEWPORT_BOUNDS_RANGE) */

/* ---- Fixed-point rasterization ---------------------------------------------------------------
 * Window coordinates are snapped to 1/256 pixel, as llvmpipe does. Snapped coordinates are kept
 * within +-2^29 (2^21 pixels) by the guard band, so edge-function products stay below 2^61 and
 * 64-bit evaluation is exact. */
#define CLR_SUBPIXEL_BITS 8
#define CLR_SUBPIXEL_ONE (1 << CLR_SUBPIXEL_BITS)
#define CLR_GUARD_BAND_PIXELS 2000000.0f /* |window x|, |window y| after clipping */

/* ---- Clipping ----------------------------------------------------------------------------------
 * A triangle is clipped against near, far and the four guard-band planes: at most 3 + 6 vertices,
 * fanned into at most 7 triangles. */
#define CLR_CLIP_PLANES 6
#define CLR_MAX_CLIP_VERTICES (3 + CLR_CLIP_PLANES)
#define CLR_MAX_CLIP_TRIANGLES (CLR_MAX_CLIP_VERTICES - 2)

/* ---- Textures ------------------------------------------------------------------------------------ */
#define CLR_MAX_TEXTURE_SIZE 16384 /* texels per side */
#define CLR_MAX_TEXTURE_LEVELS 15  /* a full mip chain of CLR_MAX_TEXTURE_SIZE */
#define CLR_MAX_TEXTURE_LOD_BIAS 16.0f /* |sampler lod bias| is clamped to this (llvmpipe's GL_MAX_TEXTURE_LOD_BIAS) */

/* ---- Framebuffer attachments --------------------------------------------------------------------- */
#define CLR_MAX_COLOR_ATTACHMENTS 8

/* ---- Work-group sizes -------------------------------------------------------------------------- */
#define CLR_ITEM_GROUP_SIZE 64    /* one-work-item-per-element kernels (vertices, primitives) */
/* Vertices one work-item of the vertex stage shades on a CPU, whose clip codes, projection and
 * snapping it then computes together, one vector lane each (the build option CLR_VERTEX_LANES; GPUs
 * take 1). PoCL does not vectorize that fixed-function work across work-items, because the vertex
 * program before it works on float4s (geometry/clip.cl). */
#define CLR_CPU_VERTEX_LANES 8
/* Scans and index validation take blocks of CLR_SCAN_BLOCK elements, one work-group each (radix
 * sorts take blocks of their own, below). Its work-items (CLR_SCAN_GROUP_SIZE, a build option) are
 * the device's choice: CLR_SCAN_GPU_ITEMS on GPUs, which share a block's work through local memory,
 * and CLR_SCAN_CPU_ITEMS on CPUs, where PoCL would run the group's many barriers (each a pass of a
 * loop over all its work-items) for what one work-item does in one pass over the block (measured). */
#define CLR_SCAN_BLOCK 2048
#define CLR_SCAN_GPU_ITEMS 256
#define CLR_SCAN_CPU_ITEMS 1
#ifdef CLR_SCAN_GROUP_SIZE
#define CLR_SCAN_ITEMS (CLR_SCAN_BLOCK / CLR_SCAN_GROUP_SIZE) /* elements per work-item */
#endif
/* The radix sort of bin pairs by tile takes blocks of pairs, one work-group each, and digits of the
 * tile key, one pass each. Where one work-item sorts a block (CPUs), its counts per digit are its
 * own and cost nothing in local memory: 11-bit digits sort 1080p's 2,040 tiles of 32x32 in one
 * pass, and blocks of 32,768 pairs keep the histogram (a count per digit and block) at a sixteenth
 * of the pairs. Where many share a block (GPUs), their counts per digit and work-item must fit the
 * 32 KiB of local memory small GPUs have: 5 bits, blocks of CLR_SCAN_BLOCK. */
#define CLR_RADIX_CPU_BITS 11
#define CLR_RADIX_CPU_BLOCK 32768
#define CLR_RADIX_GPU_BITS 5
#define CLR_RADIX_GPU_BLOCK CLR_SCAN_BLOCK
#define CLR_RADIX_BITS_FOR(items) ((items) == CLR_SCAN_CPU_ITEMS ? CLR_RADIX_CPU_BITS : CLR_RADIX_GPU_BITS)
#define CLR_RADIX_BLOCK_FOR(items) ((items) == CLR_SCAN_CPU_ITEMS ? CLR_RADIX_CPU_BLOCK : CLR_RADIX_GPU_BLOCK)
#ifdef CLR_SCAN_GROUP_SIZE
#define CLR_RADIX_BITS CLR_RADIX_BITS_FOR(CLR_SCAN_GROUP_SIZE)
#define CLR_RADIX_BUCKETS (1 << CLR_RADIX_BITS)
#define CLR_RADIX_BLOCK CLR_RADIX_BLOCK_FOR(CLR_SCAN_GROUP_SIZE)
#define CLR_RADIX_ITEMS (CLR_RADIX_BLOCK / CLR_SCAN_GROUP_SIZE) /* pairs per work-item */
#endif
#define CLR_CLEAR_TEXELS_PER_ITEM 256 /* texels one work-item of a clear writes */

/* ---- Rasterization ----------------------------------------------------------------------------- */
/* The tile size (pixels per side, one work-group per tile) is a context option; the device's
 * choice of it (kCpuShapeTileSize, kGpuShapeTileSize) and the default memory cap are in
 * clraster.hpp. */
#define CLR_RASTER_TRIANGLE_BATCH 64 /* set-up triangles staged in local memory at a time */
#define CLR_RASTER_TILE_RUN 8        /* consecutive tiles that consecutive work-groups take (raster/tile.cl) */
/* Work-items per tile work-group, but for per-fragment programs shaded in quads (below). GPUs get one
 * per pixel. A CPU device gets CLR_RASTER_CPU_ITEMS, which loop over the tile's pixels
 * themselves: PoCL runs a work-group as loops over its work-items that it cannot vectorize around
 * the per-triangle loops, and saves every live value per work-item at each barrier, so one item
 * walking the tile (its loops vectorized by the compiler where they allow it) is faster (measured). */
#define CLR_RASTER_CPU_ITEMS 1
/* Work-items of a CPU's tile work-group for per-fragment programs shaded in quads: one per pixel of
 * a 2x2 quad, exchanging values at barriers (raster/group.cl; GPUs keep one per pixel of the tile). Span
 * programs shaded in quads take CLR_RASTER_CPU_ITEMS. */
#define CLR_QUAD_PIXELS 4
/* Pixels of a tile row such a work-item shades together, one vector lane each (a span, see
 * raster/span.cl), or of a thin triangle's rows packed together (raster/strategy/spans.cl): one byte of a
 * coverage mask word, and AVX's 8 floats. Spans of 4 were
 * measured too: large triangles' fragments (fill-16) about 1.4 times slower, small triangles' no
 * faster beyond the noise. */
#define CLR_CPU_SPAN_PIXELS 8
/* Framebuffers of at least this many pixels get the tiles' write-back as non-temporal stores. A
 * pass that writes its attachments' pending clears writes lines that nothing else reads, and a
 * plain store would first fetch each one from memory; a framebuffer this large is not in the caches
 * when the next draw loads it anyway. Smaller ones stay cached between draws. */
#define CLR_STREAMING_STORE_PIXELS (1 << 20)

/* ---- Block culling -------------------------------------------------------------------------------
 * Indexed draws whose vertices are shaded once per draw reject whole blocks of consecutive primitives
 * before set-up: the vertex stage ANDs the clip codes of each group of CLR_CODE_GROUP_SLOTS
 * consecutive vertex slots, and a block of CLR_CULL_BLOCK_PRIMITIVES primitives whose vertices'
 * index ranges lie in groups that are all outside one clip plane or side of the viewport leaves
 * set-up nothing to read (geometry/setup.cl). A mesh's primitives near each other in its index order
 * are near each other in space, so the parts of a large mesh outside the view go a block at a time. */
#define CLR_CULL_BLOCK_PRIMITIVES 64
/* A CPU work-item of the vertex stage shades one group and stores its codes: a locked AND into a
 * group shared by several work-items waited for all the slot stores before it to reach the cache
 * (docs/performance.md, step 44). */
#define CLR_CODE_GROUP_SLOTS CLR_CPU_VERTEX_LANES

/* ---- Memory budget -----------------------------------------------------------------------------
 * Intermediate buffers are sized from the context's memory cap (ContextOptions::memory_cap). */
#define CLR_MAX_CHUNK_PRIMITIVES (1u << 20) /* primitives per geometry chunk at most */
#define CLR_MAX_PASS_DRAWS 4096              /* draws (instances) one raster pass takes at most */
#define CLR_INDEX_RANGE_CACHE_ENTRIES 4096   /* ranges an index buffer remembers the bounds of */
#define CLR_OVERFLOW_DIVISOR 8               /* room for clipped triangles: 1/8 of a chunk's primitives */
/* An indexed draw shades every vertex once when its transformed vertices take at most 1/2 of the
 * cap; else each chunk shades its stream positions, which for a mesh runs the vertex program about
 * six times per vertex (terrain-4m's vertex stage: 6 times slower at a quarter, measured). */
#define CLR_SHADE_ALL_CAP_DIVISOR 2
#define CLR_BUFFER_GROWTH_NUM 3              /* scratch buffers grow by 3/2 when too small */
#define CLR_BUFFER_GROWTH_DEN 2

/* ---- Program cache -------------------------------------------------------------------------------
 * The on-disk cache of built programs (runtime/program_cache.cpp) keeps at most this many MiB; beyond it,
 * the entries used longest ago go first. A program's binary takes about 1 MiB. */
#define CLR_PROGRAM_CACHE_MIB 512
#define CLR_MAX_PROGRAM_BINARY_MIB 1024 /* a cache entry claiming a larger binary is damaged */

/* ---- Program sources -----------------------------------------------------------------------------
 * A user program's file and the files it includes (program/includes.cpp), together, at most this
 * many MiB; includes nest at most CLR_MAX_INCLUDE_DEPTH deep (deeper is taken for a cycle). */
#define CLR_MAX_PROGRAM_SOURCE_MIB 16
#define CLR_MAX_INCLUDE_DEPTH 32

#endif /* CLRASTER_LIMITS_H */
