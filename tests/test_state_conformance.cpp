// Fixed-function state and vertex input of the programmable pipeline against OpenGL: each test
// draws with a program in OpenCL C on clraster and the same program in GLSL on the oracle (Mesa's
// llvmpipe), from the same data with the same DrawState, and compares every attachment.
#include "support/dual_render.hpp"

#include "io/camera.hpp"
#include "pipeline/draw_state.hpp"

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstring>
#include <map>
#include <memory>
#include <sstream>
#include <tuple>

namespace clraster::test {
namespace {

using Rgba = std::array<float, 4>;

// ---- Meshes -----------------------------------------------------------------------------------------------

using Vec3 = std::array<float, 3>;

struct Vertex {
  Vec3 position;
  Rgba color;
};

// Indexed triangles with the attributes "position" (float3) and "color" (float4), interleaved.
class ColoredMesh {
 public:
  ColoredMesh(const std::vector<Vertex>& vertices, std::vector<std::uint32_t> indices)
      : vertices_(vertices), indices_(std::move(indices)) {}

  DualDraw draw(const DualProgram& program, const DrawState& state) const {
    DualDraw draw{&program};
    draw.attributes = {{"position", &vertices_, AttributeType::Float3, offsetof(Vertex, position), sizeof(Vertex)},
                       {"color", &vertices_, AttributeType::Float4, offsetof(Vertex, color), sizeof(Vertex)}};
    draw.indices = indices_;
    draw.state = state;
    return draw;
  }

  // The same without the colours, for programs that only read positions.
  DualDraw draw_positions(const DualProgram& program, const DrawState& state) const {
    DualDraw positions = draw(program, state);
    positions.attributes.pop_back();
    return positions;
  }

 private:
  DualBuffer vertices_;
  std::vector<std::uint32_t> indices_;
};

// Collects quads, each two triangles that are counter-clockwise when the corners (0, 0), (1, 0),
// (0, 1), (1, 1) of the quad are.
struct QuadList {
  std::vector<Vertex> vertices;
  std::vector<std::uint32_t> indices;

  QuadList& add(const std::array<Vec3, 4>& corners, const std::array<Rgba, 4>& colors) {
    const auto first = static_cast<std::uint32_t>(vertices.size());
    for (int k = 0; k < 4; ++k) vertices.push_back({corners[k], colors[k]});
    for (const std::uint32_t corner : {0, 1, 2, 2, 1, 3}) indices.push_back(first + corner);
    return *this;
  }
  QuadList& add(const std::array<Vec3, 4>& corners, const Rgba& color) {
    return add(corners, {color, color, color, color});
  }
  ColoredMesh mesh() const { return {vertices, indices}; }
};

// A window-aligned rectangle (pixels, y up) of one colour at one depth. Pixel centres are never on
// its edges, so coverage cannot differ between renderers.
struct Quad {
  Rect area;
  Rgba color;
  float z = 0.0f;          // normalized device depth
  bool clockwise = false;  // its triangles' winding in the window
};

// Quads in normalized device coordinates, for identity matrices and a width x height viewport.
ColoredMesh window_quads(const std::vector<Quad>& quads, int width, int height) {
  QuadList list;
  for (const Quad& q : quads) {
    const float x0 = 2.0f * q.area.x / width - 1, x1 = 2.0f * (q.area.x + q.area.width) / width - 1;
    const float y0 = 2.0f * q.area.y / height - 1, y1 = 2.0f * (q.area.y + q.area.height) / height - 1;
    const Vec3 right{x1, y0, q.z}, up{x0, y1, q.z};
    list.add({Vec3{x0, y0, q.z}, q.clockwise ? up : right, q.clockwise ? right : up, {x1, y1, q.z}}, q.color);
  }
  return list.mesh();
}

// Passes each quad's colour through, flat, to `outputs` outputs (colour attachments 0 to outputs - 1).
DualProgram& flat_color_program(int outputs = 1) {
  static std::map<int, std::unique_ptr<DualProgram>> programs;
  std::unique_ptr<DualProgram>& program = programs[outputs];
  if (!program) {
    std::string opencl = R"(
clr_attribute(float3, position)
clr_attribute(float4, color)
clr_varying_flat(float4, color)
)";
    std::string glsl = "#version 450 core\nflat in vec4 v_color;\n";
    std::string opencl_writes, glsl_writes;
    for (int k = 0; k < outputs; ++k) {
      const std::string name = "out" + std::to_string(k);
      opencl += "clr_output(float4, " + name + ")\n";
      opencl_writes += "  f->out." + name + " = f->in.color;\n";
      glsl += "layout(location = " + std::to_string(k) + ") out vec4 " + name + ";\n";
      glsl_writes += "  " + name + " = v_color;\n";
    }
    opencl += R"(
void vertex(clr_vertex* v) {
  v->position = (float4)(v->in.position, 1.0f);
  v->out.color = v->in.color;
}
void fragment(clr_fragment* f) {
)" + opencl_writes + "}\n";
    glsl += "void main() {\n" + glsl_writes + "}\n";
    program = std::make_unique<DualProgram>(opencl, R"(#version 450 core
in vec3 position;
in vec4 color;
flat out vec4 v_color;
void main() {
  gl_Position = vec4(position, 1.0);
  v_color = color;
}
)",
                                            glsl, "flat_color_" + std::to_string(outputs));
  }
  return *program;
}

// ---- Perspective ------------------------------------------------------------------------------------------

// projection * view for a camera at `eye` looking at the origin (y up, 50 degrees vertical field of
// view, near plane `near`, far plane 20).
Mat4 perspective_mvp(const Vec3& eye, float aspect, float near = 0.5f) {
  const glm::mat4 projection = glm::perspective(glm::radians(50.0f), aspect, near, 20.0f);
  const glm::mat4 view = glm::lookAt(glm::vec3(eye[0], eye[1], eye[2]), glm::vec3(0), glm::vec3(0, 1, 0));
  return io::to_mat4(projection * view);
}

// Transforms "position" by the uniform mvp and takes each triangle's colour flat from its provoking
// vertex, so that colours are exact whatever the interpolation.
DualProgram& mvp_flat_color_program() {
  static DualProgram program(R"(
clr_attribute(float3, position)
clr_attribute(float4, color)
clr_varying_flat(float4, color)
clr_uniform(float16, mvp)
clr_output(float4, out_color)
void vertex(clr_vertex* v) {
  v->position = clr_mul(v->uniforms->mvp, (float4)(v->in.position, 1.0f));
  v->out.color = v->in.color;
}
void fragment(clr_fragment* f) { f->out.out_color = f->in.color; }
)",
                             R"(#version 450 core
in vec3 position;
in vec4 color;
uniform mat4 mvp;
flat out vec4 v_color;
void main() {
  gl_Position = mvp * vec4(position, 1.0);
  v_color = color;
}
)",
                             R"(#version 450 core
flat in vec4 v_color;
out vec4 out_color;
void main() { out_color = v_color; }
)",
                             "mvp_flat_color");
  return program;
}

// ---- Names for parameterized tests and failure messages ---------------------------------------------------

std::string name_of(Format format) { return format_info(format).name; }
std::string name_of(BlendEquation equation) {
  const char* const names[] = {"Add", "Subtract", "ReverseSubtract", "Min", "Max"};
  return names[static_cast<int>(equation)];
}
std::string name_of(BlendFactor factor) {
  const char* const names[] = {"Zero",          "One",           "SrcColor",      "OneMinusSrcColor",
                               "DstColor",      "OneMinusDstColor", "SrcAlpha",   "OneMinusSrcAlpha",
                               "DstAlpha",      "OneMinusDstAlpha", "ConstantColor", "OneMinusConstantColor",
                               "ConstantAlpha", "OneMinusConstantAlpha", "SrcAlphaSaturate"};
  return names[static_cast<int>(factor)];
}
std::string name_of(CompareFunc func) {
  const char* const names[] = {"Never", "Less", "Equal", "LessEqual", "Greater", "NotEqual", "GreaterEqual", "Always"};
  return names[static_cast<int>(func)];
}
std::string name_of(StencilOp op) {
  const char* const names[] = {"Keep", "Zero", "Replace", "Increment", "IncrementWrap", "Decrement", "DecrementWrap",
                               "Invert"};
  return names[static_cast<int>(op)];
}
std::string name_of(CullMode cull) {
  const char* const names[] = {"CullNone", "CullBack", "CullFront"};
  return names[static_cast<int>(cull)];
}
std::string name_of(FrontFace front) { return front == FrontFace::CounterClockwise ? "FrontCcw" : "FrontCw"; }
std::string name_of(Topology topology) {
  const char* const names[] = {"List", "Strip", "Fan"};
  return names[static_cast<int>(topology)];
}
std::string text_of(const Rgba& c) {
  std::ostringstream text;
  text << "(" << c[0] << ", " << c[1] << ", " << c[2] << ", " << c[3] << ")";
  return text.str();
}

// ---- Blending ---------------------------------------------------------------------------------------------

constexpr BlendEquation kEquations[] = {BlendEquation::Add, BlendEquation::Subtract, BlendEquation::ReverseSubtract,
                                        BlendEquation::Min, BlendEquation::Max};
constexpr int kFactorCount = 15;

BlendFactor factor(int index) { return static_cast<BlendFactor>(index); }

// Colours that tell every factor apart: opaque, transparent and partial alphas, black and white,
// and one colour each outside [0, 1], which normalized attachments clamp and float ones keep.
const std::vector<Rgba> kSources = {{1, 1, 1, 1},          {0, 0, 0, 0},          {0.2f, 0.5f, 0.8f, 0.6f},
                                    {0.9f, 0.1f, 0.4f, 0.3f}, {0.35f, 0.65f, 0.05f, 1}, {0.5f, 0.25f, 0.75f, 0.5f},
                                    {0.7f, 0.3f, 0.95f, 0.15f}, {1.5f, -0.25f, 0.6f, 2}};
const std::vector<Rgba> kDestinations = {{0, 0, 0, 0},           {1, 1, 1, 1},          {0.6f, 0.4f, 0.2f, 0.8f},
                                         {0.1f, 0.9f, 0.5f, 0.25f}, {0.45f, 0.55f, 0.65f, 0.5f},
                                         {0.8f, 0.05f, 0.3f, 0.95f}, {0.25f, 0.75f, 0.15f, 0.1f},
                                         {-0.5f, 2.5f, 0.33f, 1.25f}};
constexpr Rgba kBlendColor = {0.3f, 0.6f, 0.9f, 0.4f};

