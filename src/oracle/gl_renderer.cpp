#include "oracle/gl_renderer.hpp"

#include "pipeline/draw_state.hpp"

#define GL_GLEXT_PROTOTYPES
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <string_view>
#include <utility>

namespace clraster::oracle {
namespace {

constexpr int kMaxFramebufferSize = 16384;
constexpr const char* kPackageHint =
    "(Mesa's EGL and OpenGL drivers: Debian packages libegl-mesa0 and libgl1-mesa-dri)";

// ---- Errors -------------------------------------------------------------------------------------

const char* gl_error_name(GLenum error) {
  switch (error) {
    case GL_INVALID_ENUM: return "GL_INVALID_ENUM";
    case GL_INVALID_VALUE: return "GL_INVALID_VALUE";
    case GL_INVALID_OPERATION: return "GL_INVALID_OPERATION";
    case GL_INVALID_FRAMEBUFFER_OPERATION: return "GL_INVALID_FRAMEBUFFER_OPERATION";
    case GL_OUT_OF_MEMORY: return "GL_OUT_OF_MEMORY";
    case GL_STACK_UNDERFLOW: return "GL_STACK_UNDERFLOW";
    case GL_STACK_OVERFLOW: return "GL_STACK_OVERFLOW";
    case GL_CONTEXT_LOST: return "GL_CONTEXT_LOST";
    default: return "unknown GL error";
  }
}

const char* framebuffer_status_name(GLenum status) {
  switch (status) {
    case GL_FRAMEBUFFER_UNDEFINED: return "GL_FRAMEBUFFER_UNDEFINED";
    case GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT: return "GL_FRAMEBUFFER_INCOMPLETE_ATTACHMENT";
    case GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT: return "GL_FRAMEBUFFER_INCOMPLETE_MISSING_ATTACHMENT";
    case GL_FRAMEBUFFER_INCOMPLETE_DRAW_BUFFER: return "GL_FRAMEBUFFER_INCOMPLETE_DRAW_BUFFER";
    case GL_FRAMEBUFFER_INCOMPLETE_READ_BUFFER: return "GL_FRAMEBUFFER_INCOMPLETE_READ_BUFFER";
    case GL_FRAMEBUFFER_UNSUPPORTED: return "GL_FRAMEBUFFER_UNSUPPORTED";
    case GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE: return "GL_FRAMEBUFFER_INCOMPLETE_MULTISAMPLE";
    case GL_FRAMEBUFFER_INCOMPLETE_LAYER_TARGETS: return "GL_FRAMEBUFFER_INCOMPLETE_LAYER_TARGETS";
    default: return "unknown framebuffer status";
  }
}

const char* egl_error_name(EGLint error) {
  switch (error) {
    case EGL_SUCCESS: return "EGL_SUCCESS";
    case EGL_NOT_INITIALIZED: return "EGL_NOT_INITIALIZED";
    case EGL_BAD_ACCESS: return "EGL_BAD_ACCESS";
    case EGL_BAD_ALLOC: return "EGL_BAD_ALLOC";
    case EGL_BAD_ATTRIBUTE: return "EGL_BAD_ATTRIBUTE";
    case EGL_BAD_CONFIG: return "EGL_BAD_CONFIG";
    case EGL_BAD_CONTEXT: return "EGL_BAD_CONTEXT";
    case EGL_BAD_CURRENT_SURFACE: return "EGL_BAD_CURRENT_SURFACE";
    case EGL_BAD_DISPLAY: return "EGL_BAD_DISPLAY";
    case EGL_BAD_MATCH: return "EGL_BAD_MATCH";
    case EGL_BAD_NATIVE_PIXMAP: return "EGL_BAD_NATIVE_PIXMAP";
    case EGL_BAD_NATIVE_WINDOW: return "EGL_BAD_NATIVE_WINDOW";
    case EGL_BAD_PARAMETER: return "EGL_BAD_PARAMETER";
    case EGL_BAD_SURFACE: return "EGL_BAD_SURFACE";
    case EGL_CONTEXT_LOST: return "EGL_CONTEXT_LOST";
    default: return "unknown EGL error";
  }
}

[[noreturn]] void throw_egl_error(const std::string& what, EGLint error = eglGetError()) {
  throw Error(what + " failed: " + egl_error_name(error) + " " + kPackageHint);
}

// Throws if GL recorded an error since the last check. GL keeps a flag per error kind, so the
// remaining ones are drained: the next operation must not be blamed for this one's errors.
void check_gl(const char* operation) {
  const GLenum error = glGetError();
  if (error == GL_NO_ERROR) return;
  while (glGetError() != GL_NO_ERROR) {
  }
  throw Error(std::string("OpenGL error ") + gl_error_name(error) + " in " + operation);
}

// Shader logs are multi-line; clraster's error messages are one line.
std::string one_line(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == '\0')) text.pop_back();
  for (char& c : text) {
    if (c == '\n') c = ' ';
  }
  return text;
}

