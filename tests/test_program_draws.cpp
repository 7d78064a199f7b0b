// Drawing with user programs, where a program's shape changes the stage program generated for it.
//
// Quad shading: a program that takes derivatives is run in 2x2 quads, with helper invocations for
// the uncovered pixels of each quad. Helpers only feed derivatives, so the pixels written and their
// values must be exactly those of the same program shaded per pixel. The CPU shapes walk a tile's
// quads four work-items at a time, the GPU ones run a work-item per pixel of the tile: the
// derivatives must be the same bits.
//
// Span programs: fragment_span computes what fragment would, for a span of pixels at once, so the
// two must write the same bits.
#include "io/procedural.hpp"
#include "support/test_support.hpp"

#include <array>
#include <cmath>
#include <cstring>
#include <random>
#include <span>
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

// Fine and coarse derivatives of a value that varies non-linearly across the picture, in full
// floats, so that a quad put together from the wrong pixels or lanes shows.
constexpr const char* kDerivativesProgram = R"(
clr_attribute(float3, position)
clr_varying(float3, place)
clr_output(float4, fine)
clr_output(float4, coarse)
void vertex(clr_vertex* v) {
  v->position = (float4)(v->in.position, 1.0f);
  v->out.place = v->in.position;
}
void fragment(clr_fragment* f) {
  const float g = sin(7.0f * f->in.place.x) * f->frag_coord.y + f->in.place.z * f->frag_coord.x * f->frag_coord.x;
  f->out.fine = (float4)(clr_dfdx_fine(f, g), clr_dfdy_fine(f, g), clr_fwidth(f, f->in.place.y), g);
  f->out.coarse = (float4)(clr_dfdx_coarse(f, g), clr_dfdy_coarse(f, g), f->frag_coord.xy);
}
)";

std::array<std::vector<std::byte>, 2> render_derivatives(Context& context, const io::Mesh& mesh) {
  const Program program(context, kDerivativesProgram, "derivatives.cl");
  EXPECT_TRUE(program.interface().uses_derivatives);
  const Buffer positions(context, mesh.positions);
  const IndexBuffer indices(context, mesh.indices);
  Texture fine(context, 83, 71, Format::RGBA32F), coarse(context, 83, 71, Format::RGBA32F);
  Texture depth(context, 83, 71, Format::Depth32F);
  Framebuffer target(context, {&fine, &coarse}, &depth);
  target.clear({0.0f, 0.0f, 0.0f, 0.0f}, 1.0f);
  DrawCall call;
  call.program = &program;
  call.attributes = {{"position", &positions, AttributeType::Float3}};
  call.indices = &indices;
  target.draw(call);
  return {fine.read(), coarse.read()};
}

TEST(QuadShading, DerivativesAreTheSameBitsInEveryShape) {
  const io::Mesh mesh = io::make_random_triangles(900, 5, {-1, -1, -1}, {1, 1, 1}, 0.5f);
  const auto device = render_derivatives(shared_context(), mesh);
  const auto wide = render_derivatives(shared_context(WorkGroupShape::Wide), mesh);
  // Drawn: most pixels were written (their frag_coord is not the clear's 0).
  std::size_t drawn = 0;
  for (std::size_t i = 8; i < device[1].size(); i += 16) {
    float x = 0;
    std::memcpy(&x, &device[1][i], sizeof x);
    drawn += x > 0;
  }
  EXPECT_GT(drawn, 83u * 71u / 2);
  EXPECT_TRUE(device[0] == wide[0]) << "fine derivatives";
  EXPECT_TRUE(device[1] == wide[1]) << "coarse derivatives";
}

