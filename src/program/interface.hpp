// Reads a user program's interface: the clr_attribute / clr_varying / clr_uniform / clr_texture /
// clr_buffer / clr_output declarations at file scope, and which entry points it defines. The
// declarations are macros that expand to nothing in the compiled program; the generator
// (generator.hpp) turns what is read here into the structs and kernel parameters that carry them.
#pragma once

#include "clraster/clraster.hpp"

#include <string>
#include <vector>

namespace clraster::program {

// How a varying float is interpolated across a triangle (CLR_INTERPOLATE_* in types.h).
enum class Interpolation { Smooth = 0, Flat = 1, NoPerspective = 2 };

struct ParsedProgram {
  ProgramInterface interface;
  // Varyings travel as floats (integers as their bits): one entry per float, in declaration order.
  // ProgramVariable::offset of a varying is its first float here.
  std::vector<Interpolation> varying_floats;
  bool may_discard = false;  // mentions clr_discard
  bool writes_depth = false; // mentions frag_depth
  bool reads_framebuffer = false;  // mentions clr_framebuffer_fetch (or its _int, _uint forms)
};

// `source` may hold #line directives (resolve_includes puts the included files' text under them):
// messages and ProgramVariable::line name the file and line they give.
// Throws InvalidArgument with "FILE:LINE: ..." for a malformed or duplicate declaration, an
// unsupported type, an integer varying that is not flat, or a missing vertex or fragment function.
ParsedProgram parse_program(const std::string& source, const std::string& file_name);

// The source with comments, string and character literals blanked out (newlines kept), so that
// offsets and line numbers stay right and nothing inside a comment counts as code.
std::string code_only(const std::string& source);

// Components (1..4) and the scalar type ("float", "int", "uint") of a vector type name such as
// "float3"; components 0 when the name is not one.
struct VectorType {
  std::string scalar;
  int components = 0;
};
VectorType vector_type(const std::string& name);

}  // namespace clraster::program
