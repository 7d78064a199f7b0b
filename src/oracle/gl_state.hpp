// Internal to the oracle: clraster's draw state as OpenGL state. Each clraster enum has its one
// mapping here, shared by the built-in renderer (gl_renderer.cpp) and the scene layer (gl_scene.cpp).
#pragma once

#include <cstdint>
#include <string>

#include "oracle/gl_context.hpp"

namespace clraster::oracle::gl {

GLenum topology(Topology topology);

// Sets every fixed-function state a DrawState controls, for a framebuffer of width x height:
// viewport (width or height 0: the whole framebuffer), scissor, culling and front face, depth test,
// function and write mask, stencil test with separate front and back functions, operations and
// masks, and the blending and colour write masks of all kMaxColorAttachments draw buffers with the
// blend constant colour. All of it is set on every draw: the context is shared, so nothing may be
// assumed about what an earlier draw (of any renderer) left behind. Depth clamping stays off and the
// depth range [0, 1]. The built-in shading inputs are not state and are ignored here.
// Throws InvalidArgument for CompareFunc::Program and BlendEquation::Program: GL has no equivalent.
void apply_draw_state(const DrawState& state, int width, int height);

// Lifts what clears obey (the scissor test; colour, depth and stencil write masks), so that a clear
// reaches every pixel and bit whatever the last draw left.
void prepare_clear();

// How many elements a draw of `count` from `first` takes out of `available` (count == kAllElements:
// up to the end). Throws InvalidArgument, naming `what` (e.g. "the mesh"), for a range that runs past
// the end or that GL's 32-bit signed counts cannot express.
std::uint32_t draw_range(std::uint32_t first, std::uint32_t count, std::uint64_t available, const std::string& what);

}  // namespace clraster::oracle::gl
