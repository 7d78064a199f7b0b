// Frames: a span of draw calls given to Framebuffer::draw at once is rasterized in shared passes,
// and draws what the calls draw one by one, bit for bit: whatever programs and state the draws
// change between them, with instances, under the smallest memory cap, and with every call checked
// before any draws.
#include "io/procedural.hpp"
#include "support/test_support.hpp"

#include <string>
#include <vector>

namespace clraster::test {
namespace {

constexpr int kWidth = 320, kHeight = 240;

// Overlapping triangles drawn without a depth test in parts of a colour each: each pixel shows the
// last part drawn there, so the picture depends on every draw keeping its place in the frame.
struct Parts {
  explicit Parts(Context& context, int parts = 64)
      : mesh(io::make_random_triangles(6400, 7, {-1, -1, -1}, {1, 1, 1}, 0.3f)),
        vertices(context, mesh.positions, mesh.normals),
        indices(context, mesh.indices) {
    const auto per_part = static_cast<std::uint32_t>(mesh.indices.size() / 3 / parts);
    for (int part = 0; part < parts; ++part) {
      DrawCall& call = calls.emplace_back();
      call.vertices = &vertices;
      call.indices = &indices;
      call.first = static_cast<std::uint32_t>(part) * per_part * 3;
      call.count = per_part * 3;
      call.state.depth_test = false;
      call.state.shading = Shading::Constant;
      call.state.base_color = {(part % 4 + 1) / 4.0f, (part / 4 % 4 + 1) / 4.0f, (part / 16 + 1) / 4.0f, 1};
    }
  }
  io::Mesh mesh;
  VertexBuffer vertices;
  IndexBuffer indices;
  std::vector<DrawCall> calls;
};

struct Frame {
  Image image;
  DrawStats stats;
};

Frame draw_one_by_one(Context& context, const std::vector<DrawCall>& calls) {
  Framebuffer framebuffer(context, kWidth, kHeight);
  framebuffer.clear({0, 0, 0, 1});
  Frame frame;
  for (const DrawCall& call : calls) {
    const DrawStats stats = framebuffer.draw(call);
    frame.stats.triangles += stats.triangles;
    frame.stats.chunks += stats.chunks;
    frame.stats.tile_triangle_pairs += stats.tile_triangle_pairs;
  }
  frame.image = framebuffer.read_color();
  return frame;
}

Frame draw_as_frame(Context& context, const std::vector<DrawCall>& calls) {
  Framebuffer framebuffer(context, kWidth, kHeight);
  framebuffer.clear({0, 0, 0, 1});
  Frame frame;
  frame.stats = framebuffer.draw(calls);
  frame.image = framebuffer.read_color();
  return frame;
}

TEST(Frames, DrawsOfOneProgramAndStateShareRasterPassesAndDrawAsOneByOne) {
  Context& context = shared_context();
  const Parts parts(context);
  const Frame separate = draw_one_by_one(context, parts.calls);
  const Frame together = draw_as_frame(context, parts.calls);
  ASSERT_GT(covered_pixel_count(separate.image), std::uint64_t{kWidth} * kHeight / 2);
  EXPECT_TRUE(images_match(together.image, separate.image, kExact));
  EXPECT_EQ(together.stats.triangles, parts.mesh.triangle_count());
  EXPECT_EQ(together.stats.triangles, separate.stats.triangles);
  EXPECT_EQ(together.stats.tile_triangle_pairs, separate.stats.tile_triangle_pairs);
  // A pass per draw one by one; together, as many as the device's constant memory needs for the
  // pass's tables (a few hundred bytes a draw: at most 4 passes in OpenCL's minimum of 64 KiB).
  EXPECT_EQ(separate.stats.chunks, parts.calls.size());
  EXPECT_LE(together.stats.chunks, 4u);
}

// Programs, blending, depth test, scissor and culling changing between draws: the draws that can
// share a pass do, the others start a new one, and the order is kept throughout.
TEST(Frames, ChangesOfProgramAndStateBetweenDrawsKeepTheOrder) {
  Context& context = shared_context();
  Parts parts(context);
  for (std::size_t i = 0; i < parts.calls.size(); ++i) {
    DrawState& state = parts.calls[i].state;
    if (i % 7 == 3) state.shading = Shading::Lambert;
    if (i % 11 == 5) state.blend[0] = kAdditiveBlend;
    if (i % 13 == 6) state.depth_test = true;
    if (i % 5 == 2) state.cull = CullMode::Back;  // geometry state only: may share the pass
    if (i % 17 == 9) {
      state.scissor_test = true;
      state.scissor = {40, 30, 200, 150};
    }
    if (i % 9 == 4) state.model_view[12] = 0.1f;  // a uniform of the program: may share the pass
  }
  const Frame separate = draw_one_by_one(context, parts.calls);
  const Frame together = draw_as_frame(context, parts.calls);
  EXPECT_TRUE(images_match(together.image, separate.image, kExact));
  EXPECT_LT(together.stats.chunks, separate.stats.chunks);
}

// Instances of a draw share its pass; a frame of instanced draws draws what one draw per instance
// (its per-instance attribute read from that instance's element) draws, one by one.
TEST(Frames, InstancesDrawAsOneDrawPerInstance) {
  Context& context = shared_context();
  const Program program(context, R"(
clr_attribute(float3, position)
clr_attribute(float2, offset)
clr_uniform(float4, color)
clr_output(float4, out_color)
void vertex(clr_vertex* v) {
  v->position = (float4)(v->in.position.xy * 0.3f + v->in.offset, v->in.position.z, 1.0f);
}
void fragment(clr_fragment* f) { f->out.out_color = f->uniforms->color; }
)",
                        "instances.cl");
  const io::Mesh mesh = io::make_random_triangles(40, 3, {-1, -1, 0}, {1, 1, 0}, 0.8f);
  const VertexBuffer vertices(context, mesh.positions, mesh.normals);
  const IndexBuffer indices(context, mesh.indices);
  constexpr std::uint32_t kInstances = 50;
  std::vector<float> offsets;
  for (std::uint32_t i = 0; i < 2 * kInstances; ++i) offsets.insert(offsets.end(), {-0.9f + 0.018f * i, 0.8f - 0.016f * i});
  const Buffer offset_buffer(context, offsets);
  Bindings red(program), green(program);
  red.set("color", std::array<float, 4>{1, 0.2f, 0.1f, 1});
  green.set("color", std::array<float, 4>{0.1f, 1, 0.3f, 1});

