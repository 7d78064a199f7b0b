// The command line, run as a separate process: its interface (render, compare, bench, devices,
// --help, --version, both option spellings, --stats, the OpenGL backend), and its answer to bad
// input: one clear line on stderr and a non-zero exit, never a crash or a hang, and an existing
// output file left as it was.
#include "io/camera.hpp"
#include "io/image_io.hpp"
#include "io/isolated_loader.hpp"
#include "io/model_loader.hpp"
#include "io/procedural.hpp"
#include "support/cli_support.hpp"
#include "support/hostile_models.hpp"
#include "support/test_support.hpp"

#include <nlohmann/json.hpp>

#include <sys/stat.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace clraster::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// ---- Helpers -------------------------------------------------------------------------------------

// Table rows print as their name in gtest's messages.
template <typename Row>
  requires requires(const Row& row) { row.name; }
void PrintTo(const Row& row, std::ostream* stream) {
  *stream << row.name;
}

// The mesh as OBJ text: every coordinate exactly (9 significant digits round-trip a float), faces
// 1-based, no normals (the loader computes them, the same way for the CLI and for the test).
std::string to_obj(const io::Mesh& mesh) {
  std::string text;
  char line[96];
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    std::snprintf(line, sizeof line, "v %.9g %.9g %.9g\n", mesh.positions[3 * v], mesh.positions[3 * v + 1],
                  mesh.positions[3 * v + 2]);
    text += line;
  }
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    std::snprintf(line, sizeof line, "f %u %u %u\n", mesh.indices[3 * t] + 1, mesh.indices[3 * t + 1] + 1,
                  mesh.indices[3 * t + 2] + 1);
    text += line;
  }
  return text;
}

// The three vertices of a triangle, for OBJ files.
const std::string kObjTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

// A model of that one triangle.
fs::path triangle_file() {
  static const fs::path path = write_scratch_file("triangle.obj", kObjTriangle + "f 1 2 3\n");
  return path;
}

// A small landscape with no symmetry, so that any mistake in the camera shows.
const io::Mesh& landscape() {
  static const io::Mesh mesh = io::make_terrain(16, 12, 4, 3, 0.6f, 7);
  return mesh;
}

fs::path landscape_file() {
  static const fs::path path = write_scratch_file("landscape.obj", to_obj(landscape()));
  return path;
}

io::Mesh load(const fs::path& path) {
  std::vector<std::string> warnings;
  return io::load_model(path.string(), warnings);
}


// The keys of the --stats line: those of every backend, and clraster's draw counters.
const std::vector<std::string> kStatsKeys{"triangles", "width",  "height", "frames", "first_frame_ms", "peak_memory_bytes",
                                          "median_ms", "min_ms", "device", "draws"};
const std::vector<std::string> kDrawCounterKeys{"triangles_dropped", "chunks", "tile_triangle_pairs",
                                                "pipeline_memory_bytes", "framebuffer_bytes"};

::testing::AssertionResult has_keys(const json& object, const std::vector<std::string>& keys) {
  for (const std::string& key : keys) {
    if (!object.contains(key)) return ::testing::AssertionFailure() << "no \"" << key << "\" in " << object;
  }
  return ::testing::AssertionSuccess();
}

// The one line of JSON that --stats prints after `frames` (at least 1) timed frames, checked for
// the keys every backend reports.
json stats_line(const std::string& out, int width, int height, int frames) {
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  const json stats = json::parse(out);
  if (::testing::AssertionResult complete = has_keys(stats, kStatsKeys); !complete) {
    ADD_FAILURE() << complete.message();
    return stats;
  }
  EXPECT_GT(stats["triangles"].get<std::uint64_t>(), 0u);
  EXPECT_EQ(stats["width"], width);
  EXPECT_EQ(stats["height"], height);
  EXPECT_EQ(stats["frames"], frames);
  EXPECT_GT(stats["first_frame_ms"].get<double>(), 0);
  EXPECT_GT(stats["min_ms"].get<double>(), 0);
  EXPECT_LE(stats["min_ms"].get<double>(), stats["median_ms"].get<double>());
  EXPECT_FALSE(stats["device"].get<std::string>().empty());
  return stats;
}

// ---- Interface -------------------------------------------------------------------------------------

TEST(CliInterface, VersionPrintsTheLibraryVersion) {
  const CliResult result = run_cli({"--version"});
  EXPECT_TRUE(succeeded(result));
  EXPECT_EQ(result.out, std::string("clraster ") + version() + "\n");
}

TEST(CliInterface, HelpNamesTheCommands) {
  const CliResult result = run_cli({"--help"});
  EXPECT_TRUE(succeeded(result));
  for (const char* command : {"render", "compare", "bench", "devices"}) EXPECT_TRUE(mentions(result.out, command));
}

TEST(CliInterface, RenderHelpNamesEveryOption) {
  const CliResult result = run_cli({"render", "--help"});
  EXPECT_TRUE(succeeded(result));
  for (const char* option : {"--output", "--size", "--eye", "--target", "--up", "--fov", "--near", "--far", "--shading",
                             "--program", "--cull", "--frames", "--stats", "--device", "--backend", "--memory-cap",
                             "--tile-size", "--model-memory-limit", "--model-time-limit"}) {
    EXPECT_TRUE(mentions(result.out, option));
  }
}

TEST(CliInterface, BenchHelpNamesEveryOptionAndScene) {
  const CliResult result = run_cli({"bench", "--help"});
  EXPECT_TRUE(succeeded(result));
  for (const char* option : {"--scenes", "--size", "--frames", "--json", "--device", "--memory-cap", "--tile-size",
                             "--pictures", "model-50k", "terrain-1m", "terrain-4m", "fill-16", "tiny-1m",
                             "textured-50k", "materials-256", "engine-glb", "instanced-4k", "views-64",
                             "256x256 at any size"}) {
    EXPECT_TRUE(mentions(result.out, option));
  }
}

TEST(CliInterface, DevicesListsEveryOpenClDevice) {
  const CliResult result = run_cli({"devices"});
  EXPECT_TRUE(succeeded(result));
  for (const DeviceInfo& device : list_devices()) {
    EXPECT_TRUE(mentions(result.out, std::to_string(device.index) + ": " + device.name));
    EXPECT_TRUE(mentions(result.out, "local memory " + std::to_string(device.local_memory_bytes >> 10) + " KiB"));
  }
}

