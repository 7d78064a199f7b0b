/* normal.cl: the built-in program of Shading::Normal, written in the same language as user programs
 * (one program per shading, so each declares and interpolates only what it draws with). The
 * pipeline binds its uniforms from DrawState (api/draw.cpp). */

clr_attribute(float3, position)
clr_attribute(float3, normal)
clr_varying(float3, object_normal)
clr_uniform(float16, mvp) /* projection * model_view */
clr_output(float4, color)

void vertex(clr_vertex* v) {
  v->position = clr_mul(v->uniforms->mvp, (float4)(v->in.position, 1.0f));
  v->out.object_normal = v->in.normal;
}

/* The normal as a colour: n / |n| * 0.5 + 0.5, mid-grey where it has no length. |n| as GLSL's
 * length() defines it, sqrt(dot(n, n)), which the OpenGL renderer computes too. */
void fragment(clr_fragment* f) {
  const float3 n = f->in.object_normal;
  const float len = sqrt(dot(n, n));
  f->out.color = (float4)(len > 0.0f ? n / len * 0.5f + 0.5f : (float3)(0.5f), 1.0f);
}
