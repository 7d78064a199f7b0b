// Views and layers: a draw with views renders into every layer of a layered framebuffer in one
// submission, and each layer holds what its view draws alone into a framebuffer of one layer,
// whatever the layer size (tiles straddle layers when it is not a multiple of theirs), the viewport
// and scissor, and the draws around it in the frame. Programs see the view as view_id.
//
// "What it draws alone" within the conformance thresholds, not bit for bit: set-up and
// interpolation work in window coordinates, and a layer's offset in the attachments changes the
// rounding of depth and varyings in their last bits (as a viewport's offset does in OpenGL).
#include "io/camera.hpp"
#include "io/procedural.hpp"
#include "support/error_expectations.hpp"
#include "support/test_support.hpp"

#include <cmath>
#include <string>
#include <vector>

namespace clraster::test {
namespace {

// Not a multiple of any tile size, so that tiles hold pixels of two or four layers.
constexpr int kWidth = 75, kHeight = 53;
constexpr int kLayers = 5;  // a grid of 3 x 2, one cell unused

// A torus knot seen from kLayers cameras around it, some so close that it leaves their layer on
// every side (clipped, and in the guard band over the neighbouring layers).
struct KnotViews {
  explicit KnotViews(Context& context)
      : mesh(io::make_torus_knot(2, 3, 96, 12, 1.0f, 0.4f, 0.25f)),
        vertices(context, mesh.positions, mesh.normals),
        indices(context, mesh.indices) {
    for (int k = 0; k < kLayers; ++k) {
      const float angle = 1.3f * static_cast<float>(k);
      const float distance = k % 2 == 0 ? 4.0f : 1.6f;
      io::Camera camera;
      camera.eye = {distance * std::sin(angle), 0.7f * static_cast<float>(k - 2), distance * std::cos(angle)};
      const float aspect = static_cast<float>(kWidth) / kHeight;
      views.push_back({io::to_mat4(io::view_matrix(camera)), io::to_mat4(io::projection_matrix(camera, aspect)), nullptr});
    }
    call.vertices = &vertices;
    call.indices = &indices;
    call.views = views;
  }
  io::Mesh mesh;
  VertexBuffer vertices;
  IndexBuffer indices;
  std::vector<View> views;
  DrawCall call;
};

// `call` with view k's camera, drawn alone into a framebuffer of one layer.
Framebuffer draw_view_alone(Context& context, DrawCall call, int k) {
  Framebuffer framebuffer(context, kWidth, kHeight);
  framebuffer.clear({0, 0, 0, 1});
  const View view = call.views[static_cast<std::size_t>(k)];
  call.views.clear();
  if (call.program == nullptr) {
    call.state.model_view = view.model_view;
    call.state.projection = view.projection;
  } else if (view.bindings != nullptr) {
    call.bindings = view.bindings;
  }
  framebuffer.draw(call);
  return framebuffer;
}

void expect_layers_match_views_alone(Context& context, const DrawCall& call, Framebuffer& layered) {
  for (int k = 0; k < kLayers; ++k) {
    SCOPED_TRACE("layer " + std::to_string(k));
    Framebuffer alone = draw_view_alone(context, call, k);
    const Image image = alone.read_color();
    EXPECT_GT(covered_pixel_count(image), 0u);
    EXPECT_TRUE(images_match(layered.read_color(0, k), image, kNormalShading));
    const std::vector<float> depth = layered.read_depth(k), reference = alone.read_depth();
    ASSERT_EQ(depth.size(), reference.size());
    for (std::size_t i = 0; i < depth.size(); ++i) ASSERT_NEAR(depth[i], reference[i], 1e-5) << "pixel " << i;
    EXPECT_EQ(layered.read_stencil(k), alone.read_stencil());
  }
}

TEST(Views, EachLayerHoldsWhatItsViewDrawsAlone) {
  Context& context = shared_context();
  const KnotViews knot(context);
  Framebuffer layered(context, kWidth, kHeight, kLayers);
  ASSERT_EQ(layered.layer_columns(), 3);
  layered.clear({0, 0, 0, 1});
  const DrawStats stats = layered.draw(knot.call);
  EXPECT_EQ(stats.triangles, kLayers * knot.mesh.triangle_count());
  EXPECT_EQ(stats.chunks, 1u);  // every view in one pass
  expect_layers_match_views_alone(context, knot.call, layered);
  // The unused cell of the grid is never drawn.
  const Rect unused{2 * kWidth, kHeight, kWidth, kHeight};
  const std::vector<std::byte> texels = layered.color(0).read();
  for (int y = unused.y; y < unused.y + unused.height; ++y) {
    for (int x = unused.x; x < unused.x + unused.width; ++x) {
      const std::size_t at = (std::size_t(y) * std::size_t(3 * kWidth) + std::size_t(x)) * 4;
      ASSERT_EQ(std::to_integer<int>(texels[at]) + std::to_integer<int>(texels[at + 1]) + std::to_integer<int>(texels[at + 2]), 0)
          << "pixel " << x << ", " << y << " of the unused cell was drawn";
    }
  }
}

TEST(Views, ViewportAndScissorAreWithinEachLayer) {
  Context& context = shared_context();
  KnotViews knot(context);
  knot.call.state.viewport = {-9, 6, 70, 60};
  knot.call.state.scissor_test = true;
  knot.call.state.scissor = {5, 3, 61, 41};
  knot.call.state.shading = Shading::Lambert;
  knot.call.state.cull = CullMode::Back;
  Framebuffer layered(context, kWidth, kHeight, kLayers);
  layered.clear({0.2f, 0.1f, 0.3f, 1});
  layered.draw(knot.call);
  for (int k = 0; k < kLayers; ++k) {
    SCOPED_TRACE("layer " + std::to_string(k));
    Framebuffer alone(context, kWidth, kHeight);
    alone.clear({0.2f, 0.1f, 0.3f, 1});
    DrawCall call = knot.call;
    call.views.clear();
    call.state.model_view = knot.views[std::size_t(k)].model_view;
    call.state.projection = knot.views[std::size_t(k)].projection;
    alone.draw(call);
    EXPECT_TRUE(images_match(layered.read_color(0, k), alone.read_color(), kNormalShading));
  }
}

// Each view a colour of its own: a program's bindings per view, or the draw's own where a view has
// none. r, g: the view as the vertex and the fragment programs see it; b, a: the pixel in its layer.
constexpr const char* kViewColorProgram = R"(
clr_attribute(float3, position);
clr_uniform(float4, color);
clr_varying_flat(uint, vertex_view);
clr_output(float4, out_color);
void vertex(clr_vertex* v) {
  v->position = (float4)(v->in.position, 1.0f);
  v->out.vertex_view = v->view_id;
}
void fragment(clr_fragment* f) {
  f->out.out_color = (float4)((float)f->in.vertex_view, (float)f->view_id, f->frag_coord.x - 0.5f,
                              f->frag_coord.y - 0.5f) / 255.0f + f->uniforms->color;
}
)";
// The same as a span program (the fragments of a span at once).
constexpr const char* kViewColorSpanProgram = R"(
clr_attribute(float3, position);
clr_uniform(float4, color);
clr_varying_flat(uint, vertex_view);
clr_output(float4, out_color);
void vertex(clr_vertex* v) {
  v->position = (float4)(v->in.position, 1.0f);
  v->out.vertex_view = v->view_id;
}
void fragment_span(clr_span_fragment* f) {
  f->out.out_color.x = CLR_SPAN_CONVERT(float, f->in.vertex_view) / 255.0f;
  f->out.out_color.y = (clr_span_float)((float)f->view_id / 255.0f);
  f->out.out_color.z = (f->frag_coord.x - 0.5f) / 255.0f;
  f->out.out_color.w = (f->frag_coord.y - 0.5f) / 255.0f + f->uniforms->color.w;
}
)";

