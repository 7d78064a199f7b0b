#include "runtime/kernel_sources.hpp"

#include <stdexcept>

namespace clraster::runtime::sources {
namespace {

// The file an `#include "path"` line names; empty for any other line.
std::string_view included_file(std::string_view line) {
  constexpr std::string_view kInclude = "#include \"";
  const std::size_t start = line.find_first_not_of(" \t");
  if (start == std::string_view::npos || !line.substr(start).starts_with(kInclude)) return {};
  const std::string_view rest = line.substr(start + kInclude.size());
  return rest.substr(0, rest.find('"'));
}

}  // namespace

const char* text(std::string_view name) {
  for (const SourceFile& file : all()) {
    if (file.name == name) return file.text;
  }
  throw std::logic_error("kernel source " + std::string(name) + " is not embedded");
}

std::string Composer::include(std::string_view name) {
  if (!included_.emplace(name).second) return {};
  const std::string line_file = std::string("\"").append(name).append("\"\n");  // #line's file operand
  std::string program = "#line 1 " + line_file;
  std::string_view rest = text(name);
  for (int line = 1; !rest.empty(); ++line) {
    const std::size_t end = rest.find('\n');
    const std::string_view current = rest.substr(0, end);
    rest = end == std::string_view::npos ? std::string_view() : rest.substr(end + 1);
    const std::string_view file = included_file(current);
    const std::string resolved = file.empty() ? std::string() : include(file);
    if (file.empty()) {
      program.append(current) += '\n';
    } else if (resolved.empty()) {
      program += '\n';  // already in the program: the line stays, empty, so the numbering below holds
    } else {
      program += resolved + "#line " + std::to_string(line + 1) + ' ' + line_file;
    }
  }
  return program;
}

std::string core_program() {
  Composer program;
  std::string source;
  for (const char* file : {"parallel/radix_sort.cl", "parallel/scan.cl", "resources/clear.cl",
                           "resources/index_range.cl", "resources/texture.cl"}) {
    source += program.include(file);
  }
  return source;
}

}  // namespace clraster::runtime::sources
