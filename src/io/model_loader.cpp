#include "io/model_loader.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <mutex>
#include <optional>
#include <span>
#include <string_view>
#include <unordered_map>

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <assimp/DefaultLogger.hpp>
#include <assimp/Importer.hpp>
#include <assimp/LogStream.hpp>
#include <assimp/importerdesc.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/matrix.hpp>

#include "clraster/clraster.hpp"
#include "io/procedural.hpp"

namespace clraster::io {
namespace {

// Polygons become triangles, and meshes that mix triangles with points or lines are split by
// primitive type. Nothing that invents or merges vertices: normals follow our own rules, which
// need the file's vertices as they are.
constexpr unsigned kPostProcessing = aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_ValidateDataStructure;

[[noreturn]] void fail(const std::string& path, const std::string& reason) {
  throw InvalidArgument(describe_load_error(path, reason));
}

// assimp's messages can span several lines and be long; ours are one line.
std::string one_line(std::string_view text) {
  constexpr std::size_t kMaxLength = 240;
  std::string line;
  for (char c : text) {
    const bool space = std::isspace(static_cast<unsigned char>(c));
    if (space && (line.empty() || line.back() == ' ')) continue;
    line += space ? ' ' : c;
  }
  if (!line.empty() && line.back() == ' ') line.pop_back();
  if (line.size() > kMaxLength) line = line.substr(0, kMaxLength - 3) + "...";
  return line;
}

// A model file's bytes, for the checks before and after assimp reads it: mapped when it is a
// regular file, read otherwise (a device such as /dev/null, a pipe). Opened before assimp sees the
// file, whose "unable to open file" does not say why.
class ModelFile {
 public:
  explicit ModelFile(const std::string& path) {
    std::error_code ignored;
    if (std::filesystem::is_directory(path, ignored)) fail(path, "it is a directory");
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) fail(path, std::strerror(errno));
    struct stat status {};
    if (::fstat(fd, &status) == 0 && S_ISREG(status.st_mode) && status.st_size > 0) {
      void* mapping = ::mmap(nullptr, static_cast<std::size_t>(status.st_size), PROT_READ, MAP_PRIVATE, fd, 0);
      if (mapping != MAP_FAILED) {
        mapping_ = mapping;
        bytes_ = {static_cast<const char*>(mapping), static_cast<std::size_t>(status.st_size)};
      }
    }
    if (mapping_ == nullptr) {
      char buffer[1 << 16];
      for (ssize_t got; (got = ::read(fd, buffer, sizeof buffer)) != 0;) {
        if (got < 0 && errno != EINTR) break;
        if (got > 0) read_.append(buffer, static_cast<std::size_t>(got));
      }
      bytes_ = read_;
    }
    ::close(fd);
  }
  ~ModelFile() {
    if (mapping_ != nullptr) ::munmap(mapping_, bytes_.size());
  }
  ModelFile(const ModelFile&) = delete;
  ModelFile& operator=(const ModelFile&) = delete;

  std::string_view bytes() const { return bytes_; }

 private:
  void* mapping_ = nullptr;
  std::string read_;
  std::string_view bytes_;
};

// ".glb" for "Box.GLB".
std::string lowercase_extension(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

bool is_gltf(const std::string& path) {
  const std::string extension = lowercase_extension(path);
  return extension == ".gltf" || extension == ".glb";
}

// Records assimp's warnings and errors while one model loads. Some readers repair files whose
// faces reference vertices that do not exist and only say so in the log: the OFF reader clamps
// such indices, the glTF 2 reader drops such faces. assimp's logger is process-wide, so loads take
// turns while a capture exists; a logger the application installed is used and left in place.
class LogCapture final : public Assimp::LogStream {
 public:
  LogCapture() : lock_(mutex()), created_logger_(Assimp::DefaultLogger::isNullLogger()) {
    if (created_logger_) Assimp::DefaultLogger::create(nullptr, Assimp::Logger::NORMAL, 0);
    Assimp::DefaultLogger::get()->attachStream(this, kSeverities);
  }
  ~LogCapture() override {
    // Detached before the logger is killed, which would otherwise delete this stream.
    Assimp::DefaultLogger::get()->detachStream(this, kSeverities);
    if (created_logger_) Assimp::DefaultLogger::kill();
  }
  LogCapture(const LogCapture&) = delete;
  LogCapture& operator=(const LogCapture&) = delete;

  void write(const char* message) override { messages_.emplace_back(message); }

  // The messages without the logger's "Warn,  T0: " prefix.
  std::vector<std::string> messages() const {
    std::vector<std::string> texts;
    for (const std::string& message : messages_) {
      const std::size_t colon = message.find(": ");
      texts.push_back(one_line(colon == std::string::npos ? message : message.substr(colon + 2)));
    }
    return texts;
  }

 private:
  static constexpr unsigned kSeverities = Assimp::Logger::Warn | Assimp::Logger::Err;
  static std::mutex& mutex() {
    static std::mutex instance;
    return instance;
  }

  std::scoped_lock<std::mutex> lock_;
  bool created_logger_;
  std::vector<std::string> messages_;
};

// Whether a log message says that faces referenced vertices that do not exist, in the words of
// assimp's readers: "OFF: Vertex index is out of range", "Some faces had out-of-range indices.
// Those faces were dropped.", "Face has an invalid index. It will be ignored", ... Messages about
// other indices (materials, texture coordinates, colours, bones) do not count: those do not lose
// geometry.
bool reports_bad_vertex_index(std::string message) {
  std::transform(message.begin(), message.end(), message.begin(),
                 [](unsigned char c) { return c == '-' ? ' ' : static_cast<char>(std::tolower(c)); });
  const auto mentions = [&](std::initializer_list<std::string_view> words) {
    return std::any_of(words.begin(), words.end(), [&](std::string_view word) {
      return message.find(word) != std::string::npos;
    });
  };
  return mentions({"index", "indices"}) && mentions({"out of range", "outside", "invalid"}) &&
         mentions({"vertex", "vertices", "face", "polygon", "triangle", "point", "position"}) &&
         !mentions({"material", "uv", "texture", "tvertex", "color", "bone", "weight"});
}

// ---- References that assimp 5.2.5 misreads without a word ---------------------------------------
//
// Some of assimp's readers take indices with strtoul10, strtol10 or atoi, which stop at the first
// character that is not a digit and wrap around past 32 bits, and then use what they got:
// - OFF and ASCII PLY: "-1" reads as 0 (in PLY, for unsigned index types), 4294967297 as 1, a face
//   line short of indices gets zeros, and a file short of face lines loses them (OFF) or repeats
//   the last one (PLY): faces reference the wrong vertices, and nothing in the scene shows it. PLY
//   indices of floating-point type are cut to integers and wrap too, and PLY triangle strips keep
//   one triangle each;
// - OBJ: a reference to a normal or texture coordinate that does not exist, wrapped or not, makes
//   the reader drop the normals or texture coordinates of the whole mesh.
// So the text of a file for one of those readers is checked, cut into lines as that reader cuts it,
// so as to see the faces it sees: every index must be a plain decimal of something that exists.
// OFF and PLY files are checked before assimp reads them, when their extension names the format
// (their counts can make assimp allocate without bound, below); otherwise, and for OBJ, once
// assimp has picked the reader (by extension, or else by content).

// What faces reference, for messages.
struct Kind {
  const char* one;
  const char* many;
};
constexpr Kind kVertices{"vertex", "vertices"};
constexpr Kind kTextureCoordinates{"texture coordinate", "texture coordinates"};
constexpr Kind kNormals{"normal", "normals"};

// assimp's IsLineEnd.
bool is_line_end(char c) { return c == '\r' || c == '\n' || c == '\f' || c == '\0'; }

std::size_t line_end(std::string_view text) {
  return static_cast<std::size_t>(std::find_if(text.begin(), text.end(), is_line_end) - text.begin());
}

// The words of a line, between spaces and tabs.
std::vector<std::string_view> words_of(std::string_view line) {
  std::vector<std::string_view> words;
  for (std::size_t end = 0;;) {
    const std::size_t begin = line.find_first_not_of(" \t", end);
    if (begin == std::string_view::npos) return words;
    end = std::min(line.find_first_of(" \t", begin), line.size());
    words.push_back(line.substr(begin, end - begin));
  }
}

// A plain decimal below 2^32: digits only.
std::optional<std::uint32_t> decimal(std::string_view word) {
  std::uint32_t value = 0;
  const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), value);
  if (error != std::errc() || end != word.data() + word.size()) return std::nullopt;
  return value;
}

