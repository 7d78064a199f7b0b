// Image conformance against OpenGL: procedural scenes drawn by clraster and by the oracle (Mesa's
// llvmpipe), each given the same object-space meshes and the same DrawState, and compared pixel by
// pixel. Scenes in perspective are held to the issue's thresholds (kNormalShading); scenes whose
// vertices sit on the 1/256-pixel grid under identity matrices must match exactly.
#include "io/camera.hpp"
#include "io/procedural.hpp"
#include "support/test_support.hpp"

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <array>
#include <limits>
#include <map>
#include <ostream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace clraster::test {
namespace {

constexpr int kWidth = 320;
constexpr int kHeight = 240;

// Names for parameterized test cases.
std::string name_of(Shading shading) {
  const char* const names[] = {"Normal", "Lambert", "Depth", "Constant"};
  return names[static_cast<int>(shading)];
}
std::string name_of(CullMode cull) {
  const char* const names[] = {"CullNone", "CullBack", "CullFront"};
  return names[static_cast<int>(cull)];
}
std::string name_of(FrontFace front) { return front == FrontFace::CounterClockwise ? "FrontCcw" : "FrontCw"; }
std::string name_of(CompareFunc function) {
  const char* const names[] = {"Never", "Less", "Equal", "LessEqual", "Greater", "NotEqual", "GreaterEqual", "Always"};
  return names[static_cast<int>(function)];
}
std::string name_of(IndexFormat format) {
  const char* const names[] = {"Indices32", "Indices16", "NonIndexed"};
  return names[static_cast<int>(format)];
}

// What `camera` sees in a width x height picture, as a draw's state: its matrices, and Depth
// shading's range spanning its near to its far plane.
DrawState view_state(const io::Camera& camera, int width, int height, Shading shading = Shading::Normal) {
  DrawState state;
  state.shading = shading;
  state.model_view = io::to_mat4(io::view_matrix(camera));
  state.projection = io::to_mat4(io::projection_matrix(camera, static_cast<float>(width) / height));
  state.base_color = {0.9f, 0.6f, 0.3f, 1.0f};
  state.depth_shading_range = {camera.near_plane, camera.far_plane};
  return state;
}

// A sphere with a tilted torus through it and a box beside them, on a rolling terrain that runs
// out of the picture: curved and flat surfaces, silhouettes and intersections.
const io::Mesh& objects_on_terrain() {
  static const io::Mesh scene = [] {
    io::Mesh torus = io::make_torus(48, 24, 1.0f, 0.3f);
    io::transform(torus, glm::rotate(glm::mat4(1), 1.1f, glm::vec3(1, 0, 0.4f)));
    io::Mesh terrain = io::make_terrain(48, 48, 8, 8, 0.4f, 7);
    io::transform(terrain, glm::translate(glm::mat4(1), glm::vec3(0, -1.3f, 0)));
    return io::merge({io::make_sphere(48, 24, 0.8f), torus, io::make_box({0.9f, -1.2f, -1.6f}, {1.7f, -0.2f, -0.8f}),
                      terrain});
  }();
  return scene;
}

// The camera framing the objects (not the whole terrain, which reaches past the near and far planes).
io::Camera objects_camera(int width, int height) {
  return io::fit_camera({{0, -0.3f, 0}, 2.0f}, static_cast<float>(width) / height);
}

DrawState objects_view(int width, int height, Shading shading = Shading::Normal) {
  return view_state(objects_camera(width, height), width, height, shading);
}

// The square [-1, 1]^2 at depth z, facing +z: with identity matrices, the whole viewport.
io::Mesh screen_quad(float z) {
  io::Mesh quad = io::make_plane(1, 1, 2, 2);
  io::transform(quad, glm::translate(glm::mat4(1), glm::vec3(0, 0, z)));
  return quad;
}

DrawState constant(std::array<float, 4> colour) {
  DrawState state;
  state.shading = Shading::Constant;
  state.base_color = colour;
  return state;
}

// Renders the draws with both renderers, holds clraster to the oracle's picture, which must show
// something (two black pictures would prove nothing), and returns clraster's. Several draws are
// also drawn as one frame, which must give the same picture, bit for bit.
Image expect_matches_gl(const std::vector<SceneDraw>& draws, int width, int height, const Tolerance& tolerance,
                        Context& context = shared_context()) {
  const Image reference = render_scene_gl(draws, width, height);
  if (covered_pixel_count(reference) == 0) {
    ADD_FAILURE() << "OpenGL drew nothing: the scene does not test anything";
    return {};
  }
  Image result = render_scene_clraster(context, draws, width, height);
  EXPECT_TRUE(images_match(result, reference, tolerance));
  if (draws.size() > 1) {
    EXPECT_TRUE(images_match(render_scene_clraster(context, draws, width, height, Submission::Frame), result, kExact))
        << "the draws as one frame";
  }
  return result;
}

// ---- Shading ------------------------------------------------------------------------------------

class ShadingModeTest : public ::testing::TestWithParam<Shading> {};

TEST_P(ShadingModeTest, ObjectsOnATerrainMatchGl) {
  expect_matches_gl({{&objects_on_terrain(), objects_view(kWidth, kHeight, GetParam())}}, kWidth, kHeight,
                    kNormalShading);
}

INSTANTIATE_TEST_SUITE_P(Conformance, ShadingModeTest,
                         ::testing::Values(Shading::Normal, Shading::Lambert, Shading::Depth, Shading::Constant),
                         [](const auto& info) { return name_of(info.param); });

// Without a depth test the last triangle drawn at a pixel decides its colour: primitive order
// within and across draws, and coverage, all exact.
TEST(Conformance, ConstantShadingOfGridAlignedTrianglesInSequenceIsExact) {
  const Rect window{0, 0, 256, 128};
  std::vector<io::Mesh> layers;
  for (std::uint64_t seed : {1, 2, 3}) {
    layers.push_back(window_to_ndc(random_window_triangles(300, seed, window, 80), window));
  }
  std::vector<SceneDraw> draws;
  const std::array<float, 4> colours[] = {{1, 0.25f, 0, 1}, {0, 1, 0.5f, 1}, {0.5f, 0, 1, 1}};
  for (int layer = 0; layer < 3; ++layer) {
    DrawState state = constant(colours[layer]);
    state.depth_test = false;
    draws.push_back({&layers[layer], state});
  }
  expect_matches_gl(draws, window.width, window.height, kExact);
}

// ---- Face culling -------------------------------------------------------------------------------

using CullCase = std::tuple<CullMode, FrontFace>;

class CullingTest : public ::testing::TestWithParam<CullCase> {
 protected:
  DrawState with_culling(DrawState state) const {
    std::tie(state.cull, state.front_face) = GetParam();
    return state;
  }
};

// Random triangles face both ways, and a torus shows its inside through the culled front.
TEST_P(CullingTest, RandomTrianglesAndATorusInPerspectiveMatchGl) {
  const io::Mesh scene = io::merge({io::make_random_triangles(600, 11, {-1.5f, -1.5f, -1.5f}, {1.5f, 1.5f, 1.5f}, 0.8f),
                                    io::make_torus(32, 16, 1.2f, 0.4f)});
  const io::Camera camera = io::fit_camera(io::bounding_sphere(scene), static_cast<float>(kWidth) / kHeight);
  expect_matches_gl({{&scene, with_culling(view_state(camera, kWidth, kHeight))}}, kWidth, kHeight, kNormalShading);
}

// Facing comes from the sign of the snapped area: with the same snapped vertices, the same triangles go.
TEST_P(CullingTest, GridAlignedTrianglesMatchGlExactly) {
  const Rect window{0, 0, 128, 128};
  const io::Mesh triangles = window_to_ndc(random_window_triangles(500, 5, window, 40), window);
  expect_matches_gl({{&triangles, with_culling(overdraw_counter())}}, window.width, window.height, kExact);
}

INSTANTIATE_TEST_SUITE_P(Conformance, CullingTest,
                         ::testing::Combine(::testing::Values(CullMode::None, CullMode::Back, CullMode::Front),
                                            ::testing::Values(FrontFace::CounterClockwise, FrontFace::Clockwise)),
                         [](const auto& info) {
                           return name_of(std::get<0>(info.param)) + name_of(std::get<1>(info.param));
                         });

// ---- Depth test -----------------------------------------------------------------------------------

using DepthCase = std::tuple<CompareFunc, bool>;  // function, depth write

class DepthFunctionTest : public ::testing::TestWithParam<DepthCase> {
 protected:
  DrawState tested(DrawState state) const {
    std::tie(state.depth_func, state.depth_write) = GetParam();
    return state;
  }
};

// Identity matrices and screen-filling quads at z = 0 and z = -0.5 (depths 0.5 and 0.25, exact).
// Two scissored draws leave depth 0.5 (top left), 1 (top right) and 0.25 (bottom); the quad at 0.5
// drawn again with the function under test meets a smaller, an equal and a larger stored depth;
// a last additive pass with EQUAL at 0.5 shows where that draw wrote depth. The same quad is drawn
// each time, so EQUAL compares a depth with itself and does not depend on interpolation rounding.
TEST_P(DepthFunctionTest, LayeredQuadsMatchGlExactly) {
  constexpr int kSize = 64;
  const io::Mesh middle = screen_quad(0.0f);
  const io::Mesh closer = screen_quad(-0.5f);
  DrawState left = constant({1, 0, 0, 1});
  left.scissor_test = true;
  left.scissor = {0, 0, 48, kSize};
  DrawState bottom = constant({0, 1, 0, 1});
  bottom.scissor_test = true;
  bottom.scissor = {0, 0, kSize, 32};
  DrawState marker = constant({0.5f, 0.5f, 0.5f, 1});
  marker.blend[0] = kAdditiveBlend;
  marker.depth_func = CompareFunc::Equal;
  marker.depth_write = false;
  expect_matches_gl({{&middle, left}, {&closer, bottom}, {&middle, tested(constant({0, 0, 1, 1}))}, {&middle, marker}},
                    kSize, kSize, kExact);
}

// The objects, a second sphere sunk into them drawn with the function under test, then the objects
// again with it: EQUAL redraws exactly the surfaces whose depth survived.
TEST_P(DepthFunctionTest, InterpenetratingMeshesMatchGl) {
  const io::Mesh sphere = io::make_sphere(40, 20, 0.9f, {0.7f, -0.5f, 0.6f});
  const DrawState view = objects_view(kWidth, kHeight);
  DrawState lit = view;
  lit.shading = Shading::Lambert;
  DrawState depth_shaded = view;
  depth_shaded.shading = Shading::Depth;
  expect_matches_gl({{&objects_on_terrain(), view}, {&sphere, tested(lit)}, {&objects_on_terrain(), tested(depth_shaded)}},
                    kWidth, kHeight, kNormalShading);
}

INSTANTIATE_TEST_SUITE_P(
    Conformance, DepthFunctionTest,
    ::testing::Combine(::testing::Values(CompareFunc::Never, CompareFunc::Less, CompareFunc::Equal,
                                         CompareFunc::LessEqual, CompareFunc::Greater, CompareFunc::NotEqual,
                                         CompareFunc::GreaterEqual, CompareFunc::Always),
                       ::testing::Bool()),
    [](const auto& info) {
      return name_of(std::get<0>(info.param)) + (std::get<1>(info.param) ? "Write" : "NoWrite");
    });

// ---- Blending -----------------------------------------------------------------------------------

class BlendModeTest : public ::testing::TestWithParam<bool> {};  // additive or replace

// Without a depth test, overlapping draws (and the torus's own front and back) either sum, with
// saturation, or replace each other in primitive order.
TEST_P(BlendModeTest, OverlappingDrawsWithoutDepthTestMatchGl) {
  const io::Mesh left = io::make_sphere(32, 16, 0.9f, {-0.5f, 0, 0});
  const io::Mesh right = io::make_sphere(32, 16, 0.9f, {0.5f, 0.2f, 0});
  io::Mesh torus = io::make_torus(40, 20, 1.1f, 0.35f);
  io::transform(torus, glm::rotate(glm::mat4(1), 0.8f, glm::vec3(1, 0, 0)));
  const auto blended = [&](Shading shading, std::array<float, 4> colour) {
    DrawState state = objects_view(kWidth, kHeight, shading);
    state.base_color = colour;
    state.depth_test = false;
    if (GetParam()) state.blend[0] = kAdditiveBlend;
    return state;
  };
  expect_matches_gl({{&left, blended(Shading::Constant, {0.5f, 0.2f, 0.1f, 1})},
                     {&right, blended(Shading::Constant, {0.1f, 0.4f, 0.3f, 1})},
                     {&torus, blended(Shading::Normal, {})}},
                    kWidth, kHeight, kNormalShading);
}

INSTANTIATE_TEST_SUITE_P(Conformance, BlendModeTest, ::testing::Bool(),
                         [](const auto& info) { return std::string(info.param ? "Additive" : "Replace"); });

// ---- Viewport and scissor -----------------------------------------------------------------------

DrawState in_viewport(const Rect& viewport, Shading shading = Shading::Normal) {
  DrawState state = objects_view(viewport.width, viewport.height, shading);
  state.viewport = viewport;
  return state;
}

TEST(Conformance, ViewportWithAnOffsetMatchesGl) {
  expect_matches_gl({{&objects_on_terrain(), in_viewport({37, 21, 200, 150})}}, kWidth, kHeight, kNormalShading);
}

// Pixels of the viewport outside the framebuffer are not written, and do not shift the rest.
TEST(Conformance, ViewportReachingPastTheFramebufferMatchesGl) {
  expect_matches_gl({{&objects_on_terrain(), in_viewport({-90, 130, 300, 200})}}, kWidth, kHeight, kNormalShading);
}

TEST(Conformance, ScissorLimitsWritesToItsRectangleAsGl) {
  DrawState state = in_viewport({20, 10, 280, 210});
  state.scissor_test = true;
  state.scissor = {53, 31, 111, 147};
  expect_matches_gl({{&objects_on_terrain(), state}}, kWidth, kHeight, kNormalShading);
}

// One frame, four viewports: each quadrant its own view and shading, on an odd-sized framebuffer.
TEST(Conformance, FourViewportsInOneFrameMatchGl) {
  const int width = 301, height = 223;
  const Rect quadrants[] = {{0, 0, 150, 111}, {150, 0, 151, 111}, {0, 111, 150, 112}, {150, 111, 151, 112}};
  const Shading shadings[] = {Shading::Normal, Shading::Lambert, Shading::Depth, Shading::Constant};
  std::vector<SceneDraw> draws;
  for (int i = 0; i < 4; ++i) draws.push_back({&objects_on_terrain(), in_viewport(quadrants[i], shadings[i])});
  expect_matches_gl(draws, width, height, kNormalShading);
}

// Grid-aligned triangles placed in an offset viewport (partly off the framebuffer) and scissored:
// the viewport transform and the writable rectangle, exactly.
TEST(Conformance, GridAlignedViewportAndScissorAreExact) {
  const Rect viewport{-13, 9, 128, 64};
  const io::Mesh triangles = window_to_ndc(random_window_triangles(400, 8, viewport, 30), viewport);
  DrawState state = overdraw_counter();
  state.viewport = viewport;
  state.scissor_test = true;
  state.scissor = {5, 3, 60, 50};
  DrawState beyond_the_corner = state;  // a scissor reaching past the framebuffer's corner
  beyond_the_corner.scissor = {-20, 40, 70, 100};
  expect_matches_gl({{&triangles, state}, {&triangles, beyond_the_corner}}, 97, 61, kExact);
}

// ---- Topologies, index formats, sub-ranges ------------------------------------------------------

// A terrain with rows of vertices for strips and fans.
struct TerrainGrid {
  io::Mesh mesh;
  GridVertices vertices;
};

const TerrainGrid& terrain_grid() {
  static const TerrainGrid grid = [] {
    TerrainGrid g;
    g.mesh = io::make_terrain(40, 30, 4, 3, 0.5f, 3);
    g.vertices = grid_vertices(g.mesh, {0, 0, -1});
    return g;
  }();
  return grid;
}

io::Mesh with_indices(const io::Mesh& mesh, std::vector<std::uint32_t> indices) {
  io::Mesh result = mesh;
  result.indices = std::move(indices);
  return result;
}

class TopologyTest : public ::testing::TestWithParam<IndexFormat> {
 protected:
  DrawState view(Topology topology, Shading shading = Shading::Normal) const {
    io::Camera camera;  // from above the terrain, which fills most of the picture
    camera.eye = {0.4f, 2.6f, 3.0f};
    camera.target = {0, -0.2f, 0};
    camera.near_plane = 1;
    camera.far_plane = 8;
    DrawState state = view_state(camera, kWidth, kHeight, shading);
    state.topology = topology;
    return state;
  }
};

// The whole grid as one strip whose bands are joined by triangles without area. Back faces are
// culled: a strip whose every other triangle lost its winding would show holes.
TEST_P(TopologyTest, OneStripOverTheWholeGridMatchesGl) {
  const io::Mesh mesh = with_indices(terrain_grid().mesh, grid_strip(terrain_grid().vertices));
  DrawState state = view(Topology::TriangleStrip);
  state.cull = CullMode::Back;
  expect_matches_gl({{&mesh, state, GetParam()}}, kWidth, kHeight, kNormalShading);
}

// Every other band, each drawn alone from the bands laid end to end after one padding index: `first`
// and `count` choose a band, and its triangles alternate from its own (odd) first element, as back-face
// culling shows.
TEST_P(TopologyTest, StripsDrawnBandByBandWithFirstAndCountMatchGl) {
  const GridVertices& grid = terrain_grid().vertices;
  std::vector<std::uint32_t> bands = {0};
  for (int row = 0; row + 1 < grid.rows; ++row) {
    const std::vector<std::uint32_t> band = band_strip(grid, row);
    bands.insert(bands.end(), band.begin(), band.end());
  }
  const io::Mesh mesh = with_indices(terrain_grid().mesh, bands);
  const auto band_length = static_cast<std::uint32_t>(2 * grid.columns);
  std::vector<SceneDraw> draws;
  for (int row = 1; row + 1 < grid.rows; row += 2) {
    DrawState state = view(Topology::TriangleStrip, row % 4 == 1 ? Shading::Normal : Shading::Lambert);
    state.cull = CullMode::Back;
    draws.push_back({&mesh, state, GetParam(), 1 + row * band_length, band_length});
  }
  expect_matches_gl(draws, kWidth, kHeight, kNormalShading);
}

// The grid's border as a fan around its middle vertex, whole, then from sub-ranges: a `count` that
// stops part way, and a `first` that makes a border vertex the centre.
TEST_P(TopologyTest, FansAroundTheGridMatchGl) {
  const GridVertices& grid = terrain_grid().vertices;
  std::vector<std::uint32_t> fan = {grid.at(grid.columns / 2, grid.rows / 2)};
  for (int column = 0; column < grid.columns; ++column) fan.push_back(grid.at(column, 0));
  for (int row = 1; row < grid.rows; ++row) fan.push_back(grid.at(grid.columns - 1, row));
  for (int column = grid.columns - 2; column >= 0; --column) fan.push_back(grid.at(column, grid.rows - 1));
  for (int row = grid.rows - 2; row >= 0; --row) fan.push_back(grid.at(0, row));
  const io::Mesh mesh = with_indices(terrain_grid().mesh, fan);
  const auto length = static_cast<std::uint32_t>(fan.size());

  expect_matches_gl({{&mesh, view(Topology::TriangleFan), GetParam()}}, kWidth, kHeight, kNormalShading);
  expect_matches_gl({{&mesh, view(Topology::TriangleFan), GetParam(), 0, length / 2},
                     {&mesh, view(Topology::TriangleFan, Shading::Depth), GetParam(), 30, 50}},
                    kWidth, kHeight, kNormalShading);
}

// The objects' triangle list in three sub-ranges, one state each, cutting across the meshes; the
// second ends in two indices of a triangle it does not finish, and a last draw of two indices draws
// nothing.
TEST_P(TopologyTest, TriangleListSubRangesMatchGl) {
  const io::Mesh& scene = objects_on_terrain();
  const auto third = static_cast<std::uint32_t>(scene.triangle_count() / 3) * 3;  // indices
  expect_matches_gl({{&scene, objects_view(kWidth, kHeight, Shading::Depth), GetParam(), 0, third},
                     {&scene, objects_view(kWidth, kHeight, Shading::Lambert), GetParam(), third, third + 2},
                     {&scene, objects_view(kWidth, kHeight), GetParam(), 2 * third},
                     {&scene, objects_view(kWidth, kHeight, Shading::Constant), GetParam(), 301, 2}},
                    kWidth, kHeight, kNormalShading);
}

INSTANTIATE_TEST_SUITE_P(Conformance, TopologyTest,
                         ::testing::Values(IndexFormat::Uint32, IndexFormat::Uint16, IndexFormat::None),
                         [](const auto& info) { return name_of(info.param); });

// ---- Framebuffer sizes that are not a multiple of the tile ---------------------------------------

struct Size {
  int width;
  int height;
};

void PrintTo(const Size& size, std::ostream* stream) { *stream << size.width << "x" << size.height; }

class FramebufferSizeTest : public ::testing::TestWithParam<Size> {};

// The same view squeezed into every size, so that even a single row or column crosses the objects.
TEST_P(FramebufferSizeTest, ObjectsOnATerrainMatchGl) {
  const auto [width, height] = GetParam();
  expect_matches_gl({{&objects_on_terrain(), objects_view(kWidth, kHeight)}}, width, height, kNormalShading);
}

TEST_P(FramebufferSizeTest, GridAlignedFragmentCountsAreExact) {
  const auto [width, height] = GetParam();
  const Rect window{0, 0, width, height};
  const io::Mesh triangles =
      window_to_ndc(random_window_triangles(400, 21, window, static_cast<float>(std::max(width, height))), window);
  expect_matches_gl({{&triangles, overdraw_counter()}}, width, height, kExact);
}

INSTANTIATE_TEST_SUITE_P(Conformance, FramebufferSizeTest,
                         ::testing::Values(Size{97, 61}, Size{1, 1}, Size{1, 300}, Size{300, 1}, Size{1023, 17},
                                           Size{16384, 3}),
                         [](const auto& info) {
                           return std::to_string(info.param.width) + "x" + std::to_string(info.param.height);
                         });

// ---- Tile sizes ------------------------------------------------------------------------------------

// Every tile size the library offers (ContextOptions::tile_size), each in a context of its own: the
// tile size is built into the programs.
class TileSizeTest : public ::testing::TestWithParam<int> {
 protected:
  Context& context() {
    static std::map<int, Context> contexts;
    auto found = contexts.find(GetParam());
    if (found == contexts.end()) {
      ContextOptions options;
      options.tile_size = GetParam();
      found = contexts.emplace(GetParam(), Context(options)).first;
    }
    return found->second;
  }
};

TEST_P(TileSizeTest, ObjectsOnATerrainMatchGl) {
  expect_matches_gl({{&objects_on_terrain(), objects_view(301, 223)}}, 301, 223, kNormalShading, context());
}

TEST_P(TileSizeTest, GridAlignedFragmentCountsAreExact) {
  const Rect window{0, 0, 97, 61};
  const io::Mesh triangles = window_to_ndc(random_window_triangles(1500, 22, window, 25), window);
  expect_matches_gl({{&triangles, overdraw_counter()}}, window.width, window.height, kExact, context());
}

INSTANTIATE_TEST_SUITE_P(Conformance, TileSizeTest, ::testing::Values(8, 16, 32),
                         [](const auto& info) { return "Tile" + std::to_string(info.param); });

// ---- Clipping: near and far planes, w = 0 --------------------------------------------------------

// The eye in the middle of a cloud of triangles: many pass beside and behind it, crossing the near
// plane and w = 0. Culling too must see the facing of what is left after clipping.
TEST(Conformance, CameraAmongRandomTrianglesMatchesGl) {
  const io::Mesh cloud = io::make_random_triangles(3000, 4, {-4, -4, -4}, {4, 4, 4}, 2.5f);
  io::Camera camera;
  camera.eye = {0.1f, 0.2f, 0.3f};
  camera.target = {1, 0.3f, -1};
  camera.near_plane = 0.05f;
  camera.far_plane = 12;
  for (CullMode cull : {CullMode::None, CullMode::Back, CullMode::Front}) {
    SCOPED_TRACE(name_of(cull));
    DrawState state = view_state(camera, kWidth, kHeight);
    state.cull = cull;
    expect_matches_gl({{&cloud, state}}, kWidth, kHeight, kNormalShading);
  }
}

// Looking around from inside a sphere: every triangle of it that the camera sees beside or behind
// itself straddles w = 0.
TEST(Conformance, CameraInsideASphereMatchesGl) {
  const io::Mesh scene = io::merge({io::make_sphere(36, 18, 3.0f), io::make_torus(32, 16, 0.8f, 0.25f)});
  io::Camera camera;
  camera.eye = {0.4f, 0.5f, 1.6f};
  camera.target = {0, 0, 0};
  camera.fov_degrees = 100;
  camera.near_plane = 0.1f;
  camera.far_plane = 10;
  expect_matches_gl({{&scene, view_state(camera, kWidth, kHeight, Shading::Lambert)}}, kWidth, kHeight, kNormalShading);
}

// Standing on the ground: the terrain runs under and behind the eye (near plane, w = 0) and past
// the far plane; Depth shading shows the interpolation of clipped vertices.
TEST(Conformance, TerrainSeenFromJustAboveTheGroundMatchesGl) {
  const io::Mesh terrain = io::make_terrain(80, 80, 40, 40, 1.0f, 9);
  io::Camera camera;
  camera.eye = {0.3f, 1.1f, 0.2f};
  camera.target = {4, 0.6f, -6};
  camera.near_plane = 0.02f;
  camera.far_plane = 14;
  for (Shading shading : {Shading::Depth, Shading::Normal}) {
    SCOPED_TRACE(name_of(shading) + " shading");
    expect_matches_gl({{&terrain, view_state(camera, kWidth, kHeight, shading)}}, kWidth, kHeight, kNormalShading);
  }
}

// The far plane through the middle of the sphere: what lies behind it is cut away.
TEST(Conformance, FarPlaneCuttingThroughTheObjectsMatchesGl) {
  io::Camera camera = objects_camera(kWidth, kHeight);
  camera.far_plane = glm::length(camera.eye - camera.target);
  expect_matches_gl({{&objects_on_terrain(), view_state(camera, kWidth, kHeight, Shading::Depth)}}, kWidth, kHeight,
                    kNormalShading);
}

// Quads lying exactly on the near plane (depth 0) and on the far plane (depth 1), each half the
// screen, are not clipped away; LEQUAL lets the far one pass against the cleared depth of 1.
TEST(Conformance, QuadsExactlyOnTheNearAndFarPlanesAreDrawn) {
  io::Mesh on_near = io::make_plane(1, 1, 1, 2);
  io::transform(on_near, glm::translate(glm::mat4(1), glm::vec3(-0.5f, 0, -1)));
  io::Mesh on_far = io::make_plane(1, 1, 1, 2);
  io::transform(on_far, glm::translate(glm::mat4(1), glm::vec3(0.5f, 0, 1)));
  DrawState state = constant({1, 0.5f, 0.25f, 1});
  state.depth_func = CompareFunc::LessEqual;
  const Image result = expect_matches_gl({{&on_near, state}, {&on_far, state}}, 64, 64, kExact);
  EXPECT_EQ(covered_pixel_count(result), 64u * 64);
}

// Big triangles given in eye space with one or two vertices behind the eye (negative clip w), and
// a different normal at each vertex so that the interpolation of the clipped parts shows.
TEST(Conformance, TrianglesWithVerticesBehindTheEyeMatchGl) {
  io::Mesh mesh;
  mesh.positions = {-1.5f, -1, -4, 1.5f, -1.2f, -4, 0, -0.6f, 3,     // a floor running under the eye
                    0.5f, 0.3f, -3, -4, 1.5f, 2, 3, 2.5f, 2.5f,       // a ceiling fanning out over it
                    -2, -0.5f, -5, -1.2f, 1.5f, -3, -0.4f, 0.2f, 1};  // a wall to the left, passing it
  mesh.normals = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.6f, 0.8f, 0.8f, 0, 0.6f, 0.6f, 0.8f, 0, -1, 0, 0, 0, -1, 0, 0, 0, 1};
  mesh.indices = {0, 1, 2, 3, 4, 5, 6, 7, 8};
  io::Camera camera;  // only for the projection: the eye-space positions need no view matrix
  camera.near_plane = 0.5f;
  camera.far_plane = 10;
  DrawState state = view_state(camera, kWidth, kHeight);
  state.model_view = kIdentity;
  expect_matches_gl({{&mesh, state}}, kWidth, kHeight, kNormalShading);
}

