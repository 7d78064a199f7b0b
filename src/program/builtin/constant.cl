/* constant.cl: the built-in program of Shading::Constant: every fragment the base colour (with an
 * additive blend and no depth test, an overdraw counter). No varyings: nothing is interpolated.
 * The pipeline binds its uniforms from DrawState (api/draw.cpp). */

clr_attribute(float3, position)
clr_uniform(float16, mvp) /* projection * model_view */
clr_uniform(float4, base_color)
clr_output(float4, color)

void vertex(clr_vertex* v) { v->position = clr_mul(v->uniforms->mvp, (float4)(v->in.position, 1.0f)); }

void fragment_span(clr_span_fragment* f) {
  const float4 base = f->uniforms->base_color;
  f->out.color.x = base.x;
  f->out.color.y = base.y;
  f->out.color.z = base.z;
  f->out.color.w = base.w;
}
