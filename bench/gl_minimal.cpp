// The lean check of `clraster bench`: draws the benchmark's scenes with Mesa's llvmpipe (OpenGL 4.5
// core through headless EGL) as plainly as a user after speed would, and times its frames in turn
// with those of the path the benchmark times (bench::GlScene, the OpenGL oracle), in one process,
// checking that both draw the same picture. Usage:
//   build/bench/clraster_gl_minimal [--scenes model-50k,fill-16,materials-256] [--frames 9] [--size 1920x1080]
//
// The plain way: renderbuffers of the oracle's formats (RGBA8, 32-bit float depth), one small GLSL
// program per scene, one vertex array, all state set once; a frame is one glClear, per part a
// glUniform4fv of its colour and a glDrawElements, and glFinish. The scenes of materials
// (materials-256, engine-glb) are drawn part by part with the material program, as the command line
// draws a model; a scene of views (views-64) into one picture of its layers side by side, per view
// a glViewport on its layer, a glUniformMatrix4fv of its mvp and a glDrawElements.
#include "bench/runner.hpp"
#include "bench/scenes.hpp"
#include "frontend/gl_model_draws.hpp"
#include "io/image_io.hpp"
#include "pipeline/draw_state.hpp"

#define GL_GLEXT_PROTOTYPES
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using namespace clraster;
using Clock = std::chrono::steady_clock;

// ---- OpenGL, the plain way ------------------------------------------------------------------------

[[noreturn]] void fail(const std::string& what) { throw std::runtime_error(what); }

void check_gl(const char* what) {
  if (const GLenum error = glGetError(); error != GL_NO_ERROR) fail(std::string("GL error in ") + what);
}

// A headless OpenGL 4.5 core context of llvmpipe, as the oracle makes its own (gl_context.cpp).
class LeanContext {
 public:
  LeanContext() {
    setenv("LIBGL_ALWAYS_SOFTWARE", "1", 0);
    const auto get_platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!get_platform_display) fail("EGL lacks eglGetPlatformDisplayEXT");
    display_ = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display_ == EGL_NO_DISPLAY || !eglInitialize(display_, nullptr, nullptr)) fail("no surfaceless EGL display");
    if (!eglBindAPI(EGL_OPENGL_API)) fail("eglBindAPI");
    const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    context_ = eglCreateContext(display_, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
    if (context_ == EGL_NO_CONTEXT) fail("eglCreateContext");
    make_current();
  }
  // The oracle's context is current between the lean frames.
  void make_current() const {
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) fail("eglMakeCurrent");
  }

 private:
  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
};

GLuint compile(GLenum stage, const char* source) {
  const GLuint shader = glCreateShader(stage);
  glShaderSource(shader, 1, &source, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) fail("a lean shader does not compile");
  return shader;
}

GLuint link(const char* vertex_source, const char* fragment_source) {
  const GLuint program = glCreateProgram();
  const GLuint vertex = compile(GL_VERTEX_SHADER, vertex_source);
  const GLuint fragment = compile(GL_FRAGMENT_SHADER, fragment_source);
  glAttachShader(program, vertex);
  glAttachShader(program, fragment);
  glLinkProgram(program);
  glDeleteShader(vertex);
  glDeleteShader(fragment);
  GLint ok = GL_FALSE;
  glGetProgramiv(program, GL_LINK_STATUS, &ok);
  if (!ok) fail("a lean program does not link");
  return program;
}

// Shading::Normal and Shading::Constant as the oracle writes them (gl_renderer.cpp), each on its own.
constexpr const char* kNormalVertexShader = R"(#version 450 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 mvp;
out vec3 v;
void main() {
  gl_Position = mvp * vec4(position, 1.0);
  v = normal;
}
)";
constexpr const char* kNormalFragmentShader = R"(#version 450 core
in vec3 v;
layout(location = 0) out vec4 color;
void main() {
  float len = length(v);
  color = vec4(len > 0.0 ? v / len * 0.5 + 0.5 : vec3(0.5), 1.0);
}
)";
constexpr const char* kConstantVertexShader = R"(#version 450 core
layout(location = 0) in vec3 position;
uniform mat4 mvp;
void main() { gl_Position = mvp * vec4(position, 1.0); }
)";
constexpr const char* kConstantFragmentShader = R"(#version 450 core
uniform vec4 base_color;
layout(location = 0) out vec4 color;
void main() { color = base_color; }
)";