// A model file's text, for checks that fail naming the line they are about.
struct Text {
  const std::string& path;
  std::string_view all;

  std::string line_of(std::string_view part) const {
    return "line " + std::to_string(1 + std::count(all.data(), part.data(), '\n'));
  }
  [[noreturn]] void fail_on(std::string_view part, const std::string& reason) const {
    fail(path, line_of(part) + " " + reason);
  }
  [[noreturn]] void fail_reference(Kind kind, std::string_view word, std::uint32_t count) const {
    fail(path, std::string("faces reference ") + kind.many + " that do not exist: " + line_of(word) +
                   " refers to " + kind.one + " '" + std::string(word) + "' of " + std::to_string(count));
  }
  std::uint32_t count(std::string_view word) const {
    const std::optional<std::uint32_t> value = decimal(word);
    if (!value) fail_on(word, "has '" + std::string(word) + "' where a count belongs");
    return *value;
  }
  void check_vertex(std::string_view word, std::uint32_t vertices) const {
    const std::optional<std::uint32_t> index = decimal(word);
    if (!index || *index >= vertices) fail_reference(kVertices, word, vertices);
  }
  // The words of the list in `line` that starts at words[at] with its length; `at` moves past it.
  std::span<const std::string_view> take_list(std::string_view line, std::span<const std::string_view> words,
                                              std::size_t& at) const {
    const std::uint32_t length = count(at < words.size() ? words[at] : line.substr(line.size()));
    if (words.size() - at - 1 < length) fail_on(line, "ends before its face does");
    at += 1 + std::size_t{length};
    return words.subspan(at - length, length);
  }
};

// OFF as assimp's reader takes it: the header word by word across line ends and # comments (an
// optional [ST][C][N][4][n]OFF keyword, a dimension after it for n, then the vertex, face and edge
// counts); then lines as GetNextLine cuts them, empty ones skipped: one per vertex, then one per
// face, which starts with its corner count and that many vertex indices.
void check_off(const Text& text) {
  constexpr std::size_t kLineBuffer = 4096;  // GetNextLine's: longer lines go on as further lines
  std::string_view rest = text.all;
  const auto skip_blanks = [&] {
    while (!rest.empty() && (rest[0] == ' ' || rest[0] == '\t' || is_line_end(rest[0]) || rest[0] == '#')) {
      rest.remove_prefix(rest[0] == '#' ? line_end(rest) : 1);
    }
  };
  const auto next_word = [&] {
    skip_blanks();
    const std::size_t end = std::min(rest.find_first_of(" \t"), line_end(rest));
    const std::string_view word = rest.substr(0, end);
    rest.remove_prefix(end);
    return word;
  };
  const auto next_line = [&] {
    if (rest.empty()) fail(text.path, "the file ends before its last face");
    const std::size_t end = std::min(line_end(rest), kLineBuffer);
    const std::string_view line = rest.substr(0, end);
    rest.remove_prefix(end);
    while (!rest.empty() && is_line_end(rest[0])) rest.remove_prefix(1);
    return line;
  };

  skip_blanks();
  for (std::string_view prefix : {"ST", "C", "N", "4"}) {
    if (rest.starts_with(prefix)) rest.remove_prefix(prefix.size());
  }
  const bool has_dimension = rest.starts_with('n');
  if (has_dimension) rest.remove_prefix(1);
  if (rest.starts_with("OFF")) rest.remove_prefix(3);
  if (has_dimension) next_word();
  const std::string_view vertices_word = next_word();
  const std::uint32_t vertices = text.count(vertices_word);
  const std::uint32_t faces = text.count(next_word());
  text.count(next_word());  // edges, which assimp reads and ignores
  skip_blanks();
  // assimp allocates for what the counts declare before it reads: each vertex and face takes a
  // line, of a character and a line end at least (the last line end may be missing).
  if (2 * (std::uint64_t{vertices} + faces) > rest.size() + 1) {
    text.fail_on(vertices_word, "declares " + std::to_string(vertices) + " vertices and " + std::to_string(faces) +
                                    " faces, more than the " + std::to_string(rest.size()) + " bytes after it hold");
  }

  for (std::uint32_t v = 0; v < vertices; ++v) next_line();
  for (std::uint32_t f = 0; f < faces; ++f) {
    const std::string_view line = next_line();
    const std::vector<std::string_view> words = words_of(line);
    std::size_t at = 0;
    for (std::string_view index : text.take_list(line, words, at)) text.check_vertex(index, vertices);
  }
}

// The next line as assimp's PLY reader takes it (IOStreamBuffer::getNextLine): a line end where a
// line should start is skipped through the next '\n', so that one empty line is skipped but a
// second is a line; the line runs to the next line end, which is consumed.
std::optional<std::string_view> next_ply_line(std::string_view& rest) {
  if (!rest.empty() && is_line_end(rest[0])) rest.remove_prefix(std::min(rest.find('\n'), rest.size() - 1) + 1);
  if (rest.empty()) return std::nullopt;
  const std::size_t end = line_end(rest);
  const std::string_view line = rest.substr(0, end);
  rest.remove_prefix(std::min(end + 1, rest.size()));
  return line;
}

