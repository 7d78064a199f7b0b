/* quad_walk.cl: the strategy of programs that take derivatives in spans of one pixel on CPUs
 * (group.cl): a work-item per pixel of a quad, the group's four walking each triangle's quads. */

#include "raster/coverage.cl"
#include "raster/group.cl"
#include "raster/shade.cl"
#include "raster/span.cl"
#include "shared/types.h"

#if CLR_SHADE_QUAD_WALK
CLR_INLINE void shade_batch(const __local SetupTriangle* batch, __local ulong (*masks)[CLR_TILE_MASK_WORDS],
                            const __local TileCoverage* coverage, uint n, int2 origin, uint item, clr_fragment* f,
                            __local uint* tile_color, __local float* tile_depth, __local uchar* tile_stencil,
                            __constant const DrawUniforms* u) {
  /* One work-item per pixel of a quad: the four walk the quads each triangle covers together,
   * every one deciding from the same masks, so all of them reach the program's barriers. A quad's
   * pixels are in one word of a mask: a word holds whole rows, an even number of them. */
  for (uint i = 0; i < n; ++i) {
    for (int w = coverage[i].first_word; w < coverage[i].end_word; ++w) {
      for (ulong left = masks[i][w]; left != 0;) {
        const uint corner = take_lowest_quad(&left);
        const uint pixel = (uint)w * 64 + corner + (item & 1u) + (item >> 1) * CLR_TILE_SIZE;
        const clr_span_place place = {origin.x + (int)(pixel % CLR_TILE_SIZE), origin.y + (int)(pixel / CLR_TILE_SIZE),
                                      pixel, 0, 0, 0, false};
        process_span(&batch[i], &place, clr_span_lanes_from_bits((uint)(masks[i][w] >> (pixel % 64))), f,
                     tile_color, tile_depth, tile_stencil, u);
        barrier(CLK_LOCAL_MEM_FENCE); /* as in tile_quads.cl */
      }
    }
  }
}
#endif