bool has_extension(const char* extensions, std::string_view name) {
  std::istringstream words(extensions ? extensions : "");
  for (std::string word; words >> word;) {
    if (word == name) return true;
  }
  return false;
}

// ---- The built-in shading modes in GLSL -------------------------------------------------------
// One source per stage; SHADING selects the mode at compile time, so each mode is its own program
// and llvmpipe runs no per-fragment branch on the mode. Each branch is the formula documented for
// clraster::Shading in clraster.hpp.

constexpr const char* kVertexShader = R"(
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 model_view_projection;  // projection * model_view, computed on the host
uniform mat4 model_view;
uniform mat3 normal_matrix;  // inverse transpose of model_view's upper 3x3, computed on the host
out vec3 v;

void main() {
  gl_Position = model_view_projection * vec4(position, 1.0);
#if SHADING == SHADING_NORMAL
  v = normal;
#elif SHADING == SHADING_LAMBERT
  v = normal_matrix * normal;
#elif SHADING == SHADING_DEPTH
  v = vec3(-(model_view * vec4(position, 1.0)).z, 0.0, 0.0);  // view distance along -z
#elif SHADING == SHADING_CONSTANT
  v = vec3(0.0);
#endif
}
)";

constexpr const char* kFragmentShader = R"(
in vec3 v;
uniform vec4 base_color;
uniform vec2 depth_range;  // view distances drawn white and black
layout(location = 0) out vec4 color;

void main() {
#if SHADING == SHADING_NORMAL
  float len = length(v);
  color = vec4(len > 0.0 ? v / len * 0.5 + 0.5 : vec3(0.5), 1.0);
#elif SHADING == SHADING_LAMBERT
  float len = length(v);
  float k = len > 0.0 ? 0.1 + 0.9 * abs(v.z / len) : 0.1;
  color = vec4(base_color.rgb * k, base_color.a);
#elif SHADING == SHADING_DEPTH
  float g = clamp(1.0 - (v.x - depth_range.x) / (depth_range.y - depth_range.x), 0.0, 1.0);
  color = vec4(g, g, g, 1.0);
#elif SHADING == SHADING_CONSTANT
  color = base_color;
#endif
}
)";

constexpr int kShadingModes = 4;

const char* shading_define(Shading shading) {
  switch (shading) {
    case Shading::Normal: return "#define SHADING SHADING_NORMAL\n";
    case Shading::Lambert: return "#define SHADING SHADING_LAMBERT\n";
    case Shading::Depth: return "#define SHADING SHADING_DEPTH\n";
    case Shading::Constant: return "#define SHADING SHADING_CONSTANT\n";
  }
  throw InvalidArgument("unknown shading mode " + std::to_string(static_cast<int>(shading)));
}

GLuint compile_shader(GLenum stage, Shading shading, const char* body) {
  const char* sources[] = {
      "#version 450 core\n"
      "#define SHADING_NORMAL 0\n"
      "#define SHADING_LAMBERT 1\n"
      "#define SHADING_DEPTH 2\n"
      "#define SHADING_CONSTANT 3\n",
      shading_define(shading), body};
  const GLuint shader = glCreateShader(stage);
  glShaderSource(shader, 3, sources, nullptr);
  glCompileShader(shader);
  GLint ok = GL_FALSE;
  glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (!ok) {
    std::string log(4096, '\0');
    glGetShaderInfoLog(shader, GLsizei(log.size()), nullptr, log.data());
    glDeleteShader(shader);
    throw Error(std::string("oracle ") + (stage == GL_VERTEX_SHADER ? "vertex" : "fragment") +
                " shader does not compile: " + one_line(log.c_str()));
  }
  return shader;
}