// ---- PLY, checked before assimp reads it -----------------------------------------------------
//
// A PLY file is a header of elements ("element face 12") and their properties ("property float x",
// "property list uchar int vertex_indices"), then each element's entries: in ASCII files one line
// each, their values word by word in the order of the properties; in binary files the values one
// after the other. Faces are the entries of "face", their vertex indices the lists
// "vertex_indices" or "vertex_index". assimp 5.2.5's reader loops forever on a header without
// end_header, allocates for the entries a header declares before it reads them (100 million faces
// in a 188-byte file grow past 4.6 GB), and aborts or corrupts memory on a face without vertex
// indices; so all of that is checked before assimp sees the file, with the misread references of
// ASCII files.

struct PlyType {
  std::string_view name;
  unsigned size;
  bool is_signed;
};

constexpr std::array<PlyType, 16> kPlyTypes{{{"char", 1, true},    {"int8", 1, true},     {"uchar", 1, false},
                                             {"uint8", 1, false},  {"short", 2, true},    {"int16", 2, true},
                                             {"ushort", 2, false}, {"uint16", 2, false},  {"int", 4, true},
                                             {"int32", 4, true},   {"uint", 4, false},    {"uint32", 4, false},
                                             {"float", 4, true},   {"float32", 4, true},  {"double", 8, true},
                                             {"float64", 8, true}}};

const PlyType* ply_type(std::string_view name) {
  const auto type = std::find_if(kPlyTypes.begin(), kPlyTypes.end(), [&](const PlyType& t) { return t.name == name; });
  return type == kPlyTypes.end() ? nullptr : &*type;
}

struct PlyProperty {
  enum class Kind { kScalar, kList, kVertexIndices } kind;
  const PlyType* count_type;  // lists only
  const PlyType* value_type;  // null for a type the reader does not know (allowed in ASCII files)
  std::string_view value_type_name;
  std::string_view line;  // its "property" line, for messages
};

struct PlyElement {
  std::string_view name;
  std::string_view line;  // its "element" line, for messages
  std::uint32_t count;
  std::vector<PlyProperty> properties;
};

struct PlyHeader {
  bool ascii = false;
  bool big_endian = false;
  std::vector<PlyElement> elements;
  std::string_view data;  // what follows the end_header line
};

// The header as assimp's reader takes it, line by line. Fails on what assimp reads wrongly or not
// at all: no end_header, an element declared twice, triangle strips, floating-point vertex indices,
// and in binary files a type whose size is unknown.
PlyHeader read_ply_header(const Text& text) {
  PlyHeader header;
  std::string_view rest = text.all;
  for (;;) {
    const std::optional<std::string_view> line = next_ply_line(rest);
    if (!line) fail(text.path, "its PLY header has no end_header line");
    const std::vector<std::string_view> words = words_of(*line);
    const auto word = [&](std::size_t i) { return i < words.size() ? words[i] : line->substr(line->size()); };
    if (word(0) == "end_header") {
      // ASCII entries are lines from here on; binary data starts after the line's '\n', which a
      // '\r' (the line end that ended it) can precede.
      const std::size_t line_end_at = static_cast<std::size_t>(line->data() + line->size() - text.all.data());
      const bool ended_by_cr = line_end_at < text.all.size() && text.all[line_end_at] == '\r';
      header.data = !header.ascii && ended_by_cr && rest.starts_with('\n') ? rest.substr(1) : rest;
      break;
    }
    if (word(0) == "format") {
      header.ascii = word(1) == "ascii";
      header.big_endian = word(1) == "binary_big_endian";
    }
    if (word(0) == "element") {
      if (word(1) == "tristrips") {
        text.fail_on(*line, "declares triangle strips, of which assimp keeps one triangle each");
      }
      // assimp sizes its arrays by the first and corrupts its heap writing a second (found by fuzzing).
      if (std::any_of(header.elements.begin(), header.elements.end(),
                      [&](const PlyElement& element) { return element.name == word(1); })) {
        text.fail_on(*line, "declares a second '" + std::string(word(1)) + "' element");
      }
      header.elements.push_back({word(1), *line, text.count(word(2)), {}});
    }
    if (word(0) == "property" && !header.elements.empty()) {
      const bool list = word(1) == "list";
      const std::string_view value_type = list ? word(3) : word(1);
      const bool indices = list && header.elements.back().name == "face" &&
                           (word(4) == "vertex_indices" || word(4) == "vertex_index");
      if (indices && (value_type.starts_with("float") || value_type.starts_with("double"))) {
        text.fail_on(*line,
                     "declares vertex indices of type " + std::string(value_type) + ", which assimp rounds and wraps");
      }
      const PlyProperty property{indices ? PlyProperty::Kind::kVertexIndices
                                 : list  ? PlyProperty::Kind::kList
                                         : PlyProperty::Kind::kScalar,
                                 list ? ply_type(word(2)) : nullptr, ply_type(value_type), value_type, *line};
      if (list && property.count_type == nullptr) text.fail_on(*line, "declares a list without a count type");
      header.elements.back().properties.push_back(property);
    }
  }
  // Once the format is known (the last "format" line counts): binary data cannot be read without
  // each value's size.
  for (const PlyElement& element : header.elements) {
    for (const PlyProperty& property : element.properties) {
      if (!header.ascii && property.value_type == nullptr) {
        text.fail_on(property.line,
                     "declares a property of unknown type '" + std::string(property.value_type_name) + "'");
      }
    }
  }
  return header;
}

// Refuses a header that declares more entries than the data after it can hold, before assimp
// allocates for them: in binary files an entry takes at least its scalars and its lists' counts,
// in ASCII files at least a character per value (and a line end).
void check_declared_counts(const Text& text, const PlyHeader& header) {
  std::uint64_t needed = 0;
  for (const PlyElement& element : header.elements) {
    std::uint64_t entry_size = 0;
    for (const PlyProperty& property : element.properties) {
      entry_size += header.ascii ? 1
                    : property.kind == PlyProperty::Kind::kScalar ? property.value_type->size
                                                                  : property.count_type->size;
    }
    needed += std::uint64_t{element.count} * std::max<std::uint64_t>(entry_size, 1);
    // An ASCII file's last line end may be missing.
    if (needed > header.data.size() + (header.ascii ? 1 : 0)) {
      text.fail_on(element.line, "declares " + std::to_string(element.count) + " '" + std::string(element.name) +
                                      "' elements, more than the " + std::to_string(header.data.size()) +
                                      " bytes after the header hold");
    }
  }
}

// The elements up to the last "face" one: what has to be read to see every face.
std::span<const PlyElement> elements_through_faces(const PlyHeader& header) {
  const auto faces = std::find_if(header.elements.rbegin(), header.elements.rend(),
                                  [](const PlyElement& e) { return e.name == "face"; });
  return std::span(header.elements).first(static_cast<std::size_t>(header.elements.rend() - faces));
}

