/* shadowed.cl: diffuse lighting from a directional light, shadowed with a shadow map (the depth of
 * the scene as the light sees it, rendered by depth_only.cl). Used by examples/shadow_map.cpp
 * (pass 2). */

clr_attribute(float3, position)      /* world space */
clr_attribute(float3, normal)
clr_varying(float3, normal)
clr_varying(float3, light_window)    /* the point in the light's window: x, y in [0, 1] and depth */
clr_uniform(float16, mvp)            /* world to the camera's clip space */
clr_uniform(float16, light_mvp)      /* world to the light's clip space (an orthographic projection) */
clr_uniform(float3, light_direction) /* unit vector towards the light */
clr_uniform(float3, albedo)
clr_uniform(float, bias)             /* depth tolerance against self-shadowing ("shadow acne") ... */
clr_uniform(float, slope_bias)       /* ... plus this much per unit of the surface's slope to the light */
clr_texture(shadow_map)              /* Depth32F: sampled as (depth, 0, 0, 1) */
clr_output(float4, color)

void vertex(clr_vertex* v) {
  const float4 world = (float4)(v->in.position, 1.0f);
  v->position = clr_mul(v->uniforms->mvp, world);
  /* An orthographic light: clip w is 1, and window coordinates are clip coordinates * 0.5 + 0.5,
   * linear across the triangle as the varying is interpolated. */
  v->out.light_window = clr_mul(v->uniforms->light_mvp, world).xyz * 0.5f + 0.5f;
  v->out.normal = v->in.normal;
}

/* The fraction of the 3x3 shadow-map texels around the fragment's whose stored depth does not hide
 * it from the light (percentage-closer filtering, which softens the shadow's stair-stepped edge).
 * A surface's own depth varies across a texel, by more the more it slopes away from the light
 * (tan_angle: the tangent of the angle between its normal and the light): `bias` and `slope_bias`
 * keep it from shadowing itself. */
float lit_fraction(clr_fragment* f, float tan_angle) {
  const float3 p = f->in.light_window;
  const float tolerance = f->uniforms->bias + f->uniforms->slope_bias * tan_angle;
  const int2 size = clr_texture_size(f->textures.shadow_map, 0);
  const int2 texel = convert_int2(floor(p.xy * convert_float2(size)));
  int lit = 0;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      /* A texel fetch reads one texel without filtering (zero outside the texture: shadow). */
      const float occluder = clr_texel_fetch(f->textures.shadow_map, texel + (int2)(dx, dy), 0).x;
      lit += p.z - tolerance <= occluder;
    }
  }
  return lit / 9.0f;
}

void fragment(clr_fragment* f) {
  const float3 n = normalize(f->in.normal);
  const float cosine = dot(n, f->uniforms->light_direction);
  float light = 0.2f;  /* ambient */
  if (cosine > 0.0f) { /* facing the light: lit unless something hides it */
    const float tan_angle = fmin(sqrt(1.0f - cosine * cosine) / cosine, 10.0f);
    light += 0.8f * cosine * lit_fraction(f, tan_angle);
  }
  f->out.color = (float4)(f->uniforms->albedo * light, 1.0f);
}
