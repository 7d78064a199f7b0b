#include "cli/commands.hpp"
#include "cli/demo_scene.hpp"
#include "frontend/gl_model_draws.hpp"
#include "frontend/model_draws.hpp"
#include "io/image_io.hpp"
#include "io/model_loader.hpp"
#include "io/shading.hpp"
#include "oracle/gl_renderer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <sys/resource.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

namespace clraster::cli {
namespace {

struct FrameTimes {
  double first_ms = 0;
  std::vector<double> timed_ms;
};

// One warm-up frame (program builds included), then options.frames timed ones.
FrameTimes time_frames(const RenderOptions& options, const std::function<void()>& frame) {
  if (options.frames_starting) options.frames_starting();
  const auto run = [&] {
    const auto start = std::chrono::steady_clock::now();
    frame();
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  };
  FrameTimes times;
  times.first_ms = run();
  for (int i = 0; i < options.frames; ++i) times.timed_ms.push_back(run());
  return times;
}

// The most memory the process has held at once, resident: the model, the framebuffers and the
// pipeline's buffers (device memory is host memory on CPU devices; on a GPU they are not in it), the
// picture read back and its PNG encoding: everything but what the kernel swapped out.
std::uint64_t peak_resident_bytes() {
  struct rusage usage {};
  ::getrusage(RUSAGE_SELF, &usage);
  return static_cast<std::uint64_t>(usage.ru_maxrss) * 1024;  // Linux counts kilobytes
}

// Whether the model is drawn by a program following the command line's contract (part by part,
// with its materials) rather than by one of the library's built-in shadings.
bool draws_materials(const RenderOptions& options) {
  return !options.program.empty() || options.shading == ShadingOption::Material;
}

void print_warnings(const std::vector<std::string>& warnings) {
  for (const std::string& warning : warnings) std::cerr << "clraster: warning: " << printable(warning) << '\n';
}

// The model file, loaded in a process of its own with limits: a file that crashes or exhausts the
// parser is an error, not the end of this process. A limit that was reached is named with the option
// that raises it.
io::Model load_model_file(const RenderOptions& options, std::vector<std::string>& warnings) {
  try {
    return io::load_model_isolated(options.model, warnings, options.model_limits);
  } catch (const io::ModelLoadLimitExceeded& error) {
    const bool memory = error.limit() == io::ModelLoadLimitExceeded::Limit::kMemory;
    throw InvalidArgument(std::string(error.what()) + "; " +
                          (memory ? "--model-memory-limit MiB" : "--model-time-limit SECONDS") + " raises it");
  }
}

// The model file, or the built-in demo scene as a model of one part with a white material.
io::Model load_scene(const RenderOptions& options) {
  std::vector<std::string> warnings;
  io::Model model;
  if (options.model.empty()) {
    static_cast<io::Mesh&>(model) = make_demo_scene();
    model.materials.emplace_back();
    model.parts.push_back({0, static_cast<std::uint32_t>(model.indices.size()), 0});
  } else {
    model = load_model_file(options, warnings);
  }
  if (model.triangles_dropped > 0) {
    warnings.push_back(options.model + ": " + io::describe_triangles_dropped(model.triangles_dropped));
  }
  print_warnings(warnings);
  return model;
}

DrawState make_state(const RenderOptions& options, const io::Camera& camera) {
  io::BuiltinShading shading = io::BuiltinShading::Normal;  // also for material: programs read no built-in input
  switch (options.shading) {
    case ShadingOption::Normal:
    case ShadingOption::Material: break;
    case ShadingOption::Lambert: shading = io::BuiltinShading::Lambert; break;
    case ShadingOption::Depth: shading = io::BuiltinShading::Depth; break;
    case ShadingOption::Overdraw: shading = io::BuiltinShading::Overdraw; break;
  }
  DrawState state =
      io::shading_state(shading, camera, static_cast<float>(options.width) / static_cast<float>(options.height));
  state.cull = options.cull;
  return state;
}

// A backend's picture, frame times and statistics (its own keys of the --stats line).
struct Rendering {
  Image image;
  FrameTimes times;
  nlohmann::json stats;
};

// The program of --program or of --shading material, checked against the command line's contract.
frontend::ProgramSource contract_program(const RenderOptions& options) {
  frontend::ProgramSource program = options.program.empty()
                                        ? frontend::ProgramSource{frontend::kMaterialProgram, "<material>"}
                                        : frontend::read_program_file(options.program);
  frontend::check_contract(program);
  return program;
}

// `program`: what draws the model's materials, or none for a built-in shading.
Rendering render_with_clraster(const RenderOptions& options, const io::Model& model, const io::Camera& camera,
                               const DrawState& state, const std::optional<frontend::ProgramSource>& program) {
  ContextOptions context_options;
  context_options.device = options.device;
  context_options.memory_cap = options.memory_cap;
  context_options.tile_size = options.tile_size;
  context_options.profile = options.stats;
  Context context(context_options);
  const VertexBuffer vertices(context, model.positions, model.normals);
  const IndexBuffer indices(context, model.indices);
  Framebuffer framebuffer(context, options.width, options.height);

  std::optional<Program> compiled;
  std::optional<frontend::ClrasterModelDraws> material_draws;
  std::vector<DrawCall> calls;
  if (program) {
    std::vector<std::string> warnings;
    material_draws.emplace(context, compiled.emplace(context, program->text, program->file_name), model, warnings);
    print_warnings(warnings);
    const frontend::ProgramInputs view = frontend::view_inputs(camera, options.width, options.height);
    material_draws->bind({&view, 1});
    calls = material_draws->calls(vertices, indices, state);
  } else {
    DrawCall& call = calls.emplace_back();
    call.vertices = &vertices;
    call.indices = &indices;
    call.state = state;
  }

  Rendering rendering;
  DrawStats frame_stats;
  rendering.times = time_frames(options, [&] {
    framebuffer.clear({0, 0, 0, 1}, 1.0f);
    frame_stats = framebuffer.draw(calls);  // one frame: the parts rasterized together
    context.finish();
  });
  rendering.image = framebuffer.read_color();
  const StageTimes& stage = frame_stats.stage_times;
  rendering.stats = {{"backend", "clraster"},
                     {"device", context.device().name},
                     {"draws", calls.size()},
                     // Those the model loader left out, and those the pipeline dropped.
                     {"triangles_dropped", model.triangles_dropped + frame_stats.triangles_dropped},
                     {"chunks", frame_stats.chunks},
                     {"tile_triangle_pairs", frame_stats.tile_triangle_pairs},
                     {"pipeline_memory_bytes", frame_stats.peak_memory_bytes},
                     {"framebuffer_bytes", framebuffer.color().memory_bytes() + framebuffer.depth_stencil()->memory_bytes()},
                     {"stage_ms",
                      {{"vertex", stage.vertex_ms},
                       {"setup", stage.setup_ms},
                       {"binning", stage.binning_ms},
                       {"raster", stage.raster_ms},
                       {"other", stage.other_ms}}}};
  return rendering;
}

Rendering render_with_gl(const RenderOptions& options, const io::Model& model, const io::Camera& camera,
                         const DrawState& state) {
  oracle::GlRenderer gl(options.width, options.height);
  std::optional<oracle::GlMesh> mesh;
  std::optional<frontend::GlMaterialDraws> material_draws;
  if (draws_materials(options)) {
    std::vector<std::string> warnings;
    material_draws.emplace(model, frontend::view_inputs(camera, options.width, options.height), warnings);
    print_warnings(warnings);
  } else {
    mesh.emplace(model.positions, model.normals, model.indices);
  }

  Rendering rendering;
  rendering.times = time_frames(options, [&] { frontend::draw_gl_frame(gl, state, mesh, material_draws); });
  rendering.image = gl.read_color();
  // OpenGL does not say how it drew: clraster's own counters are null (triangles_dropped too: the
  // loader's count alone would pass for the whole; the warning line gives it).
  rendering.stats = {{"backend", "gl"},
                     {"device", gl.renderer()},
                     {"draws", material_draws ? material_draws->draw_count() : 1},
                     {"triangles_dropped", nullptr},
                     {"chunks", nullptr},
                     {"tile_triangle_pairs", nullptr},
                     {"pipeline_memory_bytes", nullptr},
                     {"framebuffer_bytes", nullptr},
                     {"stage_ms", nullptr}};
  return rendering;
}

}  // namespace

void check_output_writable(const std::string& path) {
  namespace fs = std::filesystem;
  if (path.empty()) throw UsageError("--output: the path is empty");
  const fs::path file(path);
  std::error_code error;
  if (fs::is_directory(file, error)) throw InvalidArgument("cannot write " + path + ": it is a directory");
  const fs::path parent = file.has_parent_path() ? file.parent_path() : fs::path(".");
  if (!fs::is_directory(parent, error)) throw InvalidArgument("cannot write " + path + ": no directory " + parent.string());
  if (::access(parent.c_str(), W_OK) != 0 || (fs::exists(file, error) && ::access(file.c_str(), W_OK) != 0)) {
    throw InvalidArgument("cannot write " + path + ": permission denied");
  }
}

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
  // The fitted camera is valid: what makes this one invalid came from the options.
  as_usage_error([&] { io::validate_camera(camera); });
  return camera;
}

