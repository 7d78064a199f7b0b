/* span.cl: spans. The rasterizer processes CLR_SPAN_PIXELS pixels of a tile row together, a span
 * (or as many pixels of one triangle anywhere in the tile, a packed span: clr_span_place below),
 * and its operations work on spans: one vector lane per pixel and one vector per colour channel
 * (structure of arrays), so that one instruction does the work of every pixel of the span, under
 * the draw's state decided once per span. Spans are CLR_CPU_SPAN_PIXELS wide where one work-item
 * walks a whole tile (CPU shapes, clr_limits.h) and one pixel wide where each work-item has its
 * pixel (GPU shapes, the quad shading of per-fragment programs), or where the program's own
 * depth_test or blend function, which take one fragment, run per fragment. The same source serves
 * both widths, so both compute the same bits.
 *
 * Masks are what comparisons give: -1 per true lane in vectors, 1 in scalars. Both are true to
 * select(), and clr_span_any tests them; they are combined with & and |, which keep either form.
 * A vector mask is never negated (not with !, == 0 or ~): the opposite comparison is written, or
 * select()'s operands swapped. Oclgrind 21.10 negates some vector masks wrongly (true as -2, false
 * as 1, depending on what its compiler made of the expression), which made its checks of the
 * kernels run on the wrong lanes. For the same reason integer min, max and clamp of span vectors
 * take vector bounds: Oclgrind reads a scalar bound of those as a vector, garbage beyond lane 0.
 *
 * The loops of the span code over channels, edges and varyings carry `#pragma unroll`: unrolled,
 * the arrays of span vectors in its structures (clr_span_color's channels, ...) become registers;
 * left as loops (LLVM's cost model keeps those with switches in them), they stay in memory and every
 * pass copies them through the stack. Unrolling took a third of the raster stage's instructions
 * away on fill-16 and a fifth on model-50k. */

#include "shared/clr_limits.h"
#include "shared/types.h"

#if (CLR_QUAD_SHADING && !CLR_SPAN_PROGRAM) || CLR_PROGRAM_DEPTH_TEST || CLR_PROGRAM_BLEND || \
    CLR_RASTER_GROUP_SIZE >= CLR_TILE_SIZE * CLR_TILE_SIZE
#define CLR_SPAN_PIXELS 1
#define CLR_SPAN_SUFFIX
#define CLR_SPAN_LANES 0
#define CLR_SPAN_TRUE 1
#define clr_span_any(mask) ((mask) != 0)
#define CLR_SPAN_LOAD(pointer) (*(pointer))
#define CLR_SPAN_STORE(value, pointer) (*(pointer) = (value))
#define CLR_SPAN_STREAM(value, pointer) CLR_SPAN_STORE(value, pointer)
#define CLR_SPAN_LANE(type, vector, lane) (vector)
#elif CLR_CPU_SPAN_PIXELS == 8
#define CLR_SPAN_PIXELS 8
#define CLR_SPAN_SUFFIX 8
#define CLR_SPAN_LANES (int8)(0, 1, 2, 3, 4, 5, 6, 7)
#define CLR_SPAN_TRUE (int8)(-1)
#define clr_span_any(mask) any(mask)
#define CLR_SPAN_LOAD(pointer) vload8(0, pointer)
#define CLR_SPAN_STORE(value, pointer) vstore8(value, 0, pointer)
/* A store to global memory that does not read the line first (non-temporal), where the span is
 * aligned to its size, which a non-temporal vector store needs; a plain store elsewhere. */
#define CLR_SPAN_STREAM(value, pointer)                                                     \
  do {                                                                                      \
    if (((ulong)(pointer) & (sizeof(value) - 1)) == 0) {                                    \
      __builtin_nontemporal_store(value, (__global __typeof__((value) + 0)*)(pointer));     \
    } else {                                                                                \
      vstore8(value, 0, pointer);                                                           \
    }                                                                                       \
  } while (0)