// ASCII entries, lines cut as assimp's reader cuts them: every face has vertex indices, each a
// plain decimal of a vertex that exists.
void check_ascii_ply_faces(const Text& text, const PlyHeader& header) {
  std::string_view rest = header.data;
  const auto vertex = std::find_if(header.elements.begin(), header.elements.end(),
                                   [](const PlyElement& e) { return e.name == "vertex"; });
  const std::uint32_t vertices = vertex == header.elements.end() ? 0 : vertex->count;
  for (const PlyElement& element : elements_through_faces(header)) {
    for (std::uint32_t i = 0; i < element.count; ++i) {
      const std::optional<std::string_view> line = next_ply_line(rest);
      if (!line) fail(text.path, "the file ends before its last face");
      if (element.name != "face") continue;
      const std::vector<std::string_view> words = words_of(*line);
      std::size_t at = 0;
      for (const PlyProperty& property : element.properties) {
        if (property.kind == PlyProperty::Kind::kScalar) {
          ++at;
          continue;
        }
        const std::span<const std::string_view> list = text.take_list(*line, words, at);
        if (property.kind != PlyProperty::Kind::kVertexIndices) continue;
        if (list.empty()) text.fail_on(*line, "is a face without vertex indices");
        for (std::string_view index : list) text.check_vertex(index, vertices);
      }
    }
  }
}

// Binary entries: every face has vertex indices. (Binary integers cannot be misspelled, and
// assimp's validation refuses those out of range.)
void check_binary_ply_faces(const Text& text, const PlyHeader& header) {
  std::string_view rest = header.data;
  const auto skip = [&](std::uint64_t bytes) {
    if (bytes > rest.size()) fail(text.path, "the file ends before its last face");
    rest.remove_prefix(static_cast<std::size_t>(bytes));
  };
  const auto read_count = [&](const PlyType& type) {
    std::array<unsigned char, 4> bytes{};
    if (type.size > rest.size()) fail(text.path, "the file ends before its last face");
    std::memcpy(bytes.data(), rest.data(), type.size);
    if (header.big_endian) std::reverse(bytes.begin(), bytes.begin() + type.size);
    rest.remove_prefix(type.size);
    std::int64_t value = 0;
    for (unsigned k = type.size; k-- > 0;) value = value << 8 | bytes[k];
    const std::int64_t sign_bit = std::int64_t{1} << (8 * type.size - 1);
    return type.is_signed && (value & sign_bit) ? value - 2 * sign_bit : value;
  };
  for (const PlyElement& element : elements_through_faces(header)) {
    const bool all_scalar = std::all_of(element.properties.begin(), element.properties.end(), [](const PlyProperty& p) {
      return p.kind == PlyProperty::Kind::kScalar;
    });
    if (all_scalar) {
      std::uint64_t entry_size = 0;
      for (const PlyProperty& property : element.properties) entry_size += property.value_type->size;
      skip(entry_size * element.count);
      continue;
    }
    for (std::uint32_t i = 0; i < element.count; ++i) {
      for (const PlyProperty& property : element.properties) {
        if (property.kind == PlyProperty::Kind::kScalar) {
          skip(property.value_type->size);
          continue;
        }
        const std::int64_t length = read_count(*property.count_type);
        const auto entry = [&] { return std::string(element.name) + " " + std::to_string(i); };
        if (length < 0) fail(text.path, entry() + " has a list of negative length " + std::to_string(length));
        if (length == 0 && property.kind == PlyProperty::Kind::kVertexIndices) {
          fail(text.path, entry() + " has no vertex indices");
        }
        skip(static_cast<std::uint64_t>(length) * property.value_type->size);
      }
    }
  }
}

void check_ply(const Text& text) {
  const PlyHeader header = read_ply_header(text);
  check_declared_counts(text, header);
  if (header.ascii) {
    check_ascii_ply_faces(text, header);
  } else {
    check_binary_ply_faces(text, header);
  }
}

// OBJ: statements are lines, continued past a line end by a '\' before it; one that starts with
// "v " (or a tab), "vt" or "vn" adds a vertex, texture coordinate or normal, one that starts with
// "f" is a face of references v, v/vt, v/vt/vn or v//vn: positive ones count from 1 through the
// whole file, negative ones back from the latest.
void check_obj(const Text& text) {
  constexpr std::array<Kind, 3> kinds{kVertices, kTextureCoordinates, kNormals};
  std::array<std::uint32_t, 3> defined{};
  std::array<std::int64_t, 3> highest{};  // positive references, checked at the end
  std::array<std::string_view, 3> highest_word{};
  const auto next_line = [](std::string_view& rest) {
    const std::size_t end = line_end(rest);
    const std::string_view line = rest.substr(0, end);
    rest.remove_prefix(std::min(end + (rest.substr(end).starts_with("\r\n") ? 2 : 1), rest.size()));
    return line;
  };
  for (std::string_view rest = text.all; !rest.empty();) {
    const std::string_view first = next_line(rest);
    std::vector<std::string_view> words;
    for (std::string_view line = first;; line = next_line(rest)) {
      const bool continued = line.ends_with('\\');
      for (std::string_view word : words_of(line.substr(0, line.size() - continued))) words.push_back(word);
      if (!continued || rest.empty()) break;
    }

    if (first.starts_with("vt")) {
      ++defined[1];
    } else if (first.starts_with("vn")) {
      ++defined[2];
    } else if (first.starts_with("v ") || first.starts_with("v\t")) {
      ++defined[0];
    } else if (first.starts_with('f')) {
      for (std::string_view word : std::span(words).subspan(1)) {
        for (std::size_t k = 0, begin = 0; k < kinds.size() && begin <= word.size(); ++k) {
          const std::string_view part = word.substr(begin, std::min(word.find('/', begin), word.size()) - begin);
          begin += part.size() + 1;
          if (part.empty()) continue;
          std::int64_t value = 0;
          const auto [end, error] = std::from_chars(part.data(), part.data() + part.size(), value);
          if (error != std::errc() || end != part.data() + part.size() || value == 0 ||
              value < -std::int64_t{defined[k]}) {
            text.fail_reference(kinds[k], part, defined[k]);
          }
          if (value > highest[k]) {
            highest[k] = value;
            highest_word[k] = part;
          }
        }
      }
    }
  }
  for (std::size_t k = 0; k < kinds.size(); ++k) {
    if (highest[k] > defined[k]) text.fail_reference(kinds[k], highest_word[k], defined[k]);
  }
}

// ---- GLB, checked before assimp reads it -------------------------------------------------------
//
// A GLB file is a 12-byte header ("glTF", the version, the file's length) and chunks, each an
// 8-byte header (its length and type) and its data; glTF 1.0's has one content chunk, with its
// length and format in the header. assimp allocates what a length declares before it reads it (a
// JSON chunk of 0xFFFFFFFE bytes: 4.2 GB), so each must lie within the file.

std::uint32_t little_endian_u32(std::string_view bytes, std::size_t at) {
  std::uint32_t value = 0;
  for (int k = 3; k >= 0; --k) value = value << 8 | static_cast<unsigned char>(bytes[at + k]);
  return value;
}

