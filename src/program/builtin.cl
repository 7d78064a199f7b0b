/* builtin.cl: the built-in program behind clraster::Shading, written in the same language as user
 * programs. The pipeline binds its uniforms from DrawState (pipeline/draw_state.cpp). */

clr_attribute(float3, position)
clr_attribute(float3, normal)
clr_varying(float3, shade)        /* normal, eye-space normal or (view distance, 0, 0) */
clr_uniform(float16, mvp)         /* projection * model_view */
clr_uniform(float16, model_view)
clr_uniform(float16, normal_matrix) /* inverse transpose of model_view's upper 3x3, in its upper 3x3 */
clr_uniform(float4, base_color)
clr_uniform(float2, depth_range)  /* view distances drawn white and black */
clr_uniform(int, shading)         /* clraster::Shading */
clr_output(float4, color)

#define SHADING_NORMAL 0
#define SHADING_LAMBERT 1
#define SHADING_DEPTH 2

void vertex(clr_vertex* v) {
  const float4 p = (float4)(v->in.position, 1.0f);
  v->position = clr_mul(v->uniforms->mvp, p);
  switch (v->uniforms->shading) {
    case SHADING_NORMAL: v->out.shade = v->in.normal; break;
    case SHADING_LAMBERT: v->out.shade = clr_mul3(v->uniforms->normal_matrix, v->in.normal); break;
    case SHADING_DEPTH: v->out.shade = (float3)(-clr_mul(v->uniforms->model_view, p).z, 0.0f, 0.0f); break;
    default: v->out.shade = (float3)(0.0f); break;
  }
}

void fragment(clr_fragment* f) {
  const float3 s = f->in.shade;
  const float4 base = f->uniforms->base_color;
  switch (f->uniforms->shading) {
    case SHADING_NORMAL: {
      const float len = length(s);
      f->out.color = (float4)(len > 0.0f ? s / len * 0.5f + 0.5f : (float3)(0.5f), 1.0f);
      break;
    }
    case SHADING_LAMBERT: {
      const float len = length(s);
      const float k = 0.1f + 0.9f * (len > 0.0f ? fabs(s.z / len) : 0.0f);
      f->out.color = (float4)(base.xyz * k, base.w);
      break;
    }
    case SHADING_DEPTH: {
      const float2 range = f->uniforms->depth_range;
      const float g = clamp(1.0f - (s.x - range.x) / (range.y - range.x), 0.0f, 1.0f);
      f->out.color = (float4)(g, g, g, 1.0f);
      break;
    }
    default: f->out.color = base; break;
  }
}