/* Lane `lane` of the span vector `vector` (a private variable), read through memory: the index
 * varies. Lanes are written with CLR_SPAN_SET_LANE. */
#define CLR_SPAN_LANE(type, vector, lane) (((type*)&(vector))[lane])
#else
#error "CLR_CPU_SPAN_PIXELS must be 8"
#endif
/* Quad spans: a span program that takes derivatives, in spans of eight, shades two 2x2 quads (aligned
 * to even window coordinates) at once, anywhere in the tile: lanes 0, 1 the first quad's lower row
 * and 4, 5 its upper one, lanes 2, 3 and 6, 7 the second quad's, so that lanes 0-3 are lower rows
 * and 4-7 the rows above them. Its derivatives are differences between lanes (prelude.cl), and the
 * quads' uncovered pixels are their helpers. A per-fragment program shades its quads one pixel to a
 * work-item instead, exchanging values through local memory at barriers (group.cl), and so does a
 * span program in spans of one pixel (GPU shapes). */
#define CLR_QUAD_SPANS (CLR_QUAD_SHADING && CLR_SPAN_PIXELS > 1)
#if CLR_SPAN_PIXELS == 8
#define CLR_QUAD_SPAN_SECOND (int8)(0, 0, -1, -1, 0, 0, -1, -1) /* the lanes of the second quad */
#define CLR_QUAD_SPAN_X (int8)(0, 1, 0, 1, 0, 1, 0, 1)          /* each lane's pixel from its quad's first */
#define CLR_QUAD_SPAN_Y (int8)(0, 0, 0, 0, 1, 1, 1, 1)
#endif
#define CLR_SPAN(type) CLR_CAT(type, CLR_SPAN_SUFFIX)         /* float -> float8, or float */
#define CLR_SPAN_CONVERT(type, value) CLR_CAT(convert_, CLR_SPAN(type))(value)
#define CLR_SPAN_AS(type, value) CLR_CAT(as_, CLR_SPAN(type))(value)
typedef CLR_SPAN(float) clr_span_float;
typedef CLR_SPAN(int) clr_span_int;
typedef CLR_SPAN(uint) clr_span_uint;
typedef CLR_SPAN(long) clr_span_long;

/* A span of 2- to 4-component values, one span vector per component: what span programs
 * (fragment_span, docs/programs.md) compute with, where a per-fragment program has float3. */
