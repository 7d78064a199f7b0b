#include "program/includes.hpp"

#include "program/interface.hpp"
#include "runtime/files.hpp"
#include "shared/clr_limits.h"

#include <filesystem>
#include <regex>

namespace clraster::program {
namespace {

namespace fs = std::filesystem;

constexpr std::uintmax_t kMaxSourceBytes = std::uintmax_t{CLR_MAX_PROGRAM_SOURCE_MIB} << 20;

// "file" as a #line directive's operand.
std::string quoted(const std::string& file) {
  std::string out = "\"";
  for (const char c : file) {
    if (c == '"' || c == '\\') out += '\\';
    if (c != '\n') out += c;
  }
  return out + '"';
}

class Resolver {
 public:
  explicit Resolver(const std::string& file_name) {
    const fs::path folder = fs::path(file_name).parent_path();
    folder_ = folder.empty() ? fs::path(".") : folder;
  }

  // `text`, the file `name` (a path relative to the program's folder, shown as `shown`), with its
  // includes resolved.
  std::string resolve(const std::string& text, const fs::path& name, const std::string& shown, int depth) {
    total_bytes_ += text.size();
    if (total_bytes_ > kMaxSourceBytes) {
      throw InvalidArgument(shown + ": the program and the files it includes take more than " +
                            std::to_string(CLR_MAX_PROGRAM_SOURCE_MIB) + " MiB");
    }
    // Directives are found in the code alone (comments and strings blanked, same offsets); a
    // directive's line may be continued with a backslash.
    static const std::regex directive(R"(^[ \t]*#[ \t]*(include_next|include|import)\b)");
    const std::string code = code_only(text);
    std::string out;
    int line = 1;
    for (std::size_t start = 0; start < text.size();) {
      std::size_t end = start;
      int lines = 1;
      for (;; ++lines) {
        end = code.find('\n', end);
        if (end == std::string::npos || end == 0 || code[end - 1] != '\\') break;
        ++end;
      }
      if (end == std::string::npos) end = text.size();
      const std::string logical = code.substr(start, end - start);
      std::smatch match;
      if (std::regex_search(logical, match, directive)) {
        if (match[1] != "include") {
          throw InvalidArgument(shown + ":" + std::to_string(line) + ": #" + match[1].str() +
                                " is not supported: use #include \"file\"");
        }
        const std::string path = operand(text, code, start + static_cast<std::size_t>(match.length()), end,
                                         shown + ":" + std::to_string(line) + ": #" + match[1].str());
        out += included(path, name, shown, line, depth);
        out += "#line " + std::to_string(line + lines) + " " + quoted(shown) + "\n";
      } else if (std::regex_search(std::regex_replace(logical, std::regex("\\\\\n"), ""), directive)) {
        throw InvalidArgument(shown + ":" + std::to_string(line) + ": an #include directive split over lines");
      } else {
        out.append(text, start, std::min(end + 1, text.size()) - start);
      }
      line += lines;
      start = end + 1;
    }
    return out;
  }

 private:
  // The file name of an #include whose operand runs over [begin, end) of the text: "path", as
  // written. `where` starts the messages ("lit.cl:3: #include").
  static std::string operand(const std::string& text, const std::string& code, std::size_t begin, std::size_t end,
                             const std::string& where) {
    const std::size_t open = code.find_first_not_of(" \t\\\n", begin);
    if (open < end && code[open] == '<') {
      throw InvalidArgument(where + " <...> is not allowed: a program includes files of its own folder, as #include "
                                    "\"file\" (the library's functions are in every program without one)");
    }
    const std::size_t close = open < end && code[open] == '"' ? code.find('"', open + 1) : std::string::npos;
    if (close == std::string::npos || close >= end || code.find_first_not_of(" \t\\\n\r", close + 1) < end ||
        close == open + 1) {
      throw InvalidArgument(where + " takes a file name in quotes, as #include \"file\", relative to the program's "
                                    "folder");
    }
    return text.substr(open + 1, close - open - 1);
  }

  // The text of `path`, included on line `line` of the file `name`, resolved in turn.
  std::string included(const std::string& path, const fs::path& name, const std::string& shown, int line, int depth) {
    const std::string where = shown + ":" + std::to_string(line) + ": #include \"" + path + "\"";
    if (fs::path(path).is_absolute()) {
      throw InvalidArgument(where + ": an absolute path; a program includes files by paths relative to its folder");
    }
    const fs::path relative = (name.parent_path() / path).lexically_normal();
    const fs::path file = folder_ / relative;
    std::error_code error;
    const fs::path real_folder = fs::weakly_canonical(folder_, error);
    const fs::path real_file = fs::weakly_canonical(file, error);
    const fs::path inside = real_file.lexically_relative(real_folder);
    if (relative.empty() || *relative.begin() == ".." || inside.empty() || *inside.begin() == "..") {
      throw InvalidArgument(where + ": the file is outside the program's folder " + folder_.string());
    }
    if (depth == CLR_MAX_INCLUDE_DEPTH) {
      throw InvalidArgument(where + ": includes nest more than " + std::to_string(CLR_MAX_INCLUDE_DEPTH) +
                            " deep (does a file include itself?)");
    }
    const runtime::FileContents contents = runtime::read_regular_file(file, kMaxSourceBytes - total_bytes_);
    if (!contents) throw InvalidArgument(where + ": cannot read " + file.string() + ": " + contents.problem);
    const std::string file_shown = (fs::path(shown).parent_path() / path).lexically_normal().string();
    return "#line 1 " + quoted(file_shown) + "\n" + resolve(contents.bytes, relative, file_shown, depth + 1) + "\n";
  }

  fs::path folder_;
  std::uintmax_t total_bytes_ = 0;
};

}  // namespace

std::string resolve_includes(const std::string& source, const std::string& file_name) {
  return Resolver(file_name).resolve(source, fs::path(file_name).filename(), file_name, 0);
}

}  // namespace clraster::program
