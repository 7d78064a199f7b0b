/* shade.cl: the fragments of a triangle in a span (process_span), which every strategy runs.
 *
 * Per fragment, in OpenGL's order: the fragment program, the stencil test, the depth test (with
 * their stencil operations and depth write), then blending, the write mask and conversion to the
 * attachment's format, for each output. A program that neither discards nor writes depth, and is
 * not a per-fragment program taking derivatives, has its tests run first (early fragment tests), so
 * hidden fragments skip it (program/generator.hpp, early_fragment_tests). */

#include "raster/group.cl"
#include "raster/interpolation.cl"
#include "raster/merge.cl"
#include "raster/span.cl"
#include "shared/types.h"

/* Where the layer of triangle t's view starts in the attachments: fragment coordinates are within it. */
static inline float2 layer_origin(const __local SetupTriangle* t, __constant const DrawUniforms* u) {
  const int view = (int)(t->flags >> CLR_TRIANGLE_VIEW_SHIFT);
  return convert_float2((int2)(view % u->layer_columns * u->layer_size[0], view / u->layer_columns * u->layer_size[1]));
}

/* The fragment of triangle t in lane `lane` of the span at `place`, from the span's interpolants.
 * helper: a helper invocation of quad shading. */
CLR_INLINE void start_fragment(clr_fragment* f, const __local SetupTriangle* t, span_weights w,
                               const span_interpolants* s, int lane, const clr_span_place* place, bool helper) {
  const float3 pw = (float3)(CLR_SPAN_LANE(float, s->pw[0], lane), CLR_SPAN_LANE(float, s->pw[1], lane),
                             CLR_SPAN_LANE(float, s->pw[2], lane));
  const float z = CLR_SPAN_LANE(float, w.z, lane);
  const float2 origin = layer_origin(t, f->clr_draw);
  f->frag_coord = (float4)((float)CLR_PLACE_LANE_X(*place, lane) + 0.5f - origin.x,
                           (float)CLR_PLACE_LANE_Y(*place, lane) + 0.5f - origin.y, z, CLR_SPAN_LANE(float, s->inv_w, lane));
  f->barycentric = pw * CLR_SPAN_LANE(float, s->norm, lane);
  f->frag_depth = z;
  f->primitive_id = t->primitive_id;
  f->view_id = t->flags >> CLR_TRIANGLE_VIEW_SHIFT;
  f->front_facing = (t->flags & CLR_TRIANGLE_FRONT_FACING) != 0;
  f->helper = helper;
  f->discarded = false;
  f->clr_lane = CLR_PLACE_LANE_PIXEL(*place, lane);
  const clr_outputs no_outputs = {0};
  f->out = no_outputs;
  clr_lane_varyings(t, s->varyings, lane, &f->in);
}

#if CLR_SPAN_PROGRAM
#if !CLR_EARLY_TESTS
#error "a span program runs after the early tests (program/interface.cpp rejects what would need late ones)"
#endif
/* Runs the span program for the span's fragments at once, `written` the lanes that passed the tests,
 * and takes its outputs. Its inputs are the per-fragment program's, lane by lane: the same
 * operations in vectors, so the same bits. The built-in normal shading as a span program: raster
 * stage of model-50k 34.6 -> 30.6 ms, terrain-1m 73.9 -> 63.0. f: the fragment whose resources
 * (uniforms, textures, buffers) it takes. */
CLR_INLINE void shade_span(const clr_fragment* f, const __local SetupTriangle* t, span_weights w,
                           const span_interpolants* s, const clr_span_place* place, clr_span_int written,
                           clr_span_outputs* outputs) {
  clr_span_fragment g;
  clr_span_program_inputs(t, s->varyings, &g.in);
  const float2 origin = layer_origin(t, f->clr_draw);
  g.frag_coord.x = CLR_SPAN_CONVERT(float, CLR_PLACE_X(*place)) + (0.5f - origin.x);
  g.frag_coord.y = CLR_SPAN_CONVERT(float, CLR_PLACE_Y(*place)) + (0.5f - origin.y);
  g.frag_coord.z = w.z;
  g.frag_coord.w = s->inv_w;
  g.barycentric.x = s->pw[0] * s->norm;
  g.barycentric.y = s->pw[1] * s->norm;
  g.barycentric.z = s->pw[2] * s->norm;
  g.written = written;
  g.primitive_id = t->primitive_id;
  g.view_id = t->flags >> CLR_TRIANGLE_VIEW_SHIFT;
  g.front_facing = (t->flags & CLR_TRIANGLE_FRONT_FACING) != 0;
  const clr_span_program_outputs no_outputs = {0};
  g.out = no_outputs;
  g.uniforms = f->uniforms;
  g.textures = f->textures;
  g.buffers = f->buffers;
  g.clr_quad = f->clr_quad;
  g.clr_lane = CLR_PLACE_LANE_PIXEL(*place, 0);
  fragment_span(&g);
  clr_span_program_results(&g.out, outputs);
}
#elif CLR_EARLY_TESTS
/* Runs the program for lane `lane` of a span whose tests passed there, and gathers its outputs. */
CLR_INLINE void shade_lane(clr_fragment* f, const __local SetupTriangle* t, span_weights w, const span_interpolants* s,
                           int lane, const clr_span_place* place, bool program_depth_test,
                           clr_span_outputs* outputs) {
  if (!program_depth_test) start_fragment(f, t, w, s, lane, place, false);
  fragment(f);
  clr_gather_outputs(f, lane, outputs);
}
#endif

