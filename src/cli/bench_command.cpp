#include "bench/report.hpp"
#include "bench/runner.hpp"
#include "bench/scenes.hpp"
#include "cli/commands.hpp"
#include "io/image_compare.hpp"
#include "io/image_io.hpp"

#include <filesystem>
#include <iostream>

namespace clraster::cli {

int bench(const BenchOptions& options) {
  // The scene names, their model files and the picture files are checked before the first scene is
  // built, so that a long run does not end in an error it could have started with.
  const std::vector<std::string> scenes = bench::parse_scene_list(options.scenes);
  const auto picture_path = [&](const std::string& scene, const char* kind) {
    return (std::filesystem::path(options.pictures) / (scene + "-" + kind + ".png")).string();
  };
  constexpr const char* kPictureKinds[] = {"clraster", "llvmpipe", "diff"};
  if (!options.pictures.empty()) {
    for (const std::string& scene : scenes) {
      for (const char* kind : kPictureKinds) check_output_writable(picture_path(scene, kind));
    }
  }

  bench::RunOptions run;
  run.width = options.width;
  run.height = options.height;
  run.frames = options.frames;
  run.context.device = options.device;
  run.context.memory_cap = options.memory_cap;
  run.context.tile_size = options.tile_size;

  if (!options.json) bench::print_table_head(std::cout, run);
  std::vector<bench::SceneResult> results;
  std::string failed;
  for (const std::string& name : scenes) {
    bench::SceneRun scene = bench::run_scene(bench::make_scene(name), run);
    if (!options.pictures.empty()) {
      io::save_png(picture_path(name, kPictureKinds[0]), scene.clraster_picture);
      io::save_png(picture_path(name, kPictureKinds[1]), scene.gl_picture);
      io::save_png(picture_path(name, kPictureKinds[2]),
                   io::diff_image(scene.clraster_picture, scene.gl_picture, bench::kTolerance.threshold));
    }
    if (!scene.result.passed) failed += (failed.empty() ? "" : ", ") + name;
    results.push_back(std::move(scene.result));
    if (!options.json) bench::print_table_row(std::cout, results.back()) << std::flush;  // as each scene ends
  }
  if (options.json) {
    std::cout << bench::to_json(run, results) << std::endl;
  } else {
    bench::print_table_foot(std::cout, results);
  }
  if (!failed.empty()) {
    std::cerr << "clraster: error: the pictures of " << failed
              << " differ from OpenGL's beyond the conformance thresholds\n";
    return 1;
  }
  return 0;
}

}  // namespace clraster::cli
