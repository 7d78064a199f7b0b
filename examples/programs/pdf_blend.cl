/* pdf_blend.cl: flat-coloured discs, blended into colour attachment 0 by one of the PDF blend modes
 * (KHR_blend_equation_advanced's), chosen per draw by a uniform. Used by examples/pdf_blend.cpp.
 *
 * The blend function runs for draws whose BlendState says BlendEquation::Program (kProgramBlend);
 * other draws of the program write their colour as it is. */

clr_attribute(float2, position)  /* a unit disc, drawn as a triangle fan */
clr_uniform(float2, center)      /* where the disc goes, in normalized device coordinates */
clr_uniform(float, radius)
clr_uniform(float4, fill)        /* the disc's colour, premultiplied by its alpha */
clr_uniform(int, mode)           /* which blend mode: one of the MODE_ values below */
clr_output(float4, color)

#define MODE_MULTIPLY 0
#define MODE_SCREEN 1
#define MODE_OVERLAY 2
#define MODE_DARKEN 3
#define MODE_COLORDODGE 4
#define MODE_DIFFERENCE 5

void vertex(clr_vertex* v) {
  v->position = (float4)(v->uniforms->center + v->uniforms->radius * v->in.position, 0.0f, 1.0f);
}

void fragment(clr_fragment* f) { f->out.color = f->uniforms->fill; }

/* source: the fragment's output; destination: what the attachment holds; both premultiplied, as the
 * library's clr_blend_* functions take and return them. The result is stored in the attachment's
 * format (8 bits per channel here). */
float4 blend(clr_fragment* f, uint target, float4 source, float4 destination) {
  switch (f->uniforms->mode) {
    case MODE_MULTIPLY: return clr_blend_multiply(source, destination);
    case MODE_SCREEN: return clr_blend_screen(source, destination);
    case MODE_OVERLAY: return clr_blend_overlay(source, destination);
    case MODE_DARKEN: return clr_blend_darken(source, destination);
    case MODE_COLORDODGE: return clr_blend_colordodge(source, destination);
    case MODE_DIFFERENCE: return clr_blend_difference(source, destination);
    default: return source; /* no such mode: the disc as it is */
  }
}
