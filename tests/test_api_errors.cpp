// The library's answer to arguments it cannot accept: a clraster::InvalidArgument (DeviceError for
// devices) with a one-line message naming the offending value, thrown before anything is rendered,
// so that a rejected draw leaves the framebuffer as it was. And the one bad input that is not an
// error: non-finite vertex coordinates, whose triangles are dropped, counted, and nothing else.
#include "io/procedural.hpp"
#include "support/error_expectations.hpp"
#include "support/test_support.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <cstdlib>
#include <limits>
#include <optional>
#include <ostream>
#include <span>
#include <string>
#include <string_view>
#include <typeinfo>
#include <vector>

namespace clraster::test {
namespace {

// ---- Contexts and framebuffers -----------------------------------------------------------------

TEST(ContextOptions, MemoryCapBelowTheMinimumIsRejected) {
  for (const std::size_t cap : {kMinMemoryCap - 1, std::size_t{1000}}) {
    EXPECT_TRUE(throws([&] { Context context(ContextOptions{.memory_cap = cap}); }, {std::to_string(cap)}));
  }
  EXPECT_EQ(Context(ContextOptions{.memory_cap = kMinMemoryCap}).options().memory_cap, kMinMemoryCap);
}

TEST(ContextOptions, TileSizesOtherThan8_16_32AreRejected) {
  for (const int size : {1, 4, 12, 24, 64, -16}) {
    EXPECT_TRUE(throws([&] { Context context(ContextOptions{.tile_size = size}); }, {std::to_string(size)}));
  }
  for (const int size : {8, 16, 32}) EXPECT_EQ(Context(ContextOptions{.tile_size = size}).options().tile_size, size);
}

// The default leaves the tile size to the context, which takes it from its work-group shapes: the
// test devices are CPUs (PoCL's and Intel's), whose work-groups hold a 16x16 tile's pixels.
TEST(ContextOptions, DeviceTileSizeFollowsTheWorkGroupShapes) {
  EXPECT_EQ(ContextOptions{}.tile_size, kDeviceTileSize);
  const Context context{ContextOptions{.work_group_shape = WorkGroupShape::Device}};
  ASSERT_EQ(context.device().type, "CPU") << "the tests run on CPU devices";
  EXPECT_EQ(context.options().tile_size, kCpuShapeTileSize);
  EXPECT_EQ(Context(ContextOptions{.work_group_shape = WorkGroupShape::Wide}).options().tile_size, kGpuShapeTileSize);
}

// Sets an environment variable for the life of the object, then puts back what it was.
class ScopedEnvironment {
 public:
  ScopedEnvironment(const char* name, const char* value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    setenv(name, value, 1);
  }
  ~ScopedEnvironment() {
    if (old_) setenv(name_, old_->c_str(), 1);
    else unsetenv(name_);
  }
  ScopedEnvironment(const ScopedEnvironment&) = delete;
  ScopedEnvironment& operator=(const ScopedEnvironment&) = delete;

