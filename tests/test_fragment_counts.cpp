// Exact fragment counts. Overdraw pictures (Constant 1/255 added up without a depth test: red counts
// the fragments of each pixel) of triangles whose vertices lie on the 1/256-pixel grid, inside the
// framebuffer, with identity matrices: clraster must draw every pixel as many times as OpenGL does,
// and as many times as OpenGL's rules (REFERENCE.md §2), evaluated exactly here, say it should.
// Closed surfaces must draw each pixel they cover exactly once.
#include "io/procedural.hpp"
#include "support/test_support.hpp"

#include <glm/gtc/matrix_transform.hpp>
#include <glm/vec2.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

namespace clraster::test {
namespace {

// Fragments per pixel of a width x height window, y up.
struct FragmentCounts {
  int width = 0;
  int height = 0;
  std::vector<int> counts;  // [y * width + x]

  FragmentCounts(int w, int h) : width(w), height(h), counts(std::size_t(w) * h) {}
  explicit FragmentCounts(const Image& overdraw) : FragmentCounts(overdraw.width, overdraw.height) {
    for (int y = 0; y < height; ++y) {
      for (int x = 0; x < width; ++x) at(x, y) = overdraw.rgba[(std::size_t(height - 1 - y) * width + x) * 4];
    }
  }
  int& at(int x, int y) { return counts[std::size_t(y) * width + x]; }
  int at(int x, int y) const { return counts[std::size_t(y) * width + x]; }
};

// The fragments of each pixel in a picture, and those it should have, listed where they differ.
::testing::AssertionResult same_counts(const FragmentCounts& actual, const FragmentCounts& expected) {
  std::ostringstream differences;
  int differing = 0;
  for (int y = 0; y < actual.height; ++y) {
    for (int x = 0; x < actual.width; ++x) {
      if (actual.at(x, y) == expected.at(x, y)) continue;
      if (++differing <= 10) {
        differences << "\n  pixel (" << x << ", " << y << "): " << actual.at(x, y) << " fragments, expected "
                    << expected.at(x, y);
      }
    }
  }
  if (differing == 0) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << differing << " pixels drawn a different number of times (window x, y up):"
                                       << differences.str();
}

// A vertex of a window-space mesh snapped to 1/256 pixel: to the nearest, and halfway between two
// to the even one, as llvmpipe rounds (meshes on the 1/256 grid need no rounding).
struct Fixed {
  std::int64_t x, y;
};
Fixed fixed_vertex(const io::Mesh& mesh, std::uint32_t v) {
  const auto snap = [](float coordinate) { return static_cast<std::int64_t>(std::nearbyint(coordinate * 256.0)); };
  return {snap(mesh.positions[3 * std::size_t{v}]), snap(mesh.positions[3 * std::size_t{v} + 1])};
}

// The triangles `topology` makes of the mesh's index sequence, as vertex ids. Their windings do not
// matter here: the rule below is the same for both.
std::vector<std::array<std::uint32_t, 3>> assembled_triangles(const io::Mesh& mesh, Topology topology) {
  const std::vector<std::uint32_t>& i = mesh.indices;
  std::vector<std::array<std::uint32_t, 3>> triangles;
  if (topology == Topology::TriangleList) {
    for (std::size_t k = 0; k + 2 < i.size(); k += 3) triangles.push_back({i[k], i[k + 1], i[k + 2]});
  } else {
    for (std::size_t k = 0; k + 2 < i.size(); ++k) {
      triangles.push_back({topology == Topology::TriangleStrip ? i[k] : i[0], i[k + 1], i[k + 2]});
    }
  }
  return triangles;
}

// What OpenGL's rules give, in exact integers: a pixel is drawn by a triangle when its centre is
// inside, or on an edge that is a left edge (going down, taken counter-clockwise) or a bottom edge
// (horizontal, going right). Triangles without area draw nothing.
FragmentCounts rule_counts(const io::Mesh& window_mesh, Topology topology, int width, int height) {
  FragmentCounts expected(width, height);
  for (const auto& ids : assembled_triangles(window_mesh, topology)) {
    Fixed v[3] = {fixed_vertex(window_mesh, ids[0]), fixed_vertex(window_mesh, ids[1]), fixed_vertex(window_mesh, ids[2])};
    const std::int64_t area = (v[1].x - v[0].x) * (v[2].y - v[0].y) - (v[2].x - v[0].x) * (v[1].y - v[0].y);
    if (area == 0) continue;
    if (area < 0) std::swap(v[1], v[2]);
    // The pixels whose centres (256 i + 128 in 1/256 pixel) the bounding box holds.
    const auto first_pixel = [](std::int64_t lo, int size) {
      return static_cast<int>(std::clamp<std::int64_t>((lo - 128 + 255) >> 8, 0, size));
    };
    const auto last_pixel = [](std::int64_t hi, int size) {
      return static_cast<int>(std::clamp<std::int64_t>((hi - 128) >> 8, -1, size - 1));
    };
    const int x_begin = first_pixel(std::min({v[0].x, v[1].x, v[2].x}), width);
    const int x_end = last_pixel(std::max({v[0].x, v[1].x, v[2].x}), width);
    const int y_begin = first_pixel(std::min({v[0].y, v[1].y, v[2].y}), height);
    const int y_end = last_pixel(std::max({v[0].y, v[1].y, v[2].y}), height);
    for (int y = y_begin; y <= y_end; ++y) {
      for (int x = x_begin; x <= x_end; ++x) {
        const std::int64_t px = 256 * std::int64_t{x} + 128, py = 256 * std::int64_t{y} + 128;
        bool inside = true;
        for (int e = 0; e < 3; ++e) {
          const Fixed a = v[e], b = v[(e + 1) % 3];
          const std::int64_t dx = b.x - a.x, dy = b.y - a.y;
          const std::int64_t edge = dx * (py - a.y) - dy * (px - a.x);
          inside = inside && (edge > 0 || (edge == 0 && (dy < 0 || (dy == 0 && dx > 0))));
        }
        expected.at(x, y) += inside;
      }
    }
  }
  return expected;
}

// Draws the window-space mesh (inside the window) as an overdraw picture with both renderers,
// requires clraster to count exactly what OpenGL counts and what the rules give, and returns the
// counts.
FragmentCounts expect_exact_counts(const io::Mesh& window_mesh, int width, int height,
                                   Topology topology = Topology::TriangleList) {
  const io::Mesh mesh = window_to_ndc(window_mesh, {0, 0, width, height});
  DrawState state = overdraw_counter();
  state.topology = topology;
  const std::vector<SceneDraw> draws = {{&mesh, state}};
  const Image result = render_scene_clraster(shared_context(), draws, width, height);
  EXPECT_TRUE(images_match(result, render_scene_gl(draws, width, height), kExact));
  const FragmentCounts counts(result);
  EXPECT_TRUE(same_counts(counts, rule_counts(window_mesh, topology, width, height)));
  return counts;
}

// ---- Random triangles ---------------------------------------------------------------------------

TEST(FragmentCounts, RandomTrianglesOnTheSubpixelGridMatchGl) {
  const io::Mesh triangles = random_window_triangles(3000, 31, {0, 0, 200, 150}, 30);
  const FragmentCounts counts = expect_exact_counts(triangles, 200, 150);
  EXPECT_GT(*std::max_element(counts.counts.begin(), counts.counts.end()), 5);  // overlapping, as meant
}

// Every vertex is a pixel centre, so edges pass through pixel centres all the time.
TEST(FragmentCounts, TrianglesWithVerticesOnPixelCentresMatchGl) {
  expect_exact_counts(random_window_triangles(2000, 32, {0, 0, 160, 120}, 20, 1.0, 0.5), 160, 120);
}

// Vertices on the 1/512 grid: half of their coordinates lie halfway between two 1/256 positions,
// where snapping must round as OpenGL does. A power-of-two window keeps them exactly halfway on the
// way through normalized device coordinates.
TEST(FragmentCounts, VerticesHalfwayBetweenSubpixelPositionsSnapAsGl) {
  expect_exact_counts(random_window_triangles(2000, 34, {0, 0, 128, 128}, 20, kSubpixel / 2), 128, 128);
}

// Spans of hundreds of pixels: edge functions in 1/256 pixel outgrow 32 bits.
TEST(FragmentCounts, TrianglesSpanningHundredsOfPixelsMatchGl) {
  expect_exact_counts(random_window_triangles(40, 33, {0, 0, 600, 450}, 600), 600, 450);
}

// ---- Closed surfaces: every pixel once ----------------------------------------------------------

constexpr double kSnapMargin = 0.01;  // pixels; snapping moves a vertex by at most 0.0028

// A closed surface whose outline is the convex polygon `outline` (window pixels, counter-clockwise)
// draws no pixel twice, every pixel whose centre is inside by more than snapping can move the
// outline once, and every pixel outside by as much not at all.
::testing::AssertionResult drawn_once_inside(const FragmentCounts& counts, const std::vector<glm::dvec2>& outline) {
  for (int y = 0; y < counts.height; ++y) {
    for (int x = 0; x < counts.width; ++x) {
      const glm::dvec2 centre(x + 0.5, y + 0.5);
      double inside = HUGE_VAL;  // distance to the nearest edge line, negative outside
      for (std::size_t i = 0; i < outline.size(); ++i) {
        const glm::dvec2 a = outline[i], b = outline[(i + 1) % outline.size()];
        const glm::dvec2 d = glm::normalize(b - a);
        inside = std::min(inside, d.x * (centre.y - a.y) - d.y * (centre.x - a.x));
      }
      const int expected = inside > kSnapMargin ? 1 : inside < -kSnapMargin ? 0 : -1;  // -1: 0 or 1
      if (counts.at(x, y) > 1 || (expected >= 0 && counts.at(x, y) != expected)) {
        return ::testing::AssertionFailure() << "pixel (" << x << ", " << y << ") drawn " << counts.at(x, y)
                                             << " times, " << inside << " pixels inside the outline";
      }
    }
  }
  return ::testing::AssertionSuccess();
}

struct GridCase {
  const char* name;
  int cells_x, cells_y;
  float size_x, size_y;  // pixels
  float angle;           // radians, counter-clockwise
  Topology topology;     // TriangleList or TriangleStrip
};

void PrintTo(const GridCase& grid, std::ostream* stream) { *stream << grid.name; }

class WatertightGridTest : public ::testing::TestWithParam<GridCase> {};

// A grid of cells (io::make_plane) turned and moved off the pixel grid, snapped: its triangles share
// every edge and vertex, so together they must cover the rectangle without a gap or a double hit.
TEST_P(WatertightGridTest, DrawsEveryPixelInsideExactlyOnce) {
  constexpr int kWidth = 160, kHeight = 120;
  const GridCase& grid = GetParam();
  io::Mesh mesh = io::make_plane(grid.cells_x, grid.cells_y, grid.size_x, grid.size_y);
  if (grid.topology == Topology::TriangleStrip) mesh.indices = grid_strip(grid_vertices(mesh, {0, 1, 0}));
  const glm::dvec2 centre(kWidth / 2 + 0.3, kHeight / 2 + 0.17);
  const glm::mat4 placement = glm::rotate(glm::translate(glm::mat4(1), glm::vec3(centre, 0)), grid.angle, {0, 0, 1});
  io::transform(mesh, placement);
  snap_to_grid(mesh, kSubpixel);

  std::vector<glm::dvec2> outline;
  for (const auto [u, v] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}) {
    const glm::dvec2 corner(u * grid.size_x / 2.0, v * grid.size_y / 2.0);
    outline.push_back(centre + glm::dvec2(std::cos(grid.angle) * corner.x - std::sin(grid.angle) * corner.y,
                                          std::sin(grid.angle) * corner.x + std::cos(grid.angle) * corner.y));
  }
  EXPECT_TRUE(drawn_once_inside(expect_exact_counts(mesh, kWidth, kHeight, grid.topology), outline));
}

INSTANTIATE_TEST_SUITE_P(FragmentCounts, WatertightGridTest,
                         ::testing::Values(GridCase{"SubPixelCells", 230, 170, 100, 75, 0.3f, Topology::TriangleList},
                                           GridCase{"MultiPixelCells", 9, 7, 130, 95, -0.45f, Topology::TriangleList},
                                           GridCase{"SubPixelCellsAsOneStrip", 130, 90, 90, 70, 0.7f,
                                                    Topology::TriangleStrip},
                                           GridCase{"MultiPixelCellsAsOneStrip", 11, 6, 120, 80, 2.0f,
                                                    Topology::TriangleStrip}),
                         [](const auto& info) { return std::string(info.param.name); });

// A grid with every vertex on a pixel centre: cell edges, horizontal, vertical and diagonal, run
// through rows of pixel centres. The rectangle it covers keeps its left and bottom edges and loses
// its right and top ones: pixels with centres in [x0, x1) x [y0, y1), each drawn once.
TEST(FragmentCounts, GridWithVerticesOnPixelCentresCoversItsHalfOpenRectangleOnce) {
  constexpr int kWidth = 96, kHeight = 64;
  constexpr double x0 = 10.5, y0 = 7.5, x1 = 82.5, y1 = 55.5;  // cells of 8 x 6 pixels
  for (Topology topology : {Topology::TriangleList, Topology::TriangleStrip}) {
    SCOPED_TRACE(topology == Topology::TriangleList ? "list" : "strip");
    io::Mesh mesh = io::make_plane(9, 8, x1 - x0, y1 - y0);
    if (topology == Topology::TriangleStrip) mesh.indices = grid_strip(grid_vertices(mesh, {0, 1, 0}));
    io::transform(mesh, glm::translate(glm::mat4(1), glm::vec3((x0 + x1) / 2, (y0 + y1) / 2, 0)));
    FragmentCounts expected(kWidth, kHeight);
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) expected.at(x, y) = x + 0.5 >= x0 && x + 0.5 < x1 && y + 0.5 >= y0 && y + 0.5 < y1;
    }
    EXPECT_TRUE(same_counts(expect_exact_counts(mesh, kWidth, kHeight, topology), expected));
  }
}

