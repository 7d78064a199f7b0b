#include "cli/commands.hpp"
#include "cli/demo_scene.hpp"
#include "io/image_io.hpp"
#include "io/model_loader.hpp"
#include "oracle/gl_renderer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <iostream>
#include <unistd.h>

#include <nlohmann/json.hpp>

namespace clraster::cli {
namespace {

// Refuses an output path that cannot be written before any work is done, so a long render never
// ends in a failed save.
void check_output_writable(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path file(path);
  std::error_code error;
  if (fs::is_directory(file, error)) throw InvalidArgument("cannot write " + path + ": it is a directory");
  const fs::path parent = file.has_parent_path() ? file.parent_path() : fs::path(".");
  if (!fs::is_directory(parent, error)) throw InvalidArgument("cannot write " + path + ": no directory " + parent.string());
  if (::access(parent.c_str(), W_OK) != 0 || (fs::exists(file, error) && ::access(file.c_str(), W_OK) != 0)) {
    throw InvalidArgument("cannot write " + path + ": permission denied");
  }
}

struct FrameTimes {
  double first_ms = 0;
  std::vector<double> timed_ms;
};

// One warm-up frame (program builds included), then `frames` timed ones.
FrameTimes time_frames(int frames, const std::function<void()>& frame) {
  const auto run = [&] {
    const auto start = std::chrono::steady_clock::now();
    frame();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  };
  FrameTimes times;
  times.first_ms = run();
  for (int i = 0; i < frames; ++i) times.timed_ms.push_back(run());
  return times;
}

DrawState make_state(const RenderOptions& options, const io::Camera& camera) {
  DrawState state;
  state.model_view = io::to_mat4(io::view_matrix(camera));
  state.projection = io::to_mat4(io::projection_matrix(camera, static_cast<float>(options.width) / options.height));
  state.cull = options.cull;
  switch (options.shading) {
    case ShadingOption::Normal: state.shading = Shading::Normal; break;
    case ShadingOption::Lambert:
      state.shading = Shading::Lambert;
      state.base_color = {0.85f, 0.85f, 0.85f, 1.0f};
      break;
    case ShadingOption::Depth:
      state.shading = Shading::Depth;
      state.depth_shading_range = {camera.near_plane, camera.far_plane};
      break;
    case ShadingOption::Overdraw:
      // Every fragment adds 1/255: the red channel counts the fragments of each pixel.
      state.shading = Shading::Constant;
      state.base_color = {1.0f / 255, 1.0f / 255, 1.0f / 255, 1.0f / 255};
      state.blend[0] = kAdditiveBlend;
      state.depth_test = false;
      break;
  }
  return state;
}

}  // namespace

io::Camera choose_camera(const RenderOptions& options, const io::BoundingSphere& bounds, io::Camera camera) {
  camera.fov_degrees = options.fov_degrees;
  if (options.eye || options.target) {
    camera.eye = options.eye.value_or(camera.eye);
    camera.target = options.target.value_or(camera.target);
    // Near and far enclose the scene as seen from the new eye.
    const glm::vec3 centre{bounds.center.x, bounds.center.y, bounds.center.z};
    const float radius = std::max(bounds.radius, 1e-3f) * 1.05f;
    const float distance = glm::length(centre - camera.eye);
    camera.far_plane = distance + radius;
    camera.near_plane = std::max(distance - radius, camera.far_plane * 1e-4f);
  }
  if (options.up) camera.up = *options.up;
  if (options.near_plane) camera.near_plane = *options.near_plane;
  if (options.far_plane) camera.far_plane = *options.far_plane;
  io::validate_camera(camera);
  return camera;
}

int render(const RenderOptions& options) {
  check_output_writable(options.output);
  std::vector<std::string> warnings;
  const io::Mesh mesh = options.model.empty() ? make_demo_scene() : io::load_model(options.model, warnings);
  for (const std::string& warning : warnings) std::cerr << "clraster: warning: " << warning << '\n';
  const io::BoundingSphere bounds = io::bounding_sphere(mesh);
  const float aspect = static_cast<float>(options.width) / static_cast<float>(options.height);
  const io::Camera camera = choose_camera(
      options, bounds,
      options.model.empty() ? demo_camera(options.fov_degrees) : io::fit_camera(bounds, aspect, options.fov_degrees));
  const DrawState state = make_state(options, camera);

  nlohmann::json stats;
  Image image;
  FrameTimes times;
  if (options.backend == Backend::Clraster) {
    ContextOptions context_options;
    context_options.device = options.device;
    context_options.memory_cap = options.memory_cap;
    context_options.tile_size = options.tile_size;
    context_options.profile = options.stats;
    Context context(context_options);
    const VertexBuffer vertices(context, mesh.positions, mesh.normals);
    const IndexBuffer indices(context, mesh.indices);
    Framebuffer framebuffer(context, options.width, options.height);
    DrawCall call;
    call.vertices = &vertices;
    call.indices = &indices;
    call.state = state;
    DrawStats draw_stats;
    times = time_frames(options.frames, [&] {
      framebuffer.clear({0, 0, 0, 1}, 1.0f);
      draw_stats = framebuffer.draw(call);
      context.finish();
    });
    image = framebuffer.read_color();
    const StageTimes& stage = draw_stats.stage_times;
    stats = {{"backend", "clraster"},
             {"device", context.device().name},
             {"triangles_dropped", draw_stats.triangles_dropped},
             {"chunks", draw_stats.chunks},
             {"tile_triangle_pairs", draw_stats.tile_triangle_pairs},
             {"peak_memory_bytes", draw_stats.peak_memory_bytes},
             {"stage_ms",
              {{"vertex", stage.vertex_ms},
               {"setup", stage.setup_ms},
               {"binning", stage.binning_ms},
               {"raster", stage.raster_ms},
               {"other", stage.other_ms}}}};
  } else {
    const oracle::GlMesh gl_mesh(mesh.positions, mesh.normals, mesh.indices);
    oracle::GlRenderer gl(options.width, options.height);
    times = time_frames(options.frames, [&] {
      gl.clear({0, 0, 0, 1}, 1.0f);
      gl.draw(gl_mesh, 0, kAllElements, state);
      gl.finish();
    });
    image = gl.read_color();
    // OpenGL does not say how it drew: clraster's own counters are null.
    stats = {{"backend", "gl"},     {"device", gl.renderer()},       {"triangles_dropped", nullptr},
             {"chunks", nullptr}, {"tile_triangle_pairs", nullptr}, {"peak_memory_bytes", nullptr},
             {"stage_ms", nullptr}};
  }
  io::save_png(options.output, image);

  if (options.stats) {
    stats["first_frame_ms"] = times.first_ms;
    // Without timed frames (--frames 0) there is no median or minimum to report: null.
    stats["median_ms"] = nullptr;
    stats["min_ms"] = nullptr;
    if (!times.timed_ms.empty()) {
      std::vector<double> sorted = times.timed_ms;
      std::sort(sorted.begin(), sorted.end());
      const std::size_t middle = sorted.size() / 2;
      stats["median_ms"] = sorted.size() % 2 ? sorted[middle] : (sorted[middle - 1] + sorted[middle]) / 2;
      stats["min_ms"] = sorted.front();
    }
    stats["triangles"] = mesh.triangle_count();
    stats["width"] = options.width;
    stats["height"] = options.height;
    stats["frames"] = options.frames;
    std::cout << stats.dump() << std::endl;
  }
  return 0;
}

}  // namespace clraster::cli
