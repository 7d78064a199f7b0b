/* visibility.cl: the visibility buffer of clraster.Context.rasterize. Output 0 is the triangle
 * drawn at the pixel (its index in the draw), output 1 its perspective-correct barycentrics; the
 * depth attachment keeps its window depth. Drawn once per view, each in its layer's viewport.
 * Positions are homogeneous: a mesh's with w = 1 and its camera's mvp, or clip positions given
 * with the identity. */

clr_attribute(float4, position)
clr_uniform(float16, mvp)      /* projection * model_view, as the built-in programs take it */
clr_uniform(float4, viewport)  /* the layer's origin in the attachments, then 2 / its width and height */
clr_buffer(const float, positions)  /* the attribute's, four floats a vertex */
clr_buffer(const uint, corners) /* the draw's indices, three per triangle */
clr_output(int4, triangle)
clr_output(float4, barycentric)

void vertex(clr_vertex* v) {
  v->position = clr_mul(v->uniforms->mvp, v->in.position);
}

/* The corners' weights from their clip positions, not f->barycentric: those weigh the corners of
 * what was rasterized, which clipping changes. In 2D homogeneous coordinates (x, y, w), corner i's
 * weight at the pixel's (x, y, 1) in normalized device coordinates is proportional to
 * dot(cross(c_j, c_k), p) (Olano and Greer, 1997): perspective-correct, whatever clipping did. */
void fragment_span(clr_span_fragment* f) {
  float3 clip[3];
  for (int i = 0; i < 3; ++i) {
    const uint vertex = f->buffers.corners[3 * f->primitive_id + i];
    const float4 p = clr_mul(f->uniforms->mvp, vload4(vertex, f->buffers.positions));
    clip[i] = (float3)(p.x, p.y, p.w);
  }
  const float3 n0 = cross(clip[1], clip[2]);
  const float3 n1 = cross(clip[2], clip[0]);
  const float3 n2 = cross(clip[0], clip[1]);
  const float4 viewport = f->uniforms->viewport;
  const clr_span_float x = (f->frag_coord.x - viewport.x) * viewport.z - 1.0f;
  const clr_span_float y = (f->frag_coord.y - viewport.y) * viewport.w - 1.0f;
  const clr_span_float w0 = n0.x * x + n0.y * y + n0.z;
  const clr_span_float w1 = n1.x * x + n1.y * y + n1.z;
  const clr_span_float w2 = n2.x * x + n2.y * y + n2.z;
  const clr_span_float sum = w0 + w1 + w2;
  f->out.triangle.x = (clr_span_int)((int)f->primitive_id);
  f->out.barycentric.x = w0 / sum;
  f->out.barycentric.y = w1 / sum;
}