// A closed fan of `rim` triangles around a vertex on a pixel centre: that pixel, touched by every
// triangle, is drawn once, as is every pixel inside. Rim vertices on the 1/256 grid (step
// kSubpixel) or on pixel centres (step 1, offset 0.5).
void expect_fan_drawn_once(glm::dvec2 centre, double radius, int rim, double step, double offset) {
  constexpr int kWidth = 128, kHeight = 96;
  io::Mesh fan;
  std::vector<glm::dvec2> outline;
  const auto add_vertex = [&](glm::dvec2 p) {
    fan.indices.push_back(static_cast<std::uint32_t>(fan.vertex_count()));
    fan.positions.insert(fan.positions.end(), {static_cast<float>(p.x), static_cast<float>(p.y), 0});
    fan.normals.insert(fan.normals.end(), {0, 0, 1});
  };
  add_vertex(centre);
  for (int k = 0; k <= rim; ++k) {  // the first rim vertex again closes the fan
    const double angle = 2 * std::numbers::pi * (k % rim) / rim + 0.1;
    add_vertex(centre + radius * glm::dvec2(std::cos(angle), std::sin(angle)));
  }
  snap_to_grid(fan, step, offset);
  for (int k = 1; k <= rim; ++k) outline.push_back({fan.positions[3 * k], fan.positions[3 * k + 1]});

  const FragmentCounts counts = expect_exact_counts(fan, kWidth, kHeight, Topology::TriangleFan);
  EXPECT_EQ(counts.at(static_cast<int>(centre.x), static_cast<int>(centre.y)), 1);
  EXPECT_TRUE(drawn_once_inside(counts, outline));
}

