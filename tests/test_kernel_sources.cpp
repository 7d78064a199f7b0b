// Kernel sources name the sources they include, and the host puts a program together from them
// (runtime/kernel_sources.hpp): each file once, with compiler messages naming each file and line.
#include "runtime/kernel_sources.hpp"

#include <gtest/gtest.h>

#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

namespace clraster::test {
namespace {

std::size_t occurrences(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++count;
  return count;
}

TEST(KernelSources, EveryIncludeNamesAnEmbeddedSource) {
  for (const runtime::sources::SourceFile& file : runtime::sources::all()) {
    SCOPED_TRACE(file.name);
    EXPECT_NO_THROW(runtime::sources::Composer().include(file.name));
  }
}

TEST(KernelSources, AProgramTakesEachSourceOnce) {
  runtime::sources::Composer program;
  // texture.cl includes format.cl and the shared headers, and format.cl the shared types again.
  const std::string texture = program.include("resources/texture.cl");
  for (const char* file : {"resources/texture.cl", "resources/format.cl", "shared/types.h", "shared/clr_limits.h"}) {
    EXPECT_EQ(occurrences(texture, "#line 1 \"" + std::string(file) + "\"\n"), 1u) << file;
  }
  EXPECT_EQ(program.include("resources/format.cl"), "");
  EXPECT_EQ(program.include("resources/texture.cl"), "");
}

// Each line of a composed source is where its #line directive says: that line of that file, or empty
// where the file includes one that the program has already.
TEST(KernelSources, LinesKeepTheirFilesAndNumbers) {
  for (const runtime::sources::SourceFile& file : runtime::sources::all()) {
    std::istringstream program(runtime::sources::Composer().include(file.name));
    std::string name;
    std::vector<std::string> lines;  // of the file `name`
    std::size_t number = 0;
    for (std::string line; std::getline(program, line);) {
      char quoted[256];
      if (std::sscanf(line.c_str(), "#line %zu \"%255[^\"]\"", &number, quoted) == 2) {
        name = quoted;
        std::istringstream text(runtime::sources::text(name));
        lines.clear();
        for (std::string l; std::getline(text, l);) lines.push_back(l);
        continue;
      }
      ASSERT_LE(number, lines.size()) << file.name << ": " << name;
      const std::string& original = lines[number - 1];
      if (line != original) EXPECT_TRUE(line.empty() && original.starts_with("#include \"")) << name << ":" << number;
      ++number;
    }
  }
}

}  // namespace
}  // namespace clraster::test
