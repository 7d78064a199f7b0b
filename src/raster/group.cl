/* group.cl: a tile's work-group: how many work-items it has (CLR_RASTER_GROUP), and which
 * strategy (strategy/) they shade its triangles' fragments with, by the program and the context's
 * shape: one work-item per pixel on GPUs, few on CPUs (clr_limits.h).
 *
 * Programs that take derivatives are shaded in 2x2 quads, the quad's uncovered pixels running the
 * program as helpers whose results are thrown away. A span program in spans of eight takes a
 * triangle's quads two to a span (strategy/quad_spans.cl), its derivatives differences between
 * lanes. Otherwise a work-item per pixel of a quad (prelude.cl exchanges the values at barriers): on
 * GPUs a work-item per pixel of the tile, every one running the program for every triangle that
 * covers any pixel of the tile (strategy/tile_quads.cl); on CPUs four work-items, which walk the
 * quads each triangle covers together (strategy/quad_walk.cl): PoCL runs a group's work-items one
 * after another between barriers, so the tile's 256 would each run the program for every triangle
 * of the tile (a textured 1080p frame of the demo scene took 2.7 s at 16x16 tiles against
 * llvmpipe's 59 ms). Programs without derivatives take the context's shape (strategy/spans.cl). */

#include "raster/span.cl"
#include "shared/clr_limits.h"

#define CLR_TILE_PIXELS (CLR_TILE_SIZE * CLR_TILE_SIZE)
/* Quad shading in spans of one pixel exchanges values between the pixels of a quad at barriers: one
 * work-item per pixel, of the tile where the context's shape has a work-item per pixel (GPUs), else
 * of one quad at a time. Other programs, quad spans included (span.cl), take the context's
 * shape (clr_limits.h). */
#define CLR_QUAD_EXCHANGE (CLR_QUAD_SHADING && !CLR_QUAD_SPANS)
#if CLR_QUAD_EXCHANGE && CLR_RASTER_GROUP_SIZE >= CLR_TILE_PIXELS
#define CLR_RASTER_GROUP CLR_TILE_PIXELS
#elif CLR_QUAD_EXCHANGE
#define CLR_RASTER_GROUP CLR_QUAD_PIXELS
#else
#define CLR_RASTER_GROUP CLR_RASTER_GROUP_SIZE
#endif

/* The strategy whose shade_batch the kernel runs for each batch of triangles, one of strategy/'s
 * files: each defines it only where its condition below holds, and exactly one does. shade_batch
 * shades the fragments of the batch's n triangles, whose coverage of the tile at `origin` is in masks. */
#define CLR_SHADE_QUAD_SPANS CLR_QUAD_SPANS                                            /* quad_spans.cl */
#define CLR_SHADE_QUAD_WALK (CLR_QUAD_EXCHANGE && CLR_RASTER_GROUP == CLR_QUAD_PIXELS) /* quad_walk.cl */
#define CLR_SHADE_TILE_QUADS (CLR_QUAD_EXCHANGE && CLR_RASTER_GROUP != CLR_QUAD_PIXELS) /* tile_quads.cl */
#define CLR_SHADE_SPANS (!CLR_QUAD_SPANS && !CLR_QUAD_EXCHANGE)                        /* spans.cl */
