// Checks that the OpenGL oracle itself is right: every expected picture here is derived in the test
// from OpenGL's rules (identity matrices, so NDC maps to window coordinates by x_w = (x + 1) * W / 2).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "oracle/gl_renderer.hpp"

namespace {

using clraster::DrawState;
using clraster::Image;
using clraster::kAllElements;
using clraster::oracle::GlMesh;
using clraster::oracle::GlRenderer;
using Rgba = std::array<std::uint8_t, 4>;

Rgba pixel(const Image& image, int x, int row) {
  const auto* p = &image.rgba[(std::size_t(row) * image.width + x) * 4];
  return {p[0], p[1], p[2], p[3]};
}

// Pixel (x, window y) of an image read top row first.
Rgba at_window(const Image& image, int x, int y) { return pixel(image, x, image.height - 1 - y); }

// Exactly the pixels of `rect` (window coordinates) have a non-zero red channel.
void expect_covers_exactly(const Image& image, const clraster::Rect& rect) {
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const bool inside = x >= rect.x && x < rect.x + rect.width && y >= rect.y && y < rect.y + rect.height;
      ASSERT_EQ(at_window(image, x, y)[0] != 0, inside) << "window pixel " << x << ", " << y;
    }
  }
}

int covered_pixels(const Image& image) {
  int covered = 0;
  for (std::size_t i = 0; i < image.rgba.size(); i += 4) covered += image.rgba[i] != 0;
  return covered;
}

// Two counter-clockwise triangles covering [x0, x1] x [y0, y1] at depth z, all with one normal.
GlMesh quad(float x0, float y0, float x1, float y1, float z = 0.0f, std::array<float, 3> normal = {0, 0, 1}) {
  const std::vector<float> positions = {x0, y0, z, x1, y0, z, x1, y1, z, x0, y0, z, x1, y1, z, x0, y1, z};
  std::vector<float> normals;
  for (int i = 0; i < 6; ++i) normals.insert(normals.end(), normal.begin(), normal.end());
  return GlMesh(positions, normals);
}

GlMesh full_screen_quad(float z = 0.0f) { return quad(-1, -1, 1, 1, z); }

DrawState constant(std::array<float, 4> colour) {
  DrawState state;
  state.shading = clraster::Shading::Constant;
  state.base_color = colour;
  return state;
}

// Constant 1/255 added up without depth test: red counts the fragments each pixel received.
DrawState overdraw_counter() {
  DrawState state = constant({1.0f / 255, 0, 0, 0});
  state.blend[0] = clraster::kAdditiveBlend;
  state.depth_test = false;
  return state;
}

TEST(GlOracle, RunsOnMesaOpenGl45) {
  const GlRenderer gl(8, 8);
  EXPECT_NE(gl.renderer().find("4.5"), std::string::npos) << gl.renderer();
  EXPECT_NE(gl.renderer().find("llvmpipe"), std::string::npos) << gl.renderer();
}

TEST(GlOracle, RejectsFramebufferSizesOutsideTheLimits) {
  EXPECT_THROW(GlRenderer(0, 16), clraster::InvalidArgument);
  EXPECT_THROW(GlRenderer(16, 16385), clraster::InvalidArgument);
}

TEST(GlOracle, ClearWritesTheClearColourAndDepth) {
  GlRenderer gl(13, 7);
  gl.clear({51.0f / 255, 102.0f / 255, 204.0f / 255, 1.0f}, 0.375f);
  const Image image = gl.read_color();
  ASSERT_EQ(image.rgba.size(), 13u * 7 * 4);
  for (int row = 0; row < 7; ++row) {
    for (int x = 0; x < 13; ++x) ASSERT_EQ(pixel(image, x, row), (Rgba{51, 102, 204, 255}));
  }
  for (float depth : gl.read_depth()) ASSERT_EQ(depth, 0.375f);
}

