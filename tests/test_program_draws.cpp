// Drawing with user programs, where a program's shape changes the stage program generated for it.
//
// Quad shading: a program that takes derivatives is run in 2x2 quads, with helper invocations for
// the uncovered pixels of each quad. Helpers only feed derivatives, so the pixels written and their
// values must be exactly those of the same program shaded per pixel.
#include "io/procedural.hpp"
#include "support/test_support.hpp"

#include <array>
#include <string>
#include <vector>

namespace clraster::test {
namespace {

// Colour from the interpolated normal. With derivatives, the program also writes the normal's
// slope to a second output, which the framebuffer has no attachment for: it is shaded in quads,
// and its picture must not change.
std::string normal_program(bool derivatives) {
  return std::string(R"(
clr_attribute(float3, position)
clr_attribute(float3, normal)
clr_varying(float3, normal)
clr_output(float4, color)
clr_output(float4, slope)
void vertex(clr_vertex* v) {
  v->position = (float4)(v->in.position, 1.0f);
  v->out.normal = v->in.normal;
}
void fragment(clr_fragment* f) {
  f->out.color = (float4)(f->in.normal * 0.5f + 0.5f, 1.0f);
)") + (derivatives ? "  f->out.slope = (float4)(clr_dfdx(f, f->in.normal), 0.0f);\n" : "") + "}\n";
}

Image render(const Program& program, const io::Mesh& mesh) {
  const Buffer positions(shared_context(), mesh.positions), normals(shared_context(), mesh.normals);
  const IndexBuffer indices(shared_context(), mesh.indices);
  Framebuffer target(shared_context(), 96, 96);
  DrawCall call;
  call.program = &program;
  call.attributes = {{"position", &positions, AttributeType::Float3}, {"normal", &normals, AttributeType::Float3}};
  call.indices = &indices;
  target.draw(call);  // depth test LESS: the random depths hide some triangles behind others
  return target.read_color();
}

// Overlapping triangles of all sizes (many per tile, some covering no pixel centre): before the
// fix, PoCL's miscompiled loop left pixels of triangles after an uncovering one unwritten.
TEST(QuadShading, WritesExactlyThePixelsAndValuesOfPerPixelShading) {
  const io::Mesh mesh = io::make_random_triangles(600, 7, {-1, -1, -1}, {1, 1, 1}, 0.6f);
  const Program per_pixel(shared_context(), normal_program(false), "per_pixel.cl");
  const Program quads(shared_context(), normal_program(true), "quads.cl");
  ASSERT_FALSE(per_pixel.interface().uses_derivatives);
  ASSERT_TRUE(quads.interface().uses_derivatives);
  EXPECT_TRUE(images_match(render(quads, mesh), render(per_pixel, mesh), kExact));
}

// A depth-only pass (a shadow map's): a program with no outputs writes depth and leaves any colour
// attachment as it was.
TEST(ProgramWithoutOutputs, WritesDepthOnly) {
  const Program depth_only(shared_context(), R"(
clr_attribute(float2, position)
void vertex(clr_vertex* v) { v->position = (float4)(v->in.position, 0.0f, 1.0f); }
void fragment(clr_fragment* f) {}
)", "depth_only.cl");
  const std::vector<float> full_screen = {-1, -1, 3, -1, -1, 3};
  const Buffer positions(shared_context(), full_screen);
  DrawCall call;
  call.program = &depth_only;
  call.attributes = {{"position", &positions, AttributeType::Float2}};

  Texture depth(shared_context(), 8, 8, Format::Depth32F);
  Framebuffer depth_target(shared_context(), {}, &depth);
  depth_target.clear_depth(1.0f);
  depth_target.draw(call);
  EXPECT_EQ(depth_target.read_depth(), std::vector<float>(64, 0.5f));  // clip z 0 is depth 0.5

  Framebuffer color_and_depth(shared_context(), 8, 8);
  color_and_depth.clear({0.2f, 0.4f, 0.6f, 1.0f}, 1.0f);
  color_and_depth.draw(call);
  EXPECT_EQ(color_and_depth.read_depth(), std::vector<float>(64, 0.5f));
  const Image color = color_and_depth.read_color();
  for (std::size_t i = 0; i < color.rgba.size(); i += 4) {
    ASSERT_EQ((std::array<int, 4>{color.rgba[i], color.rgba[i + 1], color.rgba[i + 2], color.rgba[i + 3]}),
              (std::array<int, 4>{51, 102, 153, 255}))
        << "pixel " << i / 4;
  }
}

}  // namespace
}  // namespace clraster::test