TEST(CliRender, WithoutAModelDrawsTheDemoSceneAtTheRequestedSize) {
  const Image picture = render("demo.png", {"--size", "48x30"}).picture;
  EXPECT_EQ(picture.width, 48);
  EXPECT_EQ(picture.height, 30);
  const std::uint64_t covered = covered_pixel_count(picture);
  EXPECT_GT(covered, 0u);
  EXPECT_LT(covered, 48u * 30u) << "no background left: the scene is not framed";
}

TEST(CliRender, CameraOptionsGiveTheViewAndProjectionOfTheLibrary) {
  io::Camera camera;
  camera.eye = {-3, 1.5f, 2};
  camera.target = {0.25f, 0, -0.5f};
  camera.up = {0, 1, 0.125f};
  camera.fov_degrees = 50;
  camera.near_plane = 0.5f;
  camera.far_plane = 12;
  DrawState state;
  state.model_view = io::to_mat4(io::view_matrix(camera));
  state.projection = io::to_mat4(io::projection_matrix(camera, 80.0f / 60.0f));
  const Image expected = render_clraster(shared_context(), load(landscape_file()), state, 80, 60).image;
  ASSERT_GT(covered_pixel_count(expected), 400u);

  const std::string model = landscape_file().string();
  const Image separate = render("separate.png", {model, "--size", "80x60", "--eye", "-3,1.5,2", "--target",
                                                 "0.25,0,-0.5", "--up", "0,1,0.125", "--fov", "50", "--near", "0.5",
                                                 "--far", "12"})
                             .picture;
  const Image joined = render("joined.png", {model, "--size=80x60", "--eye=-3,1.5,2", "--target=0.25,0,-0.5",
                                             "--up=0,1,0.125", "--fov=50", "--near=0.5", "--far=12"})
                           .picture;
  EXPECT_TRUE(images_match(separate, expected, kExact)) << "--option value";
  EXPECT_TRUE(images_match(joined, expected, kExact)) << "--option=value";
}

TEST(CliRender, StatsAreOneJsonLineWithTheDrawCounters) {
  const std::string out = render("stats.png", {landscape_file().string(), "--size", "40x30", "--stats", "--frames",
                                               "3", "--device", "0", "--memory-cap", "4"})
                              .out;
  const json stats = stats_line(out, 40, 30, 3);
  ASSERT_TRUE(has_keys(stats, kDrawCounterKeys));
  EXPECT_EQ(stats["triangles"], landscape().triangle_count());
  EXPECT_EQ(stats["device"], list_devices().at(0).name);
  EXPECT_EQ(stats["triangles_dropped"], 0);
  EXPECT_GE(stats["chunks"].get<std::uint64_t>(), 1u);
  EXPECT_GT(stats["tile_triangle_pairs"].get<std::uint64_t>(), 0u);
  EXPECT_GT(stats["pipeline_memory_bytes"].get<std::uint64_t>(), 0u);
  EXPECT_LE(stats["pipeline_memory_bytes"].get<std::uint64_t>(), std::uint64_t{4} << 20) << "--memory-cap 4 (MiB)";
  // RGBA8 and Depth32FStencil8 attachments: 4 + 4 + 1 bytes a pixel.
  EXPECT_EQ(stats["framebuffer_bytes"], 40 * 30 * 9);
  // The process's peak counts those and everything else (the model, the loaded libraries).
  EXPECT_GT(stats["peak_memory_bytes"].get<std::uint64_t>(),
            stats["pipeline_memory_bytes"].get<std::uint64_t>() + stats["framebuffer_bytes"].get<std::uint64_t>());
}

TEST(CliRender, StatsWithoutTimedFramesStillHaveEveryKey) {
  const json stats = json::parse(render("untimed.png", {landscape_file().string(), "--size", "40x30", "--stats"}).out);
  EXPECT_TRUE(has_keys(stats, kStatsKeys));
  EXPECT_TRUE(has_keys(stats, kDrawCounterKeys));
}

TEST(CliRender, GlBackendAgreesWithClraster) {
  const Rendered ours = render("clraster.png", {"--size", "160x120", "--stats", "--frames", "1"});
  const Rendered gl = render("gl.png", {"--size", "160x120", "--stats", "--frames", "1", "--backend", "gl"});
  EXPECT_EQ(stats_line(gl.out, 160, 120, 1).at("triangles"), stats_line(ours.out, 160, 120, 1).at("triangles"));
  ASSERT_GT(covered_pixel_count(gl.picture), 1000u);

  const CliResult compared = run_cli({"compare", ours.file.string(), gl.file.string()});
  ASSERT_TRUE(succeeded(compared));
  const json comparison = json::parse(compared.out);
  EXPECT_LE(comparison.at("coverage_mismatch").get<double>(), kNormalShading.max_coverage_mismatch) << comparison;
  EXPECT_LE(comparison.at("colour_mismatch").get<double>(), kNormalShading.max_colour_mismatch) << comparison;
  // The same judgement in the test's own comparison, which leaves the pictures and their difference
  // behind when it fails.
  EXPECT_TRUE(images_match(ours.picture, gl.picture, kNormalShading));
}

