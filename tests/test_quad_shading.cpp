// Quad shading: a program that takes derivatives (or samples textures) runs in 2x2 quads, with
// helper invocations and barriers between the tile's work-items, yet must cover, test and write
// exactly the fragments that per-pixel shading does. The same overlapping random triangles, with the
// depth test and some fragments discarded, are drawn through one program twice: as it is, and with
// a derivative whose value it does not use; the pictures must be identical.
#include "io/procedural.hpp"
#include "support/test_support.hpp"

#include <string>

namespace clraster::test {
namespace {

// Colours each fragment by its triangle and discards those of every third triangle; `extra` goes at
// the end of the fragment program.
std::string primitive_colours(const std::string& extra) {
  return R"(
clr_attribute(float3, position)
clr_output(float4, color)

void vertex(clr_vertex* v) { v->position = (float4)(v->in.position, 1.0f); }

void fragment(clr_fragment* f) {
  const uint p = f->primitive_id + 1;
  f->out.color = (float4)((p & 7) / 7.0f, ((p >> 3) & 7) / 7.0f, ((p >> 6) & 7) / 7.0f, 1.0f);
  if (p % 3 == 0) clr_discard(f);
)" + extra + "\n}\n";
}

Image render(const Program& program, const io::Mesh& mesh, int width, int height) {
  Context& context = shared_context();
  const VertexBuffer vertices(context, mesh.positions);
  const IndexBuffer indices(context, mesh.indices);
  Framebuffer framebuffer(context, width, height);
  framebuffer.clear({0, 0, 0, 1}, 1.0f);
  DrawCall call{&vertices, &indices};
  call.program = &program;
  framebuffer.draw(call);
  return framebuffer.read_color();
}

TEST(QuadShading, WritesExactlyTheFragmentsOfPerPixelShading) {
  // Clip space: scattered over the whole picture and through the depth range.
  const io::Mesh mesh = io::make_random_triangles(800, 11, {-1, -1, -0.9f}, {1, 1, 0.9f}, 0.6f);
  // Sides that are not multiples of the tile size: tiles on the edges have pixels outside.
  constexpr int kWidth = 100, kHeight = 76;
  const Program per_pixel(shared_context(), primitive_colours(""), "per_pixel.cl");
  // dFdx of x is 1: the colour's alpha stays 1.
  const Program quads(shared_context(), primitive_colours("  f->out.color.w *= clr_dfdx(f, f->frag_coord.x);"),
                      "quads.cl");
  ASSERT_FALSE(per_pixel.interface().uses_derivatives);
  ASSERT_TRUE(quads.interface().uses_derivatives);

  const Image expected = render(per_pixel, mesh, kWidth, kHeight);
  ASSERT_GT(covered_pixel_count(expected), kWidth * kHeight / 2u);
  EXPECT_TRUE(images_match(render(quads, mesh, kWidth, kHeight), expected, kExact));
}

}  // namespace
}  // namespace clraster::test