void check_glb(const Text& text) {
  const std::string_view bytes = text.all;
  const auto fail_beyond = [&](const std::string& what, std::uint64_t length, std::uint64_t available) {
    fail(text.path, what + " declares " + std::to_string(length) + " bytes, but the file has " +
                        std::to_string(available) + " for it");
  };
  // glTF 1.0's content chunk starts at 20; glTF 2.0's chunks at 12. The header's own length is not
  // held against the file's: writers of glTF 1.0 files count it differently, and assimp reads
  // what the chunks declare.
  constexpr std::size_t kHeaderSize = 12;
  constexpr std::size_t kVersion1HeaderSize = 20;
  const std::uint32_t version = bytes.size() >= kHeaderSize ? little_endian_u32(bytes, 4) : 0;
  if (bytes.size() < (version == 1 ? kVersion1HeaderSize : kHeaderSize)) {
    fail(text.path, "a GLB file of " + std::to_string(bytes.size()) + " bytes is shorter than its header");
  }
  if (version == 1) {
    const std::uint32_t content = little_endian_u32(bytes, kHeaderSize);
    if (content > bytes.size() - kVersion1HeaderSize) {
      fail_beyond("its GLB content", content, bytes.size() - kVersion1HeaderSize);
    }
    return;
  }
  constexpr std::size_t kChunkHeaderSize = 8;
  const std::size_t end = std::min<std::size_t>(little_endian_u32(bytes, 8), bytes.size());
  std::size_t at = kHeaderSize;
  for (int chunk = 0; at + kChunkHeaderSize <= end; ++chunk) {
    const std::uint32_t chunk_length = little_endian_u32(bytes, at);
    const std::string_view type = bytes.substr(at + 4, 4);
    const std::string name = type == "JSON" ? " (JSON)" : type == std::string_view("BIN\0", 4) ? " (BIN)" : "";
    at += kChunkHeaderSize;
    if (chunk_length > bytes.size() - at) {
      fail_beyond("GLB chunk " + std::to_string(chunk) + name, chunk_length, bytes.size() - at);
    }
    at += chunk_length;
  }
}

// ---- OBJ material libraries, checked before assimp reads them ------------------------------------
//
// An OBJ file names its material libraries in "mtllib FILE" statements (the rest of the line, relative
// to the OBJ file). assimp 5.2.5 crashes (SIGSEGV) on a texture statement (map_Kd, bump, disp, ...)
// that comes before a library's first "newmtl", and would give it to whichever material is current
// otherwise: such a statement belongs to no material, so it is an error.

bool is_texture_statement(std::string_view word) {
  return word.starts_with("map_") || word == "bump" || word == "disp";
}

void check_material_library(const std::string& path, const std::string& library) {
  std::ifstream file(library, std::ios::binary);
  if (!file) return;  // assimp reads the model without it, as it does with one that is missing
  std::string line;
  for (int number = 1; std::getline(file, line); ++number) {
    const std::vector<std::string_view> words = words_of(line);
    if (words.empty()) continue;
    if (words[0] == "newmtl") return;
    if (is_texture_statement(words[0])) {
      fail(path, "material library '" + library + "' line " + std::to_string(number) + " has '" +
                     std::string(words[0]) + "' before any 'newmtl': it belongs to no material");
    }
  }
}

void check_material_libraries(const Text& text) {
  for (std::size_t at = text.all.find("mtllib"); at != std::string_view::npos; at = text.all.find("mtllib", at + 1)) {
    const std::size_t line_start = text.all.find_last_of("\r\n", at) + 1;  // npos + 1 is 0
    if (text.all.find_first_not_of(" \t", line_start) != at) continue;
    const std::string_view line = text.all.substr(at, line_end(text.all.substr(at)));
    const std::vector<std::string_view> words = words_of(line);
    if (words.size() < 2 || words[0] != "mtllib") continue;
    const std::string_view name = line.substr(static_cast<std::size_t>(words[1].data() - line.data()));
    const std::string_view trimmed = name.substr(0, name.find_last_not_of(" \t") + 1);
    check_material_library(text.path, (std::filesystem::path(text.path).parent_path() / trimmed).string());
  }
}

// What assimp will read the file as, as far as the checks before it reads are concerned: it picks
// a reader by the file's extension, or when none claims it, by the content.
enum class Layout { kOther, kPly, kGlb, kObj, kOff };

Layout layout_of(const Assimp::Importer& importer, const Text& text) {
  const std::string extension = lowercase_extension(text.path);
  if (extension == ".ply") return Layout::kPly;
  if (extension == ".glb") return Layout::kGlb;
  if (extension == ".obj") return Layout::kObj;
  if (extension == ".off") return Layout::kOff;
  if (!extension.empty() && importer.IsExtensionSupported(extension)) return Layout::kOther;
  const std::string_view start = text.all.substr(0, 4);
  const auto lower = [](char c) { return static_cast<char>(std::tolower(static_cast<unsigned char>(c))); };
  if (start.size() == 4 && lower(start[0]) == 'p' && lower(start[1]) == 'l' && lower(start[2]) == 'y' &&
      is_line_end(start[3])) {
    return Layout::kPly;
  }
  return start == "glTF" ? Layout::kGlb : Layout::kOther;
}

// Checks, before assimp reads the file, what assimp would crash on, spin on or allocate without
// bound for. Returns the layout checked.
Layout check_before_reading(const Assimp::Importer& importer, const Text& text) {
  const Layout layout = layout_of(importer, text);
  if (layout == Layout::kPly) check_ply(text);
  if (layout == Layout::kGlb) check_glb(text);
  if (layout == Layout::kObj) check_material_libraries(text);
  if (layout == Layout::kOff) check_off(text);
  return layout;
}

// Checks the references of a file that assimp read with one of the readers above (OFF and PLY
// files unless they were checked before reading).
void check_references(const Assimp::Importer& importer, const Text& text, Layout checked) {
  // ReadFile chooses the reader by the file's extension, or else by its content, and leaves the
  // reader's index in this property.
  const aiImporterDesc* reader = importer.GetImporterInfo(importer.GetPropertyInteger("importerIndex", -1));
  if (reader == nullptr) return;
  const std::string_view format = reader->mFileExtensions;
  if (format == "off" && checked != Layout::kOff) check_off(text);
  if (format == "ply" && checked != Layout::kPly) check_ply(text);
  if (format == "obj") check_obj(text);
}

struct SkippedPrimitives {
  std::uint64_t points = 0;
  std::uint64_t lines = 0;

  std::vector<std::string> describe() const {
    std::vector<std::string> messages;
    if (points > 0) messages.push_back("skipped " + std::to_string(points) + " point primitives");
    if (lines > 0) messages.push_back("skipped " + std::to_string(lines) + " line primitives");
    return messages;
  }
};

// Whether the file gives the mesh normals. Some STL writers leave every facet normal zero, which is
// as good as none.
bool has_nonzero_normal(const aiMesh& source) {
  return source.HasNormals() && std::any_of(source.mNormals, source.mNormals + source.mNumVertices,
                                            [](const aiVector3D& n) { return !(n.x == 0 && n.y == 0 && n.z == 0); });
}