// A linked program of one shading mode and where its uniforms are. Uniforms the mode does not use
// are inactive (location -1), and glProgramUniform* ignores location -1.
struct ShadingProgram {
  GLuint id = 0;
  GLint model_view_projection = -1;
  GLint model_view = -1;
  GLint normal_matrix = -1;
  GLint base_color = -1;
  GLint depth_range = -1;

  explicit ShadingProgram(Shading shading) {
    const GLuint vertex = compile_shader(GL_VERTEX_SHADER, shading, kVertexShader);
    const GLuint fragment = compile_shader(GL_FRAGMENT_SHADER, shading, kFragmentShader);
    id = glCreateProgram();
    glAttachShader(id, vertex);
    glAttachShader(id, fragment);
    glLinkProgram(id);
    glDeleteShader(vertex);  // only flagged: they live on while attached
    glDeleteShader(fragment);
    GLint ok = GL_FALSE;
    glGetProgramiv(id, GL_LINK_STATUS, &ok);
    if (!ok) {
      std::string log(4096, '\0');
      glGetProgramInfoLog(id, GLsizei(log.size()), nullptr, log.data());
      throw Error("oracle shader program does not link: " + one_line(log.c_str()));
    }
    model_view_projection = glGetUniformLocation(id, "model_view_projection");
    model_view = glGetUniformLocation(id, "model_view");
    normal_matrix = glGetUniformLocation(id, "normal_matrix");
    base_color = glGetUniformLocation(id, "base_color");
    depth_range = glGetUniformLocation(id, "depth_range");
    check_gl("building the shading programs");
  }
};

// ---- The process-wide display, context and programs ---------------------------------------------

class Device {
 public:
  // Created on first use. If creation throws, the next call tries again (and fails the same way).
  // Never destroyed: meshes and renderers with static storage duration may be destroyed after any
  // destructor we could register, and still need the context; process exit releases everything.
  static Device& instance() {
    static Device* device = new Device();
    return *device;
  }

  // Called by every entry point: cheap when the context is already current on this thread. A GL
  // context can be current on one thread only, and only that thread can release it, so the oracle
  // stays on the first thread that uses it.
  void make_current() const {
    if (eglGetCurrentContext() == context_) return;
    if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
      const EGLint error = eglGetError();
      if (error == EGL_BAD_ACCESS) {
        throw Error("the OpenGL oracle is in use on another thread: use it from one thread only");
      }
      throw_egl_error("eglMakeCurrent", error);
    }
  }

  // For destructors, which must not throw. When the context cannot be made current (another thread
  // holds it), GL calls here go to GLVND's no-op dispatch: the objects leak instead of the process
  // aborting.
  void make_current_for_cleanup() const noexcept {
    if (eglGetCurrentContext() != context_)
      eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_);
  }

  const ShadingProgram& program(Shading shading) const {
    const auto index = static_cast<std::size_t>(shading);
    if (index >= programs_.size()) throw InvalidArgument("unknown shading mode " + std::to_string(index));
    return programs_[index];
  }

  const std::string& description() const { return description_; }

 private:
  Device() {
    // llvmpipe is the reference the pipeline is measured against; on a machine with a GPU, Mesa
    // would otherwise pick the hardware driver. The environment may still override this.
    setenv("LIBGL_ALWAYS_SOFTWARE", "1", /*overwrite=*/0);
    display_ = open_display();
    try {
      context_ = create_context(display_);
      make_current();
      description_ = std::string(reinterpret_cast<const char*>(glGetString(GL_RENDERER))) + ", " +
                     reinterpret_cast<const char*>(glGetString(GL_VERSION));
      for (int mode = 0; mode < kShadingModes; ++mode) programs_.emplace_back(static_cast<Shading>(mode));
      // Meshes without normals leave attribute 1 disabled and the shaders read this current value.
      glVertexAttrib4f(1, 0.0f, 0.0f, 0.0f, 1.0f);
      // GL enables dithering by default; clraster writes exact rounded colours.
      glDisable(GL_DITHER);
      check_gl("initializing the context");
    } catch (...) {
      eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
      eglTerminate(display_);
      throw;
    }
  }

  static EGLDisplay open_display() {
    const char* client_extensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    if (!has_extension(client_extensions, "EGL_MESA_platform_surfaceless")) {
      throw Error(std::string("EGL has no headless (surfaceless) platform ") + kPackageHint);
    }
    const auto get_platform_display =
        reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
    if (!get_platform_display) throw Error(std::string("EGL lacks eglGetPlatformDisplayEXT ") + kPackageHint);
    const EGLDisplay display =
        get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
    if (display == EGL_NO_DISPLAY) throw_egl_error("eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA)");
    if (!eglInitialize(display, nullptr, nullptr)) throw_egl_error("eglInitialize");
    return display;
  }

  static EGLContext create_context(EGLDisplay display) {
    const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
    for (const char* needed : {"EGL_KHR_no_config_context", "EGL_KHR_surfaceless_context"}) {
      if (!has_extension(extensions, needed))
        throw Error(std::string("EGL lacks ") + needed + " " + kPackageHint);
    }
    if (!eglBindAPI(EGL_OPENGL_API)) throw_egl_error("eglBindAPI(EGL_OPENGL_API)");
    const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                                 EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                                 EGL_NONE};
    const EGLContext context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
    if (context == EGL_NO_CONTEXT) throw_egl_error("eglCreateContext(OpenGL 4.5 core)");
    return context;
  }

  EGLDisplay display_ = EGL_NO_DISPLAY;
  EGLContext context_ = EGL_NO_CONTEXT;
  std::vector<ShadingProgram> programs_;  // indexed by Shading
  std::string description_;
};