// Blend cases, one per colour attachment of a draw, so that one draw blends kTargets states. Case k
// goes to attachment k % kTargets, block k / kTargets (blocks side by side, kColumns to a row); a
// block is kBlock x kBlock one-pixel cells with source colour i over destination colour j at cell
// (i, j), so every source meets every destination.
class BlendGrid {
 public:
  static constexpr int kTargets = kMaxColorAttachments;
  static constexpr int kBlock = 8;  // kSources.size() and kDestinations.size()
  static constexpr int kColumns = 8;

  explicit BlendGrid(int cases)
      : blocks_((cases + kTargets - 1) / kTargets),
        height_((blocks_ + kColumns - 1) / kColumns * kBlock),
        destinations_(window_quads(cells(kDestinations, false), width(), height_)),
        sources_(window_quads(cells(kSources, true), width(), height_)) {}

  int width() const { return kColumns * kBlock; }
  int height() const { return height_; }
  int blocks() const { return blocks_; }

  // Every block's destination colours into every attachment, unblended.
  void draw_destinations(DualFramebuffer& target) const {
    DrawState state;
    state.depth_test = false;
    target.draw(destinations_.draw(flat_color_program(kTargets), state));
  }

  // The source colours of `block` into every attachment, with state.blend (its depth test off).
  void draw_sources(DualFramebuffer& target, int block, DrawState state) const {
    state.depth_test = false;
    DualDraw draw = sources_.draw(flat_color_program(kTargets), state);
    draw.first = static_cast<std::uint32_t>(block * kBlock * kBlock * 6);
    draw.count = kBlock * kBlock * 6;
    target.draw(draw);
  }

  // Names attachment `target`'s pixels by case (from `case_names`), source and destination colour.
  PixelNamer namer(int target, std::vector<std::string> case_names) const {
    return [target, case_names = std::move(case_names)](int x, int y) {
      const std::size_t k = static_cast<std::size_t>((y / kBlock * kColumns + x / kBlock) * kTargets + target);
      return (k < case_names.size() ? case_names[k] : "no case, blending off") + ", source " +
             text_of(kSources[static_cast<std::size_t>(x % kBlock)]) + " over destination " +
             text_of(kDestinations[static_cast<std::size_t>(y % kBlock)]);
    };
  }

 private:
  // A cell per block and colour pair, coloured by the source (by_source) or by the destination.
  std::vector<Quad> cells(const std::vector<Rgba>& colors, bool by_source) const {
    std::vector<Quad> quads;
    for (int block = 0; block < blocks_; ++block) {
      for (int j = 0; j < kBlock; ++j) {
        for (int i = 0; i < kBlock; ++i) {
          quads.push_back({{block % kColumns * kBlock + i, block / kColumns * kBlock + j, 1, 1},
                           colors[static_cast<std::size_t>(by_source ? i : j)]});
        }
      }
    }
    return quads;
  }

  int blocks_, height_;
  ColoredMesh destinations_, sources_;
};

struct BlendCase {
  std::string name;
  BlendState state;
};

// Each case blends every source over every destination (BlendGrid) in attachments of `format`,
// with `blend_color`; clraster must match GL exactly.
void expect_blends_match(Format format, const std::vector<BlendCase>& cases, const Rgba& blend_color = kBlendColor) {
  BlendGrid grid(static_cast<int>(cases.size()));
  DualFramebuffer target(grid.width(), grid.height(), std::vector<Format>(BlendGrid::kTargets, format), false);
  target.clear({0, 0, 0, 0});
  grid.draw_destinations(target);
  std::vector<std::string> names;
  for (int block = 0; block < grid.blocks(); ++block) {
    DrawState state;
    state.blend_color = blend_color;
    for (int k = 0; k < BlendGrid::kTargets && names.size() < cases.size(); ++k) {
      state.blend[static_cast<std::size_t>(k)] = cases[names.size()].state;
      names.push_back(cases[names.size()].name);
    }
    grid.draw_sources(target, block, state);
  }
  for (int k = 0; k < BlendGrid::kTargets; ++k) EXPECT_TRUE(target.color_matches(k, {}, grid.namer(k, names)));
  // Even Min and Max of one 8-bit channel (which ignore the factors) leave 12 values.
  EXPECT_GE(distinct_texels(target.color(0).gl.read(), format_info(format).bytes_per_texel), 12u);
}

std::string name_of(const BlendState& b) {
  return "rgb " + name_of(b.rgb_equation) + " " + name_of(b.src_rgb) + ", " + name_of(b.dst_rgb) + "; alpha " +
         name_of(b.alpha_equation) + " " + name_of(b.src_alpha) + ", " + name_of(b.dst_alpha);
}

BlendCase blend_case(BlendEquation rgb_equation, BlendFactor src_rgb, BlendFactor dst_rgb, BlendEquation alpha_equation,
                     BlendFactor src_alpha, BlendFactor dst_alpha) {
  const BlendState state{true, rgb_equation, alpha_equation, src_rgb, dst_rgb, src_alpha, dst_alpha};
  return {name_of(state), state};
}

using BlendTableCase = std::tuple<Format, BlendEquation>;

class BlendTableTest : public ::testing::TestWithParam<BlendTableCase> {};

// One case per (a, b) of the 15 x 15 factor pairs: rgb blends with source factor a and
// destination factor b, alpha with b and a, so every factor meets every other on both sides and
// in both channels. Alpha uses the equation after the rgb one, so each channel has its own.
TEST_P(BlendTableTest, EveryFactorPairMatchesGl) {
  const auto [format, equation] = GetParam();
  const BlendEquation alpha_equation = kEquations[(static_cast<int>(equation) + 1) % 5];
  std::vector<BlendCase> cases;
  for (int a = 0; a < kFactorCount; ++a) {
    for (int b = 0; b < kFactorCount; ++b) {
      cases.push_back(blend_case(equation, factor(a), factor(b), alpha_equation, factor(b), factor(a)));
    }
  }
  expect_blends_match(format, cases);
}

// llvmpipe computes float blends whose rgb and alpha states each have one factor for both sides as
// (s op d) * factor, which rounds differently; Min and Max count as having the factors One, One,
// whatever they were given. Here rgb has equal factors and alpha unequal ones, under every alpha
// equation.
TEST_P(BlendTableTest, EqualRgbFactorsUnderEveryAlphaEquationMatchGl) {
  const auto [format, equation] = GetParam();
  std::vector<BlendCase> cases;
  for (int a = 0; a < kFactorCount; ++a) {
    for (const BlendEquation alpha_equation : kEquations) {
      cases.push_back(blend_case(equation, factor(a), factor(a), alpha_equation, BlendFactor::SrcAlpha,
                                 BlendFactor::OneMinusDstColor));
      cases.push_back(blend_case(alpha_equation, BlendFactor::DstColor, BlendFactor::SrcAlpha, equation, factor(a),
                                 factor(a)));
    }
  }
  expect_blends_match(format, cases);
}

// The blend states the rasterizer compiles with their state as constants on RGBA8 (types.h), each
// the same for rgb and alpha, the way an application sets them with glBlendFunc: every source over
// every destination, exactly as GL, and each taken as common, so that this is the code that ran.
TEST(StateConformance, CommonBlendsMatchGl) {
  std::vector<BlendCase> cases;
#define CLR_COMMON_BLEND_CASE(index, equation, source_factor, destination_factor)                            \
  cases.push_back(blend_case(BlendEquation(equation), factor(source_factor), factor(destination_factor),     \
                             BlendEquation(equation), factor(source_factor), factor(destination_factor)));   \
  EXPECT_EQ(pipeline::common_blend(BlendUniforms{1, equation, equation, source_factor, destination_factor,     \
                                                 source_factor, destination_factor, 15, CLR_NOT_COMMON_BLEND}, \
                                   CLR_FORMAT_RGBA8),                                                          \
            index);
  CLR_COMMON_BLENDS(CLR_COMMON_BLEND_CASE)
#undef CLR_COMMON_BLEND_CASE
  expect_blends_match(Format::RGBA8, cases);
}

INSTANTIATE_TEST_SUITE_P(StateConformance, BlendTableTest,
                         ::testing::Combine(::testing::Values(Format::RGBA8, Format::RGBA16F, Format::RGBA32F,
                                                              Format::R32F, Format::RG32F, Format::R8, Format::RG8),
                                            ::testing::ValuesIn(kEquations)),
                         [](const auto& info) {
                           return name_of(std::get<0>(info.param)) + name_of(std::get<1>(info.param));
                         });

class BlendFormatTest : public ::testing::TestWithParam<Format> {};

// The constant factors with a blend colour outside [0, 1], which normalized attachments clamp and
// float ones keep, on both sides and in both channels, under every equation that uses factors.
TEST_P(BlendFormatTest, ConstantFactorsWithABlendColorOutOfRangeMatchGl) {
  const BlendFactor constants[] = {BlendFactor::ConstantColor, BlendFactor::OneMinusConstantColor,
                                   BlendFactor::ConstantAlpha, BlendFactor::OneMinusConstantAlpha};
  std::vector<BlendCase> cases;
  for (const BlendEquation equation : {BlendEquation::Add, BlendEquation::Subtract, BlendEquation::ReverseSubtract}) {
    for (const BlendFactor constant : constants) {
      cases.push_back(blend_case(equation, constant, BlendFactor::OneMinusSrcAlpha, equation, BlendFactor::SrcAlpha,
                                 constant));
      cases.push_back(blend_case(equation, BlendFactor::DstColor, constant, equation, constant, constant));
    }
  }
  expect_blends_match(GetParam(), cases, {1.5f, -0.5f, 0.25f, 2.0f});
}

// Each of the 16 colour write masks, unblended and over a blend.
TEST_P(BlendFormatTest, EveryWriteMaskMatchesGl) {
  std::vector<BlendCase> cases;
  for (int mask = 0; mask < 16; ++mask) {
    const std::array<bool, 4> channels{(mask & 1) != 0, (mask & 2) != 0, (mask & 4) != 0, (mask & 8) != 0};
    BlendState unblended;
    unblended.write_mask = channels;
    BlendState blended{true,
                       BlendEquation::Add,
                       BlendEquation::Add,
                       BlendFactor::SrcAlpha,
                       BlendFactor::OneMinusSrcAlpha,
                       BlendFactor::One,
                       BlendFactor::OneMinusSrcAlpha,
                       channels};
    const std::string mask_name = " with write mask " + std::to_string(mask);
    cases.push_back({"no blending" + mask_name, unblended});
    cases.push_back({name_of(blended) + mask_name, blended});
  }
  expect_blends_match(GetParam(), cases);
}

