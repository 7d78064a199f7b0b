#include "program/interface.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <initializer_list>
#include <map>
#include <regex>
#include <set>
#include <system_error>

namespace clraster::program {

std::string code_only(const std::string& source) {
  std::string out = source;
  enum { Code, Line, Block, String, Char } state = Code;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const char c = out[i];
    const char next = i + 1 < out.size() ? out[i + 1] : '\0';
    switch (state) {
      case Code:
        if (c == '/' && next == '/') state = Line, out[i] = ' ';
        else if (c == '/' && next == '*') state = Block, out[i] = ' ', out[++i] = ' ';
        else if (c == '"') state = String;
        else if (c == '\'') state = Char;
        break;
      case Line:
        if (c == '\n') state = Code; else out[i] = ' ';
        break;
      case Block:
        if (c == '*' && next == '/') state = Code, out[i] = ' ', out[++i] = ' ';
        else if (c != '\n') out[i] = ' ';
        break;
      case String:
      case Char:
        if (c == '\\') { out[i] = ' '; if (next != '\n' && i + 1 < out.size()) out[++i] = ' '; }
        else if (c == (state == String ? '"' : '\'')) state = Code;
        else if (c != '\n') out[i] = ' ';
        break;
    }
  }
  return out;
}

namespace {

bool is_identifier(const std::string& name) {
  static const std::regex identifier("[A-Za-z_][A-Za-z0-9_]*");
  return std::regex_match(name, identifier);
}

std::string trim(const std::string& text) {
  const auto begin = text.find_first_not_of(" \t\r\n");
  if (begin == std::string::npos) return "";
  return text.substr(begin, text.find_last_not_of(" \t\r\n") - begin + 1);
}

// Collapses runs of white space, so "const   float4" reads as "const float4".
std::string normalize_spaces(const std::string& text) {
  std::string out;
  for (const char c : trim(text)) {
    if (std::isspace(static_cast<unsigned char>(c))) {
      if (!out.empty() && out.back() != ' ') out += ' ';
    } else {
      out += c;
    }
  }
  return out;
}

class Parser {
 public:
  Parser(const std::string& source, std::string file_name) : code_(code_only(source)) {
    find_line_directives(source, std::move(file_name));
  }

  ParsedProgram parse() {
    scan_declarations();
    find_entry_points();
    ParsedProgram& p = result_;
    const Mention derivative = first_mention({"clr_dfdx", "clr_dfdy", "clr_dfdx_fine", "clr_dfdy_fine",
                                              "clr_dfdx_coarse", "clr_dfdy_coarse", "clr_fwidth", "clr_sample"});
    const Mention discard = first_mention({"clr_discard"});
    const Mention depth_write = first_mention({"frag_depth"});
    const Mention fetch =
        first_mention({"clr_framebuffer_fetch", "clr_framebuffer_fetch_int", "clr_framebuffer_fetch_uint"});
    p.interface.uses_derivatives = derivative.found();
    p.may_discard = discard.found();
    p.writes_depth = depth_write.found();
    p.reads_framebuffer = fetch.found();
    // A span program runs after the rasterizer's early tests and has no fragment of its own: what
    // needs one fragment at a time, or late tests, belongs to per-fragment programs.
    if (p.interface.has_fragment_span) {
      const Mention first = std::min({discard, depth_write, fetch, depth_test_, blend_});
      if (first.found()) {
        fail(first.position, first.name + " needs a per-fragment program: a program with fragment_span "
                                                    "cannot use it (write void fragment(clr_fragment* f) instead)");
      }
    }
    return p;
  }

 private:
  // The message, after the file and line of code_[at].
  [[noreturn]] void fail(std::size_t at, const std::string& message) const {
    const Section& section = section_of(at);
    throw InvalidArgument(section.file + ":" + std::to_string(line_of(at)) + ": " + message);
  }