TEST(FragmentCounts, FanAroundAPixelCentreDrawsEveryPixelInsideOnce) {
  expect_fan_drawn_once({64.5, 48.5}, 40, 96, kSubpixel, 0);
}

TEST(FragmentCounts, FanWithEveryVertexOnAPixelCentreDrawsEveryPixelInsideOnce) {
  expect_fan_drawn_once({61.5, 45.5}, 38, 40, 1, 0.5);
}

// ---- The rule for pixel centres on edges ----------------------------------------------------------

// Pairs of triangles sharing an edge between two pixel centres, in many directions (axis-aligned,
// diagonal, steep, shallow) and both windings: every pixel centre along the shared edge is drawn by
// exactly one of the two.
TEST(FragmentCounts, EdgesThroughPixelCentresAreDrawnByExactlyOneOfTheirTriangles) {
  constexpr int kWidth = 160, kHeight = 96;
  const glm::ivec2 directions[] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}, {1, 1}, {-1, 1}, {2, 1}, {1, -3}, {-3, -2}, {2, 5}};
  io::Mesh pairs;
  std::vector<glm::ivec2> shared_centres;
  for (int i = 0; i < 10; ++i) {
    const glm::ivec2 d = directions[i];
    const glm::ivec2 start(16 + 32 * (i % 5), 20 + 48 * (i / 5)), end = start + 4 * d;
    for (int j = 1; j < 4; ++j) shared_centres.push_back(start + j * d);
    const glm::ivec2 normal(-d.y, d.x), middle = start + 2 * d;
    const glm::ivec2 corners[6] = {start, end, middle + 3 * normal, end, start, middle - 2 * normal};
    for (int c = 0; c < 6; ++c) {
      // i odd: the pair in the other winding.
      const glm::ivec2 p = corners[i % 2 ? 5 - c : c];
      pairs.indices.push_back(static_cast<std::uint32_t>(pairs.vertex_count()));
      pairs.positions.insert(pairs.positions.end(), {p.x + 0.5f, p.y + 0.5f, 0});
      pairs.normals.insert(pairs.normals.end(), {0, 0, 1});
    }
  }
  const FragmentCounts counts = expect_exact_counts(pairs, kWidth, kHeight);
  for (const glm::ivec2 c : shared_centres) EXPECT_EQ(counts.at(c.x, c.y), 1) << "pixel " << c.x << ", " << c.y;
}