INSTANTIATE_TEST_SUITE_P(StateConformance, BlendFormatTest,
                         ::testing::Values(Format::RGBA8, Format::RGBA16F, Format::RGBA32F),
                         [](const auto& info) { return name_of(info.param); });

// The tile holds a blended RGBA8 attachment as bytes and moves it to and from the framebuffer a span
// at a time, except for spans that the framebuffer's edge or the scissor rectangle cuts, which move
// pixel by pixel: alpha blending over a framebuffer whose sides are no multiple of a span, then
// additive blending through a scissor rectangle that cuts spans on every side, match GL.
TEST(StateConformance, BlendingThroughCutSpansMatchesGl) {
  constexpr int kWidth = 37, kHeight = 21;
  DualFramebuffer target(kWidth, kHeight, {Format::RGBA8});
  target.clear({0.2f, 0.6f, 0.4f, 0.5f}, 1.0f);
  DrawState state;
  state.depth_test = false;
  state.blend[0] = BlendState{true,
                              BlendEquation::Add,
                              BlendEquation::Add,
                              BlendFactor::SrcAlpha,
                              BlendFactor::OneMinusSrcAlpha,
                              BlendFactor::One,
                              BlendFactor::OneMinusSrcAlpha};
  const ColoredMesh everywhere = window_quads({{{0, 0, kWidth, kHeight}, {0.9f, 0.1f, 0.3f, 0.6f}}}, kWidth, kHeight);
  target.draw(everywhere.draw(flat_color_program(), state));
  state.blend[0] = kAdditiveBlend;
  state.scissor_test = true;
  state.scissor = {3, 2, 27, 15};
  const ColoredMesh across = window_quads({{{1, 1, 30, 18}, {0.25f, 0.5f, 0.125f, 0.25f}}}, kWidth, kHeight);
  target.draw(across.draw(flat_color_program(), state));
  EXPECT_TRUE(target.matches());
  EXPECT_EQ(distinct_texels(target.color(0).gl.read(), 4), 2u);  // blended everywhere, and added to within the scissor
}

// ---- Depth ------------------------------------------------------------------------------------------------

constexpr CompareFunc kCompareFuncs[] = {CompareFunc::Never,   CompareFunc::Less,     CompareFunc::Equal,
                                         CompareFunc::LessEqual, CompareFunc::Greater, CompareFunc::NotEqual,
                                         CompareFunc::GreaterEqual, CompareFunc::Always};

// clraster interpolates depth over the triangle as snapped to 1/256 pixel, llvmpipe over the
// unsnapped window positions (its depths are within a float step of the exact plane), so the two
// planes differ slightly, most on steep surfaces: measured up to 1.0e-5 on these scenes.
// Interpolated depths are compared within this, and the scenes keep every depth test they decide
// far from such differences.
constexpr float kInterpolatedDepthTolerance = 4e-5f;

// Window quads (identity matrices) whose fragments may set their own depth and discard themselves:
//   depth_plane = (a, b, c, on): when on is not 0, frag_depth = a * x + b * y + c + z at the pixel
//                 centre (x, y), z the quad's normalized device depth (exact for the values the
//                 tests use: multiples of 1/128);
//   discard_modulus > 0: fragments with (x + 2 y) % discard_modulus == 0 (x, y the pixel) discard.
DualProgram& fragment_depth_program() {
  static DualProgram program(R"(
clr_attribute(float3, position)
clr_attribute(float4, color)
clr_varying_flat(float4, color)
clr_varying_flat(float, depth_offset)
clr_uniform(float4, depth_plane)
clr_uniform(int, discard_modulus)
clr_output(float4, out_color)
void vertex(clr_vertex* v) {
  v->position = (float4)(v->in.position, 1.0f);
  v->out.color = v->in.color;
  v->out.depth_offset = v->in.position.z;
}
void fragment(clr_fragment* f) {
  const int modulus = f->uniforms->discard_modulus;
  const int2 pixel = convert_int2(f->frag_coord.xy);
  if (modulus > 0 && (pixel.x + 2 * pixel.y) % modulus == 0) {
    clr_discard(f);
    return;
  }
  const float4 plane = f->uniforms->depth_plane;
  if (plane.w != 0.0f) {
    f->frag_depth = plane.x * f->frag_coord.x + plane.y * f->frag_coord.y + plane.z + f->in.depth_offset;
  }
  f->out.out_color = f->in.color;
}
)",
                             R"(#version 450 core
in vec3 position;
in vec4 color;
flat out vec4 v_color;
flat out float v_depth_offset;
void main() {
  gl_Position = vec4(position, 1.0);
  v_color = color;
  v_depth_offset = position.z;
}
)",
                             R"(#version 450 core
flat in vec4 v_color;
flat in float v_depth_offset;
uniform vec4 depth_plane;
uniform int discard_modulus;
out vec4 out_color;
void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  if (discard_modulus > 0 && (pixel.x + 2 * pixel.y) % discard_modulus == 0) discard;
  gl_FragDepth = depth_plane.w != 0.0 ? depth_plane.x * gl_FragCoord.x + depth_plane.y * gl_FragCoord.y +
                                            depth_plane.z + v_depth_offset
                                      : gl_FragCoord.z;
  out_color = v_color;
}
)",
                             "fragment_depth");
  return program;
}

using DepthCase = std::tuple<CompareFunc, bool>;  // function, depth write

class DepthFunctionTest : public ::testing::TestWithParam<DepthCase> {
 protected:
  DrawState tested() const {
    DrawState state;
    std::tie(state.depth_func, state.depth_write) = GetParam();
    return state;
  }
};

// In perspective: a ground plane drawn with LESS; then, in one draw with the function under test, a
// quad hovering above the ground (in front of it), one sunk below it (behind) and the ground again,
// in another colour: it meets its own depths (exact ties in both renderers) and, where the quads
// wrote depth, theirs (far from ties).
TEST_P(DepthFunctionTest, SurfacesInPerspectiveMatchGl) {
  constexpr int kSize = 64;
  DualFramebuffer target(kSize, kSize, {Format::RGBA8});
  target.clear({0, 0, 0, 1}, 1.0f);
  const std::array<Vec3, 4> ground{Vec3{-2, 0, 2}, {2, 0, 2}, {-2, 0, -2}, {2, 0, -2}};
  const ColoredMesh first = QuadList().add(ground, Rgba{0.8f, 0.2f, 0.1f, 1}).mesh();
  const ColoredMesh second = QuadList()
                                 .add({Vec3{-1.5f, 0.6f, 1}, {-0.2f, 0.6f, 1}, {-1.5f, 0.6f, -1}, {-0.2f, 0.6f, -1}},
                                      Rgba{0.1f, 0.9f, 0.3f, 1})
                                 .add({Vec3{0.2f, -0.6f, 1}, {1.5f, -0.6f, 1}, {0.2f, -0.6f, -1}, {1.5f, -0.6f, -1}},
                                      Rgba{0.2f, 0.4f, 1, 1})
                                 .add(ground, Rgba{1, 1, 0.5f, 1})
                                 .mesh();
  DualProgram& program = mvp_flat_color_program();
  program.set("mvp", perspective_mvp({1.5f, 2.0f, 3.0f}, 1.0f));
  target.draw(first.draw(program, {}));
  target.draw(second.draw(program, tested()));
  EXPECT_GE(distinct_texels(target.color(0).gl.read(), 4), 2u);  // the clear and the ground at least
  EXPECT_TRUE(target.color_matches(0));
  EXPECT_TRUE(target.depth_matches(kInterpolatedDepthTolerance));
}

// Depths set by the program (frag_depth, as gl_FragDepth), exact in both renderers: x / 64 first
// (with ALWAYS); then, in one draw with the function under test, y / 64 (ties on the diagonal) and
// over it y / 64 + 0.25, which the pipeline clamps to [0, 1] (and which ties with x / 64 where the
// draw's first quad wrote no depth).
TEST_P(DepthFunctionTest, ProgramDepthsMatchGlExactly) {
  constexpr int kSize = 64;
  DualFramebuffer target(kSize, kSize, {Format::RGBA8});
  target.clear({0, 0, 0, 1}, 1.0f);
  const Rect window{0, 0, kSize, kSize};
  const ColoredMesh first = window_quads({{window, {0.8f, 0.2f, 0.1f, 1}}}, kSize, kSize);
  const ColoredMesh second =
      window_quads({{window, {0.1f, 0.9f, 0.3f, 1}}, {window, {0.2f, 0.4f, 1, 1}, 0.25f}}, kSize, kSize);
  DualProgram& program = fragment_depth_program();
  program.set("discard_modulus", 0);
  DrawState always;
  always.depth_func = CompareFunc::Always;
  program.set("depth_plane", Rgba{1.0f / kSize, 0, 0, 1});
  target.draw(first.draw(program, always));
  program.set("depth_plane", Rgba{0, 1.0f / kSize, 0, 1});
  target.draw(second.draw(program, tested()));
  EXPECT_GT(distinct_texels(target.depth_stencil()->gl.read(), 4), 1u);  // depth 1 everywhere if nothing was drawn
  EXPECT_TRUE(target.matches());
}

INSTANTIATE_TEST_SUITE_P(StateConformance, DepthFunctionTest,
                         ::testing::Combine(::testing::ValuesIn(kCompareFuncs), ::testing::Bool()),
                         [](const auto& info) {
                           return name_of(std::get<0>(info.param)) + (std::get<1>(info.param) ? "Write" : "NoWrite");
                         });