// Random triangles in a slab around the far plane: so many cross it that clipping leaves more
// triangles than the overflow records a chunk is planned with (an eighth of its primitives), and
// the draw is cut into chunks where the clipped triangles fill them. Drawn three
// triangles a draw, whose clipped triangles always fit, they make the same bin pairs and the same
// picture, bit for bit: in order (without a depth test the last triangle drawn at a pixel shows),
// nothing lost or drawn twice at the cuts.
TEST(Conformance, MoreClippedTrianglesThanPlannedForAreDrawnInChunksAsGl) {
  constexpr std::uint32_t kTriangles = 300, kTrianglesPerPiece = 3;
  const io::Mesh mesh = io::make_random_triangles(kTriangles, 4242, {-6, -4.5f, -10.4f}, {6, 4.5f, -9.6f}, 2.5f);
  io::Camera camera;  // only for the projection: the eye-space positions need no view matrix
  camera.near_plane = 0.5f;
  camera.far_plane = 10;
  DrawState state = view_state(camera, kWidth, kHeight);
  state.model_view = kIdentity;
  state.depth_test = false;

  Context& context = shared_context();
  const VertexBuffer vertices(context, mesh.positions, mesh.normals);
  const IndexBuffer indices(context, mesh.indices);
  Framebuffer whole(context, kWidth, kHeight);
  whole.clear({0, 0, 0, 1});
  const DrawStats stats = whole.draw({&vertices, &indices, 0, kAllElements, state});
  EXPECT_GT(stats.chunks, 2u);
  Framebuffer pieces(context, kWidth, kHeight);
  pieces.clear({0, 0, 0, 1});
  std::uint64_t piece_pairs = 0;
  for (std::uint32_t first = 0; first < kTriangles; first += kTrianglesPerPiece) {
    const DrawStats piece = pieces.draw({&vertices, &indices, 3 * first, 3 * kTrianglesPerPiece, state});
    ASSERT_EQ(piece.chunks, 1u);
    piece_pairs += piece.tile_triangle_pairs;
  }
  EXPECT_EQ(stats.tile_triangle_pairs, piece_pairs);
  const Image result = whole.read_color();
  EXPECT_TRUE(images_match(result, pieces.read_color(), kExact));
  EXPECT_TRUE(images_match(result, render_gl(mesh, state, kWidth, kHeight), kNormalShading));
}

