/* material.cl: a model's materials, lit by a headlight.
 *
 * This is the program behind `clraster render MODEL --shading material` (the command line carries
 * a copy of it, built in), and a complete example of a `--program` file: it uses the names the
 * command line binds (docs/cli.md, "Programs"). `clraster render MODEL --program
 * programs/material.cl` draws the same picture; copy it to start a program of your own.
 *
 * Each part of the model is drawn with its material: the base colour is the material's texture
 * times its factor, lit by a headlight (Lambert's cosine between the normal and the direction
 * toward the camera, on both sides of every face) plus a constant ambient term, so that faces seen
 * edge-on stay visible. Colours are taken as the picture shows them, as the built-in `lambert`
 * shading does: the texture's texels as the image stores them, so that a fully lit texel is drawn
 * with the image's own colour. The picture is opaque: alpha is not used. */

clr_attribute(float3, position)
clr_attribute(float3, normal)
clr_attribute(float2, uv)             /* (0, 0) for models without texture coordinates */
clr_varying(float3, eye_normal)
clr_varying(float2, uv)
clr_uniform(float16, mvp)             /* projection * model_view */
clr_uniform(float16, normal_matrix)   /* turns object-space normals into eye space */
clr_uniform(float4, base_color)       /* the material's base colour factor */
clr_uniform(float3, light_direction)  /* toward the light, in eye space */
clr_texture(base_color_texture)       /* the material's texture, or a white one */
clr_output(float4, color)

#define AMBIENT 0.2f

void vertex(clr_vertex* v) {
  v->position = clr_mul(v->uniforms->mvp, (float4)(v->in.position, 1.0f));
  v->out.eye_normal = clr_mul3(v->uniforms->normal_matrix, v->in.normal);
  v->out.uv = v->in.uv;
}

/* A span program (docs/programs.md): a span of pixels at once, one vector lane each, two quads of
 * them where it samples the texture, as llvmpipe shades. Written per fragment, it would read
 *   const float4 base = clr_sample(f, f->textures.base_color_texture, f->in.uv) * f->uniforms->base_color;
 *   const float length_of_normal = length(f->in.eye_normal);
 *   const float diffuse = length_of_normal > 0.0f ? fabs(dot(f->in.eye_normal / length_of_normal, light)) : 0.0f;
 *   f->out.color = (float4)(base.xyz * (AMBIENT + (1.0f - AMBIENT) * diffuse), 1.0f);
 * and draw the same picture (to rounding), 2 to 4 times slower on CPUs (docs/performance.md). */
void fragment_span(clr_span_fragment* f) {
  const clr_span_float4 texel = clr_sample(f, f->textures.base_color_texture, f->in.uv);
  const float4 factor = f->uniforms->base_color;
  const float3 light = f->uniforms->light_direction;
  const clr_span_float3 n = f->in.eye_normal;
  const clr_span_float length_of_normal = sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
  /* fabs: both sides of a face are lit. A zero normal (a degenerate vertex) gets the ambient term only. */
  const clr_span_float cosine = (n.x * light.x + n.y * light.y + n.z * light.z) / length_of_normal;
  const clr_span_float diffuse = length_of_normal > 0.0f ? fabs(cosine) : 0.0f;
  const clr_span_float lit = AMBIENT + (1.0f - AMBIENT) * diffuse;
  f->out.color.x = texel.x * factor.x * lit;
  f->out.color.y = texel.y * factor.y * lit;
  f->out.color.z = texel.z * factor.z * lit;
  f->out.color.w = 1.0f;
}