TEST(GlOracle, ClearIgnoresTheScissorAndDepthMaskOfEarlierDraws) {
  GlRenderer gl(16, 16);
  gl.clear({0, 0, 0, 1});
  DrawState state = constant({1, 1, 1, 1});
  state.scissor_test = true;
  state.scissor = {0, 0, 4, 4};
  state.depth_write = false;
  gl.draw(full_screen_quad(), 0, kAllElements, state);
  gl.clear({1, 0, 0, 1}, 0.25f);
  EXPECT_EQ(covered_pixels(gl.read_color()), 16 * 16);
  for (float depth : gl.read_depth()) ASSERT_EQ(depth, 0.25f);
}

// Both triangles of the quad share the diagonal through pixel centres (i + 0.5, i + 0.5) when the
// framebuffer is square: each of those must be drawn by exactly one of them.
TEST(GlOracle, ScreenFillingQuadCoversEveryPixelExactlyOnce) {
  for (auto [width, height] : {std::pair{256, 256}, std::pair{100, 37}}) {
    GlRenderer gl(width, height);
    gl.clear({0, 0, 0, 0});
    gl.draw(full_screen_quad(), 0, kAllElements, overdraw_counter());
    const Image image = gl.read_color();
    for (std::size_t i = 0; i < image.rgba.size(); i += 4) {
      ASSERT_EQ(image.rgba[i], 1) << width << "x" << height << ", pixel " << i / 4;
    }
  }
}

TEST(GlOracle, StripsAndFansCoverTheQuadOnce) {
  const std::vector<float> strip = {-1, -1, 0, 1, -1, 0, -1, 1, 0, 1, 1, 0};
  const std::vector<float> fan = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
  for (auto [topology, positions] : {std::pair{clraster::Topology::TriangleStrip, strip},
                                     std::pair{clraster::Topology::TriangleFan, fan}}) {
    GlRenderer gl(32, 32);
    gl.clear({0, 0, 0, 0});
    DrawState state = overdraw_counter();
    state.topology = topology;
    state.cull = clraster::CullMode::Back;  // both triangles of each are front-facing (strip order rule)
    gl.draw(GlMesh(positions), 0, kAllElements, state);
    const Image image = gl.read_color();
    for (std::size_t i = 0; i < image.rgba.size(); i += 4) ASSERT_EQ(image.rgba[i], 1) << "pixel " << i / 4;
  }
}

// A triangle whose vertices sit on quarter pixels, so that no pixel centre (at half pixels) lies on
// an edge: in units of 1/4 pixel, vertices are integers and centres are 4i + 2, and the expected
// coverage follows from exact integer edge functions.
TEST(GlOracle, TriangleCoversExactlyThePixelCentresInsideIt) {
  constexpr int kSize = 256;
  const std::array<std::array<std::int64_t, 2>, 3> quarters = {{{83, 121}, {921, 333}, {357, 971}}};  // CCW

  std::vector<float> positions;
  for (const auto& v : quarters) {
    // window = quarters / 4, NDC = window / (kSize / 2) - 1: exact in float.
    positions.insert(positions.end(), {float(v[0]) / (2 * kSize) - 1, float(v[1]) / (2 * kSize) - 1, 0.0f});
  }
  GlRenderer gl(kSize, kSize);
  gl.clear({0, 0, 0, 1});
  gl.draw(GlMesh(positions), 0, kAllElements, constant({1, 1, 1, 1}));
  const Image image = gl.read_color();

  int expected = 0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const std::int64_t px = 4 * x + 2, py = 4 * y + 2;
      bool inside = true;
      for (int e = 0; e < 3; ++e) {
        const auto& a = quarters[e];
        const auto& b = quarters[(e + 1) % 3];
        const std::int64_t edge = (b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]);
        ASSERT_NE(edge, 0) << "pixel centre on an edge: the test's premise is broken";
        inside = inside && edge > 0;
      }
      expected += inside;
      ASSERT_EQ(at_window(image, x, y)[0] != 0, inside) << "window pixel " << x << ", " << y;
    }
  }
  EXPECT_EQ(covered_pixels(image), expected);
  EXPECT_GT(expected, 10000);  // a large triangle: the comparison above means something
}