// ---- Guard band: triangles far larger than the screen --------------------------------------------

// A ground plane of a few huge cells reaching to the horizon, seen from above it: its triangles
// span millions of pixels and cross the near plane.
TEST(Conformance, HugeGroundPlaneReachingTheHorizonMatchesGl) {
  io::Mesh ground = io::make_plane(6, 6, 2e5f, 2e5f);
  io::transform(ground, glm::rotate(glm::mat4(1), -glm::half_pi<float>(), glm::vec3(1, 0, 0)));
  io::Camera camera;
  camera.eye = {0.3f, 1, 0.7f};
  camera.target = {2, 0.2f, -6};
  camera.near_plane = 0.05f;
  camera.far_plane = 20;
  expect_matches_gl({{&ground, view_state(camera, kWidth, kHeight, Shading::Depth)}}, kWidth, kHeight, kNormalShading);
}

// The triangle (p + s d, p - s d, p + t n): its edge through p along d crosses the screen, the
// rest of it lies s or t away, in normalized device coordinates.
void add_triangle_across_the_screen(io::Mesh& mesh, glm::vec2 p, glm::vec2 d, float s, float t,
                                    std::array<float, 3> z) {
  const glm::vec2 n(d.y, -d.x);
  const glm::vec2 corners[3] = {p + s * d, p - s * d, p + t * n};
  const auto first = static_cast<std::uint32_t>(mesh.vertex_count());
  for (int i = 0; i < 3; ++i) {
    mesh.positions.insert(mesh.positions.end(), {corners[i].x, corners[i].y, z[i]});
    mesh.indices.push_back(first + i);
  }
}

