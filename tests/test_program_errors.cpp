// Bad input around programs: names bound that a program does not declare, declared ones left
// unbound, values of the wrong size or kind, outputs that do not fit their attachments, state a
// program cannot serve, framebuffers and textures that cannot be. Each is an InvalidArgument whose
// one-line message names what is wrong, thrown before anything renders: the framebuffer keeps what
// it had.
#include "support/error_expectations.hpp"
#include "support/test_support.hpp"

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace clraster::test {
namespace {

const char* const kProgram = R"(
clr_attribute(float2, corner)
clr_uniform(float, scale)
clr_uniform(int, count)
clr_texture(albedo)
clr_buffer(const float4, palette)
clr_output(float4, color)
void vertex(clr_vertex* v) { v->position = (float4)(v->in.corner * v->uniforms->scale, 0.0f, 1.0f); }
void fragment(clr_fragment* f) { f->out.color = clr_sample_lod(f->textures.albedo, (float2)(0.5f), 0.0f) + f->buffers.palette[0]; }
)";

class ProgramErrors : public ::testing::Test {
 protected:
  ProgramErrors()
      : program_(shared_context(), kProgram, "errors.cl"),
        corners_(shared_context(), std::vector<float>{-1, -1, 1, -1, 0, 1}),
        palette_(shared_context(), std::vector<float>{0.1f, 0.2f, 0.3f, 0.4f}),
        texture_(shared_context(), 1, 1, Format::RGBA8, std::as_bytes(std::span<const std::uint8_t>(kWhite)), false),
        bindings_(program_),
        framebuffer_(shared_context(), 8, 8) {
    bindings_.set("scale", 0.5f).set("count", std::int32_t{3}).set_texture("albedo", texture_).set_buffer("palette", palette_);
    call_.program = &program_;
    call_.bindings = &bindings_;
    call_.attributes = {{"corner", &corners_, AttributeType::Float2}};
    framebuffer_.clear({0.25f, 0.5f, 0.75f, 1});
  }

  // The draw throws, mentioning every subject, and leaves the framebuffer as it was.
  ::testing::AssertionResult draw_rejected(const DrawCall& call, const std::vector<std::string_view>& subjects) {
    const Image before = framebuffer_.read_color();
    ::testing::AssertionResult result = throws([&] { framebuffer_.draw(call); }, subjects);
    if (result && framebuffer_.read_color().rgba != before.rgba) {
      return ::testing::AssertionFailure() << "the rejected draw changed the framebuffer";
    }
    return result;
  }

  static constexpr std::uint8_t kWhite[4] = {255, 255, 255, 255};
  static constexpr float kValues[1] = {1.0f};
  Program program_;
  Buffer corners_;
  Buffer palette_;
  Texture texture_;
  Bindings bindings_;
  Framebuffer framebuffer_;
  DrawCall call_;
};

// What gives the checks below their meaning: with everything bound, the draw renders. Inside the
// triangle, the white texel plus the palette's first entry, clamped: white; around it, the clear
// colour (0.25, 0.5, 0.75, 1) as bytes.
TEST_F(ProgramErrors, TheCompleteDrawRenders) {
  framebuffer_.draw(call_);
  const Image image = framebuffer_.read_color();
  const auto pixel = [&](int x, int y) {
    const std::size_t at = 4 * (static_cast<std::size_t>(y) * 8 + x);
    return std::array{image.rgba[at], image.rgba[at + 1], image.rgba[at + 2], image.rgba[at + 3]};
  };
  EXPECT_EQ(pixel(4, 4), (std::array<std::uint8_t, 4>{255, 255, 255, 255}));
  EXPECT_EQ(pixel(0, 0), (std::array<std::uint8_t, 4>{64, 128, 191, 255}));
  EXPECT_EQ(pixel(7, 7), (std::array<std::uint8_t, 4>{64, 128, 191, 255}));
}

TEST_F(ProgramErrors, BindingANameTheProgramDoesNotDeclare) {
  EXPECT_TRUE(throws([&] { bindings_.set("sclae", 1.0f); }, {"errors.cl", "declares no uniform 'sclae'"}));
  EXPECT_TRUE(throws([&] { bindings_.set_texture("albedoo", texture_); }, {"declares no texture 'albedoo'"}));
  EXPECT_TRUE(throws([&] { bindings_.set_buffer("colors", palette_); }, {"declares no buffer 'colors'"}));
  call_.attributes.push_back({"uv", &corners_, AttributeType::Float2});
  EXPECT_TRUE(draw_rejected(call_, {"errors.cl", "declares no attribute 'uv'"}));
}

TEST_F(ProgramErrors, ValuesOfTheWrongSizeOrKind) {
  EXPECT_TRUE(throws([&] { bindings_.set("scale", std::int32_t{1}); }, {"uniform 'scale' is float, not int data"}));
  EXPECT_TRUE(throws([&] { bindings_.set("count", 1.0f); }, {"uniform 'count' is int, not float data"}));
  EXPECT_TRUE(throws([&] { bindings_.set("scale", std::array<float, 2>{1, 2}); }, {"uniform 'scale'", "4 bytes", "8 bytes"}));
  EXPECT_TRUE(throws([&] { bindings_.set_bytes("scale", std::as_bytes(std::span<const float>(kValues)), 1); },
                     {"element 1 does not exist"}));
  const std::uint32_t integer[4] = {1, 2, 3, 4};
  Texture integer_texture(shared_context(), 1, 1, Format::RGBA32UI, std::as_bytes(std::span(integer)), false);
  EXPECT_TRUE(throws([&] { bindings_.set_texture("albedo", integer_texture); }, {"RGBA32UI", "cannot be filtered"}));
}

TEST_F(ProgramErrors, DeclaredNamesLeftUnbound) {
  Bindings partial(program_);
  partial.set("scale", 0.5f).set_texture("albedo", texture_).set_buffer("palette", palette_);
  call_.bindings = &partial;
  EXPECT_TRUE(draw_rejected(call_, {"uniform 'count'", "errors.cl", "line 4", "not set"}));
  Bindings fresh(program_);
  fresh.set("scale", 0.5f).set("count", std::int32_t{1}).set_buffer("palette", palette_);
  call_.bindings = &fresh;
  EXPECT_TRUE(draw_rejected(call_, {"texture 'albedo'", "line 5", "not bound"}));
  fresh.set_texture("albedo", texture_);
  Bindings no_buffer(program_);
  no_buffer.set("scale", 0.5f).set("count", std::int32_t{1}).set_texture("albedo", texture_);
  call_.bindings = &no_buffer;
  EXPECT_TRUE(draw_rejected(call_, {"buffer 'palette'", "line 6", "not bound"}));
  call_.bindings = nullptr;
  EXPECT_TRUE(draw_rejected(call_, {"errors.cl", "no bindings"}));
}

TEST_F(ProgramErrors, AttributesThatDoNotFit) {
  DrawCall missing = call_;
  missing.attributes = {};
  EXPECT_TRUE(draw_rejected(missing, {"no vertex buffer or attributes", "'corner'"}));
  DrawCall integer = call_;
  integer.attributes = {{"corner", &corners_, AttributeType::Int2}};
  EXPECT_TRUE(draw_rejected(integer, {"attribute 'corner'", "float2", "int data"}));
  DrawCall unaligned = call_;
  unaligned.attributes = {{"corner", &corners_, AttributeType::Float2, 2}};
  EXPECT_TRUE(draw_rejected(unaligned, {"attribute 'corner'", "multiples of 4"}));
  DrawCall too_many = call_;
  too_many.count = 9;  // the buffer holds three corners
  EXPECT_TRUE(draw_rejected(too_many, {"9", "runs past the 3 vertices"}));
  DrawCall instances = call_;
  instances.attributes.push_back({"corner", &corners_, AttributeType::Float2, 0, 0, true});
  instances.attributes.erase(instances.attributes.begin());
  instances.count = 3;
  instances.instance_count = 4;
  EXPECT_TRUE(draw_rejected(instances, {"4 instances", "per-instance attributes hold 3"}));
}

TEST_F(ProgramErrors, OutputsThatDoNotFitTheirAttachment) {
  Texture ids(shared_context(), 8, 8, Format::R32UI);
  Framebuffer integer_target(shared_context(), {&ids}, nullptr);
  EXPECT_TRUE(throws([&] { integer_target.draw(call_); }, {"output 'color'", "float4", "attachment 0 is R32UI"}));
}

TEST_F(ProgramErrors, StateTheProgramCannotServe) {
  DrawCall depth = call_;
  depth.state.depth_func = CompareFunc::Program;
  EXPECT_TRUE(draw_rejected(depth, {"depth_func is Program", "depth_test"}));
  DrawCall blend = call_;
  blend.state.blend[0] = kProgramBlend;
  EXPECT_TRUE(draw_rejected(blend, {"blend[0]", "BlendEquation::Program", "blend("}));
  DrawCall stencil = call_;
  stencil.state.stencil_test = true;
  stencil.state.stencil_back.func = CompareFunc::Program;
  EXPECT_TRUE(draw_rejected(stencil, {"stencil_back.func", "depth only"}));
  DrawCall garbage = call_;
  garbage.state.blend[2].src_rgb = static_cast<BlendFactor>(99);
  EXPECT_TRUE(draw_rejected(garbage, {"blend[2]", "99"}));
  DrawCall other_bindings = call_;
  const Program other(shared_context(), kProgram, "other.cl");
  other_bindings.program = &other;
  EXPECT_TRUE(draw_rejected(other_bindings, {"bindings were made for another program", "other.cl"}));
}

TEST(FramebufferErrors, AttachmentsThatCannotMakeAFramebuffer) {
  Context& context = shared_context();
  std::vector<Texture> colors;
  for (int i = 0; i < 9; ++i) colors.emplace_back(context, 4, 4, Format::RGBA8);
  std::vector<Texture*> nine;
  for (Texture& t : colors) nine.push_back(&t);
  EXPECT_TRUE(throws([&] { Framebuffer f(context, nine, nullptr); }, {"at most 8 colour attachments", "9"}));
  Texture small(context, 2, 4, Format::RGBA8);
  EXPECT_TRUE(throws([&] { Framebuffer f(context, {&colors[0], &small}, nullptr); }, {"colour attachment 1", "2x4", "4x4"}));
  Texture depth(context, 4, 4, Format::Depth32F);
  EXPECT_TRUE(throws([&] { Framebuffer f(context, {&depth}, nullptr); }, {"colour attachment 0", "Depth32F", "a depth format"}));
  EXPECT_TRUE(throws([&] { Framebuffer f(context, {&colors[0]}, &colors[1]); }, {"depth attachment", "RGBA8", "not a depth format"}));
  EXPECT_TRUE(throws([&] { Framebuffer f(context, {}, nullptr); }, {"at least one attachment"}));
  EXPECT_TRUE(throws([&] { Framebuffer f(context, {nullptr}, nullptr); }, {"colour attachment 0 is null"}));
  Framebuffer target(context, {&colors[0]}, nullptr);
  EXPECT_TRUE(throws([&] { target.color(1); }, {"colour attachment 1 does not exist"}));
  EXPECT_TRUE(throws([&] { target.read_depth(); }, {"no depth attachment"}));
  EXPECT_TRUE(throws([&] { target.clear_color_uint(0, {1, 2, 3, 4}); }, {"RGBA8", "not an unsigned integer format"}));
}

}  // namespace
}  // namespace clraster::test
