// The benchmark behind `clraster bench`, without timing anything: its scenes have the triangles and
// draws they advertise and are built the same every time, tiny-1m's are at most a pixel, the
// cameras frame the scenes as described, the scenes of materials and of views draw as llvmpipe
// does, and the report leaves scenes that failed out of the geometric mean. (tests/test_cli.cpp runs the command
// itself.)
#include "bench/report.hpp"
#include "bench/runner.hpp"
#include "bench/scenes.hpp"
#include "io/camera.hpp"
#include "io/image_io.hpp"
#include "support/mesh_inspection.hpp"
#include "support/test_support.hpp"

#include <nlohmann/json.hpp>

#include <glm/geometric.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace clraster::bench {
namespace {

constexpr int kWidth = 1920;
constexpr int kHeight = 1080;

// Built once per test process: the large ones take a while.
const Scene& scene(const std::string& name) {
  static std::map<std::string, Scene> built;
  auto found = built.find(name);
  if (found == built.end()) found = built.emplace(name, make_scene(name)).first;
  return found->second;
}

// The pixels of `image` that are covered (not black), as a fraction of all.
double coverage(const Image& image) {
  return static_cast<double>(test::covered_pixel_count(image)) / (static_cast<double>(image.width) * image.height);
}

TEST(BenchScenes, NamesInTheirOrder) {
  EXPECT_EQ(scene_names(), (std::vector<std::string>{"model-50k", "terrain-1m", "terrain-4m", "fill-16", "tiny-1m",
                                                     "textured-50k", "materials-256", "engine-glb", "instanced-4k",
                                                     "views-64"}));
  EXPECT_EQ(parse_scene_list(""), scene_names());
  EXPECT_EQ(parse_scene_list("tiny-1m,model-50k"), (std::vector<std::string>{"tiny-1m", "model-50k"}));
  for (const char* list : {"teapot", "model-50k,teapot", "model-50k,", "Model-50k"}) {
    try {
      parse_scene_list(list);
      ADD_FAILURE() << list << ": no error";
    } catch (const InvalidArgument& error) {
      EXPECT_PRED_FORMAT2(::testing::IsSubstring,
                          "(scenes: model-50k, terrain-1m, terrain-4m, fill-16, tiny-1m, textured-50k, "
                          "materials-256, engine-glb, instanced-4k, views-64)",
                          error.what());
    }
  }
  EXPECT_THROW(make_scene("teapot"), InvalidArgument);
}

struct AdvertisedCount {
  const char* name;
  std::uint64_t triangles;  // exactly, as the generator (or the model file) makes them
  std::uint64_t at_least;   // what the scene stands for
  std::uint64_t at_most;
  std::size_t draws;        // a draw per part of a scene of materials
};

class BenchSceneTriangles : public ::testing::TestWithParam<AdvertisedCount> {};

TEST_P(BenchSceneTriangles, AreTheAdvertisedCountInTheAdvertisedDraws) {
  const AdvertisedCount& count = GetParam();
  const Scene& built = scene(count.name);
  EXPECT_EQ(built.name, count.name);
  EXPECT_EQ(built.triangle_count(), count.triangles);
  EXPECT_GE(built.triangle_count(), count.at_least);
  EXPECT_LE(built.triangle_count(), count.at_most);
  EXPECT_EQ(built.draw_count(), count.draws);
  EXPECT_EQ(built.draws_materials(), !built.model.parts.empty());
  // The parts, in index order, cover every triangle once.
  std::uint32_t next = 0;
  for (const io::ModelPart& part : built.model.parts) {
    EXPECT_EQ(part.first_index, next);
    EXPECT_GT(part.index_count, 0u);
    EXPECT_LT(part.material, built.model.materials.size());
    next += part.index_count;
  }
  if (built.draws_materials()) EXPECT_EQ(next, built.model.indices.size());
}

INSTANTIATE_TEST_SUITE_P(
    Scenes, BenchSceneTriangles,
    ::testing::Values(AdvertisedCount{"model-50k", 2 * 500 * 50, 45'000, 55'000, 1},
                      AdvertisedCount{"terrain-1m", 2 * 708 * 708, 1'000'000, 1'100'000, 1},
                      AdvertisedCount{"terrain-4m", 2 * 1415 * 1415, 4'000'000, 4'100'000, 1},
                      AdvertisedCount{"fill-16", 16 * 2, 32, 32, 1},
                      AdvertisedCount{"tiny-1m", 2 * 1024 * 512, 1'000'000, 1'100'000, 1},
                      AdvertisedCount{"textured-50k", 2 * 500 * 50, 45'000, 55'000, 1},
                      AdvertisedCount{"materials-256", 2 * 500 * 50, 45'000, 55'000, 256},
                      AdvertisedCount{"engine-glb", 121'496, 100'000, 150'000, 108},
                      AdvertisedCount{"instanced-4k", 4096 * 1280, 5'000'000, 5'300'000, 1},
                      AdvertisedCount{"views-64", 64 * 2 * 500 * 50, 3'000'000, 3'300'000, 1}),
    [](const auto& info) {
      std::string name = info.param.name;
      std::replace(name.begin(), name.end(), '-', '_');
      return name;
    });

TEST(BenchScenes, TinyTrianglesAreAtMostOnePixelAndAllInView) {
  const Scene& tiny = scene("tiny-1m");
  const glm::dmat4 clip = glm::dmat4(io::projection_matrix(tiny.camera, static_cast<float>(kWidth) / kHeight)) *
                          glm::dmat4(io::view_matrix(tiny.camera));
  // Window coordinates at 1920x1080, as the viewport transform gives them.
  std::vector<glm::dvec2> window(tiny.model.vertex_count());
  for (std::uint32_t v = 0; v < window.size(); ++v) {
    const glm::dvec4 p = clip * glm::dvec4(test::position(tiny.model, v), 1);
    ASSERT_GT(p.w, 0);
    window[v] = {(p.x / p.w + 1) * kWidth / 2, (p.y / p.w + 1) * kHeight / 2};
    ASSERT_TRUE(window[v].x > 0 && window[v].x < kWidth && window[v].y > 0 && window[v].y < kHeight) << "vertex " << v;
  }
  double largest = 0;
  for (std::size_t t = 0; t < tiny.model.triangle_count(); ++t) {
    const glm::dvec2 a = window[tiny.model.indices[3 * t]];
    const glm::dvec2 b = window[tiny.model.indices[3 * t + 1]];
    const glm::dvec2 c = window[tiny.model.indices[3 * t + 2]];
    const double area = std::abs((b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y)) / 2;
    ASSERT_LE(area, 1.0) << "triangle " << t;
    const glm::dvec2 extent = glm::max(glm::max(a, b), c) - glm::min(glm::min(a, b), c);
    ASSERT_LE(std::max(extent.x, extent.y), 1.0) << "triangle " << t;
    largest = std::max(largest, area);
  }
  EXPECT_NEAR(largest, 0.7 * 0.7 / 2, 0.01) << "cells of 0.7 pixel";
}

// The cameras, checked on pictures drawn smaller (the same view at the same aspect).
constexpr int kSmallWidth = 384;
constexpr int kSmallHeight = 216;

Image draw_small(const Scene& drawn) {
  return test::render_clraster(test::shared_context(), drawn.model, drawn.state(kSmallWidth, kSmallHeight), kSmallWidth,
                               kSmallHeight)
      .image;
}

// Whether anything is drawn on the outermost rows and columns of `picture`.
bool touches_edges(const Image& picture) {
  const auto covered = [&](int x, int y) {
    const std::uint8_t* pixel = &picture.rgba[4 * (std::size_t(y) * picture.width + x)];
    return (pixel[0] | pixel[1] | pixel[2]) != 0;
  };
  for (int y = 0; y < picture.height; ++y) {
    if (covered(0, y) || covered(picture.width - 1, y)) return true;
  }
  for (int x = 0; x < picture.width; ++x) {
    if (covered(x, 0) || covered(x, picture.height - 1)) return true;
  }
  return false;
}

// The scene run as the benchmark runs it, at the small size, for one timed frame.
SceneRun run_small(const Scene& drawn) {
  RunOptions options;
  options.width = kSmallWidth;
  options.height = kSmallHeight;
  options.frames = 1;
  return run_scene(drawn, options);
}

TEST(BenchScenes, ModelCoversAThirdToAHalfOfThePictureAndIsFramed) {
  const Image picture = draw_small(scene("model-50k"));
  EXPECT_GE(coverage(picture), 1.0 / 3);
  EXPECT_LE(coverage(picture), 0.5);
  EXPECT_FALSE(touches_edges(picture));
}

TEST(BenchScenes, TerrainFillsThePicture) {
  EXPECT_EQ(coverage(draw_small(scene("terrain-1m"))), 1.0);
  // terrain-4m is the same landscape more finely sampled, from the same camera.
  const Scene& fine = scene("terrain-4m");
  const Scene& coarse = scene("terrain-1m");
  EXPECT_EQ(fine.camera.eye, coarse.camera.eye);
  EXPECT_EQ(fine.camera.target, coarse.camera.target);
  EXPECT_EQ(fine.camera.fov_degrees, coarse.camera.fov_degrees);
  const io::BoundingSphere fine_bounds = io::bounding_sphere(fine.model);
  const io::BoundingSphere coarse_bounds = io::bounding_sphere(coarse.model);
  EXPECT_NEAR(fine_bounds.radius, coarse_bounds.radius, 0.01f);
}

// The textured scene is model-50k's knot and view with texture coordinates and a material, drawn as
// `render --shading material` draws models, and llvmpipe draws the same textured picture (the
// runner's own comparison, at a smaller size: the same view, the texture further minified; a
// picture that left the texture out would differ from llvmpipe's in most pixels).
TEST(BenchScenes, TexturedKnotIsDrawnAsLlvmpipeDrawsIt) {
  const Scene& textured = scene("textured-50k");
  const Scene& plain = scene("model-50k");
  EXPECT_EQ(textured.model.positions, plain.model.positions);
  EXPECT_EQ(textured.model.indices, plain.model.indices);
  EXPECT_EQ(textured.model.texcoords.size(), 2 * textured.model.vertex_count());
  EXPECT_EQ(textured.camera.eye, plain.camera.eye);
  EXPECT_FALSE(plain.draws_materials());
  ASSERT_EQ(textured.model.materials.size(), 1u);
  ASSERT_TRUE(textured.model.materials[0].base_color_texture.has_value());
  const Image texture = io::decode_image(textured.model.materials[0].base_color_texture->encoded, "the texture");
  EXPECT_EQ(texture.width, 1024);
  EXPECT_EQ(texture.height, 1024);

  const SceneRun run = run_small(textured);
  EXPECT_TRUE(run.result.passed) << "coverage mismatch " << run.result.comparison.coverage_mismatch
                                 << ", colour mismatch " << run.result.comparison.colour_mismatch;
  EXPECT_TRUE(test::images_match(run.clraster_picture, run.gl_picture, kTolerance));  // leaves the pictures
  EXPECT_EQ(test::covered_pixel_count(run.clraster_picture), test::covered_pixel_count(draw_small(plain)));
}

// materials-256 is model-50k's knot and view cut into 256 runs of 195 or 196 triangles, each with a
// material colour of its own.
TEST(BenchScenes, KnotOfMaterialsIsTheKnotInPartsOfTheirOwnColour) {
  const Scene& parts = scene("materials-256");
  const Scene& plain = scene("model-50k");
  EXPECT_EQ(parts.model.positions, plain.model.positions);
  EXPECT_EQ(parts.model.indices, plain.model.indices);
  EXPECT_EQ(parts.camera.eye, plain.camera.eye);
  EXPECT_EQ(parts.camera.target, plain.camera.target);
  ASSERT_EQ(parts.model.materials.size(), 256u);
  std::vector<std::array<float, 4>> colours;
  for (std::size_t i = 0; i < parts.model.parts.size(); ++i) {
    const io::ModelPart& part = parts.model.parts[i];
    EXPECT_EQ(part.material, i);
    EXPECT_TRUE(part.index_count == 3 * 195 || part.index_count == 3 * 196) << "part " << i;
    EXPECT_FALSE(parts.model.materials[i].base_color_texture.has_value());
    colours.push_back(parts.model.materials[i].base_color_factor);
  }
  std::sort(colours.begin(), colours.end());
  EXPECT_EQ(std::unique(colours.begin(), colours.end()), colours.end()) << "two parts of one colour";
}

// The scenes of many draws are built the same way every time (the engine from its file).
TEST(BenchScenes, ScenesOfManyDrawsAreDeterministic) {
  for (const char* name : {"materials-256", "engine-glb"}) {
    const Scene again = make_scene(name);
    const Scene& first = scene(name);
    EXPECT_EQ(again.model.positions, first.model.positions) << name;
    EXPECT_EQ(again.model.normals, first.model.normals) << name;
    EXPECT_EQ(again.model.indices, first.model.indices) << name;
    EXPECT_EQ(again.model.parts, first.model.parts) << name;
    ASSERT_EQ(again.model.materials.size(), first.model.materials.size()) << name;
    for (std::size_t i = 0; i < again.model.materials.size(); ++i) {
      EXPECT_EQ(again.model.materials[i].base_color_factor, first.model.materials[i].base_color_factor) << name;
    }
    EXPECT_EQ(again.camera.eye, first.camera.eye) << name;
    EXPECT_EQ(again.camera.near_plane, first.camera.near_plane) << name;
  }
}

// Both scenes of many draws are drawn part by part on both sides alike, and the engine is framed
// as `render` frames a model: whole, within the picture.
class BenchManyDraws : public ::testing::TestWithParam<const char*> {};

TEST_P(BenchManyDraws, AreDrawnAsLlvmpipeDrawsThem) {
  const SceneRun run = run_small(scene(GetParam()));
  EXPECT_EQ(run.result.draws, scene(GetParam()).model.parts.size());
  EXPECT_TRUE(run.result.passed) << "coverage mismatch " << run.result.comparison.coverage_mismatch
                                 << ", colour mismatch " << run.result.comparison.colour_mismatch;
  EXPECT_TRUE(test::images_match(run.clraster_picture, run.gl_picture, kTolerance));  // leaves the pictures
  EXPECT_GT(coverage(run.clraster_picture), 0.1);
  EXPECT_FALSE(touches_edges(run.clraster_picture));
}

// instanced-4k: one instanced draw of a 1,280-triangle sphere, 4,096 placements of a 64 x 64 grid,
// drawn as llvmpipe draws it (glDrawElementsInstanced) and filling most of the picture.
TEST(BenchScenes, InstancedSpheresAreDrawnAsLlvmpipeDrawsThem) {
  const Scene& spheres = scene("instanced-4k");
  EXPECT_EQ(spheres.model.triangle_count(), 1280u);
  EXPECT_EQ(spheres.instance_count(), 4096u);
  EXPECT_FALSE(spheres.draws_materials());
  const SceneRun run = run_small(spheres);
  EXPECT_EQ(run.result.triangles, 4096u * 1280u);
  EXPECT_TRUE(run.result.passed) << "coverage mismatch " << run.result.comparison.coverage_mismatch
                                 << ", colour mismatch " << run.result.comparison.colour_mismatch;
  EXPECT_TRUE(test::images_match(run.clraster_picture, run.gl_picture, kTolerance));  // leaves the pictures
  EXPECT_GT(coverage(run.clraster_picture), 0.3);
}

// A picture's part at `rect` (window coordinates, from the bottom left), rows from the top.
Image part_of(const Image& picture, const Rect& rect) {
  const auto row_bytes = std::size_t(rect.width) * 4;
  Image part{rect.width, rect.height, std::vector<std::uint8_t>(row_bytes * std::size_t(rect.height))};
  const int top = picture.height - rect.y - rect.height;
  for (int y = 0; y < rect.height; ++y) {
    const std::size_t from = (std::size_t(top + y) * std::size_t(picture.width) + std::size_t(rect.x)) * 4;
    std::copy_n(&picture.rgba[from], row_bytes, &part.rgba[std::size_t(y) * row_bytes]);
  }
  return part;
}

// views-64's views each drawn on its own by llvmpipe, as a kViewSide-square picture.
const std::vector<Image>& views_drawn_alone() {
  static const std::vector<Image> pictures = [] {
    const Scene& views = scene("views-64");
    std::vector<Image> drawn;
    for (DrawState state : views.view_states(views.state(kViewSide, kViewSide), kViewSide, kViewSide)) {
      state.viewport = {};
      drawn.push_back(test::render_gl(views.model, state, kViewSide, kViewSide));
    }
    return drawn;
  }();
  return pictures;
}

// views-64 is model-50k's knot seen from 64 directions, each 256x256 whatever the size, the whole
// knot over a fifth to 45% of each view; built the same every time.
TEST(BenchScenes, ViewsSeeTheWholeKnotFromSixtyFourDirections) {
  const Scene& views = scene("views-64");
  const Scene& plain = scene("model-50k");
  EXPECT_EQ(views.model.positions, plain.model.positions);
  EXPECT_EQ(views.model.indices, plain.model.indices);
  EXPECT_FALSE(views.draws_materials());
  ASSERT_TRUE(views.draws_views());
  ASSERT_EQ(views.layer_count(), 64);
  EXPECT_EQ(views.layer_width(kWidth), kViewSide);
  EXPECT_EQ(views.layer_height(kHeight), kViewSide);
  EXPECT_EQ(plain.layer_width(kWidth), kWidth);
  EXPECT_EQ(views.view_matrices().size(), 64u);
  for (std::size_t i = 0; i < views.views.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      EXPECT_GT(glm::length(views.views[i].eye - views.views[j].eye), 0.5f) << "views " << j << " and " << i;
    }
  }
  const Scene again = make_scene("views-64");
  ASSERT_EQ(again.views.size(), views.views.size());
  for (std::size_t i = 0; i < views.views.size(); ++i) EXPECT_EQ(again.views[i].eye, views.views[i].eye) << i;

  const std::vector<Image>& pictures = views_drawn_alone();
  for (std::size_t view = 0; view < pictures.size(); ++view) {
    EXPECT_GE(coverage(pictures[view]), 0.2) << "view " << view;
    EXPECT_LE(coverage(pictures[view]), 0.45) << "view " << view;
    EXPECT_FALSE(touches_edges(pictures[view])) << "view " << view;
  }
}

// OpenGL draws the views where a layered Framebuffer of as many layers holds them.
TEST(BenchScenes, ViewsAreLaidOutAsALayeredFramebufferHoldsThem) {
  const Scene& views = scene("views-64");
  const Framebuffer layered(test::shared_context(), kViewSide, kViewSide, views.layer_count());
  EXPECT_EQ(views.layer_columns(), layered.layer_columns());
  EXPECT_EQ(views.layer_columns(), 8);
  EXPECT_EQ(views.layer_rows(), 8);
  const auto fields = [](const Rect& rect) { return std::array<int, 4>{rect.x, rect.y, rect.width, rect.height}; };
  const std::vector<DrawState> states = views.view_states(DrawState{}, kViewSide, kViewSide);
  ASSERT_EQ(states.size(), 64u);
  for (int layer = 0; layer < views.layer_count(); ++layer) {
    EXPECT_EQ(fields(views.layer_rect(layer, kViewSide, kViewSide)), fields(layered.layer_rect(layer))) << layer;
    EXPECT_EQ(fields(states[std::size_t(layer)].viewport), fields(layered.layer_rect(layer))) << layer;
  }
}

// views-64 is one draw of 64 views on clraster and a draw per view on llvmpipe: the two grids of
// views agree, and each view is its camera's picture where its layer is.
TEST(BenchScenes, ViewsAreDrawnAsLlvmpipeDrawsThemEachWhereItsLayerIs) {
  const Scene& views = scene("views-64");
  const SceneRun run = run_small(views);  // at any size, 64 layers of 256x256
  EXPECT_EQ(run.result.layers, 64);
  EXPECT_EQ(run.result.width, kViewSide);
  EXPECT_EQ(run.result.height, kViewSide);
  EXPECT_EQ(run.result.draws, 1u);
  EXPECT_EQ(run.result.triangles, 64u * 50'000u);
  ASSERT_EQ(run.clraster_picture.width, 8 * kViewSide);
  ASSERT_EQ(run.clraster_picture.height, 8 * kViewSide);
  EXPECT_TRUE(run.result.passed) << "coverage mismatch " << run.result.comparison.coverage_mismatch
                                 << ", colour mismatch " << run.result.comparison.colour_mismatch;
  EXPECT_TRUE(test::images_match(run.clraster_picture, run.gl_picture, kTolerance));  // leaves the pictures
  const std::vector<Image>& alone = views_drawn_alone();
  for (int layer = 0; layer < views.layer_count(); ++layer) {
    const Rect rect = views.layer_rect(layer, kViewSide, kViewSide);
    EXPECT_TRUE(test::images_match(part_of(run.clraster_picture, rect), alone[std::size_t(layer)], kTolerance))
        << "layer " << layer;
  }
}

INSTANTIATE_TEST_SUITE_P(Scenes, BenchManyDraws, ::testing::Values("materials-256", "engine-glb"),
                         [](const auto& info) {
                           std::string name = info.param;
                           std::replace(name.begin(), name.end(), '-', '_');
                           return name;
                         });

TEST(BenchScenes, FillDrawsSixteenFragmentsOnEveryPixel) {
  const Image picture = draw_small(scene("fill-16"));
  for (std::size_t p = 0; p < picture.rgba.size(); p += 4) ASSERT_EQ(picture.rgba[p], 16) << "pixel " << p / 4;
}

SceneResult result(const char* name, double clraster_ms, double gl_ms, bool passed) {
  SceneResult r;
  r.name = name;
  r.triangles = 1234567;
  r.width = kWidth;
  r.height = kHeight;
  r.clraster_ms = clraster_ms;
  r.gl_ms = gl_ms;
  r.passed = passed;
  r.comparison.coverage_mismatch = passed ? 0 : 0.25;
  return r;
}

TEST(BenchReport, ScenesOfViewsShowTheirLayers) {
  SceneResult views = result("views", 2, 1, true);
  views.width = views.height = 256;
  views.layers = 64;
  std::ostringstream table;
  print_table_row(table, views);
  print_table_foot(table, {views});
  EXPECT_PRED_FORMAT2(::testing::IsSubstring, "64x256x256", table.str());
  EXPECT_PRED_FORMAT2(::testing::IsSubstring, "LxWxH: L views of WxH pixels whatever the size", table.str());
  const nlohmann::json json = nlohmann::json::parse(to_json(RunOptions{}, {views}));
  EXPECT_EQ(json["scenes"][0]["layers"], 64);
  EXPECT_EQ(json["scenes"][0]["width"], 256);

  std::ostringstream one_layer;
  print_table_row(one_layer, result("a", 2, 1, true));
  print_table_foot(one_layer, {result("a", 2, 1, true)});
  EXPECT_PRED_FORMAT2(::testing::IsSubstring, "1920x1080", one_layer.str());
  EXPECT_PRED_FORMAT2(::testing::IsNotSubstring, "LxWxH", one_layer.str());
}

TEST(BenchReport, FailedScenesHaveNoRatioAndAreLeftOutOfTheMean) {
  const std::vector<SceneResult> results{result("a", 2, 1, true), result("b", 1, 2, false), result("c", 8, 1, true)};
  EXPECT_DOUBLE_EQ(geometric_mean_ratio(results), 4.0);
  EXPECT_TRUE(std::isnan(geometric_mean_ratio({result("b", 1, 2, false)})));

  std::ostringstream table;
  for (const SceneResult& r : results) print_table_row(table, r);
  print_table_foot(table, results);
  EXPECT_PRED_FORMAT2(::testing::IsSubstring, "1,234,567", table.str());
  EXPECT_PRED_FORMAT2(::testing::IsSubstring, "FAILED: the pictures differ: coverage mismatch 0.2500 (at most 0.002)", table.str());
  EXPECT_PRED_FORMAT2(::testing::IsSubstring, "(clraster / llvmpipe): 4.00 over 2 scenes (failed scenes are left out)", table.str());

  const nlohmann::json json = nlohmann::json::parse(to_json(RunOptions{}, results));
  ASSERT_EQ(json.at("scenes").size(), 3u);
  EXPECT_DOUBLE_EQ(json["scenes"][0]["ratio"].get<double>(), 2.0);
  EXPECT_TRUE(json["scenes"][1]["ratio"].is_null());
  EXPECT_FALSE(json["scenes"][1]["passed"].get<bool>());
  EXPECT_DOUBLE_EQ(json["geomean_ratio"].get<double>(), 4.0);
  EXPECT_TRUE(nlohmann::json::parse(to_json(RunOptions{}, {result("b", 1, 2, false)}))["geomean_ratio"].is_null());
}

}  // namespace
}  // namespace clraster::bench
