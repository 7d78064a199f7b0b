#include "cl/kernel_sources.hpp"

namespace clraster::cl_sources {

std::string pipeline_program() {
  std::string program;
  for (const SourceFile& file : all()) {
    program += "#line 1 \"";
    program += file.name;
    program += "\"\n";
    program += file.text;
    program += '\n';
  }
  return program;
}

}  // namespace clraster::cl_sources