// Triangles reaching 10^5 away in normalized device coordinates (1.6 * 10^7 pixels, eight times
// clraster's guard band), whose edges still cross the screen, with a different normal at each
// vertex: clipping at the guard band must move neither the edges nor the colours interpolated
// between the far-away vertices.
// (Much farther, float positions are themselves pixels apart and no renderer can place the edges.)
TEST(Conformance, TrianglesFarBeyondTheScreenMatchGl) {
  io::Mesh mesh;
  add_triangle_across_the_screen(mesh, {0, 0.2f}, {0.78f, 0.62f}, 1e5f, 5e4f, {0, 0, 0});
  add_triangle_across_the_screen(mesh, {-0.3f, -0.5f}, {0.6f, 0.8f}, 3e3f, 5e3f, {0.5f, -0.5f, 0.2f});
  add_triangle_across_the_screen(mesh, {0.4f, 0.1f}, {-0.28f, 0.96f}, 8e4f, 4e4f, {-0.3f, 0.6f, 0});
  mesh.normals = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0.6f, 0.8f, 0.8f, 0, 0.6f, 0.6f, 0.8f, 0, -1, 0, 0, 0, -1, 0, 0, 0, 1};
  expect_matches_gl({{&mesh, DrawState{}}}, kWidth, kHeight, kNormalShading);
}