TEST(CliRender, TrianglesWithNonFiniteCornersAreDroppedWithOneWarningAndCounted) {
  // The landscape with three vertices NaN or infinite, as scans have them, and the same landscape
  // without the triangles that use them.
  struct NonFiniteCoordinate {
    std::uint32_t vertex;
    int axis;
    float value;
  };
  const std::vector<NonFiniteCoordinate> non_finite{{0, 0, NAN}, {40, 1, INFINITY}, {100, 2, -INFINITY}};
  io::Mesh holed = landscape();
  for (const auto& [vertex, axis, value] : non_finite) holed.positions[3 * vertex + axis] = value;
  io::Mesh without = landscape();
  without.indices.clear();
  std::uint64_t dropped = 0;
  for (std::size_t t = 0; t < landscape().triangle_count(); ++t) {
    const auto first = landscape().indices.begin() + static_cast<std::ptrdiff_t>(3 * t);
    const bool uses_non_finite = std::any_of(first, first + 3, [&](std::uint32_t corner) {
      return std::any_of(non_finite.begin(), non_finite.end(), [&](const auto& bad) { return bad.vertex == corner; });
    });
    if (uses_non_finite) {
      ++dropped;
    } else {
      without.indices.insert(without.indices.end(), first, first + 3);
    }
  }
  ASSERT_GE(dropped, 3u);
  const fs::path holed_file = write_scratch_file("holed.obj", to_obj(holed));
  const fs::path without_file = write_scratch_file("without.obj", to_obj(without));
  const Rendered expected = render("without.png", {without_file.string(), "--size", "80x60"});
  ASSERT_GT(covered_pixel_count(expected.picture), 400u);

  const std::string warning = "clraster: warning: " + holed_file.string() + ": " + std::to_string(dropped) +
                              " triangles dropped: a corner's position, normal or texture coordinate is NaN or "
                              "infinite\n";
  const Rendered ours = render_with_warnings("holed.png", {holed_file.string(), "--size", "80x60", "--stats"});
  EXPECT_EQ(ours.err, warning);
  const json stats = json::parse(ours.out);
  EXPECT_EQ(stats.at("triangles"), landscape().triangle_count());
  EXPECT_EQ(stats.at("triangles_dropped"), dropped);
  EXPECT_TRUE(images_match(ours.picture, expected.picture, kExact));

  // OpenGL draws the same, and counts nothing of its own.
  const Rendered gl =
      render_with_warnings("holed-gl.png", {holed_file.string(), "--size", "80x60", "--stats", "--backend", "gl"});
  EXPECT_EQ(gl.err, warning);
  EXPECT_TRUE(json::parse(gl.out).at("triangles_dropped").is_null()) << gl.out;
  EXPECT_TRUE(images_match(gl.picture, expected.picture, kNormalShading));
}

TEST(CliCompare, ReportsTheDifferencesAsJson) {
  // 4x2 pixels, black but for: pixel 0 the same red in both; pixel 1 grey, one channel 10 apart;
  // pixel 2 blue in A only; pixel 3 green in B only.
  Image a{4, 2, std::vector<std::uint8_t>(32, 0)};
  for (int p = 0; p < 8; ++p) a.rgba[4 * p + 3] = 255;
  Image b = a;
  const auto set = [](Image& image, int pixel, std::uint8_t r, std::uint8_t g, std::uint8_t b) {
    image.rgba[4 * pixel] = r, image.rgba[4 * pixel + 1] = g, image.rgba[4 * pixel + 2] = b;
  };
  set(a, 0, 200, 0, 0);
  set(b, 0, 200, 0, 0);
  set(a, 1, 100, 100, 100);
  set(b, 1, 110, 100, 100);
  set(a, 2, 0, 0, 50);
  set(b, 3, 0, 90, 0);
  const fs::path path_a = scratch_directory() / "a.png", path_b = scratch_directory() / "b.png";
  io::save_png(path_a.string(), a);
  io::save_png(path_b.string(), b);

  const CliResult result = run_cli({"compare", path_a.string(), path_b.string()});
  ASSERT_TRUE(succeeded(result));
  EXPECT_EQ(std::count(result.out.begin(), result.out.end(), '\n'), 1) << result.out;
  const json c = json::parse(result.out);
  EXPECT_EQ(c.at("width"), 4);
  EXPECT_EQ(c.at("height"), 2);
  EXPECT_EQ(c.at("pixels"), 8);
  EXPECT_EQ(c.at("covered_a"), 3);
  EXPECT_EQ(c.at("covered_b"), 3);
  EXPECT_EQ(c.at("covered_either"), 4);
  EXPECT_EQ(c.at("covered_both"), 2);
  EXPECT_EQ(c.at("only_a"), 1);
  EXPECT_EQ(c.at("only_b"), 1);
  EXPECT_DOUBLE_EQ(c.at("coverage_mismatch").get<double>(), 0.5);
  EXPECT_EQ(c.at("colour_mismatch_pixels"), 1);
  EXPECT_DOUBLE_EQ(c.at("colour_mismatch").get<double>(), 0.5);
  EXPECT_EQ(c.at("differing_pixels"), 3);
  EXPECT_EQ(c.at("max_channel_diff"), 90);

  const CliResult lenient = run_cli({"compare", path_a.string(), path_b.string(), "--threshold", "10"});
  ASSERT_TRUE(succeeded(lenient));
  EXPECT_EQ(json::parse(lenient.out).at("colour_mismatch_pixels"), 0);
}

TEST(CliBench, JsonHasEachSceneWithItsTimesStagesAndVerdict) {
  const CliResult result =
      run_cli({"bench", "--scenes", "fill-16,model-50k", "--size", "96x64", "--frames", "1", "--json"});
  ASSERT_TRUE(succeeded(result));
  EXPECT_EQ(std::count(result.out.begin(), result.out.end(), '\n'), 1) << result.out;
  const json report = json::parse(result.out);
  EXPECT_EQ(report.at("width"), 96);
  EXPECT_EQ(report.at("height"), 64);
  EXPECT_EQ(report.at("frames"), 1);
  const json& scenes = report.at("scenes");
  ASSERT_EQ(scenes.size(), 2u) << report;
  const std::vector<std::pair<std::string, std::uint64_t>> expected{{"fill-16", 32}, {"model-50k", 50000}};
  for (std::size_t i = 0; i < expected.size(); ++i) {
    const json& scene = scenes[i];
    ASSERT_TRUE(has_keys(scene, {"name", "triangles", "draws", "clraster_ms", "llvmpipe_ms", "ratio", "stage_ms",
                                 "first_frame_ms", "pipeline_memory_bytes", "passed", "layers"}));
    EXPECT_EQ(scene["name"], expected[i].first);
    EXPECT_EQ(scene["triangles"], expected[i].second);
    EXPECT_EQ(scene["draws"], 1);
    EXPECT_EQ(scene["layers"], 1);
    EXPECT_EQ(scene["passed"], true) << scene;
    EXPECT_GT(scene["clraster_ms"].get<double>(), 0);
    EXPECT_GT(scene["llvmpipe_ms"].get<double>(), 0);
    const double ratio = scene["ratio"].get<double>();
    EXPECT_TRUE(std::isfinite(ratio) && ratio > 0) << scene;
    EXPECT_DOUBLE_EQ(ratio, scene["clraster_ms"].get<double>() / scene["llvmpipe_ms"].get<double>());
    ASSERT_TRUE(has_keys(scene["stage_ms"], {"vertex", "setup", "binning", "raster", "other"}));
    for (const auto& [stage, ms] : scene["stage_ms"].items()) EXPECT_GE(ms.get<double>(), 0) << stage;
    EXPECT_GT(scene["stage_ms"]["raster"].get<double>(), 0);
    EXPECT_GT(scene["first_frame_ms"].get<double>(), 0);
    EXPECT_GT(scene["pipeline_memory_bytes"].get<std::uint64_t>(), 0u);
  }
  EXPECT_TRUE(std::isfinite(report.at("geomean_ratio").get<double>())) << report;
}