// Discarded fragments write nothing (their stencil and depth tests never run); the others write
// the depth their program sets, then pass their stencil operation on.
TEST(StateConformance, DiscardedFragmentsWriteNoColourDepthOrStencil) {
  constexpr int kSize = 64;
  DualFramebuffer target(kSize, kSize, {Format::RGBA8});
  target.clear({0.1f, 0.2f, 0.3f, 1}, 1.0f, 3);
  const ColoredMesh first = window_quads({{{0, 0, kSize, kSize}, {0.8f, 0.2f, 0.1f, 1}}}, kSize, kSize);
  const ColoredMesh second = window_quads({{{8, 8, 48, 40}, {0.1f, 0.9f, 0.3f, 0.5f}, -0.5f}}, kSize, kSize);
  DualProgram& program = fragment_depth_program();
  DrawState state;
  state.stencil_test = true;
  state.stencil_front = state.stencil_back = {CompareFunc::Always, 9, 0xff, 0xff, StencilOp::Keep, StencilOp::Keep,
                                              StencilOp::Replace};
  program.set("discard_modulus", 3).set("depth_plane", Rgba{0, 0, 0, 0});
  target.draw(first.draw(program, state));
  state.depth_func = CompareFunc::Always;
  state.stencil_front.depth_pass = state.stencil_back.depth_pass = StencilOp::IncrementWrap;
  program.set("discard_modulus", 5).set("depth_plane", Rgba{1.0f / kSize, 0, 0.125f, 1});
  target.draw(second.draw(program, state));
  EXPECT_TRUE(target.matches());
  EXPECT_EQ(distinct_texels(target.depth_stencil()->gl.read_stencil()), 4u);  // 3, 4, 9 and 10
}

// With the depth test off, nothing is tested and no depth is written, whatever depth_write says.
TEST(StateConformance, DisabledDepthTestNeitherTestsNorWritesDepth) {
  constexpr int kSize = 32;
  DualFramebuffer target(kSize, kSize, {Format::RGBA8});
  target.clear({0, 0, 0, 1}, 0.5f);
  const ColoredMesh behind = window_quads({{{4, 4, 24, 24}, {0.8f, 0.2f, 0.1f, 1}, 0.5f}}, kSize, kSize);
  DrawState state;
  state.depth_test = false;
  target.draw(behind.draw(flat_color_program(), state));
  EXPECT_TRUE(target.matches());
  EXPECT_EQ(distinct_texels(target.color(0).gl.read(), 4), 2u);
}

// ---- Stencil ----------------------------------------------------------------------------------------------

constexpr StencilOp kStencilOps[] = {StencilOp::Keep,      StencilOp::Zero,          StencilOp::Replace,
                                     StencilOp::Increment, StencilOp::IncrementWrap, StencilOp::Decrement,
                                     StencilOp::DecrementWrap, StencilOp::Invert};

// A stencil state for both faces.
DrawState stencil_state(const StencilFace& face) {
  DrawState state;
  state.stencil_test = true;
  state.stencil_front = state.stencil_back = face;
  return state;
}

// A framebuffer holding every stencil value in each of its `copies` side by side: a grid of
// kCells x kCells cells of kCell x kCell pixels, cell c (row-major from the bottom left) holding
// (167 c + 13) mod 256. Every other cell holds depth 0.25 (the rest 1), so that a draw at depth 0.5
// with LESS fails its depth test there. Colour stays the clear colour.
class StencilPattern {
 public:
  static constexpr int kCell = 2, kCells = 16, kSide = kCell * kCells;

  explicit StencilPattern(int copies) : target_(copies * kSide, kSide, {Format::RGBA8}), copies_(copies) {
    target_.clear({0, 0, 0, 1}, 1.0f, 0);
    DrawState no_color;
    no_color.blend[0].write_mask = {false, false, false, false};
    // Bit b of every cell by a draw that writes only bit b, replacing with all ones where it is set.
    for (int bit = 0; bit < 8; ++bit) {
      const ColoredMesh cells = window_quads(cells_where([bit](int c) { return (value(c) >> bit) & 1; }, 0.0f),
                                             target_.width(), kSide);
      DrawState state = no_color;
      state.depth_test = false;
      state.stencil_test = true;
      state.stencil_front = state.stencil_back = {CompareFunc::Always, 0xff, 0xff, static_cast<std::uint8_t>(1 << bit),
                                                  StencilOp::Keep, StencilOp::Keep, StencilOp::Replace};
      target_.draw(cells.draw(flat_color_program(), state));
    }
    const ColoredMesh near_cells =
        window_quads(cells_where([](int c) { return (c + c / kCells) % 2 == 1; }, -0.5f), target_.width(), kSide);
    DrawState state = no_color;
    state.depth_func = CompareFunc::Always;
    target_.draw(near_cells.draw(flat_color_program(), state));
  }

  static std::uint8_t value(int cell) { return static_cast<std::uint8_t>((167 * cell + 13) % 256); }

  DualFramebuffer& target() { return target_; }

  // Copy k as a window rectangle.
  static Rect copy(int k) { return {k * kSide, 0, kSide, kSide}; }

  // Names a pixel by its cell's initial stencil value and depth.
  static std::string where(int x, int y) {
    const int c = y / kCell * kCells + x % kSide / kCell;
    return "stencil was " + std::to_string(value(c)) + ", depth " + ((c + c / kCells) % 2 ? "0.25" : "1");
  }

 private:
  template <typename Predicate>
  std::vector<Quad> cells_where(Predicate predicate, float z) const {
    std::vector<Quad> quads;
    for (int k = 0; k < copies_; ++k) {
      for (int c = 0; c < kCells * kCells; ++c) {
        if (predicate(c)) quads.push_back({{k * kSide + c % kCells * kCell, c / kCells * kCell, kCell, kCell}, {}, z});
      }
    }
    return quads;
  }

  DualFramebuffer target_;
  int copies_;
};

class StencilFunctionTest : public ::testing::TestWithParam<CompareFunc> {};

// The function under test compares the reference with every stored value, through two read masks;
// passing fragments increment (with wrap-around) and draw their colour, failing ones invert.
TEST_P(StencilFunctionTest, EveryStoredValueMatchesGl) {
  StencilPattern pattern(2);
  DualFramebuffer& target = pattern.target();
  const std::uint8_t references[] = {0x5a, 0x37}, read_masks[] = {0xff, 0x3c};
  const Rgba colors[] = {{0.9f, 0.5f, 0.1f, 1}, {0.2f, 0.6f, 1, 1}};
  for (int k = 0; k < 2; ++k) {
    const ColoredMesh quad = window_quads({{StencilPattern::copy(k), colors[k]}}, target.width(), target.height());
    DrawState state = stencil_state({GetParam(), references[k], read_masks[k], 0xff, StencilOp::Invert,
                                     StencilOp::Invert, StencilOp::IncrementWrap});
    state.depth_test = false;
    target.draw(quad.draw(flat_color_program(), state));
  }
  EXPECT_TRUE(target.matches({}, StencilPattern::where));
}

INSTANTIATE_TEST_SUITE_P(StateConformance, StencilFunctionTest, ::testing::ValuesIn(kCompareFuncs),
                         [](const auto& info) { return name_of(info.param); });

class StencilOpTest : public ::testing::TestWithParam<int> {};

// Operation k of kStencilOps on stencil failure, k + 1 on depth failure and k + 2 on depth pass,
// so that across the parameters every operation meets every outcome, on every stored value (LESS
// with reference 0xa5 fails on half of them; every other cell fails the depth test); all eight
// bits written in the left copy, 0x3c only in the right one.
TEST_P(StencilOpTest, EveryOutcomeOnEveryStoredValueMatchesGl) {
  const int k = GetParam();
  StencilPattern pattern(2);
  DualFramebuffer& target = pattern.target();
  const std::uint8_t write_masks[] = {0xff, 0x3c};
  for (int copy = 0; copy < 2; ++copy) {
    const ColoredMesh quad =
        window_quads({{StencilPattern::copy(copy), {0.9f, 0.5f, 0.1f, 1}}}, target.width(), target.height());
    const DrawState state = stencil_state({CompareFunc::Less, 0xa5, 0xff, write_masks[copy], kStencilOps[k],
                                           kStencilOps[(k + 1) % 8], kStencilOps[(k + 2) % 8]});
    target.draw(quad.draw(flat_color_program(), state));
  }
  EXPECT_TRUE(target.matches({}, StencilPattern::where));
}

INSTANTIATE_TEST_SUITE_P(StateConformance, StencilOpTest, ::testing::Range(0, 8), [](const auto& info) {
  return name_of(kStencilOps[info.param]) + "Then" + name_of(kStencilOps[(info.param + 1) % 8]) + "Then" +
         name_of(kStencilOps[(info.param + 2) % 8]);
});

using FacingCase = std::tuple<CullMode, FrontFace>;

class StencilFacingTest : public ::testing::TestWithParam<FacingCase> {};

// Quads of both windings in a checkerboard, culled by the mode under test or not: the front and
// the back stencil state differ in every field.
TEST_P(StencilFacingTest, FrontAndBackStatesApplyByFacing) {
  StencilPattern pattern(1);
  DualFramebuffer& target = pattern.target();
  std::vector<Quad> quads;
  for (int y = 0; y < StencilPattern::kSide; y += 4) {
    for (int x = 0; x < StencilPattern::kSide; x += 4) {
      const bool clockwise = (x + y) / 4 % 2 == 1;
      quads.push_back({{x, y, 4, 4}, clockwise ? Rgba{0.2f, 0.6f, 1, 1} : Rgba{0.9f, 0.5f, 0.1f, 1}, 0, clockwise});
    }
  }
  const ColoredMesh mesh = window_quads(quads, target.width(), target.height());
  DrawState state;
  std::tie(state.cull, state.front_face) = GetParam();
  state.stencil_test = true;
  state.stencil_front = {CompareFunc::Greater, 0x80, 0xff, 0xff, StencilOp::Keep, StencilOp::Zero, StencilOp::Replace};
  state.stencil_back = {CompareFunc::LessEqual, 0x40, 0x7f, 0xf0, StencilOp::Invert, StencilOp::IncrementWrap,
                        StencilOp::DecrementWrap};
  target.draw(mesh.draw(flat_color_program(), state));
  EXPECT_TRUE(target.matches({}, StencilPattern::where));
}

INSTANTIATE_TEST_SUITE_P(StateConformance, StencilFacingTest,
                         ::testing::Combine(::testing::Values(CullMode::None, CullMode::Back, CullMode::Front),
                                            ::testing::Values(FrontFace::CounterClockwise, FrontFace::Clockwise)),
                         [](const auto& info) {
                           return name_of(std::get<0>(info.param)) + name_of(std::get<1>(info.param));
                         });

