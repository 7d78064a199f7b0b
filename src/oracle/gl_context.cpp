#include "oracle/gl_context.hpp"

#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <algorithm>
#include <cstdlib>
#include <sstream>
#include <vector>

namespace clraster::oracle::gl {
namespace {

constexpr const char* kPackageHint =
    "(Mesa's EGL and OpenGL drivers: Debian packages libegl-mesa0 and libgl1-mesa-dri)";

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

// EGL lists its extensions as one space-separated string.
bool egl_has_extension(const char* extensions, std::string_view name) {
  std::istringstream words(extensions ? extensions : "");
  for (std::string word; words >> word;) {
    if (word == name) return true;
  }
  return false;
}

EGLDisplay open_display() {
  const char* client_extensions = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!egl_has_extension(client_extensions, "EGL_MESA_platform_surfaceless")) {
    throw Error(std::string("EGL has no headless (surfaceless) platform ") + kPackageHint);
  }
  const auto get_platform_display =
      reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (!get_platform_display) throw Error(std::string("EGL lacks eglGetPlatformDisplayEXT ") + kPackageHint);
  const EGLDisplay display = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (display == EGL_NO_DISPLAY) throw_egl_error("eglGetPlatformDisplayEXT(EGL_PLATFORM_SURFACELESS_MESA)");
  if (!eglInitialize(display, nullptr, nullptr)) throw_egl_error("eglInitialize");
  return display;
}

// OpenGL 4.5 core: Mesa 22.3's llvmpipe exposes every extension the oracle uses there
// (KHR_blend_equation_advanced, EXT_shader_framebuffer_fetch, ARB_derivative_control,
// ARB_shader_stencil_export), and asking for 4.6 fails with EGL_BAD_MATCH.
EGLContext create_context(EGLDisplay display) {
  const char* extensions = eglQueryString(display, EGL_EXTENSIONS);
  for (const char* needed : {"EGL_KHR_no_config_context", "EGL_KHR_surfaceless_context"}) {
    if (!egl_has_extension(extensions, needed)) throw Error(std::string("EGL lacks ") + needed + " " + kPackageHint);
  }
  if (!eglBindAPI(EGL_OPENGL_API)) throw_egl_error("eglBindAPI(EGL_OPENGL_API)");
  const EGLint attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 4, EGL_CONTEXT_MINOR_VERSION, 5,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
  const EGLContext context = eglCreateContext(display, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attributes);
  if (context == EGL_NO_CONTEXT) throw_egl_error("eglCreateContext(OpenGL 4.5 core)");
  return context;
}

std::string info_log(GLuint object, bool is_program) {
  GLint length = 0;
  is_program ? glGetProgramiv(object, GL_INFO_LOG_LENGTH, &length) : glGetShaderiv(object, GL_INFO_LOG_LENGTH, &length);
  std::string log(std::size_t(std::max(length, 1)), '\0');
  is_program ? glGetProgramInfoLog(object, length, nullptr, log.data())
             : glGetShaderInfoLog(object, length, nullptr, log.data());
  log.resize(log.find('\0') == std::string::npos ? log.size() : log.find('\0'));
  return log;
}

using Shader = Name<glDeleteShader>;

Shader compile_shader(GLenum stage, std::span<const char* const> sources, const std::string& what) {
  Shader shader(glCreateShader(stage));
  glShaderSource(shader.get(), GLsizei(sources.size()), sources.data(), nullptr);
  glCompileShader(shader.get());
  GLint ok = GL_FALSE;
  glGetShaderiv(shader.get(), GL_COMPILE_STATUS, &ok);
  if (!ok) {
    std::string log = info_log(shader.get(), false);
    throw BuildError(what + " " + (stage == GL_VERTEX_SHADER ? "vertex" : "fragment") +
                         " shader does not compile: " + one_line(log),
                     std::move(log));
  }
  return shader;
}

}  // namespace