  // Where the code first mentions one of `names` as a word, and which.
  struct Mention {
    std::size_t position = std::string::npos;
    std::string name;
    bool found() const { return position != std::string::npos; }
    bool operator<(const Mention& other) const { return position < other.position; }
  };
  Mention first_mention(std::initializer_list<const char*> names) const {
    std::string alternatives;
    for (const char* name : names) alternatives += (alternatives.empty() ? "" : "|") + std::string(name);
    std::smatch match;
    if (!std::regex_search(code_, match, std::regex("\\b(" + alternatives + ")\\b"))) return {};
    return {static_cast<std::size_t>(match.position()), match[1].str()};
  }

  // Where each #line directive (those of resolve_includes, or the user's own) starts a section of
  // the source: offset, first line and file, as the compiler counts them.
  struct Section {
    std::size_t start = 0;
    int first_line = 1;
    std::string file;
  };

  void find_line_directives(const std::string& source, std::string file_name) {
    sections_.push_back({0, 1, std::move(file_name)});
    // Found in the code (not in comments), at the start of a line; the file's name is read from the
    // source at the same place (the code has its characters blanked).
    static const std::regex directive(R"([ \t]*#[ \t]*line[ \t]+([0-9]{1,9})[ \t]*("[^"\n]*")?[^\n]*\n)");
    for (auto it = std::sregex_iterator(code_.begin(), code_.end(), directive); it != std::sregex_iterator(); ++it) {
      const std::size_t at = static_cast<std::size_t>(it->position());
      if (at != 0 && code_[at - 1] != '\n') continue;
      Section section{at + static_cast<std::size_t>(it->length()), std::stoi((*it)[1].str()), sections_.back().file};
      if ((*it)[2].matched) {
        section.file.clear();
        const std::string name = source.substr(static_cast<std::size_t>(it->position(2)) + 1,
                                               static_cast<std::size_t>(it->length(2)) - 2);
        for (std::size_t i = 0; i < name.size(); ++i) section.file += name[i] == '\\' && i + 1 < name.size() ? name[++i] : name[i];
      }
      sections_.push_back(std::move(section));
    }
  }

  const Section& section_of(std::size_t at) const {
    const auto after = std::upper_bound(sections_.begin(), sections_.end(), at,
                                        [](std::size_t position, const Section& s) { return position < s.start; });
    return *std::prev(after);
  }