// The classic use: a surface in perspective marks the stencil without drawing colour, then a
// full-window quad draws only where it is marked, and another one only where it is not.
TEST(StateConformance, StencilMarksThenMasksLaterDraws) {
  constexpr int kSize = 64;
  DualFramebuffer target(kSize, kSize, {Format::RGBA8});
  target.clear({0, 0, 0, 1}, 1.0f, 0);
  const ColoredMesh ground =
      QuadList().add({Vec3{-2, 0, 2}, {2, 0, 2}, {-2, 0, -2}, {2, 0, -2}}, Rgba{1, 1, 1, 1}).mesh();
  DualProgram& program = mvp_flat_color_program();
  program.set("mvp", perspective_mvp({1.0f, 1.5f, 4.0f}, 1.0f));
  DrawState mark =
      stencil_state({CompareFunc::Always, 1, 0xff, 0xff, StencilOp::Keep, StencilOp::Keep, StencilOp::Replace});
  mark.blend[0].write_mask = {false, false, false, false};
  mark.depth_write = false;
  target.draw(ground.draw(program, mark));

  const ColoredMesh inside = window_quads({{{0, 0, kSize, kSize}, {0.9f, 0.5f, 0.1f, 1}}}, kSize, kSize);
  const ColoredMesh outside = window_quads({{{0, 0, kSize, kSize}, {0.2f, 0.6f, 1, 1}}}, kSize, kSize);
  DrawState masked =
      stencil_state({CompareFunc::Equal, 1, 0xff, 0xff, StencilOp::Keep, StencilOp::Keep, StencilOp::Keep});
  masked.depth_test = false;
  target.draw(inside.draw(flat_color_program(), masked));
  masked.stencil_front.func = masked.stencil_back.func = CompareFunc::NotEqual;
  target.draw(outside.draw(flat_color_program(), masked));
  EXPECT_TRUE(target.matches());
  const std::vector<std::uint8_t> stencil = target.depth_stencil()->gl.read_stencil();
  const auto marked = std::count(stencil.begin(), stencil.end(), 1);
  EXPECT_GT(marked, kSize * kSize / 8);
  EXPECT_LT(marked, kSize * kSize * 7 / 8);
}

// ---- Multiple render targets ------------------------------------------------------------------------------

// The formats of kMrtProgram's outputs, in order.
const std::vector<Format> kMrtFormats = {Format::RGBA8, Format::R32F, Format::RGBA16F, Format::RGBA32UI, Format::R32I,
                                         Format::RG8};

// One output per format of kMrtFormats, each a different function of the quad's flat colour and
// the pixel, exact in float (power-of-two scales, sums of dyadic values) so both renderers agree to
// the bit; integer outputs go negative and use all 32 bits.
DualProgram& mrt_program() {
  static DualProgram program(R"(
clr_attribute(float3, position)
clr_attribute(float4, color)
clr_varying_flat(float4, color)
clr_output(float4, rgba8)
clr_output(float4, r32f)
clr_output(float4, rgba16f)
clr_output(uint4, rgba32ui)
clr_output(int4, r32i)
clr_output(float4, rg8)
void vertex(clr_vertex* v) {
  v->position = (float4)(v->in.position, 1.0f);
  v->out.color = v->in.color;
}
void fragment(clr_fragment* f) {
  const float4 c = f->in.color;
  const int2 p = convert_int2(f->frag_coord.xy);
  f->out.rgba8 = c;
  f->out.r32f = (float4)(f->frag_coord.x * 0.25f + f->frag_coord.y, c.x, c.y, c.z);
  f->out.rgba16f = c * 4.0f - 1.5f;
  f->out.rgba32ui = (uint4)((uint)p.x, (uint)p.y, as_uint(c.x), 0xffffffffu - (uint)p.x);
  f->out.r32i = (int4)(p.x - 3 * p.y, -1, 7, 8);
  f->out.rg8 = c.zwxy;
}
)",
                             R"(#version 450 core
in vec3 position;
in vec4 color;
flat out vec4 v_color;
void main() {
  gl_Position = vec4(position, 1.0);
  v_color = color;
}
)",
                             R"(#version 450 core
flat in vec4 v_color;
layout(location = 0) out vec4 rgba8;
layout(location = 1) out vec4 r32f;
layout(location = 2) out vec4 rgba16f;
layout(location = 3) out uvec4 rgba32ui;
layout(location = 4) out ivec4 r32i;
layout(location = 5) out vec4 rg8;
void main() {
  vec4 c = v_color;
  ivec2 p = ivec2(gl_FragCoord.xy);
  rgba8 = c;
  r32f = vec4(gl_FragCoord.x * 0.25 + gl_FragCoord.y, c.x, c.y, c.z);
  rgba16f = c * 4.0 - 1.5;
  rgba32ui = uvec4(uint(p.x), uint(p.y), floatBitsToUint(c.x), 0xffffffffu - uint(p.x));
  r32i = ivec4(p.x - 3 * p.y, -1, 7, 8);
  rg8 = c.zwxy;
}
)",
                             "mrt");
  return program;
}

class MrtTest : public ::testing::TestWithParam<int> {};  // how many of kMrtFormats are attached

// Two overlapping layers of quads; the second blends differently into each attachment: over, additive,
// MAX, a blend on an integer attachment (which OpenGL ignores), a write mask on another and REVERSE_SUBTRACT
// under a write mask. Outputs beyond the attachments are ignored.
TEST_P(MrtTest, EveryAttachmentMatchesGl) {
  constexpr int kSize = 32;
  const std::vector<Format> formats(kMrtFormats.begin(), kMrtFormats.begin() + GetParam());
  DualFramebuffer target(kSize, kSize, formats, false);
  target.clear({0.25f, 0.5f, 0.75f, 1});
  // Integer clear values that the masked channels keep.
  if (GetParam() > 3) target.clear_color_uint(3, {7, 0xfffffff0u, 3, 1});
  if (GetParam() > 4) target.clear_color_int(4, {-5, 0, 0, 0});
  const ColoredMesh under = window_quads(
      {{{0, 0, 20, 32}, {0.9f, 0.3f, 0.6f, 0.8f}}, {{20, 0, 12, 32}, {0.1f, 0.7f, 0.2f, 0.4f}}}, kSize, kSize);
  const ColoredMesh over = window_quads(
      {{{6, 6, 20, 20}, {0.5f, 0.25f, 1, 0.5f}}, {{14, 18, 16, 12}, {0.75f, 0.125f, 0.375f, 0.25f}}}, kSize, kSize);
  DrawState layer;
  layer.depth_test = false;
  target.draw(under.draw(mrt_program(), layer));
  layer.blend[0] = {true, BlendEquation::Add, BlendEquation::Add, BlendFactor::SrcAlpha, BlendFactor::OneMinusSrcAlpha,
                    BlendFactor::One, BlendFactor::OneMinusSrcAlpha};
  layer.blend[1] = kAdditiveBlend;
  layer.blend[2] = {true, BlendEquation::Max, BlendEquation::Min};
  layer.blend[3] = kAdditiveBlend;
  layer.blend[4].write_mask = {false, true, true, true};
  layer.blend[5] = {true,
                    BlendEquation::ReverseSubtract,
                    BlendEquation::Add,
                    BlendFactor::One,
                    BlendFactor::DstColor,
                    BlendFactor::One,
                    BlendFactor::Zero,
                    {true, false, true, true}};
  target.draw(over.draw(mrt_program(), layer));
  EXPECT_TRUE(target.matches());
  for (int k = 0; k < GetParam(); ++k) {
    EXPECT_GT(distinct_texels(target.color(k).gl.read(), format_info(formats[k]).bytes_per_texel), 3u)
        << "attachment " << k;
  }
}

INSTANTIATE_TEST_SUITE_P(StateConformance, MrtTest, ::testing::Values(2, 4, 6),
                         [](const auto& info) { return std::to_string(info.param) + "Attachments"; });

// ---- Render to texture ------------------------------------------------------------------------------------

// Reads what an earlier pass rendered: even rows fetch the colour texture mirrored left to right
// (clr_texel_fetch, texelFetch), odd rows sample its middle magnified twice at level 0 with the
// draw's sampler (clr_sample_lod, textureLod; pixel centres map to texel quarters, far from the
// nearest-filter boundaries); output 1 fetches the depth texture.
DualProgram& texture_reading_program() {
  static DualProgram program(R"(
clr_attribute(float3, position)
clr_texture(color_texture)
clr_texture(depth_texture)
clr_output(float4, color)
clr_output(float4, depth)
void vertex(clr_vertex* v) { v->position = (float4)(v->in.position, 1.0f); }
void fragment(clr_fragment* f) {
  const int2 p = convert_int2(f->frag_coord.xy);
  const int2 size = clr_texture_size(f->textures.color_texture, 0);
  if (p.y % 2 == 0) {
    f->out.color = clr_texel_fetch(f->textures.color_texture, (int2)(size.x - 1 - p.x, p.y), 0);
  } else {
    const float2 uv = f->frag_coord.xy * 0.5f / convert_float2(size) + 0.25f;
    f->out.color = clr_sample_lod(f->textures.color_texture, uv, 0.0f);
  }
  f->out.depth = clr_texel_fetch(f->textures.depth_texture, p, 0);
}
)",
                             R"(#version 450 core
in vec3 position;
void main() { gl_Position = vec4(position, 1.0); }
)",
                             R"(#version 450 core
uniform sampler2D color_texture;
uniform sampler2D depth_texture;
layout(location = 0) out vec4 color;
layout(location = 1) out vec4 depth;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy);
  ivec2 size = textureSize(color_texture, 0);
  if (p.y % 2 == 0) {
    color = texelFetch(color_texture, ivec2(size.x - 1 - p.x, p.y), 0);
  } else {
    vec2 uv = gl_FragCoord.xy * 0.5 / vec2(size) + 0.25;
    color = textureLod(color_texture, uv, 0.0);
  }
  depth = texelFetch(depth_texture, p, 0);
}
)",
                             "texture_reading");
  return program;
}

class RenderToTextureTest : public ::testing::TestWithParam<Format> {};

