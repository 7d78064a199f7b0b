/* vertex.cl: the vertex stage. One work-item per vertex slot runs the built-in vertex program:
 * position to clip space, and the shading mode's varyings.
 *
 * Slots: when the whole vertex buffer is shaded once per draw, slot s holds vertex s. Otherwise
 * (the draw's transformed vertices would not fit the memory cap) each chunk shades its own stream
 * positions: slot s holds the element at stream position stream_begin + s, and for fans one extra
 * slot, main_count, holds the fan's centre (stream position 0). */

inline float4 transform_point(__constant const float* m, float4 p) {
  return (float4)(m[0] * p.x + m[4] * p.y + m[8] * p.z + m[12] * p.w,
                  m[1] * p.x + m[5] * p.y + m[9] * p.z + m[13] * p.w,
                  m[2] * p.x + m[6] * p.y + m[10] * p.z + m[14] * p.w,
                  m[3] * p.x + m[7] * p.y + m[11] * p.z + m[15] * p.w);
}

inline float3 transform_normal(__constant const float* m, float3 n) {
  return (float3)(m[0] * n.x + m[3] * n.y + m[6] * n.z,
                  m[1] * n.x + m[4] * n.y + m[7] * n.z,
                  m[2] * n.x + m[5] * n.y + m[8] * n.z);
}

__kernel void vertex_shade(__global const float* positions, __global const float* normals, int has_normals,
                           __global const uchar* indices, int shade_all, uint stream_begin, uint main_count,
                           uint slot_count, __constant const DrawUniforms* u, __global float4* shaded) {
  const uint slot = get_global_id(0);
  if (slot >= slot_count) return;
  uint vertex = slot;
  if (!shade_all) {
    const uint position = u->first + (slot < main_count ? stream_begin + slot : 0u);
    vertex = u->index_size ? fetch_index(indices, u->index_size, position) : position;
  }
  const float4 p = (float4)(vload3(vertex, positions), 1.0f);
  const float3 n = has_normals ? vload3(vertex, normals) : (float3)(0.0f);

  float3 varyings = (float3)(0.0f);
  switch (u->shading) {
    case CLR_SHADING_NORMAL: varyings = n; break;
    case CLR_SHADING_LAMBERT: varyings = transform_normal(u->normal_matrix, n); break;
    case CLR_SHADING_DEPTH: varyings.x = -transform_point(u->model_view, p).z; break;
    default: break;
  }
  shaded[slot * CLR_SHADED_VERTEX_FLOAT4S] = transform_point(u->mvp, p);
  shaded[slot * CLR_SHADED_VERTEX_FLOAT4S + 1] = (float4)(varyings, 0.0f);
}