// Every input a fragment program has, written out to float and integer attachments (full floats, so
// that a value differing in its last bit, or taken from another lane, shows), by a per-fragment
// program or by its span twin. w varies across each triangle, so that smooth and noperspective
// varyings differ.
std::string inputs_program(bool span) {
  const std::string declarations = R"(
clr_attribute(float3, position)
clr_attribute(float3, normal)
clr_varying(float3, normal)
clr_varying_noperspective(float2, screen)
clr_varying_flat(int, vertex)
clr_uniform(float4, tint)
clr_output(float4, shade)
clr_output(float4, coordinates)
clr_output(float4, weights)
clr_output(uint4, ids)
void vertex(clr_vertex* v) {
  v->position = (float4)(v->in.position, 1.5f + 0.5f * v->in.position.z);
  v->out.normal = v->in.normal;
  v->out.screen = v->in.position.xy;
  v->out.vertex = (int)v->vertex_id - 1000;
}
)";
  if (!span) {
    return declarations + R"(
void fragment(clr_fragment* f) {
  const float3 n = f->in.normal;
  const float len = sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
  f->out.shade = (float4)(len > 0.0f ? n / len : (float3)(0.0f), f->in.screen.x * f->in.screen.y) * f->uniforms->tint;
  f->out.coordinates = f->frag_coord;
  f->out.weights = (float4)(f->barycentric, f->front_facing ? 1.0f : -1.0f);
  f->out.ids = (uint4)(f->primitive_id, as_uint(f->in.vertex), as_uint(f->in.screen.y), 7u);
}
)";
  }
  return declarations + R"(
void fragment_span(clr_span_fragment* f) {
  const clr_span_float3 n = f->in.normal;
  const clr_span_float len = sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
  const float4 tint = f->uniforms->tint;
  f->out.shade.x = (len > 0.0f ? n.x / len : 0.0f) * tint.x;
  f->out.shade.y = (len > 0.0f ? n.y / len : 0.0f) * tint.y;
  f->out.shade.z = (len > 0.0f ? n.z / len : 0.0f) * tint.z;
  f->out.shade.w = f->in.screen.x * f->in.screen.y * tint.w;
  f->out.coordinates = f->frag_coord;
  f->out.weights.x = f->barycentric.x;
  f->out.weights.y = f->barycentric.y;
  f->out.weights.z = f->barycentric.z;
  f->out.weights.w = f->front_facing ? 1.0f : -1.0f;
  f->out.ids.x = f->primitive_id;
  f->out.ids.y = CLR_SPAN_AS(uint, f->in.vertex);
  f->out.ids.z = CLR_SPAN_AS(uint, f->in.screen.y);
  f->out.ids.w = 7u;
}
)";
}

// The bytes of each of the program's four attachments after drawing `mesh` with it.
std::vector<std::vector<std::byte>> render_inputs(Context& context, const Program& program, const io::Mesh& mesh) {
  const Buffer positions(context, mesh.positions), normals(context, mesh.normals);
  const IndexBuffer indices(context, mesh.indices);
  Texture shade(context, 61, 47, Format::RGBA32F), coordinates(context, 61, 47, Format::RGBA32F),
      weights(context, 61, 47, Format::RGBA32F), ids(context, 61, 47, Format::RGBA32UI),
      depth(context, 61, 47, Format::Depth32F);
  Framebuffer target(context, {&shade, &coordinates, &weights, &ids}, &depth);
  target.clear({0.0f, 0.0f, 0.0f, 0.0f}, 1.0f);
  Bindings bindings(program);
  bindings.set("tint", std::array<float, 4>{0.5f, 2.0f, -1.0f, 3.0f});
  DrawCall call;
  call.program = &program;
  call.bindings = &bindings;
  call.attributes = {{"position", &positions, AttributeType::Float3}, {"normal", &normals, AttributeType::Float3}};
  call.indices = &indices;
  target.draw(call);
  return {shade.read(), coordinates.read(), weights.read(), ids.read()};
}

using Attachments = std::vector<std::vector<std::byte>>;