int render(const RenderOptions& options) {
  if (!options.program.empty() && options.backend == Backend::Gl) {
    throw UsageError("--program " + options.program +
                          ": the gl backend cannot run OpenCL C programs (it draws the --shading modes, material "
                          "included); use --backend clraster");
  }
  check_output_writable(options.output);
  // Before the model is loaded: a program the command line cannot serve is refused at once.
  std::optional<frontend::ProgramSource> program;
  if (options.backend == Backend::Clraster && draws_materials(options)) program = contract_program(options);
  const io::Model model = load_scene(options);
  const io::BoundingSphere bounds = io::bounding_sphere(model);
  const float aspect = static_cast<float>(options.width) / static_cast<float>(options.height);
  const io::Camera camera = choose_camera(
      options, bounds,
      options.model.empty() ? demo_camera(options.fov_degrees) : io::fit_camera(bounds, aspect, options.fov_degrees));
  const DrawState state = make_state(options, camera);
  const Rendering rendering = options.backend == Backend::Clraster
                                  ? render_with_clraster(options, model, camera, state, program)
                                  : render_with_gl(options, model, camera, state);
  io::save_png(options.output, rendering.image);

  if (options.stats) {
    const FrameTimes& times = rendering.times;
    nlohmann::json stats = rendering.stats;
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
    // The model file's, those the loader left out included: triangles_dropped counts them too.
    stats["triangles"] = model.triangle_count() + model.triangles_dropped;
    stats["width"] = options.width;
    stats["height"] = options.height;
    stats["frames"] = options.frames;
    stats["peak_memory_bytes"] = peak_resident_bytes();
    std::cout << stats.dump() << std::endl;
  }
  return 0;
}

}  // namespace clraster::cli