// Pass 1 renders surfaces in perspective into a colour texture of the format under test (colours
// beyond 1 for float formats) and a depth texture; pass 2 reads both (texture_reading_program) into
// a framebuffer of the same colour format and an R32F one.
TEST_P(RenderToTextureTest, SecondPassReadsWhatTheFirstRendered) {
  constexpr int kSize = 64;
  DualTexture color(kSize, kSize, GetParam()), depth(kSize, kSize, Format::Depth32FStencil8);
  DualFramebuffer first_pass({&color}, &depth);
  first_pass.clear({0.1f, 0.2f, 0.3f, 1}, 1.0f);
  const ColoredMesh scene = QuadList()
                                .add({Vec3{-2, 0, 2}, {2, 0, 2}, {-2, 0, -2}, {2, 0, -2}}, Rgba{0.8f, 0.2f, 0.1f, 1})
                                .add({Vec3{-1.5f, -0.5f, 0}, {1, -0.5f, 0}, {-1.5f, 1.2f, 0}, {1, 1.2f, 0}},
                                     std::array<Rgba, 4>{Rgba{0.1f, 0.9f, 0.3f, 1}, {1.5f, 0.4f, 1, 0.5f},
                                                         {0.2f, 0.4f, 1, 0.25f}, {1, 1, 0.5f, 1}})
                                .mesh();
  DualProgram& scene_program = mvp_flat_color_program();
  scene_program.set("mvp", perspective_mvp({1.5f, 2.0f, 3.0f}, 1.0f));
  first_pass.draw(scene.draw(scene_program, {}));
  EXPECT_TRUE(first_pass.color_matches(0));
  EXPECT_TRUE(first_pass.depth_matches(kInterpolatedDepthTolerance));

  DualFramebuffer second_pass(kSize, kSize, {GetParam(), Format::R32F}, false);
  const Sampler nearest{Filter::Nearest, Filter::Nearest, MipFilter::None, Wrap::ClampToEdge, Wrap::ClampToEdge};
  DualProgram& reader = texture_reading_program();
  reader.set_texture("color_texture", color, nearest).set_texture("depth_texture", depth, nearest);
  DrawState state;
  state.depth_test = false;
  const ColoredMesh window = window_quads({{{0, 0, kSize, kSize}, {}}}, kSize, kSize);
  second_pass.draw(window.draw_positions(reader, state));
  EXPECT_TRUE(second_pass.color_matches(0));
  EXPECT_TRUE(second_pass.color_matches(1, {0, kInterpolatedDepthTolerance}));
  // The clear colour, the ground and the upright quad's two flat-shaded triangles.
  EXPECT_EQ(distinct_texels(second_pass.color(0).gl.read(), format_info(GetParam()).bytes_per_texel), 4u);
}

INSTANTIATE_TEST_SUITE_P(StateConformance, RenderToTextureTest, ::testing::Values(Format::RGBA8, Format::RGBA16F),
                         [](const auto& info) { return name_of(info.param); });

// ---- Clears -----------------------------------------------------------------------------------------------

// A clear is written by the next draw into the attachment, with its tiles (resources/pending_clear.hpp), or
// before anything else reads the texels. Each step is compared with OpenGL on every attachment: pixels
// outside the draw's scissor and in partial tiles, attachments the draw neither tests nor writes (depth
// and stencil with their tests off, colour attachments beyond the program's outputs), a clear replaced
// before any draw, a draw that rasterizes nothing, and a cleared texture sampled before any draw wrote it.
TEST(StateConformance, ClearsReachEveryPixelWhateverTheNextDrawWrites) {
  constexpr int kWidth = 45, kHeight = 29;  // partial tiles at the right and the top
  const std::vector<Format> formats = {Format::RGBA8, Format::R32I, Format::RGBA16F};
  DualFramebuffer target(kWidth, kHeight, formats), cleared(kWidth, kHeight, formats);  // cleared: never drawn into
  for (DualFramebuffer* framebuffer : {&target, &cleared}) {
    framebuffer->clear({0.2f, 0.4f, 0.6f, 0.8f}, 0.75f, 5);
    framebuffer->clear_color_int(1, {-9, 4, 0, 0});
  }
  // z = -0.2: window depth 0.4.
  const ColoredMesh quad = window_quads({{{4, 3, 30, 20}, {0.9f, 0.1f, 0.5f, 1}, -0.2f}}, kWidth, kHeight);
  DrawState scissored;
  scissored.depth_test = false;
  scissored.scissor_test = true;
  scissored.scissor = {10, 6, 12, 9};
  target.draw(quad.draw(flat_color_program(1), scissored));  // one output for three attachments
  EXPECT_TRUE(target.color_matches(0));
  EXPECT_TRUE(target.depth_matches());
  EXPECT_TRUE(target.stencil_matches());
  EXPECT_EQ(distinct_texels(target.color(0).gl.read(), 4), 2u);  // the clear colour and the quad's
  // Attachments without an output: OpenGL leaves what the draw writes there undefined (llvmpipe writes
  // zeros), clraster leaves them alone, so they hold the clear, as written without any draw.
  EXPECT_TRUE(cleared.matches());
  for (int k : {1, 2}) EXPECT_EQ(target.color(k).clraster.read(), cleared.color(k).clraster.read()) << "attachment " << k;

  target.clear_depth(0.5f);
  target.clear_depth(0.25f);  // replaces the pending 0.5, which would let the quad through
  target.clear_stencil(7);
  target.clear_color({0.1f, 0.3f, 0.5f, 0.7f});
  target.draw(quad.draw(flat_color_program(1), {}));  // depth 0.4 is not less than 0.25: hidden
  EXPECT_TRUE(target.matches());
  EXPECT_EQ(distinct_texels(target.color(0).gl.read(), 4), 1u);

  target.clear({0.5f, 0.25f, 1, 1}, 1.0f, 3);
  DrawState culled;
  culled.cull = CullMode::Front;  // the quad is counter-clockwise, front-facing: nothing rasterizes
  target.draw(quad.draw(flat_color_program(1), culled));
  EXPECT_TRUE(target.matches());

  DualFramebuffer sampled(kWidth, kHeight, {Format::RGBA8, Format::R32F}, false);
  DualProgram& reader = texture_reading_program();
  const Sampler nearest{Filter::Nearest, Filter::Nearest, MipFilter::None, Wrap::ClampToEdge, Wrap::ClampToEdge};
  target.clear({0.0f, 0.6f, 0.2f, 1}, 0.625f);
  reader.set_texture("color_texture", target.color(0), nearest).set_texture("depth_texture", *target.depth_stencil(), nearest);
  DrawState untested;
  untested.depth_test = false;
  sampled.draw(window_quads({{{0, 0, kWidth, kHeight}, {}}}, kWidth, kHeight).draw_positions(reader, untested));
  EXPECT_TRUE(sampled.matches());
  EXPECT_EQ(distinct_texels(sampled.color(0).gl.read(), 4), 1u);
  EXPECT_EQ(distinct_texels(sampled.color(1).gl.read(), 4), 1u);
}

// ---- Vertex input -----------------------------------------------------------------------------------------

// One vertex of the interleaved buffer of InterleavedAttributesOfEveryTypeMatchGl.
struct AttributeVertex {
  float corner[2];    // float2 "corner", normalized device coordinates
  float tint[3];      // float3 data for the float4 "tint" (w reads 1)
  std::int32_t count;  // int data for the int4 "counts" (reads (count, 0, 0, 1))
  float color[4];     // float4 "color"
  std::uint32_t bits;  // uint "bits"
  std::uint32_t unused;
};
// One instance: its shift and tag, after the vertices in the same buffer.
struct AttributeInstance {
  float shift[2];     // float2 "shift"
  std::uint32_t tag;  // uint "tag"
  std::uint32_t unused;
};

// Every attribute kind, passed flat to float, signed and unsigned integer outputs, with vertex_id and
// instance_id (gl_VertexID, gl_InstanceID).
DualProgram& attributes_program() {
  static DualProgram program(R"(
clr_attribute(float2, corner)
clr_attribute(float4, tint)
clr_attribute(int4, counts)
clr_attribute(float4, color)
clr_attribute(uint, bits)
clr_attribute(float2, shift)
clr_attribute(uint, tag)
clr_varying_flat(float4, tint)
clr_varying_flat(float4, color)
clr_varying_flat(int4, ints)
clr_varying_flat(uint4, uints)
clr_output(float4, tint_out)
clr_output(float4, color_out)
clr_output(int4, ints_out)
clr_output(uint4, uints_out)
void vertex(clr_vertex* v) {
  v->position = (float4)(v->in.corner + v->in.shift, 0.0f, 1.0f);
  v->out.tint = v->in.tint;
  v->out.color = v->in.color;
  v->out.ints = (int4)(v->in.counts.x, v->in.counts.w + v->in.counts.y + v->in.counts.z, (int)v->vertex_id,
                       (int)v->instance_id);
  v->out.uints = (uint4)(v->in.bits, v->in.tag, v->vertex_id * 7u, 0u);
}
void fragment(clr_fragment* f) {
  f->out.tint_out = f->in.tint;
  f->out.color_out = f->in.color;
  f->out.ints_out = f->in.ints;
  f->out.uints_out = f->in.uints;
}
)",
                             R"(#version 450 core
in vec2 corner;
in vec4 tint;
in ivec4 counts;
in vec4 color;
in uint bits;
in vec2 shift;
in uint tag;
flat out vec4 v_tint;
flat out vec4 v_color;
flat out ivec4 v_ints;
flat out uvec4 v_uints;
void main() {
  gl_Position = vec4(corner + shift, 0.0, 1.0);
  v_tint = tint;
  v_color = color;
  v_ints = ivec4(counts.x, counts.w + counts.y + counts.z, gl_VertexID, gl_InstanceID);
  v_uints = uvec4(bits, tag, uint(gl_VertexID) * 7u, 0u);
}
)",
                             R"(#version 450 core
flat in vec4 v_tint;
flat in vec4 v_color;
flat in ivec4 v_ints;
flat in uvec4 v_uints;
layout(location = 0) out vec4 tint_out;
layout(location = 1) out vec4 color_out;
layout(location = 2) out ivec4 ints_out;
layout(location = 3) out uvec4 uints_out;
void main() {
  tint_out = v_tint;
  color_out = v_color;
  ints_out = v_ints;
  uints_out = v_uints;
}
)",
                             "attributes");
  return program;
}

