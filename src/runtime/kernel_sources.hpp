// The OpenCL C sources of the pipeline, embedded into the library at build time
// (cmake/embed_sources.cmake), so the library never reads kernel files at run time.
//
// A kernel source names the sources it needs on `#include "path"` lines, path relative to src/ as
// the C++ sources name headers, and the host resolves them as it puts a program together: each file
// once, wherever first included. An include is resolved whatever #if surrounds it, so sources
// include at top level.
#pragma once

#include <functional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace clraster::runtime::sources {

struct SourceFile {
  const char* name;  // path relative to src/, e.g. "geometry/vertex.cl"
  const char* text;
};

// Every embedded file.
const std::vector<SourceFile>& all();

// The text of one embedded file. Throws std::logic_error for a name that is not embedded.
const char* text(std::string_view name);

// One program's source as it is put together, which knows the files the program has already.
class Composer {
 public:
  // The embedded file `name` with its includes resolved, under #line directives so that compiler
  // messages name each file and line; "" where the program has it already. Throws std::logic_error
  // for a file that is not embedded.
  std::string include(std::string_view name);

 private:
  std::set<std::string, std::less<>> included_;
};

// The context-wide program: scans, radix sort, index validation, clears, texture kernels. The stages
// that run a user program are generated per program (program/generator.hpp).
std::string core_program();

}  // namespace clraster::runtime::sources