// ---- GL object names ------------------------------------------------------------------------------

// Owns one GL object name, deleted with the matching glDelete* (they all share one signature).
template <void (*Delete)(GLsizei, const GLuint*)>
class GlName {
 public:
  GlName() = default;
  explicit GlName(GLuint id) : id_(id) {}
  ~GlName() {
    if (id_ != 0) Delete(1, &id_);
  }
  GlName(GlName&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
  GlName& operator=(GlName&& other) noexcept {
    std::swap(id_, other.id_);
    return *this;
  }
  GLuint get() const { return id_; }

 private:
  GLuint id_ = 0;
};

using Buffer = GlName<glDeleteBuffers>;
using VertexArray = GlName<glDeleteVertexArrays>;
using Renderbuffer = GlName<glDeleteRenderbuffers>;
using Framebuffer = GlName<glDeleteFramebuffers>;

template <typename T>
Buffer upload_buffer(std::span<const T> data) {
  GLuint id = 0;
  glCreateBuffers(1, &id);
  Buffer buffer(id);
  // Not glNamedBufferStorage: it rejects empty data, and an empty mesh is a valid (empty) draw.
  glNamedBufferData(id, GLsizeiptr(data.size_bytes()), data.data(), GL_STATIC_DRAW);
  return buffer;
}

// Feeds attribute `location` of the vertex array from a tightly packed buffer of three floats per vertex.
void attach_vec3_attribute(GLuint vertex_array, GLuint location, const Buffer& buffer) {
  glVertexArrayVertexBuffer(vertex_array, location, buffer.get(), 0, 3 * sizeof(float));
  glVertexArrayAttribFormat(vertex_array, location, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vertex_array, location, location);
  glEnableVertexArrayAttrib(vertex_array, location);
}

// ---- Draw state -----------------------------------------------------------------------------------

GLenum gl_topology(Topology topology) {
  switch (topology) {
    case Topology::TriangleList: return GL_TRIANGLES;
    case Topology::TriangleStrip: return GL_TRIANGLE_STRIP;
    case Topology::TriangleFan: return GL_TRIANGLE_FAN;
  }
  throw InvalidArgument("unknown topology " + std::to_string(static_cast<int>(topology)));
}

GLenum gl_compare_func(CompareFunc func) {
  switch (func) {
    case CompareFunc::Never: return GL_NEVER;
    case CompareFunc::Less: return GL_LESS;
    case CompareFunc::Equal: return GL_EQUAL;
    case CompareFunc::LessEqual: return GL_LEQUAL;
    case CompareFunc::Greater: return GL_GREATER;
    case CompareFunc::NotEqual: return GL_NOTEQUAL;
    case CompareFunc::GreaterEqual: return GL_GEQUAL;
    case CompareFunc::Always: return GL_ALWAYS;
    case CompareFunc::Program: break;  // no OpenGL equivalent
  }
  throw InvalidArgument("unknown depth function " + std::to_string(static_cast<int>(func)));
}

void set_enabled(GLenum capability, bool enabled) { enabled ? glEnable(capability) : glDisable(capability); }

// Every fixed-function state a DrawState controls is set on every draw: the context is shared, so
// nothing may be assumed about what an earlier draw (of any renderer) left behind.
void apply_fixed_function_state(const DrawState& state, int framebuffer_width, int framebuffer_height) {
  const bool whole = state.viewport.width == 0 || state.viewport.height == 0;
  if (whole) {
    glViewport(0, 0, framebuffer_width, framebuffer_height);
  } else {
    glViewport(state.viewport.x, state.viewport.y, state.viewport.width, state.viewport.height);
  }
  set_enabled(GL_SCISSOR_TEST, state.scissor_test);
  if (state.scissor_test)
    glScissor(state.scissor.x, state.scissor.y, state.scissor.width, state.scissor.height);

  set_enabled(GL_CULL_FACE, state.cull != CullMode::None);
  if (state.cull != CullMode::None) glCullFace(state.cull == CullMode::Back ? GL_BACK : GL_FRONT);
  glFrontFace(state.front_face == FrontFace::CounterClockwise ? GL_CCW : GL_CW);

  set_enabled(GL_DEPTH_TEST, state.depth_test);
  glDepthFunc(gl_compare_func(state.depth_func));
  glDepthMask(state.depth_write ? GL_TRUE : GL_FALSE);

  set_enabled(GL_BLEND, state.blend[0].enabled);
  if (state.blend[0].enabled) {
    glBlendFunc(GL_ONE, GL_ONE);
    glBlendEquation(GL_FUNC_ADD);
  }
}


// The matrices are the ones clraster's pipeline computes (in double, rounded once to float), so the
// oracle and the pipeline transform the same object-space data with the same floats.
void set_uniforms(const ShadingProgram& program, const DrawState& state) {
  const Mat4 mvp = pipeline::model_view_projection(state);
  glProgramUniformMatrix4fv(program.id, program.model_view_projection, 1, GL_FALSE, mvp.data());
  glProgramUniformMatrix4fv(program.id, program.model_view, 1, GL_FALSE, state.model_view.data());
  if (state.shading == Shading::Lambert) {
    const std::array<float, 9> normals = pipeline::normal_matrix(state.model_view);
    glProgramUniformMatrix3fv(program.id, program.normal_matrix, 1, GL_FALSE, normals.data());
  }
  glProgramUniform4fv(program.id, program.base_color, 1, state.base_color.data());
  glProgramUniform2fv(program.id, program.depth_range, 1, state.depth_shading_range.data());
}

// GL's images are bottom row first; clraster's are top row first.
template <typename T>
void flip_rows(std::vector<T>& pixels, std::size_t row_length) {
  const std::size_t rows = pixels.size() / row_length;
  for (std::size_t top = 0, bottom = rows - 1; top < bottom; ++top, --bottom) {
    std::swap_ranges(pixels.begin() + top * row_length, pixels.begin() + (top + 1) * row_length,
                     pixels.begin() + bottom * row_length);
  }
}

}  // namespace