 private:
  const char* name_;
  std::optional<std::string> old_;
};

TEST(ContextOptions, WorkGroupShapeLeftUnsetComesFromTheEnvironment) {
  {
    const ScopedEnvironment wide("CLRASTER_WORK_GROUP_SHAPE", "wide");
    EXPECT_EQ(Context().options().work_group_shape, WorkGroupShape::Wide);
    EXPECT_EQ(Context().options().tile_size, kGpuShapeTileSize);
    EXPECT_EQ(Context(ContextOptions{.work_group_shape = WorkGroupShape::Device}).options().work_group_shape,
              WorkGroupShape::Device);
  }
  {
    const ScopedEnvironment device("CLRASTER_WORK_GROUP_SHAPE", "device");
    EXPECT_EQ(Context().options().work_group_shape, WorkGroupShape::Device);
  }
  const ScopedEnvironment sideways("CLRASTER_WORK_GROUP_SHAPE", "sideways");
  EXPECT_TRUE(throws([] { Context context; }, {"CLRASTER_WORK_GROUP_SHAPE='sideways' is neither 'device' nor 'wide'"}));
}

// What the device cannot hold of a program is refused when the program is made, naming the device
// and its limit: uniforms beyond its constant memory, and resources beyond its kernel arguments.
TEST(DeviceLimits, UniformsBeyondTheConstantMemoryAreRejected) {
  Context& context = shared_context();
  const std::size_t limit = context.device().constant_buffer_bytes;
  // Arrays of float16 (64 bytes each, at most 65536 elements an array), together one element more
  // than the device holds (PoCL's limit depends on the machine: 1 MiB takes more than one array).
  const std::size_t elements = limit / 64 + 1;
  const std::size_t per_array = std::min<std::size_t>(elements, 65536);
  const std::size_t arrays = (elements + per_array - 1) / per_array;
  std::string source;
  for (std::size_t i = 0; i < arrays; ++i) {
    source += "clr_uniform(float16, table" + std::to_string(i) + "[" + std::to_string(per_array) + "])\n";
  }
  source += "clr_output(float4, color)\n"
            "void vertex(clr_vertex* v) { v->position = v->uniforms->table0[0].s0123; }\n"
            "void fragment(clr_fragment* f) { f->out.color = (float4)(1.0f); }\n";
  EXPECT_TRUE(throws([&] { Program program(context, source, "big_table.cl"); },
                     {"program big_table.cl's uniforms take " + std::to_string(arrays * per_array * 64) + " bytes",
                      "device " + context.device().name + " has " + std::to_string(limit)}));
}

TEST(DeviceLimits, ResourcesBeyondTheKernelArgumentsAreRejected) {
  Context& context = shared_context();
  // Each texture is one more argument of every stage kernel: 16 bytes at most each.
  const std::size_t textures = context.device().parameter_bytes / 16 + 1;
  std::string source = "clr_output(float4, color)\n";
  for (std::size_t i = 0; i < textures; ++i) source += "clr_texture(t" + std::to_string(i) + ")\n";
  source += "void vertex(clr_vertex* v) { v->position = (float4)(0.0f, 0.0f, 0.0f, 1.0f); }\n"
            "void fragment(clr_fragment* f) { f->out.color = (float4)(1.0f); }\n";
  EXPECT_TRUE(throws([&] { Program program(context, source, "many_textures.cl"); },
                     {"program many_textures.cl cannot run: its kernel", "arguments",
                      "device " + context.device().name + " has " + std::to_string(context.device().parameter_bytes) +
                          " bytes for them"}));
}

TEST(ContextOptions, DeviceThatDoesNotExistIsRejected) {
  const int missing = static_cast<int>(list_devices().size()) + 1000;
  EXPECT_TRUE(throws<DeviceError>([&] { Context context(ContextOptions{.device = missing}); },
                                  {std::to_string(missing)}));
}

struct Size {
  int width, height;
};

void PrintTo(const Size& size, std::ostream* stream) { *stream << size.width << "x" << size.height; }

class FramebufferSizeOutOfRange : public ::testing::TestWithParam<Size> {};

TEST_P(FramebufferSizeOutOfRange, IsRejected) {
  const auto [width, height] = GetParam();
  EXPECT_TRUE(throws([&] { Framebuffer framebuffer(shared_context(), width, height); },
                     {std::to_string(width) + "x" + std::to_string(height)}));
}

INSTANTIATE_TEST_SUITE_P(Sizes, FramebufferSizeOutOfRange,
                         ::testing::Values(Size{0, 10}, Size{10, 0}, Size{-1, 10}, Size{10, -1}, Size{16385, 10},
                                           Size{10, 16385}, Size{std::numeric_limits<int>::min(), 1}),
                         [](const auto& info) {
                           const auto text = [](int side) {
                             return side < 0 ? "Minus" + std::to_string(-std::int64_t{side}) : std::to_string(side);
                           };
                           return text(info.param.width) + "x" + text(info.param.height);
                         });

TEST(FramebufferSize, SidesOf1To16384AreAccepted) {
  for (const Size size : {Size{1, 1}, Size{16384, 1}, Size{1, 16384}}) {
    const Framebuffer framebuffer(shared_context(), size.width, size.height);
    EXPECT_EQ(framebuffer.width(), size.width);
    EXPECT_EQ(framebuffer.height(), size.height);
  }
}

// ---- Vertex buffers ----------------------------------------------------------------------------

TEST(VertexBuffer, PositionsThatAreNotWholeVerticesAreRejected) {
  const std::vector<float> positions(13);
  EXPECT_TRUE(throws([&] { VertexBuffer vertices(shared_context(), positions); },
                     {"vertex positions need three floats per vertex; got 13 floats"}));
}

TEST(VertexBuffer, NormalsOfAnotherLengthThanThePositionsAreRejected) {
  const std::vector<float> positions(9), normals(21);
  EXPECT_TRUE(throws([&] { VertexBuffer vertices(shared_context(), positions, normals); },
                     {"vertex normals need three floats per vertex: 21 floats for 3 vertices"}));
}

// ---- Draws ---------------------------------------------------------------------------------------

// Checks that drawing `call` into `framebuffer` throws InvalidArgument mentioning `subjects` and
// leaves its colour and depth as they were.
::testing::AssertionResult rejected_without_change(Framebuffer& framebuffer, const DrawCall& call,
                                                   const std::vector<std::string_view>& subjects) {
  const Image colour_before = framebuffer.read_color();
  const std::vector<float> depth_before = framebuffer.read_depth();
  ::testing::AssertionResult result = throws([&] { framebuffer.draw(call); }, subjects);
  if (!result) return result;
  if (::testing::AssertionResult same = images_match(framebuffer.read_color(), colour_before, kExact); !same) {
    return ::testing::AssertionFailure() << "the rejected draw changed the colour attachment: " << same.message();
  }
  if (framebuffer.read_depth() != depth_before) {
    return ::testing::AssertionFailure() << "the rejected draw changed the depth attachment";
  }
  return result;
}

// A 32x32 framebuffer with a triangle already drawn in it, for draws that must be rejected.
class RejectedDraw : public ::testing::Test {
 protected:
  // Four vertices: a triangle over most of the framebuffer, and a spare one.
  const std::vector<float> positions_{-0.9f, -0.9f, 0.2f, 0.9f, -0.8f, -0.3f, 0.1f, 0.9f, 0.5f, 0.5f, 0.5f, 0.0f};
  const std::vector<float> normals_{1, 0, 0, 0, 1, 0, 0, 0, 1, 0.6f, 0.8f, 0};
  VertexBuffer vertices_{shared_context(), positions_, normals_};
  Framebuffer framebuffer_{shared_context(), 32, 32};