// ---- Tiny and degenerate triangles ---------------------------------------------------------------

// Triangles a few 1/256 of a pixel across, far below OCLRaster's 1/256-pixel area cull: one around
// each pixel centre of a block, in varied shapes and both windings, must each draw that pixel; the
// same triangles moved off the centres draw nothing.
TEST(FragmentCounts, TinyTrianglesDrawExactlyThePixelCentresTheyEnclose) {
  constexpr int kWidth = 64, kHeight = 32;
  const std::array<glm::dvec2, 3> shapes[] = {{{{-2, -1}, {2, -1}, {0, 2}}},
                                             {{{3, -2}, {-1, 3}, {-2, -2}}},
                                             {{{-1, 1}, {3, 0}, {-1, -1}}},
                                             {{{0, 1}, {0, -1}, {1, 0}}}};  // centre on a vertical left edge
  io::Mesh tiny;
  FragmentCounts expected(kWidth, kHeight);
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const bool enclosing = y < kHeight / 2;  // the upper half gets them moved by a third of a pixel
      const glm::dvec2 centre = glm::dvec2(x + 0.5, y + 0.5) + (enclosing ? glm::dvec2(0) : glm::dvec2(0.33, 0.2));
      const auto& shape = shapes[(x + 3 * y) % 4];
      for (int c = 0; c < 3; ++c) {
        const glm::dvec2 p = centre + shape[x % 2 ? 2 - c : c] * kSubpixel;
        tiny.indices.push_back(static_cast<std::uint32_t>(tiny.vertex_count()));
        tiny.positions.insert(tiny.positions.end(), {static_cast<float>(p.x), static_cast<float>(p.y), 0});
        tiny.normals.insert(tiny.normals.end(), {0, 0, 1});
      }
      expected.at(x, y) = enclosing;
    }
  }
  snap_to_grid(tiny, kSubpixel);
  EXPECT_TRUE(same_counts(expect_exact_counts(tiny, kWidth, kHeight), expected));
}