// ---- GlMesh ---------------------------------------------------------------------------------------

struct GlMesh::Impl {
  std::size_t vertex_count = 0;
  std::size_t index_count = 0;
  GLenum index_type = 0;  // GL_UNSIGNED_SHORT or GL_UNSIGNED_INT; 0 when not indexed
  std::size_t index_size = 0;
  Buffer positions;
  Buffer normals;
  Buffer indices;
  VertexArray vertex_array;

  template <typename Index>
  Impl(std::span<const float> position_data, std::span<const float> normal_data,
       std::span<const Index> index_data) {
    if (position_data.size() % 3 != 0) {
      throw InvalidArgument("positions hold " + std::to_string(position_data.size()) +
                            " floats, not three per vertex");
    }
    if (!normal_data.empty() && normal_data.size() != position_data.size()) {
      throw InvalidArgument(std::to_string(normal_data.size()) + " normal floats for " +
                            std::to_string(position_data.size()) + " position floats");
    }
    vertex_count = position_data.size() / 3;
    for (std::size_t i = 0; i < index_data.size(); ++i) {
      if (index_data[i] >= vertex_count) {
        throw InvalidArgument("indices[" + std::to_string(i) + "] = " + std::to_string(index_data[i]) +
                              " refers past the mesh's " + std::to_string(vertex_count) + " vertices");
      }
    }
    index_count = index_data.size();

    Device::instance().make_current();
    GLuint id = 0;
    glCreateVertexArrays(1, &id);
    vertex_array = VertexArray(id);
    positions = upload_buffer(position_data);
    attach_vec3_attribute(id, 0, positions);
    if (!normal_data.empty()) {
      normals = upload_buffer(normal_data);
      attach_vec3_attribute(id, 1, normals);
    }
    if (!index_data.empty()) {
      indices = upload_buffer(index_data);
      glVertexArrayElementBuffer(id, indices.get());
      index_type = sizeof(Index) == 2 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT;
      index_size = sizeof(Index);
    }
    check_gl("uploading a mesh");
  }