// One triangle over ten million pixels across that covers the screen: every pixel drawn once.
TEST(Conformance, ScreenCoveringTriangleDrawsEveryPixelOnce) {
  io::Mesh mesh;
  mesh.positions = {-8e4f, -7e4f, 0, 9e4f, -6e4f, 0, -5e4f, 1e5f, 0};
  mesh.normals.assign(9, 0.0f);
  mesh.indices = {0, 1, 2};
  const Image result = expect_matches_gl({{&mesh, overdraw_counter()}}, kWidth, kHeight, kExact);
  for (std::size_t i = 0; i < result.rgba.size(); i += 4) ASSERT_EQ(result.rgba[i], 1) << "pixel " << i / 4;
}

// ---- Block culling: blocks of primitives outside the view rejected whole (clr_limits.h) -----------

// A fine grid of 250 x 250 cells seen at an angle from close above, far larger than the view: whole
// blocks of its primitives lie beyond each side of the viewport and behind the near plane, and the
// blocks along the view's edges have cells on both sides. Drawn as GL draws it, with 32- and 16-bit
// indices (its 63,001 vertices fit 16 bits), looking one way and then the other, so that blocks
// outside the first view are in the second, in both work-group shapes, whose vertex stages gather
// the codes of each group of slots differently (vertex.cl).
TEST(Conformance, GridMostlyOutsideTheViewMatchesGl) {
  io::Mesh grid = io::make_plane(250, 250, 40, 40);
  io::transform(grid, glm::rotate(glm::mat4(1), -glm::half_pi<float>(), glm::vec3(1, 0, 0)));
  io::Camera camera;
  camera.near_plane = 0.5f;
  camera.far_plane = 8;
  for (WorkGroupShape shape : {WorkGroupShape::Device, WorkGroupShape::Wide}) {
    for (const float side : {1.0f, -1.0f}) {
      camera.eye = {1.5f * side, 1.2f, 3};
      camera.target = {-side, 0, -2};
      for (IndexFormat format : {IndexFormat::Uint32, IndexFormat::Uint16}) {
        SCOPED_TRACE(testing::Message() << "shape " << static_cast<int>(shape) << ", side " << side << ", "
                                        << (format == IndexFormat::Uint32 ? "32" : "16") << "-bit indices");
        SceneDraw draw{&grid, view_state(camera, kWidth, kHeight, Shading::Depth)};
        draw.index_format = format;
        expect_matches_gl({draw}, kWidth, kHeight, kNormalShading, shared_context(shape));
      }
    }
  }
}