TEST(CliBench, TableHasARowPerSceneAndWritesThePictures) {
  const fs::path pictures = scratch_directory() / "bench-pictures";
  fs::create_directories(pictures);
  const CliResult result =
      run_cli({"bench", "--scenes", "fill-16", "--size", "32x16", "--frames", "1", "--pictures", pictures.string()});
  ASSERT_TRUE(succeeded(result));
  EXPECT_TRUE(mentions(result.out, "\nfill-16               32     1 32x16 "));
  EXPECT_TRUE(mentions(result.out, "geometric mean of the ratios (clraster / llvmpipe): "));
  const Image ours = io::load_png((pictures / "fill-16-clraster.png").string());
  EXPECT_TRUE(images_match(ours, io::load_png((pictures / "fill-16-llvmpipe.png").string()), kExact));
  EXPECT_EQ(ours.rgba[0], 16) << "16 fragments";
  EXPECT_TRUE(fs::exists(pictures / "fill-16-diff.png"));
}

// ---- Bad input -------------------------------------------------------------------------------------

// Runs `clraster render --output <an existing file> args...` and checks that it is rejected with a
// "clraster: error:" line mentioning `subject`, and that the existing file keeps its bytes.
CliResult expect_render_rejected(const std::vector<std::string>& args, std::string_view subject,
                                 const std::map<std::string, std::string>& env = {}) {
  const std::string sentinel = "an earlier picture, which a failed render must leave alone\n";
  const fs::path output = write_scratch_file("existing.png", sentinel);
  std::vector<std::string> command{"render", "--output", output.string()};
  command.insert(command.end(), args.begin(), args.end());
  const CliResult result = run_cli(command, env);
  EXPECT_TRUE(failed_with_error(result, subject));
  EXPECT_TRUE(read_file(output) == sentinel) << "the failed render changed " << output;
  return result;
}

TEST(CliBadInput, UnknownCommandIsNamed) {
  EXPECT_TRUE(failed_with_error(run_cli({"rendr", "--output", "x.png"}), "rendr"));
}

TEST(CliBadInput, UnknownOptionIsNamed) { expect_render_rejected({"--colour", "red"}, "--colour"); }

TEST(CliBadInput, BenchSceneThatDoesNotExist) {
  EXPECT_TRUE(failed_with_error(run_cli({"bench", "--scenes", "model-50k,teapot"}), "'teapot'"));
}

TEST(CliBadInput, BenchSizeOutOfRange) {
  EXPECT_TRUE(failed_with_error(run_cli({"bench", "--scenes", "fill-16", "--size", "0x10"}), "0x10"));
}

TEST(CliBadInput, BenchWithoutTimedFrames) {
  EXPECT_TRUE(failed_with_error(run_cli({"bench", "--scenes", "fill-16", "--frames", "0"}), "--frames"));
}

TEST(CliBadInput, BenchPicturesInADirectoryThatDoesNotExist) {
  EXPECT_TRUE(failed_with_error(run_cli({"bench", "--scenes", "fill-16", "--pictures", "/nonexistent/pictures"}),
                                "/nonexistent/pictures"));
}

TEST(CliBadInput, NoCommand) { EXPECT_TRUE(failed_with_error(run_cli({}), "subcommand")); }

TEST(CliBadInput, RenderWithoutOutput) { EXPECT_TRUE(failed_with_error(run_cli({"render"}), "--output")); }

TEST(CliBadInput, DeviceFromTheEnvironmentThatIsNotAnIndex) {
  expect_render_rejected({"--size", "8x8"}, "CLRASTER_DEVICE", {{"CLRASTER_DEVICE", "first"}});
}

struct BadOption {
  const char* name;
  std::vector<std::string> args;
  const char* subject;
  int exit_code = 2;  // a usage error, as CLI11's own; 1 for what the machine (not the command line) lacks
};

class RejectedRenderOption : public ::testing::TestWithParam<BadOption> {};

TEST_P(RejectedRenderOption, WithAClearMessage) {
  const CliResult result = expect_render_rejected(GetParam().args, GetParam().subject);
  // The message from its start: the subject is the whole of it, or all but a count the machine gives
  // (devices) or the list CLI11 prints.
  EXPECT_TRUE(result.err.starts_with("clraster: error: " + std::string(GetParam().subject))) << result.err;
  EXPECT_EQ(result.exit_code, GetParam().exit_code) << result;
}

