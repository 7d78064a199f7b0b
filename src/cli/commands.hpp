// The clraster command line: one function per subcommand, each a thin client of the library.
#pragma once

#include "io/camera.hpp"
#include "io/isolated_loader.hpp"

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <utility>

namespace clraster::cli {

// A command line the user must change: a bad option value or combination (exit code 2, as for
// what CLI11 rejects), as against a failure while doing what was asked (exit code 1).
class UsageError : public InvalidArgument {
 public:
  using InvalidArgument::InvalidArgument;
};

// Runs `check` (which validates what the user gave), its InvalidArgument a UsageError.
template <typename Check>
decltype(auto) as_usage_error(Check&& check) {
  try {
    return std::forward<Check>(check)();
  } catch (const InvalidArgument& error) {
    throw UsageError(error.what());
  }
}

enum class Backend { Clraster, Gl };
// Normal, Lambert, Depth and Overdraw are the library's built-in shadings (clraster::Shading);
// Material draws the model's materials with the material program (programs/material.cl).
enum class ShadingOption { Normal, Lambert, Depth, Overdraw, Material };

struct RenderOptions {
  std::string model;  // empty: the built-in demo scene
  io::ModelLoadLimits model_limits;  // of the process the model file is loaded in
  std::string output;
  int width = 1280;
  int height = 720;
  std::optional<glm::vec3> eye, target, up;
  float fov_degrees = 45;
  std::optional<float> near_plane, far_plane;
  ShadingOption shading = ShadingOption::Normal;
  std::string program;  // a --program file (then `shading` is not used); empty: none
  CullMode cull = CullMode::None;
  int frames = 0;  // timed frames after the warm-up frame
  bool stats = false;
  int device = -1;
  Backend backend = Backend::Clraster;
  std::size_t memory_cap = kDefaultMemoryCap;
  int tile_size = kDeviceTileSize;
  double time_limit_seconds = 0;  // for the frames, once programs are built (cli/isolated_render.hpp)
  std::function<void()> frames_starting;  // told when the first frame begins, if set
};

struct CompareOptions {
  std::string a, b;
  int threshold = 8;
  std::string diff_output;  // empty: no diff picture
};

struct BenchOptions {
  std::string scenes;  // comma-separated scene names; empty: every scene
  int width = 1920;
  int height = 1080;
  int frames = 9;  // timed frames of each renderer per scene
  bool json = false;
  int device = -1;
  std::size_t memory_cap = kDefaultMemoryCap;
  int tile_size = kDeviceTileSize;
  std::string pictures;  // a directory for each scene's pictures; empty: none are written
};

// `text` safe to print on a terminal: control bytes (but newline and tab), C1 controls and bytes
// that are not UTF-8 become \xNN escapes, so a file's contents quoted in a message cannot move
// the cursor, recolour or retitle the user's terminal.
std::string printable(std::string_view text);

int render(const RenderOptions& options);
int compare(const CompareOptions& options);
int bench(const BenchOptions& options);
int devices();

// Refuses an output path that cannot be written before any work is done, so a long run never
// ends in a failed save (an empty path is a UsageError).
void check_output_writable(const std::string& path);

// The camera a render uses: `base` (fitted to the model, or the demo's), overridden by the options.
io::Camera choose_camera(const RenderOptions& options, const io::BoundingSphere& bounds, io::Camera base);

}  // namespace clraster::cli
