/* textured.cl: a model's base colour (texture times factor, as glTF defines it) lit by one
 * directional light plus a constant ambient term. Used by examples/textured_model.cpp. */

clr_attribute(float3, position)        /* object space: the model is drawn where its file puts it */
clr_attribute(float3, normal)
clr_attribute(float2, uv)
clr_varying(float3, normal)            /* interpolated perspective-correctly for the fragments */
clr_varying(float2, uv)
clr_uniform(float16, mvp)              /* projection * view, column-major */
clr_uniform(float3, light_direction)   /* unit vector towards the light, object space */
clr_uniform(float3, light_color)
clr_uniform(float3, ambient)
clr_uniform(float4, base_color_factor) /* linear RGBA */
clr_texture(base_color)                /* sRGB texture: sampled as linear values */
clr_output(float4, color)              /* into an sRGB attachment, which encodes it */

void vertex(clr_vertex* v) {
  v->position = clr_mul(v->uniforms->mvp, (float4)(v->in.position, 1.0f));
  v->out.normal = v->in.normal;
  v->out.uv = v->in.uv;
}

void fragment(clr_fragment* f) {
  /* clr_sample picks the mipmap level from the uv derivatives of the 2x2 quad, so every fragment
   * must reach it: sample first, branch later. */
  const float4 base = f->uniforms->base_color_factor * clr_sample(f, f->textures.base_color, f->in.uv);
  /* Surfaces seen from behind (the model is drawn without culling) are lit from their own side. */
  float3 n = normalize(f->in.normal);
  if (!f->front_facing) n = -n;
  const float diffuse = fmax(dot(n, f->uniforms->light_direction), 0.0f);
  const float3 light = f->uniforms->ambient + f->uniforms->light_color * diffuse;
  f->out.color = (float4)(base.xyz * light, base.w);
}