// One buffer holds the vertices (48-byte stride, attributes at offsets 0, 8, 20, 24 and 40) and,
// after them, the instances (16-byte stride); float3 and int data feed float4 and int4 attributes.
// Four instances of a row of quads, each moved up by its shift, drawn from the second quad on.
TEST(StateConformance, InterleavedAttributesOfEveryTypeMatchGl) {
  constexpr int kSize = 64;
  std::vector<AttributeVertex> vertices;
  std::vector<std::uint32_t> indices;
  for (int q = 0; q < 4; ++q) {
    const float x0 = q * 0.5f - 1, y0 = -1;  // 16 x 16 pixels
    for (int corner = 0; corner < 4; ++corner) {
      const auto v = static_cast<std::int32_t>(vertices.size());
      vertices.push_back({{x0 + (corner & 1) * 0.5f, y0 + (corner >> 1) * 0.5f},
                          {0.125f * v, 1.0f - 0.0625f * v, -2.5f},
                          -7 * v,
                          {0.25f * q, 0.5f, 1.0f / 3, 3.5f * corner},
                          0xfffffff0u + static_cast<std::uint32_t>(v),
                          0});
    }
    for (const std::uint32_t corner : {0, 1, 2, 2, 1, 3}) indices.push_back(static_cast<std::uint32_t>(4 * q) + corner);
  }
  const std::vector<AttributeInstance> instances = {
      {{0, 0}, 100, 0}, {{0, 0.5f}, 0x80000000u, 0}, {{0, 1}, 7, 0}, {{0, 1.5f}, 0xffffffffu, 0}};
  std::vector<std::byte> bytes = to_bytes(vertices);
  const std::size_t instance_offset = bytes.size();
  const std::vector<std::byte> instance_bytes = to_bytes(instances);
  bytes.insert(bytes.end(), instance_bytes.begin(), instance_bytes.end());
  const DualBuffer buffer(bytes);

  DualFramebuffer target(kSize, kSize, {Format::RGBA32F, Format::RGBA32F, Format::RGBA32I, Format::RGBA32UI}, false);
  target.clear({0, 0, 0, 0});
  DualDraw draw{&attributes_program()};
  constexpr std::size_t kStride = sizeof(AttributeVertex);
  draw.attributes = {{"corner", &buffer, AttributeType::Float2, offsetof(AttributeVertex, corner), kStride},
                     {"tint", &buffer, AttributeType::Float3, offsetof(AttributeVertex, tint), kStride},
                     {"counts", &buffer, AttributeType::Int, offsetof(AttributeVertex, count), kStride},
                     {"color", &buffer, AttributeType::Float4, offsetof(AttributeVertex, color), kStride},
                     {"bits", &buffer, AttributeType::UInt, offsetof(AttributeVertex, bits), kStride},
                     {"shift", &buffer, AttributeType::Float2, instance_offset + offsetof(AttributeInstance, shift),
                      sizeof(AttributeInstance), true},
                     {"tag", &buffer, AttributeType::UInt, instance_offset + offsetof(AttributeInstance, tag),
                      sizeof(AttributeInstance), true}};
  draw.indices = indices;
  draw.first = 6;
  draw.instance_count = 4;
  draw.state.depth_test = false;
  target.draw(draw);
  EXPECT_TRUE(target.matches());
  // Two flat-shaded triangles in each of 3 quads of 4 instances, and the clear value.
  EXPECT_EQ(distinct_texels(target.color(2).gl.read(), 16), 25u);
}

// Vertices pulled from a buffer by vertex_id (no attributes), each instance moved right by
// instance_id; in GLSL, from a uniform array by gl_VertexID. Flat outputs show which vertex was
// the provoking one and which primitive and instance a fragment came from.
DualProgram& vertex_pulling_program() {
  static DualProgram program(R"(
clr_buffer(const float4, vertices)
clr_varying_flat(uint4, ids)
clr_varying_flat(float4, color)
clr_output(float4, color_out)
clr_output(uint4, ids_out)
void vertex(clr_vertex* v) {
  const float4 stored = v->buffers.vertices[v->vertex_id];
  v->position = (float4)(stored.x + 0.25f * (float)v->instance_id, stored.y, 0.0f, 1.0f);
  v->out.ids = (uint4)(v->vertex_id, v->instance_id, 0u, 0u);
  v->out.color = (float4)(stored.zw, 0.5f, 1.0f);
}
void fragment(clr_fragment* f) {
  f->out.color_out = f->in.color;
  f->out.ids_out = (uint4)(f->in.ids.xy, f->primitive_id, 0u);
}
)",
                             R"(#version 450 core
uniform vec4 vertices[12];
flat out uvec4 v_ids;
flat out vec4 v_color;
void main() {
  vec4 stored = vertices[gl_VertexID];
  gl_Position = vec4(stored.x + 0.25 * float(gl_InstanceID), stored.y, 0.0, 1.0);
  v_ids = uvec4(gl_VertexID, gl_InstanceID, 0u, 0u);
  v_color = vec4(stored.zw, 0.5, 1.0);
}
)",
                             R"(#version 450 core
flat in uvec4 v_ids;
flat in vec4 v_color;
layout(location = 0) out vec4 color_out;
layout(location = 1) out uvec4 ids_out;
void main() {
  color_out = v_color;
  ids_out = uvec4(v_ids.xy, gl_PrimitiveID, 0u);
}
)",
                             "vertex_pulling");
  return program;
}

// Non-indexed from vertex 3 (vertex_id counts from there) and indexed, two instances each.
TEST(StateConformance, VerticesPulledFromABufferByVertexIdMatchGl) {
  constexpr int kSize = 64;
  std::vector<float> vertices;
  for (int v = 0; v < 12; ++v) {
    const float x = -1 + 0.125f * static_cast<float>(v / 3 * 3 + (v % 3 == 1 ? 2 : 0));
    const float y = -0.75f + (v % 3 == 2 ? 1.25f : 0.0f) + 0.0625f * static_cast<float>(v % 4);
    vertices.insert(vertices.end(), {x, y, 0.0625f * static_cast<float>(v), 1 - 0.0625f * static_cast<float>(v)});
  }
  DualProgram& program = vertex_pulling_program();
  const Buffer buffer(shared_context(), vertices);
  program.bindings.set_buffer("vertices", buffer);
  program.gl.set("vertices", std::span<const float>(vertices));
  DualFramebuffer target(kSize, kSize, {Format::RGBA8, Format::RGBA32UI}, false);
  target.clear({0, 0, 0, 1});
  DualDraw draw{&program};
  draw.first = 3;
  draw.count = 9;
  draw.instance_count = 2;
  draw.state.depth_test = false;
  target.draw(draw);
  draw.first = 0;
  draw.count = kAllElements;
  draw.indices = {11, 9, 10, 2, 0, 1};
  target.draw(draw);
  EXPECT_TRUE(target.matches());
  EXPECT_GT(distinct_texels(target.color(1).gl.read(), 16), 8u);
}

constexpr int kSmoothVaryings = 10;

// Like depth, varyings are interpolated over the snapped triangle by clraster and over the
// unsnapped one by llvmpipe, so values that change quickly across the window differ in their last
// digits: for values in [0, 1] measured up to 1.6e-4 apart, for the sum of nine varyings (up to 55)
// 4.8e-3. Flat varyings must match bit for bit.
constexpr float kInterpolatedVaryingTolerance = 5e-4f;
constexpr float kInterpolatedSumTolerance = 1e-2f;

// Interpolation of every kind, from the attribute "color" c: kSmoothVaryings perspective-correct
// float4 varyings (varying k is (k + 1) c + k / 8), a noperspective copy of c, and flat int4 and
// uint4 varyings from the provoking vertex (the last), holding vertex_id and values whose bits
// would be NaNs as floats (-1, 0x7fc00001, 0x7f800001, 0xff800000).
DualProgram& interpolation_program() {
  static DualProgram program = [] {
    std::string declarations, assignments, sum, glsl_sum;
    for (int k = 0; k < kSmoothVaryings; ++k) {
      const std::string name = "v" + std::to_string(k);
      declarations += "clr_varying(float4, " + name + ")\n";
      assignments +=
          "  v->out." + name + " = c * " + std::to_string(k + 1) + ".0f + " + std::to_string(k) + ".0f / 8.0f;\n";
      if (k > 0) {
        sum += std::string(k > 1 ? " + " : "") + "f->in." + name;
        glsl_sum += std::string(k > 1 ? " + " : "") + "v_values[" + std::to_string(k) + "]";
      }
    }
    return DualProgram(R"(
clr_attribute(float3, position)
clr_attribute(float4, color)
clr_uniform(float16, mvp)
)" + declarations + R"(clr_varying_noperspective(float4, linear)
clr_varying_flat(int4, flat_ints)
clr_varying_flat(uint4, flat_uints)
clr_output(float4, perspective_out)
clr_output(float4, linear_out)
clr_output(float4, sum_out)
clr_output(int4, ints_out)
clr_output(uint4, uints_out)
void vertex(clr_vertex* v) {
  v->position = clr_mul(v->uniforms->mvp, (float4)(v->in.position, 1.0f));
  const float4 c = v->in.color;
)" + assignments + R"(  v->out.linear = c;
  v->out.flat_ints = (int4)((int)v->vertex_id, -1, 0x7fc00001, INT_MIN);
  v->out.flat_uints = (uint4)(v->vertex_id * 3u, 0xffffffffu, 0x7f800001u, 0xff800000u);
}
void fragment(clr_fragment* f) {
  f->out.perspective_out = f->in.v0;
  f->out.linear_out = f->in.linear;
  f->out.sum_out = )" + sum + R"(;
  f->out.ints_out = f->in.flat_ints;
  f->out.uints_out = f->in.flat_uints;
}
)",
                       R"(#version 450 core
in vec3 position;
in vec4 color;
uniform mat4 mvp;
out vec4 v_values[)" + std::to_string(kSmoothVaryings) + R"(];
noperspective out vec4 v_linear;
flat out ivec4 v_ints;
flat out uvec4 v_uints;
void main() {
  gl_Position = mvp * vec4(position, 1.0);
  for (int k = 0; k < v_values.length(); ++k) v_values[k] = color * float(k + 1) + float(k) / 8.0;
  v_linear = color;
  v_ints = ivec4(gl_VertexID, -1, 0x7fc00001, int(0x80000000u));
  v_uints = uvec4(uint(gl_VertexID) * 3u, 0xffffffffu, 0x7f800001u, 0xff800000u);
}
)",
                       R"(#version 450 core
in vec4 v_values[)" + std::to_string(kSmoothVaryings) + R"(];
noperspective in vec4 v_linear;
flat in ivec4 v_ints;
flat in uvec4 v_uints;
layout(location = 0) out vec4 perspective_out;
layout(location = 1) out vec4 linear_out;
layout(location = 2) out vec4 sum_out;
layout(location = 3) out ivec4 ints_out;
layout(location = 4) out uvec4 uints_out;
void main() {
  perspective_out = v_values[0];
  linear_out = v_linear;
  sum_out = )" + glsl_sum + R"(;
  ints_out = v_ints;
  uints_out = v_uints;
}
)",
                       "interpolation");
  }();
  return program;
}