// Byte-for-byte equal, else how many elements differ and where the first is.
template <typename T>
::testing::AssertionResult same_values(const std::vector<T>& expected, const std::vector<T>& result) {
  if (expected.size() != result.size()) {
    return ::testing::AssertionFailure() << result.size() << " elements, expected " << expected.size();
  }
  std::size_t differing = 0, first = 0;
  for (std::size_t i = 0; i < expected.size(); ++i) {
    if (std::memcmp(&expected[i], &result[i], sizeof(T)) == 0) continue;
    if (differing++ == 0) first = i;
  }
  if (differing == 0) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << differing << " of " << expected.size() << " elements differ, the first at "
                                       << first;
}

// Pixels of render_inputs' attachments that a triangle wrote: its ids' last word is 7 there, the
// clear's 0 elsewhere.
std::size_t pixels_with_ids(const Attachments& attachments) {
  std::size_t count = 0;
  for (std::size_t i = 12; i < attachments[3].size(); i += 16) count += attachments[3][i] == std::byte{7};
  return count;
}

// In each work-group shape, and with the CPU shapes' smallest tiles too (a mask word of eight rows
// instead of two), a per-fragment program (`source(false)`) and its span twin (`source(true)`) draw
// `mesh` into 61x47 attachments with `render`: every attachment must hold the same bytes, and
// `drawn` must find most pixels written in the per-fragment program's.
void expect_span_twin_writes_the_same_bits(std::string (*source)(bool),
                                           Attachments (*render)(Context&, const Program&, const io::Mesh&),
                                           std::size_t (*drawn)(const Attachments&), const io::Mesh& mesh) {
  static Context small_tiles(ContextOptions{.tile_size = 8});
  for (Context* context : {&shared_context(), &shared_context(WorkGroupShape::Wide), &small_tiles}) {
    const Program per_fragment(*context, source(false), "per_fragment.cl");
    const Program per_span(*context, source(true), "per_span.cl");
    ASSERT_FALSE(per_fragment.interface().has_fragment_span);
    ASSERT_TRUE(per_span.interface().has_fragment_span);
    const Attachments expected = render(*context, per_fragment, mesh);
    const Attachments result = render(*context, per_span, mesh);
    EXPECT_GT(drawn(expected), 61u * 47u / 2);
    for (std::size_t k = 0; k < expected.size(); ++k) {
      EXPECT_TRUE(same_values(expected[k], result[k])) << "attachment " << k;
    }
  }
}

TEST(SpanPrograms, WriteTheBitsOfTheirPerFragmentTwinInEveryShape) {
  expect_span_twin_writes_the_same_bits(inputs_program, render_inputs, pixels_with_ids,
                                        io::make_random_triangles(600, 11, {-1, -1, -1}, {1, 1, 1}, 0.6f));
}