TEST(GlOracle, DepthLessKeepsTheNearerQuad) {
  GlRenderer gl(32, 32);
  gl.clear({0, 0, 0, 1});
  const GlMesh far_quad = full_screen_quad(0.5f);
  const GlMesh near_quad = full_screen_quad(-0.5f);
  gl.draw(far_quad, 0, kAllElements, constant({1, 0, 0, 1}));
  gl.draw(near_quad, 0, kAllElements, constant({0, 1, 0, 1}));
  gl.draw(far_quad, 0, kAllElements, constant({1, 0, 0, 1}));  // fails the LESS test everywhere
  const Image image = gl.read_color();
  for (int row = 0; row < 32; ++row) {
    for (int x = 0; x < 32; ++x) ASSERT_EQ(pixel(image, x, row), (Rgba{0, 255, 0, 255}));
  }
  for (float depth : gl.read_depth()) ASSERT_EQ(depth, 0.25f);  // 0.5 * -0.5 + 0.5
}

TEST(GlOracle, ScissorLimitsWrites) {
  GlRenderer gl(64, 64);
  gl.clear({0, 0, 0, 1});
  DrawState state = constant({1, 1, 1, 1});
  state.scissor_test = true;
  state.scissor = {10, 20, 30, 40};  // window x in [10, 40), y in [20, 60)
  gl.draw(full_screen_quad(), 0, kAllElements, state);
  expect_covers_exactly(gl.read_color(), {10, 20, 30, 40});
}

TEST(GlOracle, ViewportMapsNdcToItsRectangle) {
  GlRenderer gl(64, 48);
  gl.clear({0, 0, 0, 1});
  DrawState state = constant({1, 1, 1, 1});
  state.viewport = {8, 4, 16, 32};
  gl.draw(full_screen_quad(), 0, kAllElements, state);
  expect_covers_exactly(gl.read_color(), {8, 4, 16, 32});
}

TEST(GlOracle, CullingFollowsTheWindingAndFrontFace) {
  const GlMesh clockwise(std::vector<float>{-0.5f, -0.5f, 0, 0, 0.5f, 0, 0.5f, -0.5f, 0});
  auto covered_with = [&](clraster::CullMode cull, clraster::FrontFace front) {
    GlRenderer gl(32, 32);
    gl.clear({0, 0, 0, 1});
    DrawState state = constant({1, 1, 1, 1});
    state.cull = cull;
    state.front_face = front;
    gl.draw(clockwise, 0, kAllElements, state);
    return covered_pixels(gl.read_color());
  };
  using clraster::CullMode;
  using clraster::FrontFace;
  const int drawn = covered_with(CullMode::None, FrontFace::CounterClockwise);
  EXPECT_GT(drawn, 0);
  EXPECT_EQ(covered_with(CullMode::Back, FrontFace::CounterClockwise), 0);
  EXPECT_EQ(covered_with(CullMode::Front, FrontFace::CounterClockwise), drawn);
  EXPECT_EQ(covered_with(CullMode::Back, FrontFace::Clockwise), drawn);
  EXPECT_EQ(covered_with(CullMode::Front, FrontFace::Clockwise), 0);
}

TEST(GlOracle, NormalShadingOfAQuadFacingPlusZ) {
  GlRenderer gl(16, 16);
  gl.clear({0, 0, 0, 1});
  gl.draw(full_screen_quad(), 0, kAllElements, DrawState{});  // Normal shading is the default
  const Rgba colour = pixel(gl.read_color(), 5, 9);
  EXPECT_NEAR(colour[0], 128, 1);  // 0.5 * 255 = 127.5
  EXPECT_NEAR(colour[1], 128, 1);
  EXPECT_EQ(colour[2], 255);
  EXPECT_EQ(colour[3], 255);
}

