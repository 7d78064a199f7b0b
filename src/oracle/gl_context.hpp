// Internal to the oracle (gl_renderer.cpp and gl_scene.cpp): the process-wide GL context, GL error
// checks, owned GL object names and program building. Every GL call needs the context current on
// the calling thread: public entry points call Context::instance().make_current() first.
#pragma once

#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>

#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

#include "clraster/clraster.hpp"

namespace clraster::oracle::gl {

// "GL_INVALID_VALUE", ...
const char* error_name(GLenum error);
const char* framebuffer_status_name(GLenum status);

// Throws clraster::Error naming the GL error and `operation` if GL recorded an error since the last
// check. GL keeps a flag per error kind, so the remaining ones are drained: the next operation must
// not be blamed for this one's errors.
void check(const char* operation);

// Multi-line text (shader logs) as one line, as clraster's error messages are.
std::string one_line(std::string text);

// The one EGL display and OpenGL 4.5 core context of the process, created on first use. Mesa is asked
// for its software renderer (LIBGL_ALWAYS_SOFTWARE=1 unless the environment says otherwise) because
// llvmpipe is the reference. Besides GL's defaults, the context holds this state for its whole life:
// dithering off (clraster writes exactly rounded colours), GL_FRAMEBUFFER_SRGB on (sRGB attachments
// are encoded when written and decoded when blended, as in clraster), pack and unpack alignment 1
// (clraster's texel rows are tightly packed), and coherent advanced blending where Mesa offers it.
class Context {
 public:
  // If creation throws, the next call tries again (and fails the same way). Never destroyed: GL
  // objects with static storage duration may be destroyed after any destructor we could register,
  // and still need the context; process exit releases everything.
  static Context& instance();

  // Cheap when the context is already current on this thread. A GL context can be current on one
  // thread only, and only that thread can release it, so the oracle stays on the first thread that
  // uses it; others get a clraster::Error.
  void make_current() const;
  // For destructors, which must not throw. When the context cannot be made current (another thread
  // holds it), GL calls go to GLVND's no-op dispatch: the objects leak instead of the process aborting.
  void make_current_for_cleanup() const noexcept;

  // GL_RENDERER and GL_VERSION, e.g. "llvmpipe (LLVM 15.0.6, 256 bits), 4.5 (Core Profile) Mesa 22.3.6".
  const std::string& description() const { return description_; }
  // Whether glGetStringi(GL_EXTENSIONS, i) lists `name` (e.g. "GL_KHR_blend_equation_advanced").
  bool has_extension(std::string_view name) const;
  // glBlendBarrierKHR, which libOpenGL does not export: orders advanced blending between draws.
  // Throws clraster::Error when the context lacks GL_KHR_blend_equation_advanced.
  void blend_barrier() const;

 private:
  Context();

  void* display_ = nullptr;  // EGLDisplay and EGLContext, kept opaque so this header needs no EGL
  void* context_ = nullptr;
  std::string description_;
  void (*blend_barrier_)() = nullptr;
};

// Owns one GL object name and deletes it with `Delete`: glDeleteBuffers and its like (count, names),
// or glDeleteProgram and glDeleteShader (one name).
template <auto Delete>
class Name {
 public:
  Name() = default;
  explicit Name(GLuint id) : id_(id) {}
  ~Name() {
    if (id_ == 0) return;
    if constexpr (std::is_invocable_v<decltype(Delete), GLuint>) {
      Delete(id_);
    } else {
      Delete(1, &id_);
    }
  }
  Name(Name&& other) noexcept : id_(std::exchange(other.id_, 0)) {}
  Name& operator=(Name&& other) noexcept {
    std::swap(id_, other.id_);
    return *this;
  }
  GLuint get() const { return id_; }

 private:
  GLuint id_ = 0;
};

using Buffer = Name<glDeleteBuffers>;
using VertexArray = Name<glDeleteVertexArrays>;
using Texture = Name<glDeleteTextures>;
using Sampler = Name<glDeleteSamplers>;
using Framebuffer = Name<glDeleteFramebuffers>;
using Program = Name<glDeleteProgram>;

// A buffer object holding `bytes` (which may be empty: an empty mesh is a valid, empty draw).
Buffer upload_buffer(std::span<const std::byte> bytes);

// Compiles a vertex and a fragment shader, each from its source pieces (concatenated, as
// glShaderSource does), and links them. Throws clraster::BuildError whose message names `what`, the
// stage and GL's info log on one line, and whose log() is the info log as GL wrote it.
Program build_program(std::span<const char* const> vertex_sources, std::span<const char* const> fragment_sources,
                      const std::string& what);

}  // namespace clraster::oracle::gl
