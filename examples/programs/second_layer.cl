/* second_layer.cl: a depth test that keeps, at each pixel, the nearest surface *behind* the nearest
 * one: the second layer of depth peeling. Appended to lit.cl by examples/custom_depth.cpp.
 *
 * OpenGL's depth functions compare a fragment with one stored depth. This test also reads the
 * first layer's depth from a texture: a fragment passes when it lies behind the first layer and in
 * front of whatever this pass has stored so far. (OpenGL programs peel by discarding fragments in
 * the fragment shader, which turns off early depth testing; here the depth test is the program's.) */

clr_texture(first_layer) /* Depth32F, the size of the framebuffer: the depth of the nearest surfaces */
clr_uniform(float, separation) /* how far behind the first layer a surface must be to count */

bool depth_test(clr_fragment* f, float fragment_depth, float stored_depth) {
  const int2 pixel = convert_int2(f->frag_coord.xy); /* the pixel centre's window x, y, rounded down */
  const float first = clr_texel_fetch(f->textures.first_layer, pixel, 0).x;
  return fragment_depth > first + f->uniforms->separation && fragment_depth < stored_depth;
}