TEST(GlOracle, MeshWithoutNormalsShadesAsZeroNormals) {
  GlRenderer gl(8, 8);
  gl.clear({0, 0, 0, 1});
  gl.draw(GlMesh(std::vector<float>{-1, -1, 0, 3, -1, 0, -1, 3, 0}), 0, kAllElements, DrawState{});
  const Rgba colour = pixel(gl.read_color(), 4, 4);
  EXPECT_NEAR(colour[0], 128, 1);  // Normal shading of a zero normal: grey 0.5
  EXPECT_NEAR(colour[2], 128, 1);
}

// Lambert uses the inverse transpose of model_view: with x scaled by 2, the normal (1, 0, 1) becomes
// (0.5, 0, 1), so k = 0.1 + 0.9 / sqrt(1.25) = 0.905 (model_view itself would give (2, 0, 1), k = 0.50).
TEST(GlOracle, LambertShadingUsesTheInverseTransposeNormalMatrix) {
  GlRenderer gl(16, 16);
  gl.clear({0, 0, 0, 1});
  DrawState state;
  state.shading = clraster::Shading::Lambert;
  state.model_view = {2, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  state.base_color = {1.0f, 0.5f, 0.0f, 0.75f};
  gl.draw(quad(-0.5f, -1, 0.5f, 1, 0, {1, 0, 1}), 0, kAllElements, state);
  const double k = 0.1 + 0.9 / std::sqrt(1.25);
  const Rgba colour = pixel(gl.read_color(), 8, 8);
  EXPECT_NEAR(colour[0], 255 * k, 1);
  EXPECT_NEAR(colour[1], 127.5 * k, 1);
  EXPECT_EQ(colour[2], 0);
  EXPECT_NEAR(colour[3], 191, 1);  // alpha is base_color's, unshaded
}

// A singular model_view (z flattened) has no inverse; its cofactor matrix keeps normal (0, 0, 1) along z,
// so the quad is lit head-on (k = 1), as clraster lights it.
TEST(GlOracle, LambertShadingOfASingularModelViewKeepsNormalDirections) {
  GlRenderer gl(16, 16);
  gl.clear({0, 0, 0, 1});
  DrawState state;
  state.shading = clraster::Shading::Lambert;
  state.model_view = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
  state.base_color = {0.2f, 0.4f, 0.6f, 1.0f};
  gl.draw(full_screen_quad(), 0, kAllElements, state);
  const Rgba colour = pixel(gl.read_color(), 8, 8);
  EXPECT_NEAR(colour[0], 51, 1);
  EXPECT_NEAR(colour[1], 102, 1);
  EXPECT_NEAR(colour[2], 153, 1);
}

// A plane 5 units in front of the camera, depth_shading_range (1, 9): grey 1 - (5 - 1) / 8 = 0.5.
TEST(GlOracle, DepthShadingMapsViewDistanceToGrey) {
  GlRenderer gl(16, 16);
  gl.clear({0, 0, 0, 1});
  DrawState state;
  state.shading = clraster::Shading::Depth;
  state.model_view = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, -5, 1};   // translate z by -5
  state.projection = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0.1f, 0, 0, 0, 0, 1};  // clip z = -0.5
  state.depth_shading_range = {1, 9};
  gl.draw(full_screen_quad(), 0, kAllElements, state);
  const Rgba colour = pixel(gl.read_color(), 3, 12);
  EXPECT_NEAR(colour[0], 128, 1);
  EXPECT_EQ(colour[0], colour[1]);
  EXPECT_EQ(colour[0], colour[2]);
  EXPECT_EQ(colour[3], 255);
}

