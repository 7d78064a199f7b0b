#include "bench/report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

namespace clraster::bench {
namespace {

// printf into a string.
template <typename... Args>
std::string format(const char* pattern, Args... args) {
  const int size = std::snprintf(nullptr, 0, pattern, args...);
  std::string text(static_cast<std::size_t>(size) + 1, '\0');
  std::snprintf(text.data(), text.size(), pattern, args...);
  text.pop_back();
  return text;
}

// 4004450 -> "4,004,450".
std::string with_thousands(std::uint64_t value) {
  const std::string digits = std::to_string(value);
  std::string text;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) text += ',';
    text += digits[i];
  }
  return text;
}

std::string size_text(int width, int height) { return std::to_string(width) + "x" + std::to_string(height); }

// "1920x1080", or a scene of views' "64x256x256": 64 layers of 256x256.
std::string size_text(const SceneResult& result) {
  const std::string layer = size_text(result.width, result.height);
  return result.layers == 1 ? layer : std::to_string(result.layers) + "x" + layer;
}

double mebibytes(std::uint64_t bytes) { return static_cast<double>(bytes) / (1 << 20); }

}  // namespace

void print_table_head(std::ostream& out, const RunOptions& options) {
  out << "clraster bench: " << size_text(options.width, options.height) << ", the median of " << options.frames
      << (options.frames == 1 ? " frame" : " frames") << " after " << kWarmupFrames
      << " warm-up frames, clraster and llvmpipe in turn\n\n"
      << format("%-13s %10s %5s %-10s %9s %9s %6s  %-39s %8s %7s\n", "", "", "", "", "clraster", "llvmpipe", "",
                "clraster stages, device ms", "first", "pipeline")
      << format("%-13s %10s %5s %-10s %9s %9s %6s  %7s %7s %7s %7s %7s  %8s %7s\n", "scene", "triangles", "draws",
                "size", "ms", "ms", "ratio", "vertex", "setup", "binning", "raster", "other", "frame ms", "MiB");
}

std::ostream& print_table_row(std::ostream& out, const SceneResult& result) {
  out << format("%-13s %10s %5zu %-10s ", result.name.c_str(), with_thousands(result.triangles).c_str(), result.draws,
                size_text(result).c_str());
  if (!result.passed) {
    out << format("FAILED: the pictures differ: coverage mismatch %.4f (at most %g), colour mismatch %.4f (at most "
                  "%g)\n",
                  result.comparison.coverage_mismatch, kTolerance.max_coverage_mismatch,
                  result.comparison.colour_mismatch, kTolerance.max_colour_mismatch);
    return out;
  }
  const StageTimes& stage = result.stage_ms;
  out << format("%9.2f %9.2f %6.2f  %7.2f %7.2f %7.2f %7.2f %7.2f  %8.1f %7.1f\n", result.clraster_ms, result.gl_ms,
                result.ratio(), stage.vertex_ms, stage.setup_ms, stage.binning_ms, stage.raster_ms, stage.other_ms,
                result.first_frame_ms, mebibytes(result.pipeline_memory_bytes));
  return out;
}

void print_table_foot(std::ostream& out, const std::vector<SceneResult>& results) {
  int passed = 0;
  for (const SceneResult& result : results) passed += result.passed;
  const double mean = geometric_mean_ratio(results);
  out << '\n';
  if (passed == 0) {
    out << "geometric mean of the ratios: none, no scene passed\n";
  } else {
    out << format("geometric mean of the ratios (clraster / llvmpipe): %.2f over %d scene%s", mean, passed,
                  passed == 1 ? "" : "s")
        << (passed < static_cast<int>(results.size()) ? " (failed scenes are left out)\n" : "\n");
  }
  if (!results.empty()) {
    const int tile = results.front().tile_size;
    out << "clraster on " << results.front().device << ", " << tile << "x" << tile
        << " tiles; OpenGL: " << results.front().gl_renderer << '\n';
  }
  if (std::any_of(results.begin(), results.end(), [](const SceneResult& result) { return result.layers > 1; })) {
    out << "LxWxH: L views of WxH pixels whatever the size, one draw into a layered framebuffer (llvmpipe: one "
           "picture of the views side by side, a draw per view in its viewport)\n";
  }
  out << "stages: the median device time of each stage (OpenCL profiling events), the frame's draws together; "
         "other: index checks and transfers (the frame's clear is written by the raster stage)\n"
         "first frame: a new Context's, from its construction (programs from the disk cache) to the finished frame\n";
}

std::string to_json(const RunOptions& options, const std::vector<SceneResult>& results) {
  nlohmann::json scenes = nlohmann::json::array();
  for (const SceneResult& result : results) {
    const StageTimes& stage = result.stage_ms;
    const io::ImageComparison& comparison = result.comparison;
    scenes.push_back({{"name", result.name},
                      {"triangles", result.triangles},
                      {"draws", result.draws},
                      {"width", result.width},
                      {"height", result.height},
                      {"layers", result.layers},
                      {"passed", result.passed},
                      {"clraster_ms", result.clraster_ms},
                      {"llvmpipe_ms", result.gl_ms},
                      // A failed scene's time is no result: it has no ratio.
                      {"ratio", result.passed ? nlohmann::json(result.ratio()) : nlohmann::json(nullptr)},
                      {"stage_ms",
                       {{"vertex", stage.vertex_ms},
                        {"setup", stage.setup_ms},
                        {"binning", stage.binning_ms},
                        {"raster", stage.raster_ms},
                        {"other", stage.other_ms}}},
                      {"first_frame_ms", result.first_frame_ms},
                      {"pipeline_memory_bytes", result.pipeline_memory_bytes},
                      {"clraster_frame_ms", result.clraster_frame_ms},
                      {"llvmpipe_frame_ms", result.gl_frame_ms},
                      {"coverage_mismatch", comparison.coverage_mismatch},
                      {"colour_mismatch", comparison.colour_mismatch},
                      {"device", result.device},
                      {"tile_size", result.tile_size},
                      {"gl_renderer", result.gl_renderer}});
  }
  const double mean = geometric_mean_ratio(results);
  const nlohmann::json report = {{"width", options.width},
                                 {"height", options.height},
                                 {"frames", options.frames},
                                 {"warmup_frames", kWarmupFrames},
                                 {"scenes", scenes},
                                 {"geomean_ratio", std::isnan(mean) ? nlohmann::json(nullptr) : nlohmann::json(mean)}};
  return report.dump();
}

}  // namespace clraster::bench