// Derivatives and texture samples of a span program, against its per-fragment twin: in spans of
// eight the CPU shapes shade blocks of two quads, take differences between lanes and sample in
// vectors (resources/texture_span.cl); the GPU shapes shade a pixel per work-item and exchange values
// through local memory. Full floats, fine and coarse derivatives of a value that varies non-linearly,
// and samples whose level of detail comes from derivatives of coordinates stretched unevenly, so
// that a quad put together from the wrong lanes, or a lambda from the wrong differences, shows. The
// samples cover the sampler's paths: RGBA8 trilinear and repeating; sRGB, nearest level, mirrored,
// sides that are not powers of two (the wrap's division), nearest when magnified but linear when
// minified (lanes of one span on both sides); a float format, no mipmaps, clamped, biased; and an
// explicit level of detail.
std::string quad_program(bool span) {
  const std::string declarations = R"(
clr_attribute(float3, position)
clr_varying(float3, place)
clr_texture(bytes)
clr_texture(srgb)
clr_texture(floats)
clr_output(float4, fine)
clr_output(float4, coarse)
clr_output(float4, bytes_sample)
clr_output(float4, srgb_sample)
clr_output(float4, float_sample)
clr_output(float4, lod_sample)
void vertex(clr_vertex* v) {
  v->position = (float4)(v->in.position, 1.5f + 0.5f * v->in.position.z);
  v->out.place = v->in.position;
}
)";
  if (!span) {
    return declarations + R"(
void fragment(clr_fragment* f) {
  const float3 p = f->in.place;
  const float g = p.x * p.x * f->frag_coord.y + p.z * f->frag_coord.x * f->frag_coord.x;
  f->out.fine = (float4)(clr_dfdx_fine(f, g), clr_dfdy_fine(f, g), clr_fwidth(f, p.y), g);
  f->out.coarse = (float4)(clr_dfdx_coarse(f, g), clr_dfdy_coarse(f, g), clr_dfdx(f, p.z), clr_dfdy(f, p.z));
  f->out.bytes_sample = clr_sample(f, f->textures.bytes, (float2)(p.x * 3.0f, p.y * p.y * 5.0f));
  f->out.srgb_sample = clr_sample(f, f->textures.srgb, (float2)(p.x * p.x * 2.0f, p.y * 0.7f + p.z));
  f->out.float_sample = clr_sample(f, f->textures.floats, (float2)(p.y * 1.5f, p.x * p.z * 2.0f));
  f->out.lod_sample = clr_sample_lod(f->textures.bytes, (float2)(p.z, p.x), p.y * 4.0f);
}
)";
  }
  return declarations + R"(
void fragment_span(clr_span_fragment* f) {
  const clr_span_float3 p = f->in.place;
  const clr_span_float g = p.x * p.x * f->frag_coord.y + p.z * f->frag_coord.x * f->frag_coord.x;
  f->out.fine.x = clr_dfdx_fine(f, g);
  f->out.fine.y = clr_dfdy_fine(f, g);
  f->out.fine.z = clr_fwidth(f, p.y);
  f->out.fine.w = g;
  f->out.coarse.x = clr_dfdx_coarse(f, g);
  f->out.coarse.y = clr_dfdy_coarse(f, g);
  f->out.coarse.z = clr_dfdx(f, p.z);
  f->out.coarse.w = clr_dfdy(f, p.z);
  const clr_span_float2 bytes_uv = {p.x * 3.0f, p.y * p.y * 5.0f};
  f->out.bytes_sample = clr_sample(f, f->textures.bytes, bytes_uv);
  const clr_span_float2 srgb_uv = {p.x * p.x * 2.0f, p.y * 0.7f + p.z};
  f->out.srgb_sample = clr_sample(f, f->textures.srgb, srgb_uv);
  const clr_span_float2 float_uv = {p.y * 1.5f, p.x * p.z * 2.0f};
  f->out.float_sample = clr_sample(f, f->textures.floats, float_uv);
  const clr_span_float2 lod_uv = {p.z, p.x};
  f->out.lod_sample = clr_sample_lod(f->textures.bytes, lod_uv, p.y * 4.0f);
}
)";
}

// Texels that differ from their neighbours, so that every filter and level gives its own values.
std::vector<std::byte> pattern_texels(int width, int height, int bytes_per_texel) {
  std::vector<std::byte> texels(std::size_t(width) * height * bytes_per_texel);
  for (std::size_t i = 0; i < texels.size(); ++i) texels[i] = std::byte(static_cast<unsigned char>(i * 37 % 251));
  return texels;
}

