/* lambert.cl: the built-in program of Shading::Lambert: the base colour lit by a headlight at the
 * camera, both faces alike. The pipeline binds its uniforms from DrawState (api/draw.cpp). */

clr_attribute(float3, position)
clr_attribute(float3, normal)
clr_varying(float3, eye_normal)
clr_uniform(float16, mvp)           /* projection * model_view */
clr_uniform(float16, normal_matrix) /* inverse transpose of model_view's upper 3x3, in its upper 3x3 */
clr_uniform(float4, base_color)
clr_output(float4, color)

void vertex(clr_vertex* v) {
  v->position = clr_mul(v->uniforms->mvp, (float4)(v->in.position, 1.0f));
  v->out.eye_normal = clr_mul3(v->uniforms->normal_matrix, v->in.normal);
}

void fragment_span(clr_span_fragment* f) {
  const clr_span_float3 n = f->in.eye_normal;
  const clr_span_float len = sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
  const clr_span_float k = 0.1f + 0.9f * (len > 0.0f ? fabs(n.z / len) : 0.0f);
  const float4 base = f->uniforms->base_color;
  f->out.color.x = base.x * k;
  f->out.color.y = base.y * k;
  f->out.color.z = base.z * k;
  f->out.color.w = base.w;
}