TEST(Views, ProgramsSeeTheViewAndPixelsWithinTheLayer) {
  Context& context = shared_context();
  for (const char* source : {kViewColorProgram, kViewColorSpanProgram}) {
    const Program program(context, source, "view_color.cl");
    SCOPED_TRACE(source == kViewColorProgram ? "fragment program" : "span program");
    // One triangle over the whole layer, in clip space.
    const std::vector<float> positions = {-1, -1, 0, 3, -1, 0, -1, 3, 0};
    const Buffer buffer(context, positions);
    Bindings zero(program), offset(program);
    zero.set("color", std::array<float, 4>{0, 0, 0, 0});
    offset.set("color", std::array<float, 4>{0, 0, 0, 100.0f / 255});  // the draw's own, for views without
    DrawCall call;
    call.program = &program;
    call.bindings = &offset;
    call.attributes = {{"position", &buffer, AttributeType::Float3}};
    call.state.depth_test = false;
    call.views.resize(kLayers);
    for (int k = 0; k < kLayers; k += 2) call.views[std::size_t(k)].bindings = &zero;
    Framebuffer layered(context, kWidth, kHeight, kLayers);
    layered.draw(call);
    for (int k = 0; k < kLayers; ++k) {
      const Image image = layered.read_color(0, k);
      int wrong = 0;
      for (int row = 0; row < kHeight; ++row) {
        for (int x = 0; x < kWidth; ++x) {
          const int y = kHeight - 1 - row;  // images are top to bottom
          const std::uint8_t* pixel = &image.rgba[(std::size_t(row) * kWidth + std::size_t(x)) * 4];
          const int alpha = std::min(255, y + (k % 2 == 0 ? 0 : 100));
          wrong += pixel[0] != k || pixel[1] != k || pixel[2] != x || pixel[3] != alpha;
        }
      }
      EXPECT_EQ(wrong, 0) << "layer " << k;
    }
  }
}

