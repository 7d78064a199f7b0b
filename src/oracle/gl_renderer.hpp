// The conformance oracle: renders what the clraster pipeline renders (same object-space data, same
// DrawState, same four built-in shading modes) with Mesa's OpenGL 4.5, headless through EGL.
// gl_scene.hpp is the general layer underneath (GLSL programs, textures, render targets) that tests
// of programmable rendering use directly.
//
//   clraster::oracle::GlMesh mesh(positions, normals, indices);   // uploaded once
//   clraster::oracle::GlRenderer gl(1920, 1080);
//   gl.clear({0, 0, 0, 1}, 1.0f);
//   gl.draw(mesh, 0, clraster::kAllElements, state);
//   clraster::Image picture = gl.read_color();
//
// All renderers, meshes and scene objects of a process share one EGL display and one GL context,
// created on first use; Mesa is asked for its software renderer (LIBGL_ALWAYS_SOFTWARE=1 unless the
// environment says otherwise) because llvmpipe is the reference. The context stays current on the
// first thread that uses the oracle: use it from that thread only (others get a clraster::Error).
// Every failure throws clraster::Error: EGL or GL unavailable, GL errors (named, e.g.
// GL_INVALID_VALUE), incomplete framebuffers, shader build failures.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "clraster/clraster.hpp"

namespace clraster::oracle {

struct GlDrawCall;

// Vertex positions, normals and optional 16- or 32-bit indices in GL buffer objects, uploaded once
// and drawable by any GlRenderer. positions: x, y, z per vertex; normals: empty (all normals zero)
// or x, y, z per vertex. Unlike clraster, which checks the indices a draw uses, every index is
// checked here at upload: one that names a missing vertex throws clraster::InvalidArgument.
class GlMesh {
 public:
  explicit GlMesh(std::span<const float> positions, std::span<const float> normals = {},
                  std::span<const std::uint32_t> indices = {});
  GlMesh(std::span<const float> positions, std::span<const float> normals,
         std::span<const std::uint16_t> indices);
  ~GlMesh();
  GlMesh(GlMesh&&) noexcept;
  GlMesh& operator=(GlMesh&&) noexcept;

  std::size_t vertex_count() const;
  std::size_t index_count() const;  // 0 when not indexed
  bool indexed() const;

 private:
  friend class GlRenderer;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// A width x height (1..16384) GlFramebuffer of an RGBA8 colour and a Depth32F depth texture.
class GlRenderer {
 public:
  GlRenderer(int width, int height);
  ~GlRenderer();
  GlRenderer(GlRenderer&&) noexcept;
  GlRenderer& operator=(GlRenderer&&) noexcept;

  int width() const;
  int height() const;
  // GL_RENDERER and GL_VERSION, e.g. "llvmpipe (LLVM 15.0.6, 256 bits), 4.5 (Core Profile) Mesa 22.3.6".
  std::string renderer() const;

  // Clears the whole colour and depth attachments, regardless of the scissor and mask state of
  // earlier draws (as clraster::Framebuffer::clear does).
  void clear(std::array<float, 4> color, float depth = 1.0f);
  // Draws `count` indices (or vertices, when the mesh is not indexed) from `first`; count ==
  // kAllElements draws to the end. Every DrawState field maps to the GL state of the same meaning
  // (stencil state has nothing to act on: there is no stencil attachment); depth clamping is off and
  // the depth range is [0, 1]. As in clraster, projection * model_view and Lambert's normal matrix
  // (the inverse transpose of model_view's upper 3x3; its cofactors when singular) are computed on
  // the host in double. Throws InvalidArgument for a range past the end of the mesh, for Depth
  // shading with a range that is not finite with near < far, and for CompareFunc::Program and
  // BlendEquation::Program (no GL equivalent).
  void draw(const GlMesh& mesh, std::uint32_t first, std::uint32_t count, const DrawState& state);

  // Draws a GlDrawCall (gl_scene.hpp: a GLSL program, its attributes and textures) into this
  // renderer's attachments, as GlFramebuffer::draw does.
  void draw(const GlDrawCall& call);

  Image read_color() const;               // rows top to bottom
  std::vector<float> read_depth() const;  // rows top to bottom, width * height values
  void finish();                          // glFinish: for timing, waits until rendering is done

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace clraster::oracle