// Triangles with a NaN or an infinite vertex are dropped and counted, also where every other vertex
// around them is outside the view, so that their block would otherwise be culled whole: the count
// is the same as where the grid is in view. The program moves the grid without a matrix, so that
// the infinite x stays an infinite x (a matrix multiplies it by zeros into NaNs), outside the same
// side of the view as the rest of its block.
TEST(Conformance, NonFiniteVerticesAreCountedWhereTheirBlockIsOutsideTheView) {
  const Program moved(shared_context(), R"(
clr_attribute(float3, position)
clr_uniform(float, offset)
clr_output(float4, color)
void vertex(clr_vertex* v) { v->position = (float4)(v->in.position.x + v->uniforms->offset, v->in.position.yz, 1.0f); }
void fragment(clr_fragment* f) { f->out.color = (float4)(1.0f, 0.5f, 0.25f, 1.0f); }
)", "moved.cl");
  io::Mesh grid = io::make_plane(64, 64, 2, 2);  // 4,225 vertices, 8,192 triangles: 128 blocks
  // Two vertices far apart in the grid's vertex order, not sharing a triangle, each in 6 triangles.
  const std::uint32_t nan_vertex = 20 * 65 + 20, infinite_vertex = 45 * 65 + 40;
  grid.positions[3 * nan_vertex + 1] = std::numeric_limits<float>::quiet_NaN();
  grid.positions[3 * infinite_vertex] = -std::numeric_limits<float>::infinity();
  const Buffer positions(shared_context(), grid.positions);
  const IndexBuffer indices(shared_context(), grid.indices);
  for (const float offset : {0.0f, -10.0f}) {  // in view, then all of it 10 to the left of the view
    Bindings bindings(moved);
    bindings.set("offset", offset);
    DrawCall call;
    call.program = &moved;
    call.bindings = &bindings;
    call.attributes = {{"position", &positions, AttributeType::Float3}};
    call.indices = &indices;
    Framebuffer target(shared_context(), 64, 48);
    target.clear({0, 0, 0, 1}, 1.0f);
    const DrawStats stats = target.draw(call);
    EXPECT_EQ(stats.triangles_dropped, 12u) << "grid moved by " << offset;
    const std::uint64_t covered = covered_pixel_count(target.read_color());
    if (offset != 0.0f) EXPECT_EQ(covered, 0u);
    else EXPECT_GT(covered, 64u * 48u / 2);
  }
}