TEST(Views, ViewsInstancesAndOtherDrawsOfAFrameKeepTheirOrder) {
  Context& context = shared_context();
  KnotViews knot(context);
  knot.call.instance_count = 2;  // the same knot twice: the second fails the depth test, or equals
  knot.call.state.depth_func = CompareFunc::LessEqual;
  DrawCall cover = knot.call;  // then a constant colour over every layer, where depth is equal
  cover.views.clear();
  cover.instance_count = 1;
  cover.state.shading = Shading::Constant;
  cover.state.base_color = {1, 0.5f, 0, 1};
  cover.state.depth_func = CompareFunc::Equal;
  cover.state.model_view = knot.views[1].model_view;
  cover.state.projection = knot.views[1].projection;
  const std::vector<DrawCall> frame = {knot.call, cover};
  Framebuffer layered(context, kWidth, kHeight, kLayers);
  layered.clear({0, 0, 0, 1});
  const DrawStats stats = layered.draw(frame);
  EXPECT_EQ(stats.triangles, 3 * kLayers * knot.mesh.triangle_count());
  for (int k = 0; k < kLayers; ++k) {
    SCOPED_TRACE("layer " + std::to_string(k));
    Framebuffer alone(context, kWidth, kHeight);
    alone.clear({0, 0, 0, 1});
    DrawCall first = knot.call;
    first.views.clear();
    first.state.model_view = knot.views[std::size_t(k)].model_view;
    first.state.projection = knot.views[std::size_t(k)].projection;
    const std::vector<DrawCall> alone_frame = {first, cover};
    for (const DrawCall& call : alone_frame) alone.draw(call);
    EXPECT_TRUE(images_match(layered.read_color(0, k), alone.read_color(), kNormalShading));
  }
}

TEST(Views, BadLayersAndViewsAreErrors) {
  Context& context = shared_context();
  EXPECT_TRUE(throws([&] { Framebuffer framebuffer(context, 64, 64, 0); }, {"a framebuffer has 1..4096 layers, not 0"}));
  EXPECT_TRUE(throws([&] { Framebuffer framebuffer(context, 64, 64, 4097); }, {"a framebuffer has 1..4096 layers, not 4097"}));
  EXPECT_TRUE(throws([&] { Framebuffer framebuffer(context, 6000, 16, 5); }, {"5 layers of 6000x16 need attachments of 18000x32 pixels, more than 16384 per side"}));
  EXPECT_TRUE(throws([&] { Framebuffer framebuffer(context, 16, 9000, 5); }, {"5 layers of 16x9000 need attachments of 48x18000 pixels, more than 16384 per side"}));
  KnotViews knot(context);
  Framebuffer layered(context, kWidth, kHeight, kLayers);
  layered.clear({0, 0, 0, 1});
  DrawCall call = knot.call;
  call.views.pop_back();
  EXPECT_TRUE(throws([&] { layered.draw(call); }, {"the draw has 4 views but the framebuffer has 5 layers: give one view per layer, or none"}));
  const Program program(context, kViewColorProgram, "view_color.cl");
  Bindings bindings(program);
  call = knot.call;
  call.views[3].bindings = &bindings;
  EXPECT_TRUE(throws([&] { layered.draw(call); }, {"view 3 has bindings but the draw has no program"}));
  call = knot.call;
  call.views[2].model_view[5] = std::nanf("");
  EXPECT_TRUE(throws([&] { layered.draw(call); }, {"model_view has the non-finite value nan at element 5"}));
  EXPECT_EQ(covered_pixel_count(layered.read_color(0, 0)), 0u) << "a failed draw drew nothing of the frame";
  EXPECT_TRUE(throws([&] { (void)layered.read_color(0, 5); }, {"layer 5 does not exist: the framebuffer has 5"}));
  EXPECT_TRUE(throws([&] { (void)layered.read_depth(-1); }, {"layer -1 does not exist: the framebuffer has 5"}));
}

}  // namespace
}  // namespace clraster::test