  std::vector<DrawCall> instanced;
  std::vector<DrawCall> one_per_instance;
  for (const Bindings* bindings : {&red, &green}) {
    DrawCall call;
    call.vertices = &vertices;
    call.indices = &indices;
    call.program = &program;
    call.bindings = bindings;
    call.state.depth_test = false;
    // The green draw's instances take the offsets after the red one's.
    const std::size_t first_offset = bindings == &green ? kInstances * 2 * sizeof(float) : 0;
    call.attributes = {{"offset", &offset_buffer, AttributeType::Float2, first_offset, 0, true}};
    call.instance_count = kInstances;
    instanced.push_back(call);
    for (std::uint32_t instance = 0; instance < kInstances; ++instance) {
      DrawCall single = call;
      single.instance_count = 1;
      single.attributes[0].offset += instance * 2 * sizeof(float);
      one_per_instance.push_back(single);
    }
  }
  const Frame separate = draw_one_by_one(context, one_per_instance);
  const Frame together = draw_as_frame(context, instanced);
  ASSERT_GT(covered_pixel_count(separate.image), 1000u);
  EXPECT_TRUE(images_match(together.image, separate.image, kExact));
  EXPECT_EQ(together.stats.triangles, 2u * kInstances * mesh.triangle_count());
  EXPECT_LE(together.stats.chunks, 2u);
}

// Every call of a frame is checked before any draws: a bad one leaves the framebuffer as it was.
TEST(Frames, ACallThatFailsItsChecksDrawsNothingOfTheFrame) {
  Context& context = shared_context();
  Parts parts(context, 8);
  parts.calls[5].count = static_cast<std::uint32_t>(parts.mesh.indices.size() + 3);  // past the indices
  Framebuffer framebuffer(context, kWidth, kHeight);
  framebuffer.clear({0, 0, 0, 1});
  EXPECT_THROW(framebuffer.draw(parts.calls), InvalidArgument);
  EXPECT_EQ(covered_pixel_count(framebuffer.read_color()), 0u);
}

// Under the smallest cap, with the smallest tiles, draws of triangles across the near plane, each
// clipped into up to three, overflow the room a pass has for clipped triangles: the frame splits
// and still draws what the calls draw one by one in a context of the default cap.
TEST(Frames, UnderTheSmallestCapClippedDrawsSplitAndDrawAsOneByOne) {
  const io::Mesh mesh = io::make_random_triangles(60000, 5, {-1, -1, -2}, {1, 1, 2}, 1.5f);
  constexpr std::uint32_t kDraws = 24;
  const auto draw = [&](Context& context, bool as_frame) {
    const VertexBuffer vertices(context, mesh.positions, mesh.normals);
    const IndexBuffer indices(context, mesh.indices);
    std::vector<DrawCall> calls;
    const auto per_draw = static_cast<std::uint32_t>(mesh.indices.size() / 3 / kDraws * 3);
    for (std::uint32_t i = 0; i < kDraws; ++i) {
      DrawCall& call = calls.emplace_back();
      call.vertices = &vertices;
      call.indices = &indices;
      call.first = i * per_draw;
      call.count = per_draw;
      call.state.depth_test = false;
      call.state.projection = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, -1.2f, -1, 0, 0, -2.2f, 0};  // near 1, far 11
      call.state.model_view[14] = -1.5f;  // a third of the triangles reach in front of the near plane
    }
    Framebuffer framebuffer(context, kWidth, kHeight);
    framebuffer.clear({0, 0, 0, 1});
    DrawStats stats;
    if (as_frame) {
      stats = framebuffer.draw(calls);
    } else {
      for (const DrawCall& call : calls) stats = framebuffer.draw(call);
    }
    return std::make_pair(framebuffer.read_color(), stats);
  };
  Context small(ContextOptions{.memory_cap = kMinMemoryCap, .tile_size = 8});
  const auto [frame_image, frame_stats] = draw(small, true);
  const auto [reference, reference_stats] = draw(shared_context(), false);
  ASSERT_GT(covered_pixel_count(reference), std::uint64_t{kWidth} * kHeight / 2);
  EXPECT_TRUE(images_match(frame_image, reference, kExact));
  EXPECT_LE(frame_stats.peak_memory_bytes, kMinMemoryCap);
  EXPECT_EQ(frame_stats.triangles, kDraws * (mesh.triangle_count() / kDraws));
}

}  // namespace
}  // namespace clraster::test