/* The fragments of triangle t in the span of the tile at `place`, where `covered` (writable pixels the
 * triangle covers). In quad shading (spans of one pixel), an uncovered pixel runs the program as a
 * helper. */
CLR_INLINE void process_span(const __local SetupTriangle* t, const clr_span_place* place, clr_span_int covered,
                             clr_fragment* f, __local uint* tile_color, __local float* tile_depth,
                             __local uchar* tile_stencil, __constant const DrawUniforms* u) {
  f->uniforms = f->clr_uniform_table + ((t->flags >> CLR_TRIANGLE_DRAW_SHIFT) & CLR_TRIANGLE_DRAW_MASK); /* its draw's */
  span_weights w = {0};
  const bool front_facing = (t->flags & CLR_TRIANGLE_FRONT_FACING) != 0;
  clr_span_outputs outputs = {0};
  span_interpolants s;
#if CLR_EARLY_TESTS
  /* The tests need the weights (for depth) only with the depth test on. Without it they wait for a
   * fragment to pass, and the compiler drops them as dead code where the program reads neither
   * varyings nor its fragment's coordinates (a constant colour: fill-16's raster stage 93 -> 53 ms).
   * Hidden fragments skip the program and the interpolation, unless the program's depth test may
   * read them (spans of one pixel). */
  const bool weighed_before_tests = u->depth_test;
  if (weighed_before_tests) interpolation_weights(t, place, &w);
#if CLR_PROGRAM_DEPTH_TEST
  const bool program_depth_test = u->depth_test && u->depth_func == CLR_COMPARE_PROGRAM;
  if (program_depth_test) {
    interpolate_span(t, w, &s);
    start_fragment(f, t, w, &s, 0, place, false);
  }
#else
  const bool program_depth_test = false;
#endif
  const clr_span_int written = fragment_tests(f, front_facing, covered, w.z, u, tile_depth, tile_stencil, place);
  const uint passed = clr_span_bits_of_lanes(written);
#if CLR_QUAD_EXCHANGE
  /* A span program in spans of one pixel that takes derivatives: every pixel runs it, helpers and
   * hidden fragments too, so that its quad has values to exchange at the barriers. */
  const bool shaded = true;
#else
  const bool shaded = passed != 0;
#endif
  /* Two ifs, not one &&: program_depth_test is a constant in most programs, and clang warns about
   * && with a constant operand on stderr, which the examples require to be empty. */
  if (shaded) {
    if (!weighed_before_tests) interpolation_weights(t, place, &w);
    if (!program_depth_test) interpolate_span(t, w, &s); /* a program's depth test had it done first */
  }
#if CLR_SPAN_PROGRAM
  if (shaded) shade_span(f, t, w, &s, place, written, &outputs);
#else
  /* A per-fragment program runs for the lanes that passed only, in order: a span of a small
   * triangle has one or two. A span that passed whole takes the lanes in an unrolled loop instead:
   * no search for the next lane, and each lane's outputs go to a constant place in the span, where
   * what does not vary between lanes folds (a constant colour is one vector). Unrolled, not left to
   * the compiler, which kept the loop (fill-16 raster 48 -> 38 ms; a program's first build ~5%
   * longer). */
  if (passed == (uint)CLR_SPAN_BITS) {
#pragma unroll
    for (int lane = 0; lane < CLR_SPAN_PIXELS; ++lane) {
      shade_lane(f, t, w, &s, lane, place, program_depth_test, &outputs);
    }
  } else {
    for (uint lanes = passed; lanes != 0; lanes &= lanes - 1) {
      shade_lane(f, t, w, &s, 31 - clz(lanes & (0 - lanes)), place, program_depth_test, &outputs);
    }
  }
#endif
#else
  interpolation_weights(t, place, &w);
  clr_span_int kept = covered;
  clr_span_float frag_depth = w.z;
  interpolate_span(t, w, &s);
  for (int lane = 0; lane < CLR_SPAN_PIXELS; ++lane) {
    const bool live = CLR_SPAN_LANE(int, covered, lane) != 0;
#if !CLR_QUAD_SHADING /* quad shading runs the program for uncovered pixels too, as helpers */
    if (!live) continue;
#endif
    start_fragment(f, t, w, &s, lane, place, !live);
    fragment(f);
    if (!live || f->discarded) {
      CLR_SPAN_SET_LANE(kept, lane, 0);
      continue;
    }
    CLR_SPAN_SET_LANE(frag_depth, lane, clamp(f->frag_depth, 0.0f, 1.0f));
    clr_gather_outputs(f, lane, &outputs);
  }
  const clr_span_int written = fragment_tests(f, front_facing, kept, frag_depth, u, tile_depth, tile_stencil, place);
#endif
  if (clr_span_any(written)) clr_merge_outputs(f, &outputs, written, tile_color, place, u);
}
