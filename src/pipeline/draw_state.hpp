// Turns a public DrawState into the kernels' DrawUniforms, checking every value on the way.
#pragma once

#include "clraster/clraster.hpp"
#include "pipeline/pipeline.hpp"
#include "program/interface.hpp"
#include "shared/types.h"

#include <array>

namespace clraster::pipeline {

// projection * model_view, computed in double and rounded once to float: the matrix the vertex
// program applies (the OpenGL oracle uses the same one, so both start from the same floats).
Mat4 model_view_projection(const DrawState& state);

// The inverse transpose of model_view's upper 3x3, column-major: what keeps normals perpendicular to
// surfaces. A singular matrix gets its cofactor matrix, which keeps the normals' directions.
std::array<float, 9> normal_matrix(const Mat4& model_view);

// Throws InvalidArgument naming the field and value for anything out of range, or for state the
// program cannot serve (a Program depth function or blend equation it does not define). The
// viewport and scissor are within layer `view` of the target.
DrawUniforms make_uniforms(const DrawState& state, const RenderTarget& target, const program::ParsedProgram& program,
                           std::uint32_t view);

// The index in CLR_COMMON_BLENDS (types.h) of blend state `b` on an attachment of format `format`
// (CLR_FORMAT_*), or CLR_NOT_COMMON_BLEND: the blends the rasterizer runs with their state compiled in.
int common_blend(const BlendUniforms& b, int format);

}  // namespace clraster::pipeline
