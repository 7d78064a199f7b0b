#include "runtime/kernel_sources.hpp"

#include <stdexcept>
#include <string_view>

namespace clraster::cl_sources {

const char* text(const char* name) {
  for (const SourceFile& file : all()) {
    if (std::string_view(file.name) == name) return file.text;
  }
  throw std::logic_error(std::string("kernel source ") + name + " is not embedded");
}

std::string compose(std::initializer_list<const char*> names) {
  std::string program;
  for (const char* name : names) {
    program += "#line 1 \"";
    program += name;
    program += "\"\n";
    program += text(name);
    program += '\n';
  }
  return program;
}

std::string core_program() {
  return compose({"shared/clr_limits.h", "shared/types.h", "parallel/scan.cl", "parallel/radix_sort.cl",
                  "resources/index_range.cl", "resources/format.cl", "resources/texture.cl", "resources/clear.cl"});
}

}  // namespace clraster::cl_sources
