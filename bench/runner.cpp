#include "bench/runner.hpp"

#include "frontend/gl_model_draws.hpp"
#include "frontend/model_draws.hpp"
#include "oracle/gl_renderer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#ifdef __GLIBC__
#include <malloc.h>
#endif

namespace clraster::bench {
namespace {

using Clock = std::chrono::steady_clock;

double milliseconds_since(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t middle = values.size() / 2;
  return values.size() % 2 ? values[middle] : (values[middle - 1] + values[middle]) / 2;
}

double median_of(const std::vector<StageTimes>& frames, double StageTimes::*stage) {
  std::vector<double> values;
  for (const StageTimes& frame : frames) values.push_back(frame.*stage);
  return median(values);
}

// A scene's materials are built in and their textures embedded: nothing to warn about. A warning
// would mean the scene is not drawn as it says.
void require_no_warnings(const std::vector<std::string>& warnings, const std::string& scene) {
  if (!warnings.empty()) throw Error("benchmark scene " + scene + ": " + warnings.front());
}

// A scene on clraster: its mesh in device buffers, drawn into textures of the formats GlRenderer
// draws into, with its built-in shading in one draw or with the material program part by part; a
// scene of views in one draw into a layered framebuffer (RGBA8 and Depth32FStencil8: its own
// attachments, which draw depth as GL's Depth32F does).
class ClrasterScene {
 public:
  // width x height: a layer's size (Scene::layer_width).
  ClrasterScene(Context& context, const Scene& scene, const DrawState& state, int width, int height)
      : context_(context),
        vertices_(context, scene.model.positions, scene.model.normals),
        indices_(context, scene.model.indices),
        framebuffer_(make_framebuffer(context, scene, width, height)) {
    if (scene.draws_materials()) {
      std::vector<std::string> warnings;
      material_draws_.emplace(context, material_program_.emplace(context, frontend::kMaterialProgram, "<material>"),
                              scene.model, warnings);
      require_no_warnings(warnings, scene.name);
      const frontend::ProgramInputs view = frontend::view_inputs(scene.camera, width, height);
      material_draws_->bind({&view, 1});
      calls_ = material_draws_->calls(vertices_, indices_, state);
    } else if (!scene.instances.empty()) {
      const Program& program = instanced_program_.emplace(context, kInstancedProgram, "<instanced>");
      instanced_bindings_.emplace(program).set("mvp", frontend::view_inputs(scene.camera, width, height).mvp);
      const Buffer& placements = placements_.emplace(context, scene.instances);
      DrawCall& call = calls_.emplace_back();
      call.vertices = &vertices_;
      call.indices = &indices_;
      call.program = &program;
      call.bindings = &*instanced_bindings_;
      call.attributes = {{"placement", &placements, AttributeType::Float4, 0, 0, true}};
      call.instance_count = scene.instance_count();
      call.state = state;
    } else {
      DrawCall& call = calls_.emplace_back();
      call.vertices = &vertices_;
      call.indices = &indices_;
      call.state = state;
      call.views = scene.view_matrices();
    }
  }
  ClrasterScene(const ClrasterScene&) = delete;  // the framebuffer and the calls point into it
  ClrasterScene& operator=(const ClrasterScene&) = delete;

  // One frame of every part's draw.
  DrawStats frame() {
    framebuffer_.clear({0, 0, 0, 1}, 1.0f);
    const DrawStats stats = framebuffer_.draw(calls_);
    context_.finish();
    return stats;
  }

  // The layers side by side as the framebuffer holds them (Framebuffer::layer_rect), each read as
  // an application reads it: the picture GlScene draws.
  Image picture() const {
    const int columns = framebuffer_.layer_columns();
    const int rows = (framebuffer_.layers() + columns - 1) / columns;
    Image picture{framebuffer_.width() * columns, framebuffer_.height() * rows, {}};
    picture.rgba.resize(std::size_t(picture.width) * std::size_t(picture.height) * 4);
    for (int layer = 0; layer < framebuffer_.layers(); ++layer) {
      const Image read = framebuffer_.read_color(0, layer);
      const Rect rect = framebuffer_.layer_rect(layer);
      const int top = picture.height - rect.y - rect.height;  // rows from the top, rect's from the bottom
      for (int y = 0; y < read.height; ++y) {
        std::copy_n(&read.rgba[std::size_t(y) * std::size_t(read.width) * 4], std::size_t(read.width) * 4,
                    &picture.rgba[(std::size_t(top + y) * std::size_t(picture.width) + std::size_t(rect.x)) * 4]);
      }
    }
    return picture;
  }

 private:
  Framebuffer make_framebuffer(Context& context, const Scene& scene, int width, int height) {
    if (scene.draws_views()) return Framebuffer(context, width, height, scene.layer_count());
    return Framebuffer(context, {&color_.emplace(context, width, height, Format::RGBA8)},
                       &depth_.emplace(context, width, height, Format::Depth32F));
  }