INSTANTIATE_TEST_SUITE_P(
    Options, RejectedRenderOption,
    ::testing::Values(
        BadOption{"SizeOfZeroWidth", {"--size", "0x10"}, "--size 0x10 is out of range: each side must be 1..16384"},
        BadOption{"SizeTooWide", {"--size", "16385x10"}, "--size 16385x10 is out of range: each side must be 1..16384"},
        BadOption{"SizeOfNegativeHeight", {"--size", "10x-1"}, "--size 10x-1 is out of range: each side must be 1..16384"},
        BadOption{"SizeThatIsNotNumbers", {"--size", "abc"}, "--size: expected WIDTHxHEIGHT, e.g. 1920x1080, got 'abc'"},
        BadOption{"SizeWithAWidthOverflowingInt", {"--size", "4294967306x10"},
                  "--size 4294967306x10 is out of range: each side must be 1..16384"},
        BadOption{"FovZero", {"--fov", "0"}, "camera: fov_degrees must be in (0, 180), got 0"},
        BadOption{"Fov180", {"--fov", "180"}, "camera: fov_degrees must be in (0, 180), got 180"},
        BadOption{"FovNegative", {"--fov", "-5"}, "camera: fov_degrees must be in (0, 180), got -5"},
        BadOption{"FovNegativeJoined", {"--fov=-5"}, "camera: fov_degrees must be in (0, 180), got -5"},
        BadOption{"FovNotANumber", {"--fov", "wide"}, "Could not convert: --fov = wide"},
        BadOption{"NearZero", {"--near", "0"}, "camera: near_plane must be greater than 0, got 0"},
        BadOption{"NearNegative", {"--near", "-2.5"}, "camera: near_plane must be greater than 0, got -2.5"},
        BadOption{"FarEqualToNear", {"--near", "5", "--far", "5"},
                  "camera: far_plane must be greater than near_plane (5), got 5"},
        BadOption{"FarBelowNear", {"--near", "5", "--far", "0.25"},
                  "camera: far_plane must be greater than near_plane (5), got 0.25"},
        BadOption{"EyeOfTwoNumbers", {"--eye", "1,2"}, "--eye: expected three numbers X,Y,Z, got '1,2'"},
        BadOption{"EyeOfLetters", {"--eye", "a,b,c"}, "--eye: expected three numbers X,Y,Z, got 'a,b,c'"},
        BadOption{"EyeOfFourNumbers", {"--eye", "1,2,3,4"}, "--eye: expected three numbers X,Y,Z, got '1,2,3,4'"},
        BadOption{"TargetWithAnEmptyNumber", {"--target", "1,,3"}, "--target: expected three numbers X,Y,Z, got '1,,3'"},
        BadOption{"UpOfTwoNumbers", {"--up", "0,1"}, "--up: expected three numbers X,Y,Z, got '0,1'"},
        BadOption{"EyeAtTheTarget", {"--eye", "-1,-2,-3", "--target=-1,-2,-3"},
                  "camera: eye and target are the same point (-1, -2, -3)"},
        BadOption{"UpAlongTheViewDirection", {"--eye", "0,0,5", "--target", "0,0,0", "--up", "0,0,1"},
                  "camera: up (0, 0, 1) is zero or parallel to the view direction (0, 0, -5)"},
        // CLI11's own wording for values outside a list or range.
        BadOption{"ShadingUnknown", {"--shading", "phong"}, "--shading: Check phong value in"},
        BadOption{"CullUnknown", {"--cull", "sideways"}, "--cull: Check sideways value in"},
        BadOption{"BackendUnknown", {"--backend", "vulkan"}, "--backend: Check vulkan value in"},
        BadOption{"TileSizeUnsupported", {"--tile-size", "12"}, "--tile-size: 12 not in {8,16,32}"},
        BadOption{"MemoryCapBelowTheMinimum", {"--memory-cap", "3"}, "--memory-cap: Value 3 not in range 4 to 1048576"},
        BadOption{"FramesNegative", {"--frames", "-1"}, "--frames: Value -1 not in range 0 to 100000"},
        BadOption{"DeviceNegative", {"--device", "-1"}, "--device: Value -1 not in range 0 to 1048576"},
        BadOption{"FovNotFinite", {"--fov", "nan"}, "camera: fov_degrees must be finite, got nan"},
        BadOption{"FarNotFinite", {"--far", "inf"}, "camera: far_plane must be finite, got inf"},
        BadOption{"TimeLimitNegative", {"--time-limit", "-1"}, "--time-limit: expected seconds in (0, 1000000], got -1"},
        BadOption{"TimeLimitNotFinite", {"--time-limit", "nan"}, "--time-limit: expected seconds in (0, 1000000], got nan"},
        BadOption{"DeviceThatDoesNotExist", {"--device", "1000"}, "no OpenCL device 1000: this machine has ", 1}),
    [](const auto& info) { return std::string(info.param.name); });

// A program declaring `declarations`, whose functions use none of them but the output `color`, for
// the command line to reject (or accept) for what it declares.
std::string program_declaring(const std::string& declarations) {
  return declarations +
         "\nvoid vertex(clr_vertex* v) { v->position = (float4)(0.0f, 0.0f, 0.0f, 1.0f); }\n"
         "void fragment(clr_fragment* f) { f->out.color = 1; }\n";
}

const std::string kPositionAndColour = "clr_attribute(float3, position)\nclr_output(float4, color)\n";

struct BadProgram {
  const char* name;
  std::string declarations;
  const char* subject;
};

// Programs that compile but declare what the command line does not provide (docs/cli.md).
class RejectedProgram : public ::testing::TestWithParam<BadProgram> {};

TEST_P(RejectedProgram, IsNamedWithTheDeclarationAndItsLine) {
  const fs::path program = write_scratch_file(std::string(GetParam().name) + ".cl", program_declaring(GetParam().declarations));
  expect_render_rejected({triangle_file().string(), "--program", program.string(), "--size", "16x16"}, GetParam().subject);
}

