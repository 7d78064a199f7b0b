/* clear.cl: clearing texture levels (framebuffer attachments) to one value, converted by the same
 * code that stores rendered fragments (format.cl), so a cleared pixel equals a rendered one.
 *
 * Each work-item converts the value into the first of its CLR_CLEAR_TEXELS_PER_ITEM texels and
 * copies those bytes into the others: the conversion is the costly part, the copies are plain
 * stores the compiler vectorizes. */

#include "resources/format.cl"
#include "shared/clr_limits.h"
#include "shared/types.h"

/* Texels [first + 1, end) take texel first's bytes. */
static inline void copy_first_texel(int format, __global uchar* data, uint first, uint end) {
  const clr_texel_layout layout = clr_texel_layout_of(format);
#define CLR_COPY_TEXEL(T)                                                   \
  {                                                                         \
    __global T* texels = (__global T*)data;                                 \
    const T value = texels[first];                                          \
    for (uint i = first + 1; i < end; ++i) texels[i] = value;               \
  }
  switch (layout.channels * CLR_CHANNEL_BYTES(layout.channel_type)) {
    case 1: CLR_COPY_TEXEL(uchar) break;
    case 2: CLR_COPY_TEXEL(ushort) break;
    case 4: CLR_COPY_TEXEL(uint) break;
    case 8: CLR_COPY_TEXEL(uint2) break;
    case 16: CLR_COPY_TEXEL(uint4) break;
  }
#undef CLR_COPY_TEXEL
}

#define CLR_CLEAR_KERNEL(kind, value_type, store)                                                 \
  __kernel void clear_texels_##kind(int format, __global uchar* data, uint count, value_type value) { \
    const uint first = get_global_id(0) * CLR_CLEAR_TEXELS_PER_ITEM;                              \
    if (first >= count) return;                                                                   \
    store(format, data, first, value);                                                            \
    copy_first_texel(format, data, first, min(count, first + CLR_CLEAR_TEXELS_PER_ITEM));         \
  }
CLR_CLEAR_KERNEL(float, float4, clr_store_texel_float)
CLR_CLEAR_KERNEL(int, int4, clr_store_texel_int)
CLR_CLEAR_KERNEL(uint, uint4, clr_store_texel_uint)
#undef CLR_CLEAR_KERNEL