// Triangles whose bounding box holds a single pixel centre that they miss: one that a corner's long
// edge passes beside, one with the centre on its top edge, one with it on its right edge, in both
// windings. They draw nothing, as OpenGL's rules say, and culling drops them before binning: the
// draw makes no (tile, triangle) pair.
TEST(FragmentCounts, TrianglesMissingTheOnlyCentreOfTheirBoxAreCulledBeforeBinning) {
  constexpr int kWidth = 48, kHeight = 32;
  const std::array<glm::dvec2, 3> shapes[] = {{{{0.35, -0.25}, {0.35, 0.35}, {-0.25, 0.35}}},  // x + y >= 0.1
                                             {{{-0.3, 0}, {0.3, 0}, {0, -0.3}}},             // top edge y = 0
                                             {{{0, -0.3}, {0, 0.3}, {-0.3, 0}}}};            // right edge x = 0
  io::Mesh missing;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const auto& shape = shapes[(x + y) % 3];
      for (int c = 0; c < 3; ++c) {
        const glm::dvec2 p = glm::dvec2(x + 0.5, y + 0.5) + shape[y % 2 ? 2 - c : c];
        missing.indices.push_back(static_cast<std::uint32_t>(missing.vertex_count()));
        missing.positions.insert(missing.positions.end(), {static_cast<float>(p.x), static_cast<float>(p.y), 0});
        missing.normals.insert(missing.normals.end(), {0, 0, 1});
      }
    }
  }
  snap_to_grid(missing, kSubpixel);
  EXPECT_TRUE(same_counts(expect_exact_counts(missing, kWidth, kHeight), FragmentCounts(kWidth, kHeight)));
  const RenderResult drawn = render_clraster(shared_context(), window_to_ndc(missing, {0, 0, kWidth, kHeight}),
                                             overdraw_counter(), kWidth, kHeight);
  EXPECT_EQ(drawn.stats.triangles, std::uint64_t{kWidth} * kHeight);
  EXPECT_EQ(drawn.stats.tile_triangle_pairs, 0u);
}

