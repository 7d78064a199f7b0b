/* lit.cl: one colour per draw, lit by a directional light from both sides of each surface, with an
 * alpha for blending. Used by examples/custom_depth.cpp. */

clr_attribute(float3, position)
clr_attribute(float3, normal)
clr_varying(float3, normal)
clr_uniform(float16, mvp)
clr_uniform(float3, light_direction) /* unit vector towards the light */
clr_uniform(float3, albedo)
clr_uniform(float, alpha)
clr_output(float4, color)

void vertex(clr_vertex* v) {
  v->position = clr_mul(v->uniforms->mvp, (float4)(v->in.position, 1.0f));
  v->out.normal = v->in.normal;
}

void fragment(clr_fragment* f) {
  float3 n = normalize(f->in.normal);
  if (!f->front_facing) n = -n; /* inside surfaces are seen too: light them from their own side */
  const float diffuse = fmax(dot(n, f->uniforms->light_direction), 0.0f);
  f->out.color = (float4)(f->uniforms->albedo * (0.25f + 0.75f * diffuse), f->uniforms->alpha);
}