// What a scene draws: its mesh, its parts (index ranges, each with its colour), and how.
struct LeanPart {
  std::uint32_t first = 0;
  std::uint32_t count = 0;
  std::array<float, 4> color{1, 1, 1, 1};
};

enum class LeanShading { Normal, Overdraw, Material, Instanced };

// A view of a scene of views: where it is drawn and its camera.
struct LeanView {
  Rect viewport;
  Mat4 mvp{};
};

struct LeanSceneData {
  io::Mesh mesh;
  std::vector<LeanPart> parts;
  LeanShading shading = LeanShading::Normal;
  bool depth_test = true;
  Mat4 mvp{};
  frontend::ProgramInputs view;  // the material program's uniforms
  std::optional<Image> texture;  // the material's, rows from the top; none: one white texel
  std::vector<float> instances;  // an instanced scene's placements (bench::Scene::instances)
  std::vector<LeanView> views;   // a scene of views', each part drawn once per view
};

// Feeds attribute `location` (none when -1: the program does not use it) from a new buffer, which it returns.
GLuint upload_attribute(GLuint vertex_array, GLint location, const std::vector<float>& data, int components) {
  if (location < 0) return 0;
  GLuint buffer = 0;
  glCreateBuffers(1, &buffer);
  glNamedBufferStorage(buffer, GLsizeiptr(data.size() * sizeof(float)), data.data(), 0);
  glVertexArrayVertexBuffer(vertex_array, GLuint(location), buffer, 0, GLsizei(components * sizeof(float)));
  glVertexArrayAttribFormat(vertex_array, GLuint(location), components, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vertex_array, GLuint(location), GLuint(location));
  glEnableVertexArrayAttrib(vertex_array, GLuint(location));
  return buffer;
}

// A mipmapped RGBA8 texture, bound to unit 0 and sampled trilinearly with repeat (Sampler{}).
GLuint bind_texture(const std::optional<Image>& image) {
  const int width = image ? image->width : 1;
  const int height = image ? image->height : 1;
  std::vector<std::uint8_t> texels(std::size_t(width) * std::size_t(height) * 4, 255);
  const std::size_t row = std::size_t(width) * 4;
  for (int y = 0; image && y < height; ++y) {  // the image's bottom row at t = 0
    std::memcpy(&texels[std::size_t(height - 1 - y) * row], &image->rgba[std::size_t(y) * row], row);
  }
  const int levels = int(std::bit_width(unsigned(std::max(width, height))));
  GLuint texture = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &texture);
  glTextureStorage2D(texture, levels, GL_RGBA8, width, height);
  glTextureSubImage2D(texture, 0, 0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, texels.data());
  glGenerateTextureMipmap(texture);
  glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glBindTextureUnit(0, texture);
  return texture;
}