Attachments render_quads(Context& context, const Program& program, const io::Mesh& mesh) {
  const Buffer positions(context, mesh.positions);
  const IndexBuffer indices(context, mesh.indices);
  const Texture bytes(context, 64, 32, Format::RGBA8, pattern_texels(64, 32, 4));
  const Texture srgb(context, 24, 10, Format::SRGB8_A8, pattern_texels(24, 10, 4));
  std::vector<float> floats(16 * 16 * 4);
  for (std::size_t i = 0; i < floats.size(); ++i) floats[i] = std::sin(0.37f * static_cast<float>(i)) * 3.0f;
  const Texture float_texture(context, 16, 16, Format::RGBA32F, std::as_bytes(std::span(floats)), false);
  std::vector<Texture> outputs;
  for (int k = 0; k < 6; ++k) outputs.emplace_back(context, 61, 47, Format::RGBA32F);
  Texture depth(context, 61, 47, Format::Depth32F);
  Framebuffer target(context, {&outputs[0], &outputs[1], &outputs[2], &outputs[3], &outputs[4], &outputs[5]}, &depth);
  target.clear({0.0f, 0.0f, 0.0f, 0.0f}, 1.0f);
  Bindings bindings(program);
  bindings.set_texture("bytes", bytes);
  Sampler mirrored;
  mirrored.mag_filter = Filter::Nearest;
  mirrored.mip_filter = MipFilter::Nearest;
  mirrored.wrap_s = Wrap::MirroredRepeat;
  bindings.set_texture("srgb", srgb, mirrored);
  Sampler clamped;
  clamped.min_filter = Filter::Nearest;
  clamped.mip_filter = MipFilter::None;
  clamped.wrap_s = clamped.wrap_t = Wrap::ClampToEdge;
  clamped.lod_bias = 1.5f;
  bindings.set_texture("floats", float_texture, clamped);
  DrawCall call;
  call.program = &program;
  call.bindings = &bindings;
  call.attributes = {{"position", &positions, AttributeType::Float3}};
  call.indices = &indices;
  target.draw(call);  // depth test LESS: some fragments hidden, their quads' helpers still shaded
  Attachments result;
  for (const Texture& output : outputs) result.push_back(output.read());
  return result;
}

TEST(SpanPrograms, TakeTheDerivativesAndSamplesOfTheirPerFragmentTwinInEveryShape) {
  ASSERT_TRUE(Program::read_interface(quad_program(true)).uses_derivatives);
  // Drawn: a written pixel's RGBA8 sample has an alpha, not the clear's 0.
  const auto drawn = [](const Attachments& attachments) {
    std::size_t count = 0;
    for (std::size_t i = 12; i < attachments[2].size(); i += 16) {
      float alpha = 0;
      std::memcpy(&alpha, &attachments[2][i], sizeof alpha);
      count += alpha > 0;
    }
    return count;
  };
  expect_span_twin_writes_the_same_bits(quad_program, render_quads, drawn,
                                        io::make_random_triangles(700, 13, {-1, -1, -1}, {1, 1, 1}, 0.5f));
}

// Slivers: triangles a pixel or so wide and 8 to 40 long at any angle, in a 61x47 framebuffer. Most
// of their (tile, triangle) pairs cover a pixel or two in each of many rows, so the CPU rasterizer
// shades them as packed spans (raster/strategy/spans.cl), while GPU shapes shade one pixel at a time.
io::Mesh slivers(int count, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const float pixel_x = 2.0f / 61.0f, pixel_y = 2.0f / 47.0f;
  io::Mesh mesh;
  for (int i = 0; i < count; ++i) {
    const float cx = unit(random) * 2 - 1, cy = unit(random) * 2 - 1, angle = unit(random) * 6.2832f;
    const float length = 8 + 32 * unit(random), width = 0.3f + 1.5f * unit(random);
    const float dx = std::cos(angle), dy = std::sin(angle);
    const std::array<std::array<float, 2>, 3> corners = {{{cx - dx * length / 2 * pixel_x, cy - dy * length / 2 * pixel_y},
                                                          {cx + dx * length / 2 * pixel_x, cy + dy * length / 2 * pixel_y},
                                                          {cx - dy * width * pixel_x, cy + dx * width * pixel_y}}};
    for (const auto& corner : corners) {
      mesh.positions.insert(mesh.positions.end(), {corner[0], corner[1], unit(random) * 1.8f - 0.9f});
      mesh.normals.insert(mesh.normals.end(), {unit(random) - 0.5f, unit(random) - 0.5f, unit(random) - 0.5f});
      mesh.indices.push_back(static_cast<std::uint32_t>(mesh.indices.size()));
    }
  }
  return mesh;
}