// Slivers one 1/256 pixel high on a row of pixel centres, 1 to 6 pixels long (areas of 1/512 to
// 6/512 of a pixel): those resting on the row draw the centres of its bottom edge, [x0, x1); those
// hanging from it, whose edge on the row is a top edge, draw nothing. Triangles with no area at all
// (three points on the row, or one point) draw nothing either.
TEST(FragmentCounts, SliversDrawTheCentresOnTheirBottomEdgeAndZeroAreaTrianglesNothing) {
  constexpr int kWidth = 48, kHeight = 24;
  io::Mesh triangles;
  FragmentCounts expected(kWidth, kHeight);
  const auto add = [&](std::array<glm::dvec2, 3> corners) {
    for (const glm::dvec2 p : corners) {
      triangles.indices.push_back(static_cast<std::uint32_t>(triangles.vertex_count()));
      triangles.positions.insert(triangles.positions.end(), {static_cast<float>(p.x), static_cast<float>(p.y), 0});
      triangles.normals.insert(triangles.normals.end(), {0, 0, 1});
    }
  };
  for (int length = 1; length <= 6; ++length) {
    const double x0 = 2.5 + 7 * (length - 1), x1 = x0 + length;
    const int resting = 2 + 2 * (length % 3), hanging = 10 + length, flat = 18 + length % 3;
    add({{{x0, resting + 0.5}, {x1, resting + 0.5}, {x1, resting + 0.5 + kSubpixel}}});
    add({{{x0, hanging + 0.5}, {x1, hanging + 0.5 - kSubpixel}, {x1, hanging + 0.5}}});
    add({{{x0, flat + 0.5}, {x1, flat + 0.5}, {(x0 + x1) / 2, flat + 0.5}}});
    add({{{x0, flat + 0.5}, {x0, flat + 0.5}, {x0, flat + 0.5}}});
    for (int x = static_cast<int>(x0); x < x1 - 0.5; ++x) expected.at(x, resting) = 1;
  }
  EXPECT_TRUE(same_counts(expect_exact_counts(triangles, kWidth, kHeight), expected));
}

}  // namespace
}  // namespace clraster::test