class LeanScene {
 public:
  LeanScene(const LeanContext& context, const LeanSceneData& scene, int width, int height)
      : context_(context), width_(width), height_(height), parts_(scene.parts), views_(scene.views) {
    context_.make_current();
    glCreateRenderbuffers(2, renderbuffers_);
    glNamedRenderbufferStorage(renderbuffers_[0], GL_RGBA8, width, height);
    glNamedRenderbufferStorage(renderbuffers_[1], GL_DEPTH_COMPONENT32F, width, height);
    glCreateFramebuffers(1, &framebuffer_);
    glNamedFramebufferRenderbuffer(framebuffer_, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, renderbuffers_[0]);
    glNamedFramebufferRenderbuffer(framebuffer_, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, renderbuffers_[1]);
    glBindFramebuffer(GL_FRAMEBUFFER, framebuffer_);
    glViewport(0, 0, width, height);

    switch (scene.shading) {
      case LeanShading::Normal: program_ = link(kNormalVertexShader, kNormalFragmentShader); break;
      case LeanShading::Overdraw: program_ = link(kConstantVertexShader, kConstantFragmentShader); break;
      case LeanShading::Material:
        program_ = link(frontend::kGlMaterialVertexShader, frontend::kGlMaterialFragmentShader);
        break;
      case LeanShading::Instanced: program_ = link(bench::kGlInstancedVertexShader, bench::kGlInstancedFragmentShader); break;
    }
    const GLuint program = program_;
    glUseProgram(program);
    if (scene.shading == LeanShading::Material) {
      glUniformMatrix4fv(glGetUniformLocation(program, "mvp"), 1, GL_FALSE, scene.view.mvp.data());
      glUniformMatrix4fv(glGetUniformLocation(program, "normal_matrix"), 1, GL_FALSE, scene.view.normal_matrix.data());
      glUniform3fv(glGetUniformLocation(program, "light_direction"), 1, scene.view.light_direction.data());
      texture_ = bind_texture(scene.texture);
    } else {
      mvp_location_ = glGetUniformLocation(program, "mvp");
      glUniformMatrix4fv(mvp_location_, 1, GL_FALSE, scene.mvp.data());
    }
    color_location_ = glGetUniformLocation(program, "base_color");
    // One colour for every part is set once.
    const bool one_color = std::all_of(parts_.begin(), parts_.end(),
                                       [&](const LeanPart& part) { return part.color == parts_.front().color; });
    if (one_color) {
      glUniform4fv(color_location_, 1, parts_.front().color.data());
      color_location_ = -1;
    }

    glCreateVertexArrays(1, &vertex_array_);
    buffers_[0] = upload_attribute(vertex_array_, glGetAttribLocation(program, "position"), scene.mesh.positions, 3);
    buffers_[1] = upload_attribute(vertex_array_, glGetAttribLocation(program, "normal"), scene.mesh.normals, 3);
    const std::vector<float> zeros(2 * scene.mesh.vertex_count(), 0.0f);
    buffers_[2] = upload_attribute(vertex_array_, glGetAttribLocation(program, "uv"),
                                   scene.mesh.texcoords.empty() ? zeros : scene.mesh.texcoords, 2);
    glCreateBuffers(1, &buffers_[3]);
    glNamedBufferStorage(buffers_[3], GLsizeiptr(scene.mesh.indices.size() * 4), scene.mesh.indices.data(), 0);
    glVertexArrayElementBuffer(vertex_array_, buffers_[3]);
    const GLint placement = glGetAttribLocation(program, "placement");
    buffers_[4] = upload_attribute(vertex_array_, placement, scene.instances, 4);
    if (placement >= 0) glVertexArrayBindingDivisor(vertex_array_, GLuint(placement), 1);
    instance_count_ = scene.instances.empty() ? 1 : GLsizei(scene.instances.size() / 4);
    glBindVertexArray(vertex_array_);

    // Both ways: the scenes before this one drew in the same context.
    scene.depth_test ? glEnable(GL_DEPTH_TEST) : glDisable(GL_DEPTH_TEST);  // GL_LESS, GL's default
    scene.shading == LeanShading::Overdraw ? glEnable(GL_BLEND) : glDisable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    glClearColor(0, 0, 0, 1);
    check_gl("setting up a lean scene");
  }
  LeanScene(const LeanScene&) = delete;
  LeanScene& operator=(const LeanScene&) = delete;

  ~LeanScene() {
    context_.make_current();
    glDeleteFramebuffers(1, &framebuffer_);
    glDeleteRenderbuffers(2, renderbuffers_);
    glDeleteProgram(program_);
    glDeleteVertexArrays(1, &vertex_array_);
    glDeleteBuffers(5, buffers_);
    glDeleteTextures(1, &texture_);
  }