  // The line of code_[at] in its file.
  int line_of(std::size_t at) const {
    const Section& section = section_of(at);
    return section.first_line + static_cast<int>(std::count(code_.begin() + static_cast<std::ptrdiff_t>(section.start),
                                                            code_.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
  }

  // Walks the code at brace depth 0 looking for declaration macros.
  void scan_declarations() {
    static const std::regex declaration(
        "\\b(clr_attribute|clr_varying_flat|clr_varying_noperspective|clr_varying|clr_uniform|clr_texture|clr_buffer|"
        "clr_output)\\s*\\(");
    int depth = 0;
    std::size_t depth_checked = 0;
    for (auto it = std::sregex_iterator(code_.begin(), code_.end(), declaration); it != std::sregex_iterator(); ++it) {
      const std::size_t at = static_cast<std::size_t>(it->position());
      for (; depth_checked < at; ++depth_checked) {
        if (code_[depth_checked] == '{') ++depth;
        if (code_[depth_checked] == '}') --depth;
      }
      if (depth != 0) fail(at, (*it)[1].str() + " must be declared at file scope, outside any function");
      const std::size_t open = at + static_cast<std::size_t>(it->length());
      const std::size_t close = code_.find(')', open);
      if (close == std::string::npos) fail(at, "unterminated " + (*it)[1].str() + "(");
      std::vector<std::string> arguments;
      std::string current;
      for (std::size_t i = open; i < close; ++i) {
        if (code_[i] == ',') arguments.push_back(normalize_spaces(current)), current.clear();
        else current += code_[i];
      }
      arguments.push_back(normalize_spaces(current));
      declare((*it)[1].str(), arguments, at);
    }
  }

  void expect_arguments(const std::string& kind, const std::vector<std::string>& arguments, std::size_t count,
                        const char* form, std::size_t at) const {
    if (arguments.size() != count) fail(at, kind + " takes " + form);
  }

  void check_name(const std::string& kind, const std::string& name, const std::vector<ProgramVariable>& existing,
                  std::size_t at) const {
    if (!is_identifier(name)) fail(at, kind + " name '" + name + "' is not an identifier");
    for (const ProgramVariable& v : existing) {
      if (v.name == name) fail(at, kind + " '" + name + "' is already declared on line " + std::to_string(v.line));
    }
  }

  void declare(const std::string& kind, const std::vector<std::string>& arguments, std::size_t at) {
    ProgramInterface& in = result_.interface;
    ProgramVariable v;
    v.line = line_of(at);
    if (kind == "clr_texture") {
      expect_arguments(kind, arguments, 1, "one argument: (name)", at);
      v.name = arguments[0];
      v.type = "texture";
      check_name("texture", v.name, in.textures, at);
      in.textures.push_back(v);
      return;
    }
    expect_arguments(kind, arguments, 2, "two arguments: (type, name)", at);
    v.type = arguments[0];
    v.name = arguments[1];
    const VectorType vector = vector_type(v.type);
    if (kind == "clr_attribute") {
      if (vector.components == 0) fail(at, "attribute type '" + v.type + "' is not a float, int or uint vector of 1 to 4 components");
      check_name("attribute", v.name, in.attributes, at);
      in.attributes.push_back(v);
    } else if (kind.starts_with("clr_varying")) {
      declare_varying(kind, v, vector, at);
    } else if (kind == "clr_uniform") {
      declare_uniform(v, at);
    } else if (kind == "clr_buffer") {
      std::string element = v.type;
      v.writable = !element.starts_with("const ");
      if (!v.writable) element = element.substr(6);
      if (!is_identifier(element)) fail(at, "buffer element type '" + v.type + "' must be a type name, optionally after const");
      check_name("buffer", v.name, in.buffers, at);
      in.buffers.push_back(v);
    } else {  // clr_output
      if (v.type != "float4" && v.type != "int4" && v.type != "uint4") {
        fail(at, "output type '" + v.type + "' is not float4, int4 or uint4");
      }
      check_name("output", v.name, in.outputs, at);
      if (in.outputs.size() == kMaxColorAttachments) {
        fail(at, "more than " + std::to_string(kMaxColorAttachments) + " outputs (one per colour attachment)");
      }
      in.outputs.push_back(v);
    }
  }

  void declare_varying(const std::string& kind, ProgramVariable& v, const VectorType& vector, std::size_t at) {
    if (vector.components == 0) fail(at, "varying type '" + v.type + "' is not a float, int or uint vector of 1 to 4 components");
    const Interpolation mode = kind == "clr_varying_flat"            ? Interpolation::Flat
                               : kind == "clr_varying_noperspective" ? Interpolation::NoPerspective
                                                                     : Interpolation::Smooth;
    if (vector.scalar != "float" && mode != Interpolation::Flat) {
      fail(at, "integer varying '" + v.name + "' must be declared with clr_varying_flat (integers are not interpolated)");
    }
    check_name("varying", v.name, result_.interface.varyings, at);
    v.interpolation = mode == Interpolation::Flat ? "flat" : mode == Interpolation::NoPerspective ? "noperspective" : "smooth";
    v.offset = result_.varying_floats.size();
    v.bytes = static_cast<std::size_t>(vector.components) * 4;
    result_.varying_floats.insert(result_.varying_floats.end(), static_cast<std::size_t>(vector.components), mode);
    result_.interface.varyings.push_back(v);
  }

  // Lays the uniform out as the OpenCL C compiler lays out the generated struct: every type is
  // aligned to its size (three-component vectors take the room of four), arrays are runs of it.
  void declare_uniform(ProgramVariable& v, std::size_t at) {
    static const std::regex array("([A-Za-z_][A-Za-z0-9_]*)\\s*\\[\\s*([0-9]+)\\s*\\]");
    std::smatch match;
    if (std::regex_match(v.name, match, array)) {
      v.name = match[1];
      // Digits of any length: from_chars reports a count past unsigned long instead of throwing.
      const std::string digits = match[2];
      unsigned long size = 0;
      const std::errc error = std::from_chars(digits.data(), digits.data() + digits.size(), size).ec;
      if (error != std::errc() || size < 1 || size > 65536) {
        fail(at, "uniform array '" + v.name + "' needs 1 to 65536 elements");
      }
      v.array_size = static_cast<int>(size);
    }
    std::size_t size = 0;
    const VectorType vector = vector_type(v.type);
    if (vector.components != 0) size = 4u * (vector.components == 3 ? 4u : static_cast<unsigned>(vector.components));
    else if (v.type == "float8" || v.type == "int8" || v.type == "uint8") size = 32;
    else if (v.type == "float16" || v.type == "int16" || v.type == "uint16") size = 64;
    else fail(at, "uniform type '" + v.type + "' is not a float, int or uint vector (1, 2, 3, 4, 8 or 16 components)");
    check_name("uniform", v.name, result_.interface.uniforms, at);
    v.offset = (next_offset_ + size - 1) / size * size;
    v.bytes = size * static_cast<std::size_t>(std::max(v.array_size, 1));
    next_offset_ = v.offset + v.bytes;
    alignment_ = std::max(alignment_, size);
    // The struct's size is a multiple of its alignment.
    result_.interface.uniform_bytes = (next_offset_ + alignment_ - 1) / alignment_ * alignment_;
    result_.interface.uniforms.push_back(v);
  }

  void find_entry_points() {
    // Where the function `pattern` matches is defined at file scope, named `name`.
    const auto definition = [&](const char* pattern, const char* name) -> Mention {
      const std::regex function(pattern);
      int depth = 0;
      std::size_t checked = 0;
      for (auto it = std::sregex_iterator(code_.begin(), code_.end(), function); it != std::sregex_iterator(); ++it) {
        for (; checked < static_cast<std::size_t>(it->position()); ++checked) {
          if (code_[checked] == '{') ++depth;
          if (code_[checked] == '}') --depth;
        }
        if (depth == 0) return {checked, name};
      }
      return {};
    };
    const auto defines = [&](const char* pattern) { return definition(pattern, "").found(); };
    if (!defines("\\bvoid\\s+vertex\\s*\\([^)]*\\)\\s*\\{")) {
      fail(0, "the program defines no vertex program: void vertex(clr_vertex* v) { ... }");
    }
    const bool per_fragment = defines("\\bvoid\\s+fragment\\s*\\([^)]*\\)\\s*\\{");
    const bool per_span = defines("\\bvoid\\s+fragment_span\\s*\\([^)]*\\)\\s*\\{");
    if (!per_fragment && !per_span) {
      fail(0, "the program defines no fragment program: void fragment(clr_fragment* f) { ... } (or void "
              "fragment_span(clr_span_fragment* f) { ... })");
    }
    if (per_fragment && per_span) {
      fail(0, "the program defines both void fragment(...) and void fragment_span(...): one fragment program, per "
              "fragment or per span");
    }
    result_.interface.has_fragment_span = per_span;
    depth_test_ = definition("\\bbool\\s+depth_test\\s*\\([^)]*\\)\\s*\\{", "bool depth_test");
    blend_ = definition("\\bfloat4\\s+blend\\s*\\([^)]*\\)\\s*\\{", "float4 blend");
    result_.interface.has_depth_test = depth_test_.found();
    result_.interface.has_blend = blend_.found();
  }

  std::string code_;
  std::vector<Section> sections_;  // in order of their start
  ParsedProgram result_;
  std::size_t alignment_ = 4;   // of the uniform struct
  std::size_t next_offset_ = 0;  // where the next uniform would start
  Mention depth_test_, blend_;   // the definitions of the optional per-fragment functions
};

}  // namespace

VectorType vector_type(const std::string& name) {
  for (const char* scalar : {"float", "uint", "int"}) {
    const std::string s = scalar;
    if (name == s) return {s, 1};
    if (name.size() == s.size() + 1 && name.starts_with(s) && name.back() >= '2' && name.back() <= '4') {
      return {s, name.back() - '0'};
    }
  }
  return {};
}

ParsedProgram parse_program(const std::string& source, const std::string& file_name) {
  return Parser(source, file_name).parse();
}

}  // namespace clraster::program
