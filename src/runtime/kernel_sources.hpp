// The OpenCL C sources of the pipeline, embedded into the library at build time
// (cmake/embed_sources.cmake), so the library never reads kernel files at run time.
#pragma once

#include <initializer_list>
#include <string>
#include <vector>

namespace clraster::cl_sources {

struct SourceFile {
  const char* name;  // path relative to src/, e.g. "geometry/vertex.cl"
  const char* text;
};

// Every embedded file.
const std::vector<SourceFile>& all();

// The text of one embedded file. Throws std::logic_error for a name that is not embedded.
const char* text(const char* name);

// The named files concatenated in the given order, each preceded by a #line directive so that
// compiler messages name the original file and line. Throws std::logic_error for a name that is
// not embedded.
std::string compose(std::initializer_list<const char*> names);

// The context-wide program: scans, radix sort, index validation, texture kernels. The stages that
// run a user program are generated per program (program/generator.hpp).
std::string core_program();

}  // namespace clraster::cl_sources