  void frame() const {
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    for (const LeanPart& part : parts_) {
      if (color_location_ >= 0) glUniform4fv(color_location_, 1, part.color.data());
      if (views_.empty()) draw(part);
      for (const LeanView& view : views_) {
        glViewport(view.viewport.x, view.viewport.y, view.viewport.width, view.viewport.height);
        glUniformMatrix4fv(mvp_location_, 1, GL_FALSE, view.mvp.data());
        draw(part);
      }
    }
    glFinish();
  }

  Image picture() const {
    Image image{width_, height_, std::vector<std::uint8_t>(std::size_t(width_) * std::size_t(height_) * 4)};
    std::vector<std::uint8_t> rows(image.rgba.size());
    glReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, rows.data());
    check_gl("reading the lean picture");
    const std::size_t row = std::size_t(width_) * 4;
    for (int y = 0; y < height_; ++y) {
      std::memcpy(&image.rgba[std::size_t(height_ - 1 - y) * row], &rows[std::size_t(y) * row], row);
    }
    return image;
  }

  void make_current() const { context_.make_current(); }

 private:
  void draw(const LeanPart& part) const {
    glDrawElementsInstanced(GL_TRIANGLES, GLsizei(part.count), GL_UNSIGNED_INT,
                            reinterpret_cast<const void*>(std::uintptr_t(part.first) * 4), instance_count_);
  }

  const LeanContext& context_;
  int width_;
  int height_;
  std::vector<LeanPart> parts_;
  std::vector<LeanView> views_;
  GLint color_location_ = -1;  // set per part; -1 when every part has one colour
  GLint mvp_location_ = -1;    // set per view of a scene of views
  GLuint framebuffer_ = 0;
  GLuint renderbuffers_[2] = {};
  GLuint program_ = 0;
  GLuint vertex_array_ = 0;
  GLuint buffers_[5] = {};  // positions, normals, texture coordinates, indices, instance placements
  GLsizei instance_count_ = 1;
  GLuint texture_ = 0;
};

// ---- The scenes -----------------------------------------------------------------------------------

// The benchmark scene `name`, both for the lean program and for the oracle's path.
struct SceneSetup {
  LeanSceneData lean;
  bench::Scene scene;
  DrawState state;
  int width = 0;  // of a layer (bench::Scene::layer_width)
  int height = 0;
};

// run_width x run_height: the size the check runs at (--size).
SceneSetup make_setup(const std::string& name, int run_width, int run_height) {
  SceneSetup setup;
  setup.scene = bench::make_scene(name);
  const bench::Scene& scene = setup.scene;
  const int width = setup.width = scene.layer_width(run_width);
  const int height = setup.height = scene.layer_height(run_height);
  setup.state = scene.state(width, height);
  LeanSceneData& lean = setup.lean;
  lean.mesh = scene.model;
  lean.depth_test = setup.state.depth_test;
  lean.mvp = pipeline::model_view_projection(setup.state);
  lean.view = frontend::view_inputs(scene.camera, width, height);
  const auto index_count = static_cast<std::uint32_t>(scene.model.indices.size());
  if (scene.draws_materials()) {
    lean.shading = LeanShading::Material;
    for (const io::ModelPart& part : scene.model.parts) {
      const io::Material& material = scene.model.materials.at(part.material);
      lean.parts.push_back({part.first_index, part.index_count, material.base_color_factor});
      if (const auto& image = material.base_color_texture) {
        // One texture, bound once: the scenes have at most one textured material.
        if (lean.texture) fail("scene " + name + ": the lean check draws one texture only");
        lean.texture = io::decode_image(image->encoded, name);
      }
    }
  } else if (!scene.instances.empty()) {
    lean.shading = LeanShading::Instanced;
    lean.instances = scene.instances;
    lean.parts = {{0, index_count, setup.state.base_color}};
  } else {
    const bool additive = setup.state.blend[0].enabled;
    lean.shading = additive ? LeanShading::Overdraw : LeanShading::Normal;
    if (additive != (scene.shading == io::BuiltinShading::Overdraw) ||
        (!additive && scene.shading != io::BuiltinShading::Normal)) {
      fail("scene " + name + ": the lean check draws normal and overdraw shading only");
    }
    lean.parts = {{0, index_count, setup.state.base_color}};
  }
  for (const DrawState& view : scene.view_states(setup.state, width, height)) {
    lean.views.push_back({view.viewport, pipeline::model_view_projection(view)});
  }
  return setup;
}

