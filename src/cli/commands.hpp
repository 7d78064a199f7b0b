// The clraster command line: one function per subcommand, each a thin client of the library.
#pragma once

#include "io/camera.hpp"
#include "io/isolated_loader.hpp"

#include <optional>
#include <string>

namespace clraster::cli {

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

int render(const RenderOptions& options);
int compare(const CompareOptions& options);
int bench(const BenchOptions& options);
int devices();

// Refuses an output path that cannot be written before any work is done, so a long run never
// ends in a failed save.
void check_output_writable(const std::string& path);

// The camera a render uses: `base` (fitted to the model, or the demo's), overridden by the options.
io::Camera choose_camera(const RenderOptions& options, const io::BoundingSphere& bounds, io::Camera base);

}  // namespace clraster::cli
