/* depth_only.cl: positions only, as seen from a light. Drawn into a framebuffer whose only
 * attachment is a depth texture: the fragments write depth and nothing else, so the program
 * declares no outputs. Used by examples/shadow_map.cpp (pass 1). */

clr_attribute(float3, position)
clr_uniform(float16, light_mvp)  /* world to the light's clip space */

void vertex(clr_vertex* v) { v->position = clr_mul(v->uniforms->light_mvp, (float4)(v->in.position, 1.0f)); }

void fragment(clr_fragment* f) {}
