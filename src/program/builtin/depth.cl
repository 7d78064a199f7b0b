/* depth.cl: the built-in program of Shading::Depth: view distance as grey, white at the near end of
 * depth_range and black at the far end. The pipeline binds its uniforms from DrawState
 * (api/draw.cpp). */

clr_attribute(float3, position)
clr_varying(float, view_distance)
clr_uniform(float16, mvp)        /* projection * model_view */
clr_uniform(float16, model_view)
clr_uniform(float2, depth_range) /* view distances drawn white and black */
clr_output(float4, color)

void vertex(clr_vertex* v) {
  const float4 p = (float4)(v->in.position, 1.0f);
  v->position = clr_mul(v->uniforms->mvp, p);
  v->out.view_distance = -clr_mul(v->uniforms->model_view, p).z;
}

void fragment_span(clr_span_fragment* f) {
  const float2 range = f->uniforms->depth_range;
  const clr_span_float g = clamp(1.0f - (f->in.view_distance - range.x) / (range.y - range.x), 0.0f, 1.0f);
  f->out.color.x = g;
  f->out.color.y = g;
  f->out.color.z = g;
  f->out.color.w = 1.0f;
}