// ---- Several draws per frame ----------------------------------------------------------------------

// Draws that change every piece of state between them: nothing of one may leak into the next.
TEST(Conformance, DrawsWithDifferentStatesInOneFrameMatchGl) {
  const io::Mesh& objects = objects_on_terrain();
  const io::Mesh sphere = io::make_sphere(32, 16, 0.6f, {-1.2f, 0.4f, 0.5f});
  const io::Mesh cloud = io::make_random_triangles(300, 6, {-2, -1, -1}, {2, 1.5f, 1}, 0.5f);
  const DrawState view = objects_view(kWidth, kHeight);

  DrawState lit_back_culled = view;
  lit_back_culled.shading = Shading::Lambert;
  lit_back_culled.cull = CullMode::Back;
  DrawState scissored_depth = view;
  scissored_depth.shading = Shading::Depth;
  scissored_depth.scissor_test = true;
  scissored_depth.scissor = {40, 30, 150, 120};
  DrawState additive_cloud = view;
  additive_cloud.shading = Shading::Constant;
  additive_cloud.base_color = {0.1f, 0.15f, 0.2f, 1};
  additive_cloud.blend[0] = kAdditiveBlend;
  additive_cloud.depth_write = false;
  DrawState front_culled_cw = view;
  front_culled_cw.cull = CullMode::Front;
  front_culled_cw.front_face = FrontFace::Clockwise;
  front_culled_cw.depth_func = CompareFunc::LessEqual;
  DrawState small_viewport = objects_view(96, 72, Shading::Lambert);
  small_viewport.viewport = {210, 150, 96, 72};
  // Mirrored and unevenly scaled: Lambert needs the inverse transpose, and culling the window-space
  // winding, which the mirror reverses.
  DrawState mirrored_lit = view;
  mirrored_lit.shading = Shading::Lambert;
  mirrored_lit.cull = CullMode::Back;
  mirrored_lit.model_view = io::to_mat4(io::view_matrix(objects_camera(kWidth, kHeight)) *
                                        glm::scale(glm::translate(glm::mat4(1), {1.5f, 0.5f, 0.6f}), {-0.4f, 1.3f, 0.7f}));

  expect_matches_gl({{&objects, view},
                     {&sphere, lit_back_culled},
                     {&objects, scissored_depth},
                     {&cloud, additive_cloud},
                     {&sphere, front_culled_cw},
                     {&objects, small_viewport},
                     {&sphere, mirrored_lit}},
                    kWidth, kHeight, kNormalShading);
}

}  // namespace
}  // namespace clraster::test