// Whether `vertex` has no NaN or infinite component in `values`, `components` per vertex.
bool finite_at(const std::vector<float>& values, std::size_t components, std::uint32_t vertex) {
  const float* begin = values.data() + components * vertex;
  return std::all_of(begin, begin + components, [](float x) { return std::isfinite(x); });
}

// The triangles a mesh loses for NaN or infinite values, and the vertices they used.
struct DroppedTriangles {
  std::uint64_t count = 0;
  std::vector<bool> vertices;  // by vertex: a corner of a dropped triangle; empty until one is dropped
};

// Removes the triangles of `mesh` with a corner whose vertex `finite_vertex` refuses, keeping the
// others in order, and adds them to `dropped`.
template <typename FiniteVertex>
void drop_non_finite_triangles(Mesh& mesh, FiniteVertex finite_vertex, DroppedTriangles& dropped) {
  std::size_t kept = 0;
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const std::uint32_t* corners = &mesh.indices[3 * t];
    if (finite_vertex(corners[0]) && finite_vertex(corners[1]) && finite_vertex(corners[2])) {
      for (int k = 0; k < 3; ++k) mesh.indices[3 * kept + k] = corners[k];
      ++kept;
      continue;
    }
    if (dropped.vertices.empty()) dropped.vertices.resize(mesh.vertex_count());
    for (int k = 0; k < 3; ++k) dropped.vertices[corners[k]] = true;
    ++dropped.count;
  }
  mesh.indices.resize(3 * kept);
}

// Removes the vertices that dropped triangles used and no kept one does, numbering the others
// anew, so that what reads every vertex (bounding spheres, smooth normals) sees only what is drawn.
void remove_vertices_of_dropped_triangles(Mesh& mesh, const DroppedTriangles& dropped) {
  if (dropped.count == 0) return;
  std::vector<bool> removed = dropped.vertices;
  for (std::uint32_t vertex : mesh.indices) removed[vertex] = false;
  std::vector<std::uint32_t> new_index(mesh.vertex_count());
  std::uint32_t kept = 0;
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    new_index[v] = kept;
    kept += removed[v] ? 0 : 1;
  }
  const auto keep_vertices = [&](std::vector<float>& values, std::size_t components) {
    std::size_t end = 0;
    for (std::size_t v = 0; v < removed.size(); ++v) {
      if (removed[v]) continue;
      for (std::size_t k = 0; k < components; ++k) values[end++] = values[components * v + k];
    }
    values.resize(end);
  };
  keep_vertices(mesh.positions, 3);
  keep_vertices(mesh.normals, 3);
  if (!mesh.texcoords.empty()) keep_vertices(mesh.texcoords, 2);
  for (std::uint32_t& vertex : mesh.indices) vertex = new_index[vertex];
}

// The triangles of one assimp mesh in its own coordinates, with the file's normals or zeros, and its
// first set of texture coordinates when it has one. Points and lines are counted in `skipped`
// instead.
Mesh triangles_of(const aiMesh& source, bool file_normals, SkippedPrimitives& skipped, const std::string& path) {
  Mesh mesh;
  mesh.indices.reserve(3 * std::size_t{source.mNumFaces});
  for (unsigned f = 0; f < source.mNumFaces; ++f) {
    const aiFace& face = source.mFaces[f];
    if (face.mNumIndices == 1) {
      ++skipped.points;
    } else if (face.mNumIndices == 2) {
      ++skipped.lines;
    } else if (face.mNumIndices == 3) {
      for (unsigned k = 0; k < 3; ++k) {
        // assimp validates this too; checked again because an out-of-range index here would read
        // past the vertex arrays.
        if (face.mIndices[k] >= source.mNumVertices) {
          fail(path, "face " + std::to_string(f) + " of mesh '" + source.mName.C_Str() + "' references vertex " +
                         std::to_string(face.mIndices[k]) + ", but the mesh has " +
                         std::to_string(source.mNumVertices) + " vertices");
        }
        mesh.indices.push_back(face.mIndices[k]);
      }
    } else {
      fail(path, "a face with " + std::to_string(face.mNumIndices) + " vertices was left after triangulation");
    }
  }
  if (mesh.indices.empty()) return mesh;

  const bool file_texcoords = source.HasTextureCoords(0);
  mesh.positions.reserve(3 * std::size_t{source.mNumVertices});
  mesh.normals.assign(3 * std::size_t{source.mNumVertices}, 0.0f);
  if (file_texcoords) mesh.texcoords.reserve(2 * std::size_t{source.mNumVertices});
  for (unsigned v = 0; v < source.mNumVertices; ++v) {
    const aiVector3D& p = source.mVertices[v];
    mesh.positions.insert(mesh.positions.end(), {p.x, p.y, p.z});
    if (file_normals) {
      const aiVector3D& n = source.mNormals[v];
      mesh.normals[3 * v] = n.x, mesh.normals[3 * v + 1] = n.y, mesh.normals[3 * v + 2] = n.z;
    }
    if (file_texcoords) {
      const aiVector3D& uv = source.mTextureCoords[0][v];
      mesh.texcoords.insert(mesh.texcoords.end(), {uv.x, uv.y});
    }
  }
  return mesh;
}

// aiMatrix4x4 is stored row by row, glm::mat4 column by column.
glm::mat4 to_glm(const aiMatrix4x4& matrix) { return glm::transpose(glm::make_mat4(&matrix.a1)); }

glm::dvec3 position_of(const Mesh& mesh, std::uint32_t vertex) {
  return {mesh.positions[3 * vertex], mesh.positions[3 * vertex + 1], mesh.positions[3 * vertex + 2]};
}

// cross(v1 - v0, v2 - v0) of triangle t: its normal times twice its area. In double, so that
// neither tiny nor large triangles lose it to underflow or overflow.
glm::dvec3 face_normal(const Mesh& mesh, std::size_t t) {
  const glm::dvec3 v0 = position_of(mesh, mesh.indices[3 * t]);
  return glm::cross(position_of(mesh, mesh.indices[3 * t + 1]) - v0, position_of(mesh, mesh.indices[3 * t + 2]) - v0);
}

glm::vec3 unit_or_zero(glm::dvec3 v) {
  const double length = glm::length(v);
  return length > 0 ? glm::vec3(v / length) : glm::vec3(0);
}

// Every triangle gets its own three vertices, carrying its face normal.
Mesh flat_shaded(const Mesh& mesh) {
  const bool has_texcoords = !mesh.texcoords.empty();
  Mesh flat;
  flat.positions.reserve(3 * mesh.indices.size());
  flat.normals.reserve(3 * mesh.indices.size());
  if (has_texcoords) flat.texcoords.reserve(2 * mesh.indices.size());
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const glm::vec3 normal = unit_or_zero(face_normal(mesh, t));
    for (int corner = 0; corner < 3; ++corner) {
      const std::uint32_t source = mesh.indices[3 * t + corner];
      flat.indices.push_back(static_cast<std::uint32_t>(flat.vertex_count()));
      flat.positions.insert(flat.positions.end(), &mesh.positions[3 * source], &mesh.positions[3 * source + 3]);
      flat.normals.insert(flat.normals.end(), {normal.x, normal.y, normal.z});
      if (has_texcoords) {
        flat.texcoords.insert(flat.texcoords.end(), &mesh.texcoords[2 * source], &mesh.texcoords[2 * source + 2]);
      }
    }
  }
  return flat;
}