  ~Impl() { Device::instance().make_current_for_cleanup(); }  // the members' glDelete* need the context
};

GlMesh::GlMesh(std::span<const float> positions, std::span<const float> normals,
               std::span<const std::uint32_t> indices)
    : impl_(std::make_unique<Impl>(positions, normals, indices)) {}
GlMesh::GlMesh(std::span<const float> positions, std::span<const float> normals,
               std::span<const std::uint16_t> indices)
    : impl_(std::make_unique<Impl>(positions, normals, indices)) {}
GlMesh::~GlMesh() = default;
GlMesh::GlMesh(GlMesh&&) noexcept = default;
GlMesh& GlMesh::operator=(GlMesh&&) noexcept = default;

std::size_t GlMesh::vertex_count() const { return impl_->vertex_count; }
std::size_t GlMesh::index_count() const { return impl_->index_count; }
bool GlMesh::indexed() const { return impl_->index_type != 0; }

// ---- GlRenderer -----------------------------------------------------------------------------------

struct GlRenderer::Impl {
  int width;
  int height;
  Renderbuffer color;
  Renderbuffer depth;
  Framebuffer framebuffer;

  Impl(int w, int h) : width(w), height(h) {
    if (w < 1 || h < 1 || w > kMaxFramebufferSize || h > kMaxFramebufferSize) {
      throw InvalidArgument("framebuffer size " + std::to_string(w) + "x" + std::to_string(h) +
                            " is outside 1.." + std::to_string(kMaxFramebufferSize));
    }
    Device::instance().make_current();
    color = make_renderbuffer(GL_RGBA8);
    depth = make_renderbuffer(GL_DEPTH_COMPONENT32F);
    GLuint id = 0;
    glCreateFramebuffers(1, &id);
    framebuffer = Framebuffer(id);
    glNamedFramebufferRenderbuffer(id, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color.get());
    glNamedFramebufferRenderbuffer(id, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth.get());
    check_gl("creating the framebuffer");
    const GLenum status = glCheckNamedFramebufferStatus(id, GL_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE) {
      throw Error(std::string("oracle framebuffer of ") + std::to_string(w) + "x" + std::to_string(h) +
                  " is incomplete: " + framebuffer_status_name(status));
    }
  }

  ~Impl() { Device::instance().make_current_for_cleanup(); }  // the members' glDelete* need the context

  Renderbuffer make_renderbuffer(GLenum format) const {
    GLuint id = 0;
    glCreateRenderbuffers(1, &id);
    Renderbuffer renderbuffer(id);
    glNamedRenderbufferStorage(id, format, width, height);
    return renderbuffer;
  }

