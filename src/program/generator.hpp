// Generates the OpenCL C program that runs a user program through every pipeline stage:
//
//   generated constants (varying and output counts, quad shading, early tests)
//   raster/span.cl and resources/texture.cl, which the interface names, with what they include
//   generated interface: clr_attributes, clr_varyings, clr_uniforms, clr_textures, clr_buffers,
//     clr_outputs, clr_vertex, clr_fragment, the resource kernel parameters, the attribute fetch
//     (CLR_FETCH_ATTRIBUTES), glue prototypes
//   program/prelude.cl: what programs call (clr_mul, derivatives, clr_sample, clr_discard, ...)
//     and what it includes (spans' texture sampling, blend modes)
//   #line 1 "<user file>" + the user's source, so compiler messages name the user's lines
//   the stage kernels: geometry/vertex.cl, setup.cl, bin.cl and raster/tile.cl, with what they include
//   generated glue: varyings packed into floats and back (raster/ interpolates the floats), the
//     program's depth test and blend function called, outputs gathered and merged into the tile
#pragma once

#include "program/interface.hpp"

#include <string>

namespace clraster::program {

std::string generate_stage_program(const ParsedProgram& program, const std::string& user_source,
                                   const std::string& file_name);

// Whether the depth and stencil tests may run before the fragment program: it neither discards nor
// writes depth (OpenGL's early fragment tests), and it is not a per-fragment program shaded in
// quads (whose quads run the program for every pixel whatever the tests say; a span program shaded
// in quads tests first, and runs for its whole spans anyway).
bool early_fragment_tests(const ParsedProgram& program);

// Bytes the vertex stage stores per vertex, and one set-up triangle's record, for this program.
std::size_t shaded_vertex_bytes(const ParsedProgram& program);
std::size_t setup_triangle_bytes(const ParsedProgram& program);

}  // namespace clraster::program
