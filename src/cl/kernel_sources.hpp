// The OpenCL C sources of the pipeline, embedded into the library at build time
// (cmake/embed_sources.cmake), so the library never reads kernel files at run time.
#pragma once

#include <string>
#include <vector>

namespace clraster::cl_sources {

struct SourceFile {
  const char* name;  // path relative to src/, e.g. "stages/raster.cl"
  const char* text;
};

// Every embedded file, in the order they are concatenated into the pipeline program.
const std::vector<SourceFile>& all();

// The program text: all files concatenated, each preceded by a #line directive so that compiler
// messages name the original file and line.
std::string pipeline_program();

}  // namespace clraster::cl_sources