  // Reads one attachment, bottom row first as GL gives it, then flips it to top row first.
  template <typename T>
  std::vector<T> read(GLenum format, GLenum type, std::size_t values_per_pixel, const char* operation) const {
    Device::instance().make_current();
    std::vector<T> pixels(std::size_t(width) * height * values_per_pixel);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, framebuffer.get());
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, format, type, pixels.data());
    check_gl(operation);
    flip_rows(pixels, std::size_t(width) * values_per_pixel);
    return pixels;
  }
};

GlRenderer::GlRenderer(int width, int height) : impl_(std::make_unique<Impl>(width, height)) {}
GlRenderer::~GlRenderer() = default;
GlRenderer::GlRenderer(GlRenderer&&) noexcept = default;
GlRenderer& GlRenderer::operator=(GlRenderer&&) noexcept = default;

int GlRenderer::width() const { return impl_->width; }
int GlRenderer::height() const { return impl_->height; }
std::string GlRenderer::renderer() const { return Device::instance().description(); }

void GlRenderer::clear(std::array<float, 4> color, float depth) {
  Device::instance().make_current();
  // Clears obey the scissor test and the depth mask; a draw may have left either set.
  glDisable(GL_SCISSOR_TEST);
  glDepthMask(GL_TRUE);
  glClearNamedFramebufferfv(impl_->framebuffer.get(), GL_COLOR, 0, color.data());
  glClearNamedFramebufferfv(impl_->framebuffer.get(), GL_DEPTH, 0, &depth);
  check_gl("clear");
}

void GlRenderer::draw(const GlMesh& mesh, std::uint32_t first, std::uint32_t count, const DrawState& state) {
  const GlMesh::Impl& data = *mesh.impl_;
  const std::uint64_t available = data.index_type != 0 ? data.index_count : data.vertex_count;
  if (first > available) {
    throw InvalidArgument("draw starts at element " + std::to_string(first) + " of a mesh of " +
                          std::to_string(available));
  }
  const std::uint64_t elements = count == kAllElements ? available - first : count;
  if (first + elements > available) {
    throw InvalidArgument("draw of " + std::to_string(elements) + " elements from " + std::to_string(first) +
                          " runs past the mesh's " + std::to_string(available));
  }
  constexpr std::uint64_t kMaxGlCount = std::numeric_limits<GLint>::max();
  if (first > kMaxGlCount || elements > kMaxGlCount) {
    throw InvalidArgument("draw of " + std::to_string(elements) + " elements from " + std::to_string(first) +
                          " exceeds OpenGL's 32-bit signed counts");
  }
  const auto [nearest, farthest] = state.depth_shading_range;
  if (state.shading == Shading::Depth &&
      !(std::isfinite(nearest) && std::isfinite(farthest) && nearest < farthest)) {
    throw InvalidArgument("depth shading range [" + std::to_string(nearest) + ", " +
                          std::to_string(farthest) + "] must be finite with near < far");
  }
  const GLenum mode = gl_topology(state.topology);
  const ShadingProgram& program = Device::instance().program(state.shading);

  Device::instance().make_current();
  glBindFramebuffer(GL_DRAW_FRAMEBUFFER, impl_->framebuffer.get());
  apply_fixed_function_state(state, impl_->width, impl_->height);
  set_uniforms(program, state);
  check_gl("setting the draw state");
  glUseProgram(program.id);
  glBindVertexArray(data.vertex_array.get());
  if (data.index_type != 0) {
    const auto offset = static_cast<std::uintptr_t>(first * data.index_size);
    glDrawElements(mode, GLsizei(elements), data.index_type, reinterpret_cast<const void*>(offset));
  } else {
    glDrawArrays(mode, GLint(first), GLsizei(elements));
  }
  check_gl(data.index_type != 0 ? "glDrawElements" : "glDrawArrays");
}

Image GlRenderer::read_color() const {
  return Image{impl_->width, impl_->height,
               impl_->read<std::uint8_t>(GL_RGBA, GL_UNSIGNED_BYTE, 4, "read_color")};
}

std::vector<float> GlRenderer::read_depth() const {
  return impl_->read<float>(GL_DEPTH_COMPONENT, GL_FLOAT, 1, "read_depth");
}

void GlRenderer::finish() {
  Device::instance().make_current();
  glFinish();
  check_gl("glFinish");
}

}  // namespace clraster::oracle