const char* error_name(GLenum error) {
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

void check(const char* operation) {
  const GLenum error = glGetError();
  if (error == GL_NO_ERROR) return;
  while (glGetError() != GL_NO_ERROR) {
  }
  throw Error(std::string("OpenGL error ") + error_name(error) + " in " + operation);
}

std::string one_line(std::string text) {
  while (!text.empty() && (text.back() == '\n' || text.back() == '\0')) text.pop_back();
  for (char& c : text) {
    if (c == '\n') c = ' ';
  }
  return text;
}

// ---- Context --------------------------------------------------------------------------------------

Context& Context::instance() {
  static Context* context = new Context();
  return *context;
}

Context::Context() {
  // llvmpipe is the reference the pipeline is measured against; on a machine with a GPU, Mesa would
  // otherwise pick the hardware driver. The environment may still override this.
  setenv("LIBGL_ALWAYS_SOFTWARE", "1", /*overwrite=*/0);
  const EGLDisplay display = open_display();
  display_ = display;
  try {
    context_ = create_context(display);
    make_current();
    description_ = std::string(reinterpret_cast<const char*>(glGetString(GL_RENDERER))) + ", " +
                   reinterpret_cast<const char*>(glGetString(GL_VERSION));
    glDisable(GL_DITHER);
    glEnable(GL_FRAMEBUFFER_SRGB);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    if (has_extension("GL_KHR_blend_equation_advanced")) {
      blend_barrier_ = reinterpret_cast<void (*)()>(eglGetProcAddress("glBlendBarrierKHR"));
    }
    // Coherent: overlapping primitives of one draw blend in order, as in clraster, with no barrier.
    if (has_extension("GL_KHR_blend_equation_advanced_coherent")) glEnable(GL_BLEND_ADVANCED_COHERENT_KHR);
    check("initializing the context");
  } catch (...) {
    eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglTerminate(display);
    throw;
  }
}

void Context::make_current() const {
  if (eglGetCurrentContext() == context_) return;
  if (!eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_)) {
    const EGLint error = eglGetError();
    if (error == EGL_BAD_ACCESS) {
      throw Error("the OpenGL oracle is in use on another thread: use it from one thread only");
    }
    throw_egl_error("eglMakeCurrent", error);
  }
}

void Context::make_current_for_cleanup() const noexcept {
  if (eglGetCurrentContext() != context_) eglMakeCurrent(display_, EGL_NO_SURFACE, EGL_NO_SURFACE, context_);
}

bool Context::has_extension(std::string_view name) const {
  make_current();
  GLint count = 0;
  glGetIntegerv(GL_NUM_EXTENSIONS, &count);
  for (GLint i = 0; i < count; ++i) {
    if (name == reinterpret_cast<const char*>(glGetStringi(GL_EXTENSIONS, GLuint(i)))) return true;
  }
  return false;
}

void Context::blend_barrier() const {
  if (!blend_barrier_) throw Error("this OpenGL context lacks GL_KHR_blend_equation_advanced " + description_);
  blend_barrier_();
}

// ---- Objects --------------------------------------------------------------------------------------

Buffer upload_buffer(std::span<const std::byte> bytes) {
  GLuint id = 0;
  glCreateBuffers(1, &id);
  Buffer buffer(id);
  // Not glNamedBufferStorage: it rejects empty data.
  glNamedBufferData(id, GLsizeiptr(bytes.size()), bytes.data(), GL_STATIC_DRAW);
  return buffer;
}

Program build_program(std::span<const char* const> vertex_sources, std::span<const char* const> fragment_sources,
                      const std::string& what) {
  const Shader vertex = compile_shader(GL_VERTEX_SHADER, vertex_sources, what);
  const Shader fragment = compile_shader(GL_FRAGMENT_SHADER, fragment_sources, what);
  Program program(glCreateProgram());
  glAttachShader(program.get(), vertex.get());
  glAttachShader(program.get(), fragment.get());
  glLinkProgram(program.get());
  // The shaders are deleted when `vertex` and `fragment` go: only flagged, they live on while attached.
  GLint ok = GL_FALSE;
  glGetProgramiv(program.get(), GL_LINK_STATUS, &ok);
  if (!ok) {
    std::string log = info_log(program.get(), true);
    throw BuildError(what + " does not link: " + one_line(log), std::move(log));
  }
  check("building a program");
  return program;
}

}  // namespace clraster::oracle::gl
