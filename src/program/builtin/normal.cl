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
 * length() defines it, sqrt(dot(n, n)), which the OpenGL renderer computes too. A span program (as
 * the other built-in ones): a span's pixels at once, one vector lane each. */
void fragment_span(clr_span_fragment* f) {
  const clr_span_float3 n = f->in.object_normal;
  const clr_span_float len = sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
  f->out.color.x = len > 0.0f ? n.x / len * 0.5f + 0.5f : 0.5f;
  f->out.color.y = len > 0.0f ? n.y / len * 0.5f + 0.5f : 0.5f;
  f->out.color.z = len > 0.0f ? n.z / len * 0.5f + 0.5f : 0.5f;
  f->out.color.w = 1.0f;
}
