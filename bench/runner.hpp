// Times a benchmark scene drawn by clraster and by Mesa's OpenGL (llvmpipe, headless EGL) in the
// same process, a frame of one then a frame of the other, and checks that both drew the same
// picture.
//
// A frame is the same for both: clear to (0, 0, 0, 1) and depth 1, the scene's draws (one, or one
// per part of a model; a scene of views is one draw for clraster, one per view for OpenGL) from
// buffers uploaded before, finish (Context::finish, glFinish), timed with steady_clock around the
// three. Both draw into an RGBA8 colour and a Depth32F depth attachment (no stencil to clear; a
// scene of views: clraster's layered framebuffer's Depth32FStencil8, its stencil unused). Nothing
// is read back inside a frame, and every clraster frame runs every pipeline stage: of an earlier
// frame the library keeps only what it read of the index buffer, the largest index of the range
// and the index ranges of its blocks of primitives (block culling), which cannot change.
// The process keeps the memory it frees (glibc's trim threshold raised), so that neither renderer
// pays for paging in again, each frame, memory it freed in the previous one (runner.cpp).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "bench/scenes.hpp"
#include "clraster/clraster.hpp"
#include "frontend/gl_model_draws.hpp"
#include "io/image_compare.hpp"
#include "oracle/gl_renderer.hpp"

namespace clraster::bench {

struct RunOptions {
  int width = 1920;
  int height = 1080;
  int frames = 9;          // timed frames of each renderer (at least 1), after kWarmupFrames
  ContextOptions context;  // device, memory cap, tile size; profiling is switched on for the timed frames
};

// Untimed frames of each renderer before the timed ones: the first grows clraster's scratch
// buffers and has llvmpipe compile its shaders; the second starts from that steady state.
inline constexpr int kWarmupFrames = 2;

// The pictures must agree within the core pipeline's conformance thresholds.
inline constexpr io::Tolerance kTolerance = io::kNormalShading;

struct SceneResult {
  std::string name;
  std::uint64_t triangles = 0;
  std::size_t draws = 0;
  int width = 0;  // of a layer: a scene of views draws `layers` (Scene::layer_width)
  int height = 0;
  int layers = 1;
  std::string device;       // clraster's OpenCL device
  int tile_size = 0;        // and the tile size its context took
  std::string gl_renderer;  // GL_RENDERER and GL_VERSION
  std::vector<double> clraster_frame_ms;  // the timed frames, in order
  std::vector<double> gl_frame_ms;
  double clraster_ms = 0;  // the medians of those
  double gl_ms = 0;
  // Per stage, the median over the timed frames of the stage's device time (OpenCL profiling
  // events), summed over the frame's draws. The frame's clears are pending until the raster stage
  // writes them with its tiles.
  StageTimes stage_ms;
  // A new Context's first frame: from the Context's construction (programs loaded from the disk
  // cache, which the timed context filled if it was empty) to the end of its first frame, uploads
  // included.
  double first_frame_ms = 0;
  std::uint64_t pipeline_memory_bytes = 0;  // the pipeline's intermediate buffers at their peak
  io::ImageComparison comparison;       // clraster's last timed frame against llvmpipe's
  bool passed = false;                  // comparison is within kTolerance

  double ratio() const { return clraster_ms / gl_ms; }
};

struct SceneRun {
  SceneResult result;
  Image clraster_picture;  // the last timed frames
  Image gl_picture;
};

// A scene on llvmpipe as the benchmark draws it, through the OpenGL oracle: its mesh with its
// built-in shading in one draw, or its model with the material program part by part, as the
// command line draws models (frontend::GlMaterialDraws), a frame as `render --backend gl` draws one
// (frontend::draw_gl_frame); a scene of views in one picture of its layers side by side, a draw per
// view with the viewport on its layer. bench/gl_minimal.cpp times it against OpenGL used directly.
class GlScene {
 public:
  // width x height: a layer's size (Scene::layer_width).
  GlScene(const Scene& scene, const DrawState& state, int width, int height);
  GlScene(const GlScene&) = delete;  // the material draws point into the model
  GlScene& operator=(const GlScene&) = delete;

  // Clears to (0, 0, 0, 1) and depth 1, draws, and waits for the rendering (glFinish).
  void frame();
  Image picture() const;
  std::string renderer() const;

 private:
  oracle::GlRenderer renderer_;
  DrawState state_;
  std::optional<oracle::GlMesh> mesh_;  // a scene with a built-in shading
  std::optional<io::Model> model_;      // or one with materials, drawn part by part
  std::optional<frontend::GlMaterialDraws> material_draws_;
  // Or an instanced scene: its mesh and placements uploaded once, drawn with glDrawElementsInstanced.
  struct Instanced {
    Instanced(const Scene& scene, const Mat4& mvp, const DrawState& state);
    oracle::GlProgram program;
    oracle::GlVertexInput input;
    oracle::GlDrawCall call;
  };
  std::optional<Instanced> instanced_;
  // Or a scene of views: `mesh_` drawn with each view's state, its camera and its layer's viewport.
  std::vector<DrawState> view_states_;
};

// Has the process keep the memory it frees (runner.cpp says why); run_scene calls it.
void keep_freed_memory();

// Runs one scene: a profiling Context and a GlRenderer, kWarmupFrames then options.frames timed
// frames of each in turn, the pictures compared, then the first frame of a new Context. Throws
// clraster::Error when either renderer fails.
SceneRun run_scene(const Scene& scene, const RunOptions& options);

// The geometric mean of the ratios of the scenes that passed; NaN when none did.
double geometric_mean_ratio(const std::vector<SceneResult>& results);

}  // namespace clraster::bench
