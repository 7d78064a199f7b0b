// Scale: a million triangles under the smallest memory cap are drawn in chunks, within the cap,
// with the same picture as in one piece; renders are bit-identical run after run, in one process
// and across processes, thread counts, tile sizes, memory caps and work-group shapes; and four million triangles
// match OpenGL.
#include "io/camera.hpp"
#include "io/image_io.hpp"
#include "io/procedural.hpp"
#include "pipeline/memory_plan.hpp"
#include "support/cli_support.hpp"
#include "support/test_support.hpp"

#include <chrono>
#include <cstdio>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace clraster::test {
namespace {

namespace fs = std::filesystem;

constexpr int kWidth = 960, kHeight = 540;

struct Scene {
  io::Mesh mesh;
  DrawState state;
};

// A landscape of 2 * cells * cells triangles over 10 x 10 units, about a pixel each at 708 x 708
// cells, seen from above at an angle so that it fills most of the picture.
Scene landscape(int cells) {
  Scene scene{io::make_terrain(cells, cells, 10, 10, 1.5f, 2024), {}};
  io::Camera camera;
  camera.eye = {0, 8, 6};
  camera.target = {0, 0, -0.5f};
  camera.near_plane = 1;
  camera.far_plane = 30;
  scene.state.model_view = io::to_mat4(io::view_matrix(camera));
  scene.state.projection = io::to_mat4(io::projection_matrix(camera, float{kWidth} / kHeight));
  return scene;
}

// Overlapping triangles of every size drawn without a depth test, so that each pixel shows the last
// triangle drawn there: the picture depends on every triangle being drawn in order.
Scene pile_of_triangles() {
  Scene scene{io::make_random_triangles(100000, 99, {-1, -1, -1}, {1, 1, 1}, 0.1f), {}};
  scene.state.depth_test = false;
  return scene;
}

RenderResult render(Context& context, const Scene& scene) {
  return render_clraster(context, scene.mesh, scene.state, kWidth, kHeight);
}

// Most of the picture drawn, so that comparing it means something.
::testing::AssertionResult mostly_covered(const Image& image) {
  const std::uint64_t covered = covered_pixel_count(image);
  if (2 * covered > std::uint64_t{kWidth} * kHeight) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "only " << covered << " of " << kWidth * kHeight << " pixels drawn";
}

Context& smallest_cap_context() {
  static Context context(ContextOptions{.memory_cap = kMinMemoryCap});
  return context;
}

TEST(Chunking, AMillionTrianglesUnderTheSmallestCapMatchOnePiece) {
  const Scene scene = landscape(708);
  ASSERT_GE(scene.mesh.triangle_count(), 1'000'000u);
  const RenderResult whole = render(shared_context(), scene);
  const RenderResult chunked = render(smallest_cap_context(), scene);
  ASSERT_TRUE(mostly_covered(whole.image));

  EXPECT_GT(chunked.stats.chunks, 1u);
  EXPECT_LE(chunked.stats.peak_memory_bytes, kMinMemoryCap);
  EXPECT_LE(whole.stats.peak_memory_bytes, kDefaultMemoryCap);
  EXPECT_EQ(chunked.stats.triangles, scene.mesh.triangle_count());
  EXPECT_EQ(chunked.stats.tile_triangle_pairs, whole.stats.tile_triangle_pairs);
  EXPECT_TRUE(images_match(chunked.image, whole.image, kExact));
}

TEST(Chunking, ChunkedDrawsKeepThePrimitiveOrder) {
  const Scene scene = pile_of_triangles();
  const RenderResult chunked = render(smallest_cap_context(), scene);
  ASSERT_TRUE(mostly_covered(chunked.image));
  EXPECT_GT(chunked.stats.chunks, 1u);
  EXPECT_TRUE(images_match(chunked.image, render(shared_context(), scene).image, kExact));
}

// Under the smallest cap with the smallest tiles, a chunk of many primitives leaves little room for
// bin pairs, while one primitive across the near and far planes is clipped into three triangles that
// each cover most of the picture's tiles. Each raster batch takes whole primitives, so the plan
// keeps room for the most bin pairs one primitive can make (a tile for each of its clipped
// triangles): the draw neither stalls nor drops it, and draws what one piece draws.
TEST(Chunking, ScreenCoveringClippedPrimitivesUnderTheSmallestCapMatchOnePiece) {
  constexpr int kBigWidth = 1920, kBigHeight = 1080;
  io::Mesh crossing;
  crossing.positions = {-3, -3, -3, 3, -3, 3, 0, 4, 0, 3, 3, -3, -3, 3, 3, 0, -4, 0};
  crossing.normals = {1, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 1, 1, 1, 0};
  crossing.indices = {0, 1, 2, 3, 4, 5};
  Scene scene = pile_of_triangles();
  scene.mesh = io::merge({crossing, scene.mesh, crossing});

  Context small_tiles(ContextOptions{.memory_cap = kMinMemoryCap, .tile_size = 8});
  const RenderResult chunked = render_clraster(small_tiles, scene.mesh, scene.state, kBigWidth, kBigHeight);
  const RenderResult whole = render_clraster(shared_context(), scene.mesh, scene.state, kBigWidth, kBigHeight);
  EXPECT_GT(chunked.stats.chunks, 1u);
  EXPECT_LE(chunked.stats.peak_memory_bytes, kMinMemoryCap);
  EXPECT_EQ(chunked.stats.triangles, scene.mesh.triangle_count());
  EXPECT_TRUE(images_match(chunked.image, whole.image, kExact));
}

// A device allocates buffers up to a size (CL_DEVICE_MAX_MEM_ALLOC_SIZE, a quarter of its memory by
// OpenCL's minimum, Oclgrind's 128 MiB): the plan keeps every buffer within it, taking smaller chunks
// and shading vertices per chunk where the whole mesh's would not fit one buffer.
TEST(Chunking, ThePlanKeepsEveryBufferWithinTheDevicesLargestAllocation) {
  pipeline::PlanInput input;
  input.memory_cap = kDefaultMemoryCap;
  input.buffer_bytes = kDefaultMemoryCap;
  input.vertex_count = 2'000'000;
  input.indexed = true;
  input.topology = CLR_TOPOLOGY_LIST;
  input.primitive_count = 4'000'000;
  input.tile_count = 60 * 34;
  input.shaded_vertex_bytes = 64;
  input.setup_triangle_bytes = 168;
  const pipeline::MemoryPlan unlimited = pipeline::plan_memory(input);
  ASSERT_TRUE(unlimited.shade_all_vertices);

  input.buffer_bytes = std::size_t{16} << 20;  // below the 122 MiB of transformed vertices
  const pipeline::MemoryPlan limited = pipeline::plan_memory(input);
  EXPECT_FALSE(limited.shade_all_vertices);
  EXPECT_LT(limited.chunk_primitives, unlimited.chunk_primitives);
  for (std::size_t i = 0; i < limited.buffer_bytes.size(); ++i) {
    EXPECT_LE(limited.buffer_bytes[i], input.buffer_bytes) << "scratch buffer " << i;
  }

  // Not even one primitive's bin pairs fit: refused, naming the device's limit.
  input.buffer_bytes = 4 * input.tile_count;
  EXPECT_THROW(
      {
        try {
          pipeline::plan_memory(input);
        } catch (const InvalidArgument& error) {
          EXPECT_TRUE(std::string(error.what()).find("the device allocates at most") != std::string::npos) << error.what();
          throw;
        }
      },
      InvalidArgument);
}

TEST(Determinism, TheSameRenderTwiceInOneProcessIsBitIdentical) {
  for (const Scene& scene : {landscape(708), pile_of_triangles()}) {
    const Image first = render(shared_context(), scene).image;
    ASSERT_TRUE(mostly_covered(first));
    EXPECT_TRUE(images_match(render(shared_context(), scene).image, first, kExact));
  }
}

// The GPU's work-group shapes (a work-item per pixel of a tile, 256 per block of a scan or sort) run
// the same arithmetic in another order of work-items: the pictures are the same, bit for bit, with
// a depth test, without one, and counting every fragment.
TEST(Determinism, WideWorkGroupsDrawTheSamePictures) {
  Scene overdraw = landscape(300);
  DrawState counter = overdraw_counter();
  counter.model_view = overdraw.state.model_view;
  counter.projection = overdraw.state.projection;
  overdraw.state = counter;
  for (const Scene& scene : {landscape(708), pile_of_triangles(), overdraw}) {
    const Image device = render(shared_context(), scene).image;
    ASSERT_TRUE(mostly_covered(device));
    EXPECT_TRUE(images_match(render(shared_context(WorkGroupShape::Wide), scene).image, device, kExact));
  }
}

// A way of running the command line that must not change a single pixel.
struct RunVariant {
  const char* name;
  std::vector<std::string> args;
  std::map<std::string, std::string> env;
};

void PrintTo(const RunVariant& variant, std::ostream* stream) { *stream << variant.name; }

class AcrossProcesses : public ::testing::TestWithParam<RunVariant> {};

// Each render in its own process: the demo scene, then the same with the variant's options.
TEST_P(AcrossProcesses, RendersAreBitIdentical) {
  const auto render_demo = [](const std::string& name, const std::vector<std::string>& extra_args,
                              const std::map<std::string, std::string>& env) {
    const fs::path output = scratch_directory() / (name + ".png");
    std::vector<std::string> args{"render", "--output", output.string(), "--size",
                                  std::to_string(kWidth) + "x" + std::to_string(kHeight)};
    args.insert(args.end(), extra_args.begin(), extra_args.end());
    const CliResult result = run_cli(args, env);
    EXPECT_TRUE(succeeded(result));
    return result.exit_code == 0 ? io::load_png(output.string()) : Image{};
  };
  const Image reference = render_demo("reference", {}, {});
  ASSERT_TRUE(mostly_covered(reference));
  const Image variant = render_demo(GetParam().name, GetParam().args, GetParam().env);
  EXPECT_TRUE(images_match(variant, reference, kExact));
}

INSTANTIATE_TEST_SUITE_P(Variants, AcrossProcesses,
                         ::testing::Values(RunVariant{"SameOptions", {}, {}},
                                           RunVariant{"OneThread", {}, {{"POCL_MAX_PTHREAD_COUNT", "1"}}},
                                           RunVariant{"TileSize8", {"--tile-size", "8"}, {}},
                                           RunVariant{"TileSize16", {"--tile-size", "16"}, {}},
                                           RunVariant{"TileSize32", {"--tile-size", "32"}, {}},
                                           RunVariant{"SmallestMemoryCap", {"--memory-cap", "4"}, {}}),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(Scale, FourMillionTrianglesMatchOpenGl) {
  const Scene scene = landscape(1415);
  ASSERT_GE(scene.mesh.triangle_count(), 4'000'000u);

  Context& context = shared_context();
  const VertexBuffer vertices(context, scene.mesh.positions, scene.mesh.normals);
  const IndexBuffer indices(context, scene.mesh.indices);
  Framebuffer framebuffer(context, kWidth, kHeight);
  DrawCall call{&vertices, &indices};
  call.state = scene.state;
  const auto frame = [&] {
    framebuffer.clear({0, 0, 0, 1}, 1.0f);
    const DrawStats stats = framebuffer.draw(call);
    context.finish();
    return stats;
  };
  frame();  // warm-up: programs built or loaded, scratch buffers grown
  const auto start = std::chrono::steady_clock::now();
  const DrawStats stats = frame();
  const double frame_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();

  const std::pair<std::string, std::string> measured[] = {
      {"triangles", std::to_string(stats.triangles)},
      {"frame_ms", std::to_string(static_cast<long>(frame_ms))},
      {"peak_memory_bytes", std::to_string(stats.peak_memory_bytes)},
      {"chunks", std::to_string(stats.chunks)},
      {"tile_triangle_pairs", std::to_string(stats.tile_triangle_pairs)}};
  std::string line = std::to_string(kWidth) + "x" + std::to_string(kHeight) + " on " + context.device().name + ":";
  for (const auto& [key, value] : measured) {
    RecordProperty(key, value);
    line += " " + key + "=" + value;
  }
  std::printf("%s\n", line.c_str());

  EXPECT_EQ(stats.triangles, scene.mesh.triangle_count());
  EXPECT_EQ(stats.triangles_dropped, 0u);
  EXPECT_LE(stats.peak_memory_bytes, kDefaultMemoryCap);
  const Image reference = render_gl(scene.mesh, scene.state, kWidth, kHeight);
  ASSERT_TRUE(mostly_covered(reference));
  EXPECT_TRUE(images_match(framebuffer.read_color(), reference, kNormalShading));
}

}  // namespace
}  // namespace clraster::test
