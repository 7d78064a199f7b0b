/* setup.cl: triangle set-up. For each primitive, the triangles primitive_count counted are written
 * at the primitive's offset (so set-up triangles stay in primitive order) with their exact edge
 * functions, interpolation data and the tiles their bounding box touches, whose number is what the
 * binning stage needs to place them. */

inline void write_setup_triangle(const WindowVertex* v0, const WindowVertex* v1, const WindowVertex* v2,
                                 uint primitive_id, __constant const DrawUniforms* u,
                                 __global SetupTriangle* out, __global uint* pair_count) {
  long area = double_area(v0->fixed, v1->fixed, v2->fixed);
  const bool front = (area > 0) == (u->front_face_ccw != 0);
  /* Rasterization wants counter-clockwise vertices: swap the last two of a clockwise triangle. */
  const WindowVertex* v[3] = {v0, area > 0 ? v1 : v2, area > 0 ? v2 : v1};
  area = area > 0 ? area : -area;

  SetupTriangle t;
  t.flags = front ? CLR_TRIANGLE_FRONT_FACING : 0u;
  for (int k = 0; k < 3; ++k) {
    /* Edge k runs from vertex k+1 to vertex k+2, opposite vertex k. */
    const int2 a = v[(k + 1) % 3]->fixed;
    const int2 b = v[(k + 2) % 3]->fixed;
    const int dx = b.x - a.x;
    const int dy = b.y - a.y;
    t.edge_a[k] = -dy;
    t.edge_b[k] = dx;
    t.edge_c[k] = (long)dy * a.x - (long)dx * a.y;
    if (edge_includes_centres(a, b)) t.flags |= 1u << k;
    t.z[k] = v[k]->z;
    t.inv_w[k] = v[k]->inv_w;
    for (int j = 0; j < CLR_NUM_VARYINGS; ++j) t.varyings[k][j] = v[k]->varyings[j];
  }
  t.inv_double_area = 1.0f / (float)area;
  t.primitive_id = primitive_id;

  int2 lo, hi;
  pixel_bounds(v0->fixed, v1->fixed, v2->fixed, u, &lo, &hi);
  t.pixel_min = (uint)lo.x | (uint)lo.y << 16;
  t.pixel_max = (uint)hi.x | (uint)hi.y << 16;
  *out = t;
  const int2 tile_lo = lo / CLR_TILE_SIZE;
  const int2 tile_hi = hi / CLR_TILE_SIZE;
  *pair_count = (uint)((tile_hi.x - tile_lo.x + 1) * (tile_hi.y - tile_lo.y + 1));
}

__kernel void triangle_setup(uint primitive_begin, uint primitive_count, SlotMap slots,
                             __global const uchar* indices, __global const float4* shaded,
                             __constant const DrawUniforms* u, __global const uint* triangle_offsets,
                             __global SetupTriangle* triangles, __global uint* pair_counts) {
  const uint i = get_global_id(0);
  if (i >= primitive_count) return;
  WindowVertex polygon[CLR_MAX_CLIP_VERTICES];
  const int n = primitive_window_polygon(primitive_begin + i, &slots, indices, shaded, u, polygon);
  uint out = triangle_offsets[i];
  for (int k = 1; k + 1 < n; ++k) {
    if (triangle_survives(&polygon[0], &polygon[k], &polygon[k + 1], u)) {
      write_setup_triangle(&polygon[0], &polygon[k], &polygon[k + 1], primitive_begin + i, u, &triangles[out],
                           &pair_counts[out]);
      ++out;
    }
  }
}
