/* tile_quads.cl: the strategy of programs that take derivatives in spans of one pixel on GPUs
 * (group.cl): a work-item per pixel of the tile, each in its quad. */

#include "raster/coverage.cl"
#include "raster/group.cl"
#include "raster/shade.cl"
#include "raster/span.cl"
#include "shared/types.h"

#if CLR_SHADE_TILE_QUADS
CLR_INLINE void shade_batch(const __local SetupTriangle* batch, __local ulong (*masks)[CLR_TILE_MASK_WORDS],
                            const __local TileCoverage* coverage, uint n, int2 origin, uint item, clr_fragment* f,
                            __local uint* tile_color, __local float* tile_depth, __local uchar* tile_stencil,
                            __constant const DrawUniforms* u) {
  /* One work-item per pixel: every one runs the program for each triangle that covers any pixel
   * of the tile, the uncovered ones as helpers. */
  const int x = origin.x + (int)(item % CLR_TILE_SIZE);
  const int y = origin.y + (int)(item / CLR_TILE_SIZE);
  for (uint i = 0; i < n; ++i) {
    ulong any = 0;
    for (int w = 0; w < CLR_TILE_MASK_WORDS; ++w) any |= masks[i][w];
    /* The same decision in every work-item, so all of them reach the program's barriers. */
    if (!any) continue;
    const clr_span_place place = {x, y, item, 0, 0, 0, false};
    process_span(&batch[i], &place, clr_span_lanes_from_bits((uint)(masks[i][item / 64] >> (item % 64))), f,
                 tile_color, tile_depth, tile_stencil, u);
    /* What follows the program's last barrier branches per pixel (helper or not, discard, the
     * tests, blending, the program's own code). Those branches must meet again at a barrier before
     * the loop goes on: PoCL otherwise takes a branch that leads on toward the next iteration's
     * barriers as uniform and follows work-item 0's way for the whole group, so every pixel of the
     * tile was written, or left, as its first pixel was. */
    barrier(CLK_LOCAL_MEM_FENCE);
  }
}
#endif