// ---- Timing ---------------------------------------------------------------------------------------

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t middle = values.size() / 2;
  return values.size() % 2 ? values[middle] : (values[middle - 1] + values[middle]) / 2;
}

template <typename Frame>
double time_frame(Frame&& frame) {
  const Clock::time_point start = Clock::now();
  frame();
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// "identical", or how many bytes differ and by how much at most.
std::string compare(const Image& a, const Image& b) {
  std::size_t differ = 0;
  int most = 0;
  for (std::size_t i = 0; i < a.rgba.size() && i < b.rgba.size(); ++i) {
    const int difference = std::abs(int(a.rgba[i]) - int(b.rgba[i]));
    differ += difference != 0;
    most = std::max(most, difference);
  }
  if (differ == 0 && a.rgba.size() == b.rgba.size()) return "identical";
  return std::to_string(differ) + " bytes differ, by up to " + std::to_string(most);
}

struct Options {
  std::vector<std::string> scenes;
  int frames = 9;
  int width = 1920;
  int height = 1080;
};

Options parse(int argc, char** argv) {
  Options options;
  std::string scenes;
  for (int i = 1; i < argc; ++i) {
    const std::string argument = argv[i];
    if (i + 1 >= argc) fail("usage: clraster_gl_minimal [--scenes a,b] [--frames N] [--size WxH]");
    const std::string value = argv[++i];
    const bool known = argument == "--scenes"   ? (scenes = value, true)
                       : argument == "--frames" ? (options.frames = std::max(1, std::atoi(value.c_str())), true)
                       : argument == "--size" &&
                           std::sscanf(value.c_str(), "%dx%d", &options.width, &options.height) == 2;
    if (!known) fail("unknown option " + argument + " " + value);
  }
  std::size_t start = 0;
  while (!scenes.empty()) {
    const std::size_t comma = scenes.find(',', start);
    options.scenes.push_back(scenes.substr(start, comma - start));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (options.scenes.empty()) options.scenes = bench::scene_names();
  return options;
}

}  // namespace

int main(int argc, char** argv) try {
  const Options options = parse(argc, argv);
  bench::keep_freed_memory();  // as the benchmark runs both renderers
  const LeanContext context;
  std::printf("%-14s %6s %9s %10s %12s  %s\n", "scene", "draws", "lean ms", "oracle ms", "oracle/lean", "pictures");
  for (const std::string& name : options.scenes) {
    const SceneSetup setup = make_setup(name, options.width, options.height);
    const LeanScene lean(context, setup.lean, setup.width * setup.scene.layer_columns(),
                         setup.height * setup.scene.layer_rows());
    bench::GlScene oracle(setup.scene, setup.state, setup.width, setup.height);
    std::vector<double> lean_ms;
    std::vector<double> oracle_ms;
    for (int i = 0; i < bench::kWarmupFrames + options.frames; ++i) {
      lean.make_current();
      const double lean_frame = time_frame([&] { lean.frame(); });
      const double oracle_frame = time_frame([&] { oracle.frame(); });
      if (i < bench::kWarmupFrames) continue;
      lean_ms.push_back(lean_frame);
      oracle_ms.push_back(oracle_frame);
    }
    const Image oracle_picture = oracle.picture();
    lean.make_current();
    const double lean_median = median(lean_ms);
    const double oracle_median = median(oracle_ms);
    const std::size_t draws = setup.lean.parts.size() * std::max<std::size_t>(1, setup.lean.views.size());
    std::printf("%-14s %6zu %9.1f %10.1f %12.2f  %s\n", name.c_str(), draws, lean_median,
                oracle_median, oracle_median / lean_median, compare(lean.picture(), oracle_picture).c_str());
    std::fflush(stdout);
  }
  return 0;
} catch (const std::exception& error) {
  std::fprintf(stderr, "clraster_gl_minimal: %s\n", error.what());
  return 1;
}
