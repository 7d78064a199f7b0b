#include "io/model_loader.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <span>
#include <string_view>
#include <unordered_map>

#include <assimp/DefaultLogger.hpp>
#include <assimp/Importer.hpp>
#include <assimp/LogStream.hpp>
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
  throw InvalidArgument("cannot load model '" + path + "': " + reason);
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

// Checked before assimp sees the file, whose "unable to open file" does not say why.
void require_readable(const std::string& path) {
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored)) fail(path, "it is a directory");
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr) fail(path, std::strerror(errno));
  std::fclose(file);
}

bool is_gltf(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
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

// The triangles of one assimp mesh in its own coordinates, with the file's normals or zeros.
// Points and lines are counted in `skipped` instead.
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

  mesh.positions.reserve(3 * std::size_t{source.mNumVertices});
  mesh.normals.assign(3 * std::size_t{source.mNumVertices}, 0.0f);
  for (unsigned v = 0; v < source.mNumVertices; ++v) {
    const aiVector3D& p = source.mVertices[v];
    mesh.positions.insert(mesh.positions.end(), {p.x, p.y, p.z});
    if (file_normals) {
      const aiVector3D& n = source.mNormals[v];
      mesh.normals[3 * v] = n.x, mesh.normals[3 * v + 1] = n.y, mesh.normals[3 * v + 2] = n.z;
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
  Mesh flat;
  flat.positions.reserve(3 * mesh.indices.size());
  flat.normals.reserve(3 * mesh.indices.size());
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const glm::vec3 normal = unit_or_zero(face_normal(mesh, t));
    for (int corner = 0; corner < 3; ++corner) {
      const std::uint32_t source = mesh.indices[3 * t + corner];
      flat.indices.push_back(static_cast<std::uint32_t>(flat.vertex_count()));
      flat.positions.insert(flat.positions.end(), &mesh.positions[3 * source], &mesh.positions[3 * source + 3]);
      flat.normals.insert(flat.normals.end(), {normal.x, normal.y, normal.z});
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

// Sets every vertex normal of `meshes` to the normalized sum of the area-weighted normals of the
// triangles, across all of them, that have a corner at the vertex's position.
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
      // A triangle with a non-finite corner is dropped by the pipeline; its normal must not turn
      // the normals of its finite neighbours into NaN.
      if (!std::isfinite(normal.x) || !std::isfinite(normal.y) || !std::isfinite(normal.z)) continue;
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
  if (scene == nullptr) fail(path, one_line(importer.GetErrorString()));
  for (const std::string& message : log.messages()) {
    if (reports_bad_vertex_index(message)) fail(path, "faces reference vertices that do not exist (" + message + ")");
  }
  return *scene;
}

// The triangles of one mesh instance in model space, and whether its normals are still to be
// computed by smooth_normals.
struct Piece {
  Mesh mesh;
  bool needs_smooth_normals;
};

// Every mesh instance of the node tree, depth first in the file's order, moved by its node's
// accumulated transform. Normals come from the file, or are flat for glTF; the others are left
// for smooth_normals, which must see every instance because instances that touch share them.
std::vector<Piece> mesh_instances(const aiScene& scene, bool gltf, SkippedPrimitives& skipped,
                                  const std::string& path) {
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
      transform(piece, to_glm(node_transform));
      if (file_normals) {
        pieces.push_back({std::move(piece), false});
      } else if (gltf) {
        pieces.push_back({flat_shaded(piece), false});
      } else {
        pieces.push_back({std::move(piece), true});
      }
    }
    // Pushed in reverse, so that children are visited in the file's order.
    for (unsigned c = node->mNumChildren; c-- > 0;) pending.push_back({node->mChildren[c], node_transform});
  }
  return pieces;
}

}  // namespace

Mesh load_model(const std::string& path, std::vector<std::string>& warnings) {
  require_readable(path);
  Assimp::Importer importer;
  const aiScene& scene = read_scene(importer, path);
  SkippedPrimitives skipped;
  std::vector<Piece> pieces = mesh_instances(scene, is_gltf(path), skipped, path);

  const std::vector<std::string> skipped_messages = skipped.describe();
  if (pieces.empty()) {
    std::string reason = "no triangles in the file";
    for (std::size_t i = 0; i < skipped_messages.size(); ++i) reason += (i == 0 ? " (" : ", ") + skipped_messages[i];
    fail(path, skipped_messages.empty() ? reason : reason + ")");
  }

  std::vector<Mesh*> to_smooth;
  for (Piece& piece : pieces) {
    if (piece.needs_smooth_normals) to_smooth.push_back(&piece.mesh);
  }
  smooth_normals(to_smooth);

  std::vector<Mesh> meshes;
  meshes.reserve(pieces.size());
  for (Piece& piece : pieces) meshes.push_back(std::move(piece.mesh));
  Mesh model;
  try {
    model = merge(meshes);
  } catch (const InvalidArgument& error) {  // more vertices than 32-bit indices address
    fail(path, error.what());
  }
  warnings.insert(warnings.end(), skipped_messages.begin(), skipped_messages.end());
  return model;
}

}  // namespace clraster::io