// Packed spans (a pair's scattered pixels in one span) write the bits that spans of one pixel write:
// the interpolation, the fragment's coordinates and the integer output of both program forms, and
// the depth and stencil tests, blending and framebuffer fetch of a per-fragment program.
TEST(PackedSpans, WriteTheBitsOfOnePixelSpans) {
  const io::Mesh mesh = slivers(400, 5);
  std::vector<std::vector<std::vector<std::byte>>> inputs;
  for (Context* context : {&shared_context(), &shared_context(WorkGroupShape::Wide)}) {
    for (bool per_span : {false, true}) {
      inputs.push_back(render_inputs(*context, Program(*context, inputs_program(per_span), "inputs.cl"), mesh));
    }
  }
  EXPECT_GT(pixels_with_ids(inputs[0]), 400u);  // the slivers drew
  for (std::size_t k = 0; k < inputs[0].size(); ++k) {
    EXPECT_TRUE(same_values(inputs[0][k], inputs[2][k])) << "per-fragment program, attachment " << k;
    EXPECT_TRUE(same_values(inputs[1][k], inputs[3][k])) << "span program, attachment " << k;
  }

  const char* const blended = R"(
clr_attribute(float3, position)
clr_varying(float, tone)
clr_output(float4, color)
void vertex(clr_vertex* v) {
  v->position = (float4)(v->in.position, 1.0f);
  v->out.tone = v->in.position.x * 0.5f + 0.5f;
}
void fragment(clr_fragment* f) {
  const float4 under = clr_framebuffer_fetch(f, 0);
  f->out.color = (float4)(f->in.tone, under.x * 0.5f + 0.25f, f->frag_coord.y / 47.0f, 0.6f);
}
)";
  struct Result {
    std::vector<std::byte> color;
    std::vector<float> depth;
    std::vector<std::uint8_t> stencil;
  };
  std::vector<Result> results;
  std::size_t stenciled = 0;
  for (Context* context : {&shared_context(), &shared_context(WorkGroupShape::Wide)}) {
    const Program program(*context, blended, "blended.cl");
    const Buffer positions(*context, mesh.positions);
    const IndexBuffer indices(*context, mesh.indices);
    Texture color(*context, 61, 47, Format::RGBA8), depth(*context, 61, 47, Format::Depth32FStencil8);
    Framebuffer target(*context, {&color}, &depth);
    target.clear({0.1f, 0.2f, 0.3f, 1.0f}, 1.0f);
    DrawCall call;
    call.program = &program;
    call.attributes = {{"position", &positions, AttributeType::Float3}};
    call.indices = &indices;
    call.state.stencil_test = true;
    call.state.stencil_front = {CompareFunc::Always, 0, 0xff, 0xff, StencilOp::Keep, StencilOp::Increment,
                                StencilOp::IncrementWrap};
    call.state.stencil_back = call.state.stencil_front;
    call.state.blend[0] = {true, BlendEquation::Add, BlendEquation::Add, BlendFactor::SrcAlpha,
                           BlendFactor::OneMinusSrcAlpha, BlendFactor::One, BlendFactor::Zero, {true, true, true, true}};
    target.draw(call);
    call.state.depth_func = CompareFunc::LessEqual;  // the same slivers again: their fragments pass
    target.draw(call);
    results.push_back({color.read(), target.read_depth(), target.read_stencil()});
    for (std::uint8_t s : results.back().stencil) stenciled += s >= 2;
  }
  EXPECT_GT(stenciled, 2u * 200u);  // the second draw passed where the first did, in both shapes
  EXPECT_TRUE(same_values(results[0].color, results[1].color));
  EXPECT_TRUE(same_values(results[0].depth, results[1].depth));
  EXPECT_TRUE(same_values(results[0].stencil, results[1].stencil));
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