  void SetUp() override {
    framebuffer_.clear({0.2f, 0.3f, 0.4f, 1.0f}, 0.75f);
    framebuffer_.draw({&vertices_, nullptr, 0, 3});
    ASSERT_GT(covered_pixel_count(framebuffer_.read_color()), 100u);
  }

  ::testing::AssertionResult rejected(const DrawCall& call, const std::vector<std::string_view>& subjects) {
    return rejected_without_change(framebuffer_, call, subjects);
  }
};

TEST_F(RejectedDraw, NoVertexBuffer) { EXPECT_TRUE(rejected(DrawCall{}, {"vertex buffer"})); }

struct BadIndex {
  int index_size;  // bytes: 2 or 4
  std::uint32_t index;
};

void PrintTo(const BadIndex& bad, std::ostream* stream) {
  *stream << 8 * bad.index_size << "-bit index " << bad.index;
}

class IndexPastTheVertexBuffer : public RejectedDraw, public ::testing::WithParamInterface<BadIndex> {
 protected:
  // An index buffer of GetParam().index_size bytes per index holding `indices`.
  IndexBuffer index_buffer(const std::vector<std::uint32_t>& indices) {
    if (GetParam().index_size == 4) return IndexBuffer(shared_context(), indices);
    const std::vector<std::uint16_t> narrow(indices.begin(), indices.end());
    return IndexBuffer(shared_context(), narrow);
  }
};

TEST_P(IndexPastTheVertexBuffer, IsRejectedInATriangleList) {
  const IndexBuffer indices = index_buffer({0, 1, 2, 3, GetParam().index, 1, 0, 2, 3});
  ASSERT_EQ(indices.index_size(), GetParam().index_size);
  EXPECT_TRUE(rejected({&vertices_, &indices}, {std::to_string(GetParam().index)}));
}

TEST_P(IndexPastTheVertexBuffer, IsRejectedInAStrip) {
  const IndexBuffer indices = index_buffer({0, 1, 2, 3, GetParam().index});
  DrawCall call{&vertices_, &indices};
  call.state.topology = Topology::TriangleStrip;
  EXPECT_TRUE(rejected(call, {std::to_string(GetParam().index)}));
}

TEST_P(IndexPastTheVertexBuffer, IsIgnoredOutsideTheDrawnRange) {
  const IndexBuffer indices = index_buffer({0, 1, 3, GetParam().index, 2, 3});
  Framebuffer expected(shared_context(), 32, 32);
  expected.clear({0.2f, 0.3f, 0.4f, 1.0f}, 0.75f);
  const IndexBuffer good = index_buffer({0, 1, 2, 0, 1, 3});
  expected.draw({&vertices_, &good});

  EXPECT_NO_THROW(framebuffer_.draw({&vertices_, &indices, 0, 3}));
  EXPECT_TRUE(images_match(framebuffer_.read_color(), expected.read_color(), kExact));
}

INSTANTIATE_TEST_SUITE_P(Indices, IndexPastTheVertexBuffer,
                         ::testing::Values(BadIndex{2, 4}, BadIndex{2, 4099}, BadIndex{2, 65535}, BadIndex{4, 4099},
                                           BadIndex{4, 0xffffffffu}),
                         [](const auto& info) {
                           return "Uint" + std::to_string(8 * info.param.index_size) + "Index" +
                                  std::to_string(info.param.index);
                         });

struct DrawRange {
  const char* name;
  bool indexed;
  std::uint32_t first, count;
  std::vector<std::string_view> subjects;
};

void PrintTo(const DrawRange& range, std::ostream* stream) { *stream << range.name; }

class DrawRangePastTheEnd : public RejectedDraw, public ::testing::WithParamInterface<DrawRange> {};

TEST_P(DrawRangePastTheEnd, IsRejected) {
  // 30 elements either way: 30 indices, or 30 vertices.
  std::vector<std::uint32_t> index_data(30);
  for (std::size_t i = 0; i < index_data.size(); ++i) index_data[i] = static_cast<std::uint32_t>(i % 4);
  const IndexBuffer indices(shared_context(), index_data);
  std::vector<float> vertex_data;
  for (int i = 0; i < 10; ++i) vertex_data.insert(vertex_data.end(), positions_.begin(), positions_.begin() + 9);
  const VertexBuffer vertices(shared_context(), vertex_data);

  const DrawRange& range = GetParam();
  const DrawCall call{range.indexed ? &vertices_ : &vertices, range.indexed ? &indices : nullptr, range.first,
                      range.count};
  EXPECT_TRUE(rejected(call, range.subjects));
}

INSTANTIATE_TEST_SUITE_P(
    Ranges, DrawRangePastTheEnd,
    ::testing::Values(DrawRange{"IndexedFirstPastTheEnd", true, 33, kAllElements, {"33"}},
                      DrawRange{"IndexedCountPastTheEnd", true, 21, 12, {"21", "12"}},
                      DrawRange{"IndexedCountWrappingAround", true, 27, 0xfffffff0u, {"4294967280"}},
                      DrawRange{"VerticesFirstPastTheEnd", false, 31, kAllElements, {"31"}},
                      DrawRange{"VerticesCountPastTheEnd", false, 18, 15, {"18", "15"}},
                      DrawRange{"VerticesCountWrappingAround", false, 3, 0xfffffffdu, {"4294967293"}}),
    [](const auto& info) { return std::string(info.param.name); });

struct BadRect {
  const char* name;
  bool scissor;  // the scissor rectangle (with the scissor test on), else the viewport
  Rect rect;
  const char* value;  // the number the message must name
};

void PrintTo(const BadRect& bad, std::ostream* stream) { *stream << bad.name; }

class RectangleOutOfRange : public RejectedDraw, public ::testing::WithParamInterface<BadRect> {};

TEST_P(RectangleOutOfRange, IsRejected) {
  const BadRect& bad = GetParam();
  DrawCall call{&vertices_};
  (bad.scissor ? call.state.scissor : call.state.viewport) = bad.rect;
  call.state.scissor_test = bad.scissor;
  EXPECT_TRUE(rejected(call, {bad.scissor ? "scissor" : "viewport", bad.value}));
}

INSTANTIATE_TEST_SUITE_P(Rectangles, RectangleOutOfRange,
                         ::testing::Values(BadRect{"ViewportNegativeWidth", false, {0, 0, -7, 32}, "-7"},
                                           BadRect{"ViewportTooWide", false, {0, 0, 16385, 32}, "16385"},
                                           BadRect{"ViewportTooTall", false, {0, 0, 32, 20000}, "20000"},
                                           BadRect{"ViewportFarRight", false, {40000, 0, 32, 32}, "40000"},
                                           BadRect{"ViewportFarBelow", false, {0, -40000, 32, 32}, "-40000"},
                                           BadRect{"ScissorNegativeHeight", true, {0, 0, 32, -3}, "-3"},
                                           BadRect{"ScissorTooWide", true, {0, 0, 16385, 32}, "16385"},
                                           BadRect{"ScissorFarLeft", true, {-50000, 0, 8, 8}, "-50000"}),
                         [](const auto& info) { return std::string(info.param.name); });

TEST_F(RejectedDraw, DepthShadingRangeThatIsNotFiniteAndIncreasing) {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const struct {
    std::array<float, 2> range;
    const char* value;
  } cases[] = {{{7.5f, 2.25f}, "7.5"}, {{3.25f, 3.25f}, "3.25"}, {{nan, 1.0f}, "nan"}, {{0.5f, inf}, "inf"}};
  for (const auto& [range, value] : cases) {
    SCOPED_TRACE(value);
    DrawCall call{&vertices_};
    call.state.shading = Shading::Depth;
    call.state.depth_shading_range = range;
    EXPECT_TRUE(rejected(call, {"depth", value}));
  }
}

TEST_F(RejectedDraw, MatricesThatAreNotFinite) {
  DrawCall call{&vertices_};
  call.state.model_view[13] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(rejected(call, {"model_view has the non-finite value nan at element 13"}));
  call = DrawCall{&vertices_};
  call.state.projection[0] = -std::numeric_limits<float>::infinity();
  EXPECT_TRUE(rejected(call, {"projection has the non-finite value -inf at element 0"}));
}

TEST_F(RejectedDraw, BuffersOfAnotherContext) {
  Context other;
  const VertexBuffer other_vertices(other, positions_, normals_);
  const std::vector<std::uint32_t> index_data{0, 1, 2};
  const IndexBuffer other_indices(other, index_data);
  const IndexBuffer indices(shared_context(), index_data);
  EXPECT_TRUE(rejected({&other_vertices, &indices}, {"vertex buffer", "context"}));
  EXPECT_TRUE(rejected({&vertices_, &other_indices}, {"index buffer", "context"}));
}

TEST(MemoryCap, ADrawItCannotHoldIsRejectedWithoutChange) {
  // 512 x 512 tiles of 8 pixels: the bin entries of one primitive clipped into 7 triangles that
  // each cover every tile, and the tile ranges, alone exceed the smallest cap.
  Context context(ContextOptions{.memory_cap = kMinMemoryCap, .tile_size = 8});
  Framebuffer framebuffer(context, 4096, 4096);
  framebuffer.clear({0.2f, 0.3f, 0.4f, 1.0f}, 0.75f);
  const std::vector<float> positions{-1, -1, 0, 1, -1, 0, 0, 1, 0};
  const VertexBuffer vertices(context, positions);
  EXPECT_TRUE(rejected_without_change(framebuffer, {&vertices},
                                      {"memory cap of 4096 KiB cannot hold one primitive's 1835008 bin entries",
                                       "raise the memory cap or the tile size"}));
}

// ---- Non-finite coordinates: not an error ---------------------------------------------------------

TEST(NonFiniteVertices, DropTheirTrianglesAndCountThemAndTheRestRenders) {
  io::Mesh mesh = io::make_sphere(24, 12, 0.6f);
  const std::size_t good_triangles = mesh.triangle_count();
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  // Finite, but model_view (below) adds x and y: 3e38 + 3e38 overflows to infinity in clip space.
  const std::vector<float> bad_positions{nan, 0, 0, 0, inf, 0, 0, 0, -inf, 3e38f, 3e38f, 0};
  const auto first_bad = static_cast<std::uint32_t>(mesh.vertex_count());
  mesh.positions.insert(mesh.positions.end(), bad_positions.begin(), bad_positions.end());
  mesh.normals.insert(mesh.normals.end(), bad_positions.size(), 0.5f);

  // Each bad vertex with two good ones, and one triangle of bad vertices only, placed among the
  // good triangles: at the start, in the middle and at the end.
  const std::vector<std::uint32_t> good = mesh.indices;
  const std::array<std::uint32_t, 3> bad[] = {{first_bad, 10, 11},
                                              {first_bad + 1, 10, 11},
                                              {first_bad + 2, 10, 11},
                                              {first_bad + 3, 10, 11},
                                              {first_bad, first_bad + 1, first_bad + 2}};
  const auto append = [&](std::span<const std::uint32_t> indices) {
    mesh.indices.insert(mesh.indices.end(), indices.begin(), indices.end());
  };
  const std::size_t half = 3 * (good_triangles / 2);
  mesh.indices.clear();
  append(bad[0]);
  append(bad[1]);
  append(std::span(good).first(half));
  append(bad[2]);
  append(std::span(good).subspan(half));
  append(bad[3]);
  append(bad[4]);
  io::Mesh clean = mesh;
  clean.indices = good;

  DrawState state;
  state.model_view[4] = 1;  // x += y
  state.cull = CullMode::Back;
  const RenderResult with_bad = render_clraster(shared_context(), mesh, state, 96, 64);
  const RenderResult reference = render_clraster(shared_context(), clean, state, 96, 64);

  EXPECT_EQ(with_bad.stats.triangles, good_triangles + 5);
  EXPECT_EQ(with_bad.stats.triangles_dropped, 5u);
  EXPECT_EQ(reference.stats.triangles_dropped, 0u);
  EXPECT_GT(covered_pixel_count(reference.image), 1000u);
  EXPECT_TRUE(images_match(with_bad.image, reference.image, kExact));
}

// A float clear of integer attachments truncates toward zero; values past the integer's range
// saturate and NaN clears to 0, where a plain conversion would be undefined behaviour.
TEST(NonFiniteClearValues, IntegerAttachmentsSaturateAndTakeNanAsZero) {
  Context& context = shared_context();
  Texture signed_texture(context, 1, 1, Format::RGBA32I), unsigned_texture(context, 1, 1, Format::RGBA32UI);
  Framebuffer framebuffer(context, {&signed_texture, &unsigned_texture}, nullptr);
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  const auto texel = [](const Texture& texture, auto type) {
    std::array<decltype(type), 4> value{};
    const std::vector<std::byte> bytes = texture.read();
    EXPECT_EQ(bytes.size(), sizeof(value));
    std::memcpy(value.data(), bytes.data(), std::min(bytes.size(), sizeof(value)));
    return value;
  };
  framebuffer.clear_color({nan, 1e10f, -inf, -3.75f});
  EXPECT_EQ(texel(signed_texture, std::int32_t{}),
            (std::array<std::int32_t, 4>{0, std::numeric_limits<std::int32_t>::max(),
                                         std::numeric_limits<std::int32_t>::min(), -3}));
  EXPECT_EQ(texel(unsigned_texture, std::uint32_t{}), (std::array<std::uint32_t, 4>{0, 0xffffffffu, 0, 0}));
  // The last two: the largest floats below 2^31 and 2^32.
  framebuffer.clear_color({inf, -1e10f, 2147483520.0f, 4294967040.0f});
  EXPECT_EQ(texel(signed_texture, std::int32_t{}),
            (std::array<std::int32_t, 4>{std::numeric_limits<std::int32_t>::max(),
                                         std::numeric_limits<std::int32_t>::min(), 2147483520,
                                         std::numeric_limits<std::int32_t>::max()}));
  EXPECT_EQ(texel(unsigned_texture, std::uint32_t{}),
            (std::array<std::uint32_t, 4>{0xffffffffu, 0, 2147483520u, 4294967040u}));
}

}  // namespace
}  // namespace clraster::test