#define CLR_SPAN_VECTOR_TYPES(scalar)                                   \
  typedef struct { clr_span_##scalar x, y; } clr_span_##scalar##2;       \
  typedef struct { clr_span_##scalar x, y, z; } clr_span_##scalar##3;    \
  typedef struct { clr_span_##scalar x, y, z, w; } clr_span_##scalar##4;
CLR_SPAN_VECTOR_TYPES(float)
CLR_SPAN_VECTOR_TYPES(int)
CLR_SPAN_VECTOR_TYPES(uint)
#undef CLR_SPAN_VECTOR_TYPES

/* A span's colours as floats, and the same as the bits a tile holds (tile.cl). */
typedef struct {
  clr_span_float c[4];
} clr_span_color;
typedef struct {
  clr_span_uint c[4];
} clr_span_bits;

/* Lanes from bits: lane k is bit k of `bits`. */
CLR_INLINE clr_span_int clr_span_lanes_from_bits(uint bits) {
  return (((clr_span_int)((int)bits) >> CLR_SPAN_LANES) & 1) != 0;
}

/* Bits from lanes: bit k set where lane k of `mask` is true. */
CLR_INLINE uint clr_span_bits_of_lanes(clr_span_int mask) {
#if CLR_SPAN_PIXELS == 1
  return mask != 0;
#else
  const clr_span_uint bits = CLR_SPAN_AS(uint, mask) & (CLR_SPAN(uint))(1u) << CLR_SPAN_AS(uint, CLR_SPAN_LANES);
  const uint4 halves = bits.lo | bits.hi;
  const uint2 quarters = halves.lo | halves.hi;
  return quarters.x | quarters.y;
#endif
}

/* Every lane's bit, as clr_span_bits_of_lanes gives them. */
#define CLR_SPAN_BITS ((1ul << CLR_SPAN_PIXELS) - 1)

/* The pixel in lane `lane` as a float4, and a float4 into lane `lane`. */
CLR_INLINE float4 clr_span_color_lane(clr_span_color color, int lane) {
  return (float4)(CLR_SPAN_LANE(float, color.c[0], lane), CLR_SPAN_LANE(float, color.c[1], lane),
                  CLR_SPAN_LANE(float, color.c[2], lane), CLR_SPAN_LANE(float, color.c[3], lane));
}
/* Lane `lane` set by selection, in registers: a scalar store into a vector in memory that is then
 * read as a vector stalls the load (no store forwarding), per channel and pixel. */
#define CLR_SPAN_SET_LANE(vector, lane, value) \
  ((vector) = select((vector), (__typeof__(vector))(value), CLR_SPAN_LANES == (lane)))
CLR_INLINE void clr_span_set_color_lane(clr_span_color* color, int lane, float4 value) {
  CLR_SPAN_SET_LANE(color->c[0], lane, value.x);
  CLR_SPAN_SET_LANE(color->c[1], lane, value.y);
  CLR_SPAN_SET_LANE(color->c[2], lane, value.z);
  CLR_SPAN_SET_LANE(color->c[3], lane, value.w);
}
CLR_INLINE void clr_span_set_bits_lane(clr_span_bits* bits, int lane, uint4 value) {
  CLR_SPAN_SET_LANE(bits->c[0], lane, value.x);
  CLR_SPAN_SET_LANE(bits->c[1], lane, value.y);
  CLR_SPAN_SET_LANE(bits->c[2], lane, value.z);
  CLR_SPAN_SET_LANE(bits->c[3], lane, value.w);
}
/* Every lane the same colour; a span's colours as bits and back (macros, not functions: LLVM's
 * inliner marks a function's returned structure with an intrinsic Oclgrind cannot run, so nothing
 * here returns a structure). */
#define CLR_SPAN_COLOR_SPLAT(value)                                                                 \
  ((clr_span_color){{(clr_span_float)((value).x), (clr_span_float)((value).y), (clr_span_float)((value).z), \
                     (clr_span_float)((value).w)}})
#define CLR_SPAN_COLOR_BITS(color)                                                            \
  ((clr_span_bits){{CLR_SPAN_AS(uint, (color).c[0]), CLR_SPAN_AS(uint, (color).c[1]), \
                    CLR_SPAN_AS(uint, (color).c[2]), CLR_SPAN_AS(uint, (color).c[3])}})
#define CLR_SPAN_BITS_COLOR(bits)                                                              \
  ((clr_span_color){{CLR_SPAN_AS(float, (bits).c[0]), CLR_SPAN_AS(float, (bits).c[1]), \
                     CLR_SPAN_AS(float, (bits).c[2]), CLR_SPAN_AS(float, (bits).c[3])}})

/* The rasterizer's tile (tile.cl) holds each colour attachment channel by channel, so that a span
 * of one channel is one vector: channel c of attachment k at the tile's pixel p is word
 * CLR_TILE_WORD(k, c, p). */
#define CLR_TILE_SPARE_PIXEL (CLR_TILE_SIZE * CLR_TILE_SIZE)
#define CLR_TILE_CHANNEL_WORDS (CLR_TILE_SIZE * CLR_TILE_SIZE + CLR_SPAN_PIXELS)
#define CLR_TILE_WORD(target, channel, pixel) (((target) * 4 + (channel)) * CLR_TILE_CHANNEL_WORDS + (pixel))

/* Where a span's lanes are in the tile: a row span's are CLR_SPAN_PIXELS pixels of a row from the
 * tile's pixel `first`, at window coordinates (x, y); a packed span's are any pixels of the tile,
 * `pixels` lane by lane at (xs, ys), lanes without one at the spare pixel CLR_TILE_SPARE_PIXEL. */
typedef struct {
  int x, y;
  uint first;
  clr_span_int xs, ys;
  clr_span_uint pixels;
  bool packed;
} clr_span_place;
/* Each lane's window coordinates, and its pixel in the tile. */
#define CLR_PLACE_X(place) ((place).packed ? (place).xs : (place).x + CLR_SPAN_LANES)
#define CLR_PLACE_Y(place) ((place).packed ? (place).ys : (clr_span_int)((place).y))
#define CLR_PLACE_LANE_X(place, lane) ((place).packed ? CLR_SPAN_LANE(int, (place).xs, lane) : (place).x + (lane))
#define CLR_PLACE_LANE_Y(place, lane) ((place).packed ? CLR_SPAN_LANE(int, (place).ys, lane) : (place).y)
#define CLR_PLACE_LANE_PIXEL(place, lane) \
  ((place).packed ? CLR_SPAN_LANE(uint, (place).pixels, lane) : (place).first + (uint)(lane))

#if CLR_SPAN_PIXELS == 1
#define CLR_SPAN_GATHER(array, index) ((array)[index])
#define CLR_SPAN_SCATTER(value, array, index) ((array)[index] = (value))
#else
#define CLR_SPAN_GATHER(array, index)                                                                        \
  ((__typeof__(vload8(0, array)))((array)[(index).s0], (array)[(index).s1], (array)[(index).s2],              \
                                  (array)[(index).s3], (array)[(index).s4], (array)[(index).s5],              \
                                  (array)[(index).s6], (array)[(index).s7]))
#define CLR_SPAN_SCATTER(value, array, index)                                            \
  do {                                                                                   \
    const __typeof__(value) clr_scattered_ = (value);                                    \
    (array)[(index).s0] = clr_scattered_.s0;                                             \
    (array)[(index).s1] = clr_scattered_.s1;                                             \
    (array)[(index).s2] = clr_scattered_.s2;                                             \
    (array)[(index).s3] = clr_scattered_.s3;                                             \
    (array)[(index).s4] = clr_scattered_.s4;                                             \
    (array)[(index).s5] = clr_scattered_.s5;                                             \
    (array)[(index).s6] = clr_scattered_.s6;                                             \
    (array)[(index).s7] = clr_scattered_.s7;                                             \
  } while (0)
#endif
/* A span of the tile array `array` (one channel, depth or stencil) at `place`; and `value` stored
 * there as `type`s where `mask`, `stored` (what the span held) elsewhere. A packed span stores its other lanes
 * at the spare pixel instead, and needs no `stored`: they may hold any pixel, or none. */
#define CLR_TILE_LOAD(array, place) \
  ((place).packed ? CLR_SPAN_GATHER(array, (place).pixels) : CLR_SPAN_LOAD(&(array)[(place).first]))
#define CLR_TILE_UPDATE(type, stored, value, mask, array, place)                                      \
  do {                                                                                               \
    if ((place).packed) {                                                                            \
      const clr_span_uint clr_pixels_ = select((clr_span_uint)(CLR_TILE_SPARE_PIXEL), (place).pixels, mask); \
      CLR_SPAN_SCATTER(CLR_SPAN_CONVERT(type, value), array, clr_pixels_);                          \
    } else {                                                                                         \
      CLR_SPAN_STORE(CLR_SPAN_CONVERT(type, select(stored, value, mask)), &(array)[(place).first]);  \
    }                                                                                                \
  } while (0)
CLR_INLINE uint4 clr_tile_pixel(__local const uint* tile, uint target, uint pixel) {
  return (uint4)(tile[CLR_TILE_WORD(target, 0, pixel)], tile[CLR_TILE_WORD(target, 1, pixel)],
                 tile[CLR_TILE_WORD(target, 2, pixel)], tile[CLR_TILE_WORD(target, 3, pixel)]);
}