INSTANTIATE_TEST_SUITE_P(
    Declarations, RejectedProgram,
    ::testing::Values(
        // The whole list of what the command line provides follows a name it does not.
        BadProgram{"UnknownUniform", kPositionAndColour + "clr_uniform(float3, light)",
                   "(line 3) declares uniform 'light', which the command line does not provide (it provides "
                   "attributes position (float3), normal (float3), uv (float2); uniforms mvp (float16), model_view "
                   "(float16), normal_matrix (float16), projection (float16), base_color (float4), light_direction "
                   "(float3), viewport (float2); texture base_color_texture; one float4 output)"},
        BadProgram{"UnknownAttribute", kPositionAndColour + "clr_attribute(float4, colour)", "attribute 'colour'"},
        BadProgram{"UnknownTexture", kPositionAndColour + "clr_texture(albedo)", "texture 'albedo'"},
        BadProgram{"Buffer", kPositionAndColour + "clr_buffer(float, data)", "buffer 'data'"},
        BadProgram{"UniformOfAnotherType", kPositionAndColour + "clr_uniform(float4, mvp)",
                   "uniform 'mvp' as float4; the command line provides it as float16"},
        BadProgram{"UniformArray", kPositionAndColour + "clr_uniform(float4, base_color[2])",
                   "uniform 'base_color' as an array of 2"},
        BadProgram{"AttributeOfAnotherType", "clr_attribute(float4, position)\nclr_output(float4, color)",
                   "attribute 'position' as float4; the command line provides it as float3"},
        BadProgram{"TwoOutputs", kPositionAndColour + "clr_output(float4, glow)", "declares 2 outputs"},
        BadProgram{"IntegerOutput", "clr_attribute(float3, position)\nclr_output(uint4, color)",
                   "output 'color' as uint4"}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(CliBadInput, ProgramFileThatDoesNotExist) {
  expect_render_rejected({triangle_file().string(), "--program", "/nonexistent/lit.cl"}, "/nonexistent/lit.cl");
}

// The frames of a program that never ends are stopped at --time-limit (counted from when the
// programs are built); the earlier picture stays.
TEST(CliBadInput, ProgramThatLoopsForEverIsStoppedAtTheTimeLimit) {
  const fs::path program = write_scratch_file(
      "endless.cl", "clr_attribute(float3, position)\nclr_uniform(float16, mvp)\nclr_output(float4, color)\n"
                    "void vertex(clr_vertex* v) { v->position = clr_mul(v->uniforms->mvp, (float4)(v->in.position, 1.0f)); }\n"
                    "void fragment(clr_fragment* f) {\n"
                    "  float x = 0.0f;\n"
                    "  while (x >= 0.0f) x += 1.0f;  // x reaches infinity and stays there\n"
                    "  f->out.color = (float4)(x);\n"
                    "}\n");
  const CliResult result = expect_render_rejected(
      {triangle_file().string(), "--program", program.string(), "--size", "16x16", "--time-limit", "0.5"},
      "the frames took longer than --time-limit 0.5 s and were stopped (does a program loop for ever?)");
  EXPECT_EQ(result.exit_code, 1) << result;
}

// A program that crashes the process (here a write through a wild pointer, which a CPU device
// runs as it is) takes down only the child process the render runs in: an error names the signal.
TEST(CliBadInput, ProgramThatCrashesEndsInAnErrorNamingTheSignal) {
  const fs::path program = write_scratch_file(
      "wild.cl", "clr_attribute(float3, position)\nclr_uniform(float16, mvp)\nclr_output(float4, color)\n"
                 "void vertex(clr_vertex* v) { v->position = clr_mul(v->uniforms->mvp, (float4)(v->in.position, 1.0f)); }\n"
                 "void fragment(clr_fragment* f) {\n"
                 "  __global volatile int* wild = (__global volatile int*)(ulong)(16.0f + f->frag_coord.x * 0.0f);\n"
                 "  *wild = 1;\n"
                 "  f->out.color = (float4)(1.0f);\n"
                 "}\n");
  // (AddressSanitizer, in the sanitizer build, would report the crash itself and exit.) Intel's
  // runtime prints its own crash report first, which is relayed: the error is the last line.
  const std::string sentinel = "an earlier picture\n";
  const fs::path output = write_scratch_file("crashed.png", sentinel);
  const CliResult result =
      run_cli({"render", "--output", output.string(), triangle_file().string(), "--program", program.string(),
               "--size", "16x16"},
              {{"ASAN_OPTIONS", "handle_segv=0"}});
  EXPECT_EQ(result.exit_code, 1) << result;
  EXPECT_TRUE(result.err.ends_with("clraster: error: the render process was ended by signal 11 (Segmentation fault) "
                                   "during its frames: a program crashed (a write through a wild pointer?)\n"))
      << result;
  EXPECT_EQ(read_file(output), sentinel);
}

TEST(CliRender, TimeLimitThatIsNotReachedChangesNothing) {
  const Image unlimited = render("unlimited.png", {triangle_file().string(), "--size", "32x32"}).picture;
  const Image limited =
      render("limited.png", {triangle_file().string(), "--size", "32x32", "--time-limit", "120"}).picture;
  EXPECT_GT(covered_pixel_count(limited), 0u);
  EXPECT_EQ(limited.rgba, unlimited.rgba);
}

TEST(CliBadInput, ProgramThatDoesNotCompileShowsTheCompilersFileLineAndColumn) {
  const fs::path program = write_scratch_file(
      "broken.cl", "clr_attribute(float3, position)\nclr_output(float4, color)\n\n"
                   "void vertex(clr_vertex* v) { v->position = undefined_thing; }\n"
                   "void fragment(clr_fragment* f) { f->out.color = 1; }\n");
  const std::string sentinel = "an earlier picture\n";
  const fs::path output = write_scratch_file("kept.png", sentinel);
  const CliResult result =
      run_cli({"render", triangle_file().string(), "--output", output.string(), "--program", program.string()});
  EXPECT_EQ(result.exit_code, 1) << result;
  // One "clraster: error:" line naming the program, then the compiler's messages.
  EXPECT_TRUE(result.err.starts_with("clraster: error: program " + program.string() + " failed to compile:\n"))
      << result;
  EXPECT_TRUE(mentions(result.err, "\n" + program.string() + ":4:44: error: use of undeclared identifier 'undefined_thing'\n"));
  EXPECT_EQ(result.err.find("clraster: error:", 1), std::string::npos) << result;
  EXPECT_TRUE(read_file(output) == sentinel);
}

TEST(CliBadInput, ProgramTogetherWithShading) {
  expect_render_rejected({triangle_file().string(), "--program", "lit.cl", "--shading", "material"}, "--shading");
}

TEST(CliBadInput, ProgramOnTheGlBackend) {
  const CliResult result =
      expect_render_rejected({triangle_file().string(), "--program", "lit.cl", "--backend", "gl"}, "--program lit.cl");
  EXPECT_EQ(result.exit_code, 2);
}

struct BadModelFile {
  std::string name;
  fs::path path;
};

class RejectedModelFile : public ::testing::TestWithParam<BadModelFile> {};

TEST_P(RejectedModelFile, IsNamedInTheMessage) {
  expect_render_rejected({GetParam().path.string(), "--size", "16x16"}, GetParam().path.string());
}

const fs::path kAssimpGltf2 = "/usr/share/assimp/models/glTF2";  // the assimp-testmodels package

// Unreadable files, and assimp's test files that must fail to load: glTF 2.0 with members of the
// wrong JSON type, or not following the schema.
std::vector<BadModelFile> bad_model_files() {
  std::vector<BadModelFile> files{{"Missing", "/nonexistent/model.obj"},
                                  {"Directory", "/usr/share/assimp/models"},
                                  {"UnderARegularFile", "/etc/hostname/model.obj"},
                                  {"NotAModel", "/etc/hostname"},
                                  {"Empty", "/dev/null"}};
  for (const char* directory : {"wrongTypes", "SchemaFailures"}) {
    for (const fs::directory_entry& entry : fs::directory_iterator(kAssimpGltf2 / directory)) {
      if (entry.path().extension() == ".gltf") {
        files.push_back({std::string("glTF2_") + directory + "_" + entry.path().stem().string(), entry.path()});
      }
    }
  }
  return files;
}

INSTANTIATE_TEST_SUITE_P(Files, RejectedModelFile, ::testing::ValuesIn(bad_model_files()),
                         [](const auto& info) { return info.param.name; });

struct CraftedModel {
  const char* name;
  const char* file_name;
  std::string contents;
};

// Models that must not load: no triangles, or faces that reference vertices that do not exist,
// also through indices beyond 32 bits that a parser could wrap around to existing ones.
class RejectedCraftedModel : public ::testing::TestWithParam<CraftedModel> {};

TEST_P(RejectedCraftedModel, IsNamedInTheMessage) {
  const fs::path path = write_scratch_file(GetParam().file_name, GetParam().contents);
  expect_render_rejected({path.string(), "--size", "16x16"}, path.string());
}

const std::string kPlyVertices =
    "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
const std::string kPlyTriangle = kPlyVertices + "element face 1\nproperty list uchar int vertex_indices\nend_header\n" +
                                 "0 0 0\n1 0 0\n0 1 0\n";
const std::string kOffTriangle = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n";

INSTANTIATE_TEST_SUITE_P(
    Models, RejectedCraftedModel,
    ::testing::Values(
        CraftedModel{"EmptyObj", "empty.obj", ""},
        CraftedModel{"ObjOfPointsOnly", "points.obj", kObjTriangle + "p 1\np 2\np 3\n"},
        CraftedModel{"ObjOfLinesOnly", "lines.obj", kObjTriangle + "l 1 2\nl 2 3\n"},
        CraftedModel{"PlyOfPointsOnly", "points.ply", kPlyVertices + "end_header\n0 0 0\n1 0 0\n0 1 0\n"},
        CraftedModel{"ObjWhoseEveryTriangleHasANonFiniteCorner", "non-finite.obj",
                     kObjTriangle + "v nan 0 0\nv 0 inf 0\nf 4 2 3\nf 1 5 3\n"},
        CraftedModel{"ObjFaceIndexPastTheEnd", "past-end.obj", kObjTriangle + "f 1 2 3\nf 1 2 7\n"},
        CraftedModel{"ObjFaceIndexZero", "zero.obj", kObjTriangle + "f 0 1 2\n"},
        CraftedModel{"ObjRelativeIndexBeforeTheStart", "before-start.obj", kObjTriangle + "f -1 -2 -7\n"},
        CraftedModel{"ObjFaceIndexBeyond32Bits", "beyond-32-bits.obj", kObjTriangle + "f 1 2 4294967298\n"},
        CraftedModel{"PlyFaceIndexPastTheEnd", "past-end.ply", kPlyTriangle + "3 0 1 9\n"},
        CraftedModel{"PlyNegativeFaceIndex", "negative.ply", kPlyTriangle + "3 0 -1 2\n"},
        CraftedModel{"PlyFaceIndexWrappingAround32Bits", "wrapping.ply", kPlyTriangle + "3 0 1 4294967297\n"},
        CraftedModel{"OffFaceIndexPastTheEnd", "past-end.off", kOffTriangle + "3 0 1 5\n"},
        CraftedModel{"OffNegativeFaceIndex", "negative.off", kOffTriangle + "3 0 1 -1\n"},
        CraftedModel{"OffFaceIndexWrappingAround32Bits", "wrapping.off", kOffTriangle + "3 0 1 4294967297\n"},
        // Three vertices and the indices 0, 1, 7 (16-bit), in an embedded buffer.
        CraftedModel{"GltfIndexPastTheEnd", "past-end.gltf",
                     R"({"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],)"
                     R"("meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1, "mode": 4}]}],)"
                     R"("buffers": [{"byteLength": 44, "uri": "data:application/octet-stream;base64,)"
                     R"(AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAcAAAA="}],)"
                     R"("bufferViews": [{"buffer": 0, "byteLength": 36},)"
                     R"({"buffer": 0, "byteOffset": 36, "byteLength": 6}],)"
                     R"("accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",)"
                     R"("min": [0, 0, 0], "max": [1, 1, 0]},)"
                     R"({"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"}]})"}),
    [](const auto& info) { return std::string(info.param.name); });