  Context& context_;
  VertexBuffer vertices_;
  IndexBuffer indices_;
  std::optional<Texture> color_;  // none for a scene of views: the layered framebuffer's own
  std::optional<Texture> depth_;
  Framebuffer framebuffer_;
  std::optional<Program> material_program_;
  std::optional<frontend::ClrasterModelDraws> material_draws_;
  std::optional<Program> instanced_program_;  // an instanced scene's
  std::optional<Bindings> instanced_bindings_;
  std::optional<Buffer> placements_;
  std::vector<DrawCall> calls_;
};

// As an application would draw its first frame: without profiling.
double time_first_frame(const Scene& scene, const DrawState& state, const RunOptions& options, int width,
                        int height) {
  ContextOptions unprofiled = options.context;
  unprofiled.profile = false;
  const Clock::time_point start = Clock::now();
  Context context(unprofiled);
  ClrasterScene drawn(context, scene, state, width, height);
  drawn.frame();
  return milliseconds_since(start);
}

}  // namespace

// glibc gives memory freed at the top of a heap back to the system once it exceeds the trim
// threshold, and llvmpipe frees and allocates its per-frame memory every frame: depending on
// what ran before in the process, its frames then page that memory in again each time or not
// (model-50k run first, 29 ms a frame; after another scene, or with this, 20-22 ms; clraster's
// buffers stay allocated and it ran the same). Keeping freed memory makes every scene's frames
// the steady state of a running application, whatever the order.
void keep_freed_memory() {
#ifdef __GLIBC__
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
#endif
}

GlScene::GlScene(const Scene& scene, const DrawState& state, int width, int height)
    : renderer_(width * scene.layer_columns(), height * scene.layer_rows()),
      state_(state),
      view_states_(scene.view_states(state, width, height)) {
  if (scene.draws_materials()) {
    model_ = scene.model;
    std::vector<std::string> warnings;
    material_draws_.emplace(*model_, frontend::view_inputs(scene.camera, width, height), warnings);
    require_no_warnings(warnings, scene.name);
  } else if (!scene.instances.empty()) {
    instanced_.emplace(scene, frontend::view_inputs(scene.camera, width, height).mvp, state);
  } else {
    mesh_.emplace(scene.model.positions, scene.model.normals, scene.model.indices);
  }
}

GlScene::Instanced::Instanced(const Scene& scene, const Mat4& mvp, const DrawState& state)
    : program(kGlInstancedVertexShader, kGlInstancedFragmentShader, "instancing program (GLSL)"),
      input(program,
            std::vector<oracle::GlAttribute>{
                {"position", std::as_bytes(std::span(scene.model.positions)), AttributeType::Float3},
                {"normal", std::as_bytes(std::span(scene.model.normals)), AttributeType::Float3},
                {"placement", std::as_bytes(std::span(scene.instances)), AttributeType::Float4, 0, 0, true}},
            std::span<const std::uint32_t>(scene.model.indices)) {
  program.set("mvp", std::span<const float>(mvp));
  call.program = &program;
  call.vertex_input = &input;
  call.instance_count = scene.instance_count();
  call.state = state;
}

void GlScene::frame() {
  if (!instanced_ && view_states_.empty()) return frontend::draw_gl_frame(renderer_, state_, mesh_, material_draws_);
  // As draw_gl_frame, with one instanced draw or a draw per view instead of the mesh's one.
  renderer_.clear({0, 0, 0, 1}, 1.0f);
  if (instanced_) renderer_.draw(instanced_->call);
  for (const DrawState& view : view_states_) renderer_.draw(*mesh_, 0, kAllElements, view);
  renderer_.finish();
}

Image GlScene::picture() const { return renderer_.read_color(); }
std::string GlScene::renderer() const { return renderer_.renderer(); }

SceneRun run_scene(const Scene& scene, const RunOptions& options) {
  if (options.frames < 1) throw InvalidArgument("a benchmark needs at least one timed frame");
  keep_freed_memory();
  const int width = scene.layer_width(options.width);
  const int height = scene.layer_height(options.height);
  const DrawState state = scene.state(width, height);
  SceneRun run;
  SceneResult& result = run.result;
  result.name = scene.name;
  result.triangles = scene.triangle_count();
  result.draws = scene.draw_count();
  result.width = width;
  result.height = height;
  result.layers = scene.layer_count();
  {
    ContextOptions profiled = options.context;
    profiled.profile = true;
    Context context(profiled);
    ClrasterScene ours(context, scene, state, width, height);
    GlScene theirs(scene, state, width, height);
    result.device = context.device().name;
    result.tile_size = context.options().tile_size;
    result.gl_renderer = theirs.renderer();

    for (int i = 0; i < kWarmupFrames; ++i) {
      ours.frame();
      theirs.frame();
    }
    std::vector<StageTimes> stages;
    for (int i = 0; i < options.frames; ++i) {
      Clock::time_point start = Clock::now();
      const DrawStats stats = ours.frame();
      result.clraster_frame_ms.push_back(milliseconds_since(start));
      stages.push_back(stats.stage_times);
      result.pipeline_memory_bytes = stats.peak_memory_bytes;

      start = Clock::now();
      theirs.frame();
      result.gl_frame_ms.push_back(milliseconds_since(start));
    }
    result.clraster_ms = median(result.clraster_frame_ms);
    result.gl_ms = median(result.gl_frame_ms);
    result.stage_ms = {median_of(stages, &StageTimes::vertex_ms), median_of(stages, &StageTimes::setup_ms),
                       median_of(stages, &StageTimes::binning_ms), median_of(stages, &StageTimes::raster_ms),
                       median_of(stages, &StageTimes::other_ms)};
    run.clraster_picture = ours.picture();
    run.gl_picture = theirs.picture();
  }
  // Once the timed context is gone, so that the two do not hold the scene's memory at once.
  result.first_frame_ms = time_first_frame(scene, state, options, width, height);
  result.comparison = io::compare_images(run.clraster_picture, run.gl_picture, kTolerance);
  result.passed = io::within(result.comparison, kTolerance);
  return run;
}

double geometric_mean_ratio(const std::vector<SceneResult>& results) {
  double log_sum = 0;
  int count = 0;
  for (const SceneResult& result : results) {
    if (!result.passed) continue;
    log_sum += std::log(result.ratio());
    ++count;
  }
  return count == 0 ? std::numeric_limits<double>::quiet_NaN() : std::exp(log_sum / count);
}

}  // namespace clraster::bench