// A position by its bits, so that exactly the vertices at bit-identical positions are one.
struct PositionKey {
  std::array<std::uint32_t, 3> bits;
  bool operator==(const PositionKey&) const = default;
};

struct PositionKeyHash {
  std::size_t operator()(const PositionKey& key) const {
    std::uint64_t hash = 0xcbf29ce484222325ull;  // FNV-1a over the three words
    for (std::uint32_t word : key.bits) hash = (hash ^ word) * 0x100000001b3ull;
    return static_cast<std::size_t>(hash);
  }
};

}  // namespace

void smooth_normals(std::span<Mesh* const> meshes) {
  std::unordered_map<PositionKey, std::uint32_t, PositionKeyHash> slot_of_position;
  std::vector<std::vector<std::uint32_t>> slot_of_vertex(meshes.size());
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const Mesh& mesh = *meshes[m];
    slot_of_vertex[m].reserve(mesh.vertex_count());
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
      const PositionKey key{{std::bit_cast<std::uint32_t>(mesh.positions[3 * v]),
                             std::bit_cast<std::uint32_t>(mesh.positions[3 * v + 1]),
                             std::bit_cast<std::uint32_t>(mesh.positions[3 * v + 2])}};
      const auto [entry, inserted] =
          slot_of_position.try_emplace(key, static_cast<std::uint32_t>(slot_of_position.size()));
      slot_of_vertex[m].push_back(entry->second);
    }
  }

  std::vector<glm::dvec3> sums(slot_of_position.size(), glm::dvec3(0));
  for (std::size_t m = 0; m < meshes.size(); ++m) {
    const Mesh& mesh = *meshes[m];
    for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
      const glm::dvec3 normal = face_normal(mesh, t);
      for (int corner = 0; corner < 3; ++corner) sums[slot_of_vertex[m][mesh.indices[3 * t + corner]]] += normal;
    }
  }

  for (std::size_t m = 0; m < meshes.size(); ++m) {
    Mesh& mesh = *meshes[m];
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
      const glm::vec3 normal = unit_or_zero(sums[slot_of_vertex[m][v]]);
      mesh.normals[3 * v] = normal.x, mesh.normals[3 * v + 1] = normal.y, mesh.normals[3 * v + 2] = normal.z;
    }
  }
}