// The model files of issue 38 that took the command line down, hung it or ate gigabytes: each is
// one error line within seconds. The memory limit is far below what they took, so a check that
// stopped working shows as another message.
class HostileModelFile : public ::testing::TestWithParam<HostileModel> {};

const fs::path& hostile_directory() {
  static const fs::path directory = scratch_directory() / "hostile";
  return directory;
}

TEST_P(HostileModelFile, IsOneErrorLineWithinSeconds) {
  fs::create_directories(hostile_directory());
  const fs::path path = write_hostile_model(GetParam(), hostile_directory());
  const auto start = std::chrono::steady_clock::now();
  const CliResult result = expect_render_rejected({path.string(), "--size", "16x16", "--model-memory-limit", "256"},
                                                  path.string());
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
  EXPECT_EQ(result.err, "clraster: error: cannot load model '" + path.string() + "': " + GetParam().reason + "\n");
  EXPECT_EQ(result.exit_code, 1);
}

INSTANTIATE_TEST_SUITE_P(Issue38, HostileModelFile,
                         ::testing::ValuesIn(hostile_models(hostile_directory())),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(CliBadInput, ModelLoaderCrashIsOneErrorLine) {
  // Without an extension assimp picks its OBJ reader by the content, past the check of .obj files'
  // material libraries, and crashes on the texture before any material.
  const fs::path model = write_scratch_file("early_map", kObjTriangle + "mtllib early.mtl\nusemtl m\nf 1 2 3\n");
  write_scratch_file("early.mtl", "map_Kd texture.png\nnewmtl m\n");
  const CliResult result = expect_render_rejected({model.string(), "--size", "16x16"}, model.string());
  const std::string crashed = "clraster: error: cannot load model '" + model.string() + "': the model loader ";
  if (io::kBuiltWithAddressSanitizer) {
    EXPECT_TRUE(result.err.starts_with(crashed)) << result.err;  // AddressSanitizer's report and exit code
  } else {
    EXPECT_EQ(result.err, crashed + "crashed (SIGSEGV, Segmentation fault)\n");
  }
}

TEST(CliBadInput, ModelLoaderBeyondItsTimeNamesTheOption) {
  const fs::path pipe = scratch_directory() / "pipe.obj";  // opening it blocks: nobody writes
  ASSERT_EQ(::mkfifo(pipe.c_str(), 0600), 0);
  const auto start = std::chrono::steady_clock::now();
  const CliResult result =
      expect_render_rejected({pipe.string(), "--size", "16x16", "--model-time-limit", "0.5"}, pipe.string());
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
  EXPECT_EQ(result.err, "clraster: error: cannot load model '" + pipe.string() +
                            "': the model loader ran longer than its time limit of 0.5 s; --model-time-limit "
                            "SECONDS raises it\n");
}

TEST(CliBadInput, ModelLoaderBeyondItsMemoryNamesTheOption) {
  if (io::kBuiltWithAddressSanitizer) GTEST_SKIP() << "no memory limit under AddressSanitizer";
  // 255 KB that instance a mesh into 20 million triangles need more than the default; the landscape
  // loads within the smallest limit the option takes.
  const fs::path instances = write_scratch_file("instances.glb", instancing_glb());
  const CliResult result = expect_render_rejected({instances.string(), "--size", "16x16"}, instances.string());
  EXPECT_EQ(result.err, "clraster: error: cannot load model '" + instances.string() +
                            "': the model loader needed more than its memory limit of " +
                            std::to_string(io::kLoadMemoryFloor >> 20) + " MiB; --model-memory-limit MiB raises it\n");
  EXPECT_TRUE(succeeded(run_cli({"render", landscape_file().string(), "--output",
                                 (scratch_directory() / "landscape.png").string(), "--size", "16x16",
                                 "--model-memory-limit", "64"})));
}

struct BadOutput {
  std::string name;
  fs::path path;
};

class UnwritableOutput : public ::testing::TestWithParam<BadOutput> {};

TEST_P(UnwritableOutput, IsNamedInTheMessage) {
  const std::string path = GetParam().path.string();
  EXPECT_TRUE(failed_with_error(
      run_cli({"render", landscape_file().string(), "--size", "16x16", "--output", path}), path));
}

INSTANTIATE_TEST_SUITE_P(Paths, UnwritableOutput,
                         ::testing::Values(BadOutput{"UnderARegularFile", "/etc/hostname/picture.png"},
                                           BadOutput{"InAMissingDirectory", "/nonexistent/picture.png"},
                                           BadOutput{"Directory", fs::temp_directory_path()},
                                           BadOutput{"FullDevice", "/dev/full"},
                                           BadOutput{"ReadOnlyProcFile", "/proc/version"}),
                         [](const auto& info) { return info.param.name; });

TEST(CliBadInput, EmptyOutputPathIsAUsageError) {
  const CliResult result = run_cli({"render", "--output", ""});
  EXPECT_TRUE(failed_with_error(result, "--output: the path is empty"));
  EXPECT_EQ(result.exit_code, 2);
}

// A write that fails half way (here at the file size limit, as on a full disk) leaves the earlier
// picture as it was, and no temporary file beside it.
TEST(CliBadInput, FailedWriteLeavesTheEarlierPicture) {
  const fs::path directory = scratch_directory() / "failed-write";
  fs::remove_all(directory);
  fs::create_directories(directory);
  const fs::path output = directory / "picture.png";
  const std::string earlier = "an earlier picture\n";
  std::ofstream(output) << earlier;
  // 1 KiB at most per file; SIGXFSZ ignored (kept over exec), so the write fails with EFBIG. Drawn
  // by OpenGL: the OpenCL runtimes fail (PoCL aborts, Intel's prints a crash report) when they
  // cannot write their own caches, which is theirs to mend, not what this test is about.
  const CliResult result = run_executable(
      "/bin/bash",
      {"-c", "ulimit -f 1 && trap '' XFSZ && exec \"$0\" render --backend gl --size 64x64 --output \"$1\"",
       CLRASTER_CLI_PATH, output.string()});
  EXPECT_TRUE(failed_with_error(result, "cannot write " + output.string() + ": File too large"));
  EXPECT_EQ(read_file(output), earlier);
  EXPECT_EQ(std::distance(fs::directory_iterator(directory), fs::directory_iterator()), 1);
}

// Bytes of a file's name or contents that a terminal would act on are printed as escapes.
TEST(CliBadInput, ControlBytesInMessagesAreEscaped) {
  const std::string model = "/nonexistent/\x1b]0;title\x07\x1b[31mred\r\xc2\x9b.obj";
  const CliResult result = run_cli({"render", "--output", (scratch_directory() / "escaped.png").string(), model});
  EXPECT_TRUE(failed_with_error(result, "/nonexistent/\\x1b]0;title\\x07\\x1b[31mred\\x0d\\xc2\\x9b.obj"));
  EXPECT_EQ(result.err.find('\x1b'), std::string::npos) << result;
}

// Two pictures for compare: 8x4 and 4x4.
struct ComparePictures {
  fs::path wide = scratch_directory() / "wide.png";
  fs::path square = scratch_directory() / "square.png";
  ComparePictures() {
    io::save_png(wide.string(), Image{8, 4, std::vector<std::uint8_t>(8 * 4 * 4, 255)});
    io::save_png(square.string(), Image{4, 4, std::vector<std::uint8_t>(4 * 4 * 4, 255)});
  }
};

TEST(CliBadInput, CompareOfPicturesThatCannotBeRead) {
  const ComparePictures pictures;
  for (const std::string unreadable : {"/nonexistent/picture.png", "/etc/hostname", "/usr/share/assimp/models"}) {
    EXPECT_TRUE(failed_with_error(run_cli({"compare", pictures.wide.string(), unreadable}), unreadable));
    EXPECT_TRUE(failed_with_error(run_cli({"compare", unreadable, pictures.wide.string()}), unreadable));
  }
}

TEST(CliBadInput, CompareOfPicturesOfDifferentSizes) {
  const ComparePictures pictures;
  EXPECT_TRUE(failed_with_error(run_cli({"compare", pictures.wide.string(), pictures.square.string()}), "4x4"));
}

TEST(CliBadInput, CompareWithAnUnwritableDiffPicture) {
  const ComparePictures pictures;
  EXPECT_TRUE(failed_with_error(run_cli({"compare", pictures.wide.string(), pictures.wide.string(), "--diff",
                                         "/etc/hostname/diff.png"}),
                                "/etc/hostname/diff.png"));
}

TEST(CliBadInput, CompareWithAThresholdOutOfRange) {
  const ComparePictures pictures;
  EXPECT_TRUE(failed_with_error(
      run_cli({"compare", pictures.wide.string(), pictures.wide.string(), "--threshold", "256"}), "--threshold"));
}

}  // namespace
}  // namespace clraster::test
