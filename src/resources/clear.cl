/* clear.cl: clearing texture levels (framebuffer attachments) to one value, converted by the same
 * code that stores rendered fragments (format.cl), so a cleared pixel equals a rendered one. */

__kernel void clear_texels_float(int format, __global uchar* data, uint count, float4 value) {
  const uint i = get_global_id(0);
  if (i < count) clr_store_texel_float(format, data, i, value);
}

__kernel void clear_texels_int(int format, __global uchar* data, uint count, int4 value) {
  const uint i = get_global_id(0);
  if (i < count) clr_store_texel_int(format, data, i, value);
}

__kernel void clear_texels_uint(int format, __global uchar* data, uint count, uint4 value) {
  const uint i = get_global_id(0);
  if (i < count) clr_store_texel_uint(format, data, i, value);
}