// 2 x 2 quads of a ground plane (y = 0) from x0 to x0 + 8 and from z0 back to z0 - 14, with
// distinct values at their corners.
ColoredMesh ground_quads(float x0, float z0) {
  QuadList ground;
  for (int i = 0; i < 2; ++i) {
    for (int j = 0; j < 2; ++j) {
      const float x = x0 + 4.0f * static_cast<float>(i), z = z0 - 7.0f * static_cast<float>(j);
      std::array<Rgba, 4> values;
      for (int c = 0; c < 4; ++c) {
        const float k = static_cast<float>(4 * (2 * i + j) + c);
        values[c] = {k / 16.0f, 1.0f - k / 16.0f, (c & 1) ? 1.0f : 0.0f, 0.5f + k / 32.0f};
      }
      ground.add({Vec3{x, 0, z}, {x + 4, 0, z}, {x, 0, z - 7}, {x + 4, 0, z - 7}}, values);
    }
  }
  return ground.mesh();
}

// Renders `mesh` with interpolation_program into its five outputs.
DualFramebuffer& render_interpolation(DualFramebuffer& target, const ColoredMesh& mesh, const Mat4& mvp) {
  DualProgram& program = interpolation_program();
  program.set("mvp", mvp);
  target.clear({0, 0, 0, 0});
  DrawState state;
  state.depth_test = false;
  target.draw(mesh.draw(program, state));
  return target;
}

// The largest difference between two channels of any texel of RGBA32F textures.
float largest_difference(const std::vector<std::byte>& a, const std::vector<std::byte>& b) {
  std::vector<float> x(a.size() / 4), y(b.size() / 4);
  std::memcpy(x.data(), a.data(), a.size());
  std::memcpy(y.data(), b.data(), b.size());
  float largest = 0;
  for (std::size_t i = 0; i < x.size(); ++i) largest = std::max(largest, std::abs(x[i] - y[i]));
  return largest;
}

const std::vector<Format> kInterpolationFormats = {Format::RGBA32F, Format::RGBA32F, Format::RGBA32F, Format::RGBA32I,
                                                   Format::RGBA32UI};

// A ground in perspective ahead of the camera: every kind of interpolation, and enough varyings
// to fill ten float4s.
TEST(StateConformance, VaryingsOfEveryInterpolationMatchGl) {
  constexpr int kSize = 64;
  DualFramebuffer target(kSize, kSize, kInterpolationFormats, false);
  render_interpolation(target, ground_quads(-4, 1), perspective_mvp({0.5f, 2.0f, 4.0f}, 1.0f));
  EXPECT_TRUE(target.color_matches(0, {0, kInterpolatedVaryingTolerance}));
  EXPECT_TRUE(target.color_matches(1, {0, kInterpolatedVaryingTolerance}));
  EXPECT_TRUE(target.color_matches(2, {0, kInterpolatedSumTolerance}));
  EXPECT_TRUE(target.color_matches(3));
  EXPECT_TRUE(target.color_matches(4));
  // The same values interpolated with and without perspective differ far beyond the tolerance.
  EXPECT_GT(largest_difference(target.color(0).gl.read(), target.color(1).gl.read()), 0.05f);
}

// A ground that runs from ahead of the camera to behind it, so that its triangles cross the near
// plane and are clipped: flat varyings keep the original provoking vertex's values, bit for bit.
// (Its noperspective values are not compared: where a clipped triangle has a vertex behind the
// eye, llvmpipe's depart from the values that vary linearly in the window, which clraster
// computes, by up to 0.012.)
TEST(StateConformance, ClippedTrianglesKeepTheirVaryingsAsGl) {
  constexpr int kSize = 64;
  DualFramebuffer target(kSize, kSize, kInterpolationFormats, false);
  render_interpolation(target, ground_quads(-4, 6), perspective_mvp({0.5f, 1.0f, 3.0f}, 1.0f, 0.25f));
  EXPECT_TRUE(target.color_matches(0, {0, kInterpolatedVaryingTolerance}));
  EXPECT_TRUE(target.color_matches(2, {0, kInterpolatedSumTolerance}));
  EXPECT_TRUE(target.color_matches(3));
  EXPECT_TRUE(target.color_matches(4));
  EXPECT_GT(distinct_texels(target.color(3).gl.read(), 16), 5u);
}

// Facing and primitive identity: front faces orange, back faces blue, and as integers the
// primitive_id (gl_PrimitiveID), front_facing (gl_FrontFacing) and the instance. Each instance is
// moved right by two pixels.
DualProgram& facing_program() {
  static DualProgram program(R"(
clr_attribute(float3, position)
clr_varying_flat(uint, instance)
clr_output(float4, color)
clr_output(uint4, ids)
void vertex(clr_vertex* v) {
  v->position = (float4)(v->in.position.x + 0.0625f * (float)v->instance_id, v->in.position.yz, 1.0f);
  v->out.instance = v->instance_id;
}
void fragment(clr_fragment* f) {
  f->out.color = f->front_facing ? (float4)(0.9f, 0.5f, 0.1f, 1.0f) : (float4)(0.2f, 0.6f, 1.0f, 1.0f);
  f->out.ids = (uint4)(f->primitive_id, f->front_facing ? 1u : 0u, f->in.instance, 0u);
}
)",
                             R"(#version 450 core
in vec3 position;
flat out uint v_instance;
void main() {
  gl_Position = vec4(position.x + 0.0625 * float(gl_InstanceID), position.yz, 1.0);
  v_instance = uint(gl_InstanceID);
}
)",
                             R"(#version 450 core
flat in uint v_instance;
layout(location = 0) out vec4 color;
layout(location = 1) out uvec4 ids;
void main() {
  color = gl_FrontFacing ? vec4(0.9, 0.5, 0.1, 1.0) : vec4(0.2, 0.6, 1.0, 1.0);
  ids = uvec4(uint(gl_PrimitiveID), gl_FrontFacing ? 1u : 0u, v_instance, 0u);
}
)",
                             "facing");
  return program;
}

using FacingDrawCase = std::tuple<Topology, CullMode, FrontFace>;

class FacingTest : public ::testing::TestWithParam<FacingDrawCase> {};

// Random triangles of both windings on the 1/256-pixel grid (so that both renderers snap them
// alike), read as a list, a strip or a fan, two instances.
TEST_P(FacingTest, FrontFacingAndPrimitiveIdMatchGl) {
  constexpr int kSize = 64;
  const auto [topology, cull, front_face] = GetParam();
  const Rect window{0, 0, kSize, kSize};
  const io::Mesh triangles = window_to_ndc(random_window_triangles(40, 3, {2, 2, 56, 60}, 30), window);
  std::vector<Vertex> vertices;
  for (std::size_t v = 0; v < triangles.vertex_count(); ++v) {
    vertices.push_back({{triangles.positions[3 * v], triangles.positions[3 * v + 1], 0}, {}});
  }
  const ColoredMesh mesh(vertices, triangles.indices);
  DualFramebuffer target(kSize, kSize, {Format::RGBA8, Format::RGBA32UI}, false);
  target.clear({0, 0, 0, 1});
  DrawState state;
  state.topology = topology;
  state.cull = cull;
  state.front_face = front_face;
  state.depth_test = false;
  DualDraw draw = mesh.draw_positions(facing_program(), state);
  draw.instance_count = 2;
  target.draw(draw);
  EXPECT_TRUE(target.matches());
  EXPECT_GT(distinct_texels(target.color(1).gl.read(), 16), 10u);
}

INSTANTIATE_TEST_SUITE_P(StateConformance, FacingTest,
                         ::testing::Combine(::testing::Values(Topology::TriangleList, Topology::TriangleStrip,
                                                              Topology::TriangleFan),
                                            ::testing::Values(CullMode::None, CullMode::Back, CullMode::Front),
                                            ::testing::Values(FrontFace::CounterClockwise, FrontFace::Clockwise)),
                         [](const auto& info) {
                           return name_of(std::get<0>(info.param)) + name_of(std::get<1>(info.param)) +
                                  name_of(std::get<2>(info.param));
                         });

struct ViewportCase {
  std::string name;
  Rect viewport;  // empty: the whole window
  bool scissor_test;
  Rect scissor;
};

class ViewportTest : public ::testing::TestWithParam<ViewportCase> {};

// Surfaces in perspective through a viewport (offset, not square, or reaching out of the window)
// and a scissor rectangle, with a user program.
TEST_P(ViewportTest, PerspectiveSurfacesMatchGl) {
  constexpr int kWidth = 64, kHeight = 48;
  DualFramebuffer target(kWidth, kHeight, {Format::RGBA8});
  target.clear({0.1f, 0.1f, 0.1f, 1}, 1.0f);
  const ColoredMesh scene = QuadList()
                                .add({Vec3{-2, 0, 2}, {2, 0, 2}, {-2, 0, -2}, {2, 0, -2}}, Rgba{0.8f, 0.2f, 0.1f, 1})
                                .add({Vec3{-1.5f, -0.5f, 0}, {1, -0.5f, 0}, {-1.5f, 1.2f, 0}, {1, 1.2f, 0}},
                                     std::array<Rgba, 4>{Rgba{0.1f, 0.9f, 0.3f, 1}, {1, 0.4f, 1, 0.5f},
                                                         {0.2f, 0.4f, 1, 0.25f}, {1, 1, 0.5f, 1}})
                                .mesh();
  const ViewportCase& c = GetParam();
  DualProgram& program = mvp_flat_color_program();
  const Rect viewport = c.viewport.width ? c.viewport : Rect{0, 0, kWidth, kHeight};
  program.set("mvp", perspective_mvp({1.5f, 2.0f, 3.0f}, static_cast<float>(viewport.width) / viewport.height));
  DrawState state;
  state.viewport = c.viewport;
  state.scissor_test = c.scissor_test;
  state.scissor = c.scissor;
  target.draw(scene.draw(program, state));
  EXPECT_GE(distinct_texels(target.color(0).gl.read(), 4), 3u);  // the clear, the ground and the quad at least
  EXPECT_TRUE(target.color_matches(0));
  EXPECT_TRUE(target.depth_matches(kInterpolatedDepthTolerance));
}

INSTANTIATE_TEST_SUITE_P(StateConformance, ViewportTest,
                         ::testing::Values(ViewportCase{"WholeWindow", {}, false, {}},
                                           ViewportCase{"OffsetViewport", {9, 5, 41, 37}, false, {}},
                                           ViewportCase{"Scissor", {}, true, {12, 10, 30, 23}},
                                           ViewportCase{"ViewportBeyondTheWindowAndScissor", {-20, 6, 100, 70}, true,
                                                        {5, 3, 50, 40}}),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace clraster::test