namespace {

// Reads the file with assimp, refusing what assimp cannot read and what it read only by repairing
// faces with indices of vertices that do not exist. The scene belongs to `importer`.
const aiScene& read_scene(Assimp::Importer& importer, const std::string& path) {
  LogCapture log;
  const aiScene* scene = nullptr;
  try {
    scene = importer.ReadFile(path, kPostProcessing);
  } catch (const std::exception& error) {  // e.g. std::bad_alloc for absurd element counts
    fail(path, one_line(error.what()));
  }
  // Before assimp's own failure, which can follow from the repair: a glTF mesh whose faces were all
  // dropped "has no faces".
  for (const std::string& message : log.messages()) {
    if (reports_bad_vertex_index(message)) fail(path, "faces reference vertices that do not exist (" + message + ")");
  }
  if (scene == nullptr) fail(path, one_line(importer.GetErrorString()));
  return *scene;
}

// The triangles of one mesh instance in model space, whether its normals are still to be computed
// by smooth_normals, and its material (an index into aiScene::mMaterials).
struct Piece {
  Mesh mesh;
  bool needs_smooth_normals;
  unsigned material;
};

// Every mesh instance of the node tree, depth first in the file's order, moved by its node's
// accumulated transform, without the triangles that have a NaN or infinite value at a corner
// (counted in `triangles_dropped`). Normals come from the file, or are flat for glTF; the others
// are left for smooth_normals, which must see every instance because instances that touch share
// them.
std::vector<Piece> mesh_instances(const aiScene& scene, bool gltf, SkippedPrimitives& skipped,
                                  std::uint64_t& triangles_dropped, const std::string& path) {
  std::vector<Piece> pieces;
  struct Visit {
    const aiNode* node;
    aiMatrix4x4 parent_transform;
  };
  std::vector<Visit> pending;
  if (scene.mRootNode != nullptr) pending.push_back({scene.mRootNode, aiMatrix4x4()});
  while (!pending.empty()) {
    const auto [node, parent_transform] = pending.back();
    pending.pop_back();
    const aiMatrix4x4 node_transform = parent_transform * node->mTransformation;
    for (unsigned k = 0; k < node->mNumMeshes; ++k) {
      const aiMesh& source = *scene.mMeshes[node->mMeshes[k]];
      const bool file_normals = has_nonzero_normal(source);
      Mesh piece = triangles_of(source, file_normals, skipped, path);
      if (piece.indices.empty()) continue;
      DroppedTriangles dropped;
      // Before the transform, which turns a NaN normal into a zero one.
      drop_non_finite_triangles(
          piece,
          [&](std::uint32_t v) {
            return finite_at(piece.positions, 3, v) && finite_at(piece.normals, 3, v) &&
                   (piece.texcoords.empty() || finite_at(piece.texcoords, 2, v));
          },
          dropped);
      transform(piece, to_glm(node_transform));
      // Finite in the file, but a node's scale can still carry a position beyond float's range.
      drop_non_finite_triangles(piece, [&](std::uint32_t v) { return finite_at(piece.positions, 3, v); }, dropped);
      remove_vertices_of_dropped_triangles(piece, dropped);
      triangles_dropped += dropped.count;
      if (piece.indices.empty()) continue;
      if (file_normals) {
        pieces.push_back({std::move(piece), false, source.mMaterialIndex});
      } else if (gltf) {
        pieces.push_back({flat_shaded(piece), false, source.mMaterialIndex});
      } else {
        pieces.push_back({std::move(piece), true, source.mMaterialIndex});
      }
    }
    // Pushed in reverse, so that children are visited in the file's order.
    for (unsigned c = node->mNumChildren; c-- > 0;) pending.push_back({node->mChildren[c], node_transform});
  }
  return pieces;
}

// The pieces' triangles, one after the other.
Mesh merged(std::vector<Piece>&& pieces, const std::string& path) {
  std::vector<Mesh> meshes;
  meshes.reserve(pieces.size());
  for (Piece& piece : pieces) meshes.push_back(std::move(piece.mesh));
  try {
    return merge(meshes);
  } catch (const InvalidArgument& error) {  // more vertices than 32-bit indices address
    fail(path, error.what());
  }
}

// ---- Materials and parts ------------------------------------------------------------------------

// Cuts the pieces, in order, into parts: pieces that follow each other with the same material make
// one. Model materials are numbered in the order of their first part; `scene_materials` receives
// each one's index in aiScene::mMaterials.
std::vector<ModelPart> cut_into_parts(std::span<const Piece> pieces, std::vector<unsigned>& scene_materials,
                                      const std::string& path) {
  std::unordered_map<unsigned, std::uint32_t> model_material;
  std::vector<ModelPart> parts;
  std::uint64_t first_index = 0;
  for (const Piece& piece : pieces) {
    const auto [entry, first_use] =
        model_material.try_emplace(piece.material, static_cast<std::uint32_t>(scene_materials.size()));
    if (first_use) scene_materials.push_back(piece.material);
    const std::uint64_t index_count = piece.mesh.indices.size();
    // Parts are drawn with 32-bit DrawCall::first and count.
    if (first_index + index_count > std::numeric_limits<std::uint32_t>::max()) {
      fail(path, "more indices than 32-bit draws address");
    }
    if (!parts.empty() && parts.back().material == entry->second) {
      parts.back().index_count += static_cast<std::uint32_t>(index_count);
    } else {
      parts.push_back(
          {static_cast<std::uint32_t>(first_index), static_cast<std::uint32_t>(index_count), entry->second});
    }
    first_index += index_count;
  }
  return parts;
}

std::array<float, 4> base_color_factor(const aiMaterial& material) {
  aiColor4D color;
  if (material.Get(AI_MATKEY_BASE_COLOR, color) == AI_SUCCESS ||
      material.Get(AI_MATKEY_COLOR_DIFFUSE, color) == AI_SUCCESS) {
    return {color.r, color.g, color.b, color.a};
  }
  return {1, 1, 1, 1};
}

// A texture file named by a model file, which names it relative to itself. Backslashes are read as
// directory separators: Windows tools write them into OBJ material files (spider.mtl's
// ".\wal67ar_small.jpg"), and a file name that contains one is rare.
std::string texture_file(const std::string& model_path, std::string reference) {
  std::replace(reference.begin(), reference.end(), '\\', '/');
  return (std::filesystem::path(model_path).parent_path() / reference).string();
}

// The material's base colour texture, if it has one that can be passed on. `label` names the
// material in warnings.
std::optional<MaterialTexture> base_color_texture(const aiMaterial& material, const aiScene& scene,
                                                  const std::string& path, const std::string& label,
                                                  std::vector<std::string>& warnings) {
  aiString reference;
  unsigned uv_channel = 0;  // left as it is when the file does not say
  // glTF materials have their base colour texture as both; other formats have a diffuse texture.
  if (material.GetTexture(aiTextureType_BASE_COLOR, 0, &reference, nullptr, &uv_channel) != AI_SUCCESS &&
      material.GetTexture(aiTextureType_DIFFUSE, 0, &reference, nullptr, &uv_channel) != AI_SUCCESS) {
    return std::nullopt;
  }
  MaterialTexture texture;
  texture.reference = reference.C_Str();
  texture.uv_channel = uv_channel;
  // Not a path to resolve, and assimp would take it for the name of an embedded image that has none.
  if (texture.reference.empty()) {
    warnings.push_back(label + ": its base colour texture names no image");
    return std::nullopt;
  }
  // Embedded images are named "*N", or, in some formats, by the file name they were embedded from.
  if (const aiTexture* image = scene.GetEmbeddedTexture(reference.C_Str())) {
    // mHeight 0 means that pcData holds mWidth bytes of an image file; otherwise it holds
    // mWidth x mHeight texels, which nothing downstream reads.
    if (image->mHeight != 0) {
      warnings.push_back(label + ": its base colour texture '" + texture.reference +
                         "' is embedded as raw texels, which are not loaded");
      return std::nullopt;
    }
    const auto* bytes = reinterpret_cast<const std::byte*>(image->pcData);
    texture.encoded.assign(bytes, bytes + image->mWidth);
    texture.format_hint.assign(image->achFormatHint, strnlen(image->achFormatHint, sizeof image->achFormatHint));
  } else {
    texture.file = texture_file(path, texture.reference);
  }
  if (uv_channel != 0) {
    warnings.push_back(label + ": its base colour texture is mapped by texture coordinate set " +
                       std::to_string(uv_channel) + ", which is not loaded (only set 0 is)");
  }
  return texture;
}

// Model material `index`, made of scene material `scene_index`.
Material material_of(const aiScene& scene, unsigned scene_index, std::size_t index, const std::string& path,
                     std::vector<std::string>& warnings) {
  const aiMaterial& source = *scene.mMaterials[scene_index];
  Material material;
  material.name = source.GetName().C_Str();
  material.base_color_factor = base_color_factor(source);
  material.base_color_texture = base_color_texture(source, scene, path, material_label(material, index), warnings);
  return material;
}

}  // namespace

std::string describe_load_error(const std::string& path, const std::string& reason) {
  return "cannot load model '" + path + "': " + reason;
}

std::string describe_triangles_dropped(std::uint64_t count) {
  return std::to_string(count) + (count == 1 ? " triangle" : " triangles") +
         " dropped: a corner's position, normal or texture coordinate is NaN or infinite";
}

std::string material_label(const Material& material, std::size_t index) {
  return material.name.empty() ? "material " + std::to_string(index) : "material '" + material.name + "'";
}

Model load_model(const std::string& path, std::vector<std::string>& warnings) {
  const ModelFile file(path);
  const Text text{path, file.bytes()};
  Assimp::Importer importer;
  const Layout checked = check_before_reading(importer, text);
  const aiScene& scene = read_scene(importer, path);
  check_references(importer, text, checked);
  SkippedPrimitives skipped;
  std::uint64_t triangles_dropped = 0;
  std::vector<Piece> pieces = mesh_instances(scene, is_gltf(path), skipped, triangles_dropped, path);

  const std::vector<std::string> skipped_messages = skipped.describe();
  if (pieces.empty()) {
    std::string reason = triangles_dropped == 0 ? "no triangles in the file"
                                                : "no triangles left: " + describe_triangles_dropped(triangles_dropped);
    for (std::size_t i = 0; i < skipped_messages.size(); ++i) reason += (i == 0 ? " (" : ", ") + skipped_messages[i];
    fail(path, skipped_messages.empty() ? reason : reason + ")");
  }

  std::vector<Mesh*> to_smooth;
  for (Piece& piece : pieces) {
    if (piece.needs_smooth_normals) to_smooth.push_back(&piece.mesh);
  }
  smooth_normals(to_smooth);

  std::vector<unsigned> scene_materials;
  std::vector<ModelPart> parts = cut_into_parts(pieces, scene_materials, path);
  std::vector<Material> materials;
  std::vector<std::string> material_warnings;
  for (unsigned scene_index : scene_materials) {
    materials.push_back(material_of(scene, scene_index, materials.size(), path, material_warnings));
  }
  Model model{merged(std::move(pieces), path), std::move(materials), std::move(parts), std::move(material_warnings),
              triangles_dropped};
  warnings.insert(warnings.end(), skipped_messages.begin(), skipped_messages.end());
  return model;
}

}  // namespace clraster::io