// Depth is z_ndc * 0.5 + 0.5 at each pixel centre; a plane tilted along y also checks that
// read_depth's rows run top to bottom.
TEST(GlOracle, ReadDepthReturnsThePlanesDepth) {
  constexpr int kSize = 64;
  GlRenderer gl(kSize, kSize);
  gl.clear({0, 0, 0, 1});
  const std::vector<float> tilted = {-1, -1, -0.5f, 1, -1, -0.5f, 1, 1, 0.5f,  // z = y / 2
                                     -1, -1, -0.5f, 1, 1, 0.5f,  -1, 1, 0.5f};
  gl.draw(GlMesh(tilted), 0, kAllElements, constant({1, 1, 1, 1}));
  const std::vector<float> depth = gl.read_depth();
  ASSERT_EQ(depth.size(), std::size_t(kSize) * kSize);
  for (int row = 0; row < kSize; ++row) {
    const double y_ndc = (kSize - 1 - row + 0.5) / (kSize / 2) - 1;  // window y of this row
    const double expected = 0.5 * (0.5 * y_ndc) + 0.5;
    for (int x = 0; x < kSize; ++x) ASSERT_NEAR(depth[row * kSize + x], expected, 1e-6) << "row " << row;
  }
}

TEST(GlOracle, IndexedDrawsUseFirstAndCount) {
  // Two quads, left and right half of the screen, as 16-bit indices into six vertices.
  const std::vector<float> positions = {-1, -1, 0, 0, -1, 0, 1, -1, 0, -1, 1, 0, 0, 1, 0, 1, 1, 0};
  const std::vector<std::uint16_t> indices = {0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4};
  const GlMesh mesh(positions, {}, indices);
  EXPECT_TRUE(mesh.indexed());
  EXPECT_EQ(mesh.index_count(), 12u);
  for (std::uint32_t count : {6u, kAllElements}) {
    GlRenderer gl(32, 16);
    gl.clear({0, 0, 0, 0});
    gl.draw(mesh, 6, count, overdraw_counter());
    const Image image = gl.read_color();
    for (int y = 0; y < 16; ++y) {
      for (int x = 0; x < 32; ++x) ASSERT_EQ(at_window(image, x, y)[0], x >= 16 ? 1 : 0) << x << ", " << y;
    }
  }
}

TEST(GlOracle, RejectsDrawRangesAndIndicesOutsideTheMesh) {
  const std::vector<float> triangle = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  GlRenderer gl(8, 8);
  const GlMesh mesh(triangle);
  EXPECT_THROW(gl.draw(mesh, 4, kAllElements, DrawState{}), clraster::InvalidArgument);
  EXPECT_THROW(gl.draw(mesh, 1, 3, DrawState{}), clraster::InvalidArgument);
  EXPECT_THROW(GlMesh(triangle, {}, std::vector<std::uint32_t>{0, 1, 3}), clraster::InvalidArgument);
  EXPECT_THROW(GlMesh(std::vector<float>{0, 0}), clraster::InvalidArgument);
}

TEST(GlOracle, RejectsEmptyDepthShadingRanges) {
  GlRenderer gl(8, 8);
  DrawState state;
  state.shading = clraster::Shading::Depth;
  state.depth_shading_range = {5, 5};
  EXPECT_THROW(gl.draw(full_screen_quad(), 0, kAllElements, state), clraster::InvalidArgument);
}

TEST(GlOracle, EmptyMeshDrawsNothing) {
  GlRenderer gl(8, 8);
  gl.clear({0, 0, 0, 1});
  const GlMesh empty{std::span<const float>{}};
  EXPECT_EQ(empty.vertex_count(), 0u);
  gl.draw(empty, 0, kAllElements, DrawState{});
  EXPECT_EQ(covered_pixels(gl.read_color()), 0);
}

TEST(GlOracle, GlErrorsThrowWithTheirName) {
  GlRenderer gl(8, 8);
  DrawState state;
  state.viewport = {0, 0, -4, 8};  // a negative viewport width is GL_INVALID_VALUE
  try {
    gl.draw(full_screen_quad(), 0, kAllElements, state);
    FAIL() << "expected a clraster::Error";
  } catch (const clraster::Error& error) {
    EXPECT_NE(std::string(error.what()).find("GL_INVALID_VALUE"), std::string::npos) << error.what();
  }
}

}  // namespace
