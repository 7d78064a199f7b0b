// Turns a public DrawState into the kernels' DrawUniforms, checking every value on the way.
#pragma once

#include "clraster/clraster.hpp"
#include "stages/types.h"

namespace clraster::pipeline {

// Throws InvalidArgument naming the field and value for anything out of range.
DrawUniforms make_uniforms(const DrawState& state, int framebuffer_width, int framebuffer_height);

// The pixels a draw may write: framebuffer, viewport and scissor intersected (may be empty).
bool writable_rect_empty(const DrawUniforms& uniforms);

}  // namespace clraster::pipeline
