// Model loading: triangle counts checked against the files themselves, node transforms and
// instancing, the three normal rules, and a one-line error for every broken file.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <assimp/DefaultLogger.hpp>
#include <atomic>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "clraster/clraster.hpp"
#include "support/mesh_inspection.hpp"
#include "io/mesh.hpp"
#include "io/model_loader.hpp"

namespace clraster::io {
namespace {

using test::corner;
using test::face_cross;
using test::normal;
using test::position;

namespace fs = std::filesystem;

// Installed by the assimp-testmodels package (scripts/setup.sh).
const fs::path kModels = "/usr/share/assimp/models";



testing::AssertionResult near(glm::dvec3 actual, glm::dvec3 expected, double tolerance) {
  if (glm::all(glm::lessThanEqual(glm::abs(actual - expected), glm::dvec3(tolerance)))) {
    return testing::AssertionSuccess();
  }
  const auto text = [](glm::dvec3 v) {
    return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")";
  };
  return testing::AssertionFailure() << text(actual) << " is not within " << tolerance << " of " << text(expected);
}

Mesh load(const fs::path& path) {
  std::vector<std::string> warnings;
  return load_model(path.string(), warnings);
}

std::string read_text(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

// The message load_model throws for `path`, after checking that it throws InvalidArgument with a
// one-line message naming the file.
std::string load_error(const fs::path& path) {
  std::vector<std::string> warnings;
  try {
    load_model(path.string(), warnings);
  } catch (const InvalidArgument& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.find_first_of("\r\n"), std::string::npos) << message;
    EXPECT_NE(message.find(path.string()), std::string::npos) << message;
    return message;
  }
  ADD_FAILURE() << path << " loaded without an error";
  return {};
}

// ---- Triangle counts read from the files themselves ----------------------------------------------

// An n-gon becomes n - 2 triangles.
std::size_t obj_triangles(const fs::path& path) {
  std::istringstream lines(read_text(path));
  std::size_t triangles = 0;
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    std::string keyword, vertex;
    words >> keyword;
    if (keyword != "f") continue;
    int corners = 0;
    while (words >> vertex) ++corners;
    triangles += corners - 2;
  }
  return triangles;
}

// Points and line segments of the OBJ 'p' and 'l' statements.
std::pair<std::size_t, std::size_t> obj_points_and_lines(const fs::path& path) {
  std::istringstream lines(read_text(path));
  std::size_t points = 0, segments = 0;
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    std::string keyword, vertex;
    words >> keyword;
    int count = 0;
    while (words >> vertex) ++count;
    if (keyword == "p") points += count;
    if (keyword == "l") segments += count - 1;
  }
  return {points, segments};
}

// OFF, and ASCII PLY with a vertex and a face element: faces follow the vertices, each line
// starting with its corner count.
std::size_t polygon_file_triangles(const fs::path& path, std::size_t vertices, std::size_t faces,
                                   std::istream& body) {
  std::string line;
  for (std::size_t v = 0; v < vertices;) {
    std::getline(body, line);
    if (!line.empty() && line[0] != '#') ++v;
  }
  std::size_t triangles = 0;
  for (std::size_t f = 0; f < faces;) {
    EXPECT_TRUE(std::getline(body, line)) << path;
    if (line.empty() || line[0] == '#') continue;
    triangles += std::stoul(line) - 2;
    ++f;
  }
  return triangles;
}

std::size_t off_triangles(const fs::path& path) {
  std::istringstream body(read_text(path));
  std::string magic;
  std::size_t vertices = 0, faces = 0, edges = 0;
  body >> magic >> vertices >> faces >> edges;
  body.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
  return polygon_file_triangles(path, vertices, faces, body);
}

std::size_t ascii_ply_triangles(const fs::path& path) {
  std::istringstream body(read_text(path));
  std::size_t vertices = 0, faces = 0;
  for (std::string line; std::getline(body, line) && line.rfind("end_header", 0) != 0;) {
    std::istringstream words(line);
    std::string keyword, element;
    std::size_t count = 0;
    if (words >> keyword >> element >> count && keyword == "element") (element == "vertex" ? vertices : faces) = count;
  }
  return polygon_file_triangles(path, vertices, faces, body);
}

std::size_t ascii_stl_triangles(const fs::path& path) {
  std::istringstream words(read_text(path));
  std::size_t facets = 0;
  for (std::string word; words >> word;) facets += word == "facet";
  return facets;
}

// Binary STL: an 80-byte header, then the triangle count.
std::size_t binary_stl_triangles(const fs::path& path) {
  const std::string bytes = read_text(path);
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, sizeof count);
  return count;
}

nlohmann::json gltf_document(const fs::path& path) {
  const std::string bytes = read_text(path);
  if (path.extension() != ".glb") return nlohmann::json::parse(bytes);
  // A 12-byte header, then the JSON chunk: its length, its type, its bytes.
  std::uint32_t json_length = 0;
  std::memcpy(&json_length, bytes.data() + 12, sizeof json_length);
  return nlohmann::json::parse(bytes.substr(20, json_length));
}

// Triangles of the default scene: every mesh instance of the node tree, by primitive mode.
std::size_t gltf_triangles(const fs::path& path) {
  const nlohmann::json document = gltf_document(path);
  const auto& accessors = document["accessors"];
  std::function<std::size_t(std::size_t)> node_triangles = [&](std::size_t index) {
    const auto& node = document["nodes"][index];
    std::size_t triangles = 0;
    if (node.contains("mesh")) {
      for (const auto& primitive : document["meshes"][node["mesh"].get<std::size_t>()]["primitives"]) {
        // Corners: the index count, or the vertex count when the primitive has no indices.
        const auto& corner_accessor =
            primitive.contains("indices") ? primitive["indices"] : primitive["attributes"]["POSITION"];
        const auto corners = accessors[corner_accessor.get<std::size_t>()]["count"].get<std::size_t>();
        const int mode = primitive.value("mode", 4);
        if (mode == 4) triangles += corners / 3;
        if (mode == 5 || mode == 6) triangles += corners - 2;
      }
    }
    for (const auto& child : node.value("children", nlohmann::json::array())) triangles += node_triangles(child);
    return triangles;
  };
  std::size_t triangles = 0;
  for (const auto& root : document["scenes"][document.value("scene", 0)]["nodes"]) triangles += node_triangles(root);
  return triangles;
}

// Unit normals at the corners of every triangle with an area. (Some files have triangles that are
// single points, whose normals are zero.)
void expect_unit_normals(const Mesh& mesh) {
  ASSERT_EQ(mesh.normals.size(), mesh.positions.size());
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    if (glm::length(face_cross(mesh, t)) == 0) continue;
    for (int k = 0; k < 3; ++k) {
      ASSERT_NEAR(glm::length(normal(mesh, mesh.indices[3 * t + k])), 1.0, 1e-5) << "triangle " << t;
    }
  }
}

void expect_valid_indices(const Mesh& mesh) {
  for (std::uint32_t index : mesh.indices) ASSERT_LT(index, mesh.vertex_count());
}

TEST(LoadModel, TriangleCountsMatchTheFiles) {
  struct Case {
    fs::path file;
    std::size_t (*count)(const fs::path&);
  };
  const Case cases[] = {
      {"OBJ/box.obj", obj_triangles},
      {"OBJ/WusonOBJ.obj", obj_triangles},
      {"OBJ/spider.obj", obj_triangles},
      {"OFF/Cube.off", off_triangles},
      {"OFF/Wuson.off", off_triangles},
      {"PLY/cube.ply", ascii_ply_triangles},
      {"PLY/Wuson.ply", ascii_ply_triangles},
      {"STL/Spider_ascii.stl", ascii_stl_triangles},
      {"STL/Spider_binary.stl", binary_stl_triangles},
      {"STL/Wuson.stl", binary_stl_triangles},
      {"glTF2/BoxTextured-glTF/BoxTextured.gltf", gltf_triangles},
      {"glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb", gltf_triangles},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    const fs::path path = kModels / c.file;
    const std::size_t expected = c.count(path);
    ASSERT_GT(expected, 0u);
    const Mesh mesh = load(path);
    EXPECT_EQ(mesh.triangle_count(), expected);
    EXPECT_EQ(mesh.indices.size() % 3, 0u);
    expect_valid_indices(mesh);
    expect_unit_normals(mesh);
  }
}

TEST(LoadModel, BinaryAndAsciiPlyAgree) {
  const Mesh ascii = load(kModels / "PLY/cube.ply");
  const Mesh binary = load(kModels / "PLY/cube_binary.ply");
  EXPECT_EQ(ascii.positions, binary.positions);
  EXPECT_EQ(ascii.normals, binary.normals);
  EXPECT_EQ(ascii.indices, binary.indices);
}

TEST(LoadModel, SkipsPointsAndLinesWithAWarning) {
  const fs::path path = kModels / "OBJ/testmixed.obj";
  const auto [points, segments] = obj_points_and_lines(path);
  std::vector<std::string> warnings;
  const Mesh mesh = load_model(path.string(), warnings);
  EXPECT_EQ(mesh.triangle_count(), obj_triangles(path));
  EXPECT_EQ(warnings, (std::vector<std::string>{"skipped " + std::to_string(points) + " point primitives",
                                                "skipped " + std::to_string(segments) + " line primitives"}));
}

// ---- Crafted files -------------------------------------------------------------------------------

class CraftedModel : public testing::Test {
 protected:
  void SetUp() override {
    directory_ = fs::path(testing::TempDir()) /
                 ("clraster_model_loader_" + std::to_string(getpid()) + "_" +
                  testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(directory_);
  }
  void TearDown() override { fs::remove_all(directory_); }

  fs::path write(const std::string& name, const std::string& content) const {
    const fs::path path = directory_ / name;
    std::ofstream(path, std::ios::binary) << content;
    return path;
  }

  fs::path directory_;
};

template <typename T>
std::string bytes_of(std::initializer_list<T> values) {
  std::string bytes(values.size() * sizeof(T), '\0');
  std::memcpy(bytes.data(), std::data(values), bytes.size());
  return bytes;
}

// Two meshes over the triangle (0,0,0) (1,0,0) (0,1,0): mesh 0 without normals, mesh 1 with the
// normal (1,0,1)/sqrt(2) at every corner. Mesh 0 is instanced twice, by a translated child of a
// translated node and by a mirroring node; mesh 1 by a node that scales x by 2.
constexpr const char* kInstancedGltf = R"({
  "asset": {"version": "2.0"},
  "buffers": [{"uri": "triangle.bin", "byteLength": 72}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                  {"buffer": 0, "byteOffset": 36, "byteLength": 36}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]},
             {"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}}]}],
  "nodes": [{"children": [1], "translation": [0, 0, 5]},
            {"mesh": 0, "translation": [10, 0, 0]},
            {"mesh": 0, "scale": [-1, 1, 1]},
            {"mesh": 1, "scale": [2, 1, 1]}],
  "scenes": [{"nodes": [0, 2, 3]}],
  "scene": 0
})";

TEST_F(CraftedModel, GltfNodeTransformsInstancesAndFlatNormals) {
  const float h = static_cast<float>(1 / std::sqrt(2.0));
  write("triangle.bin", bytes_of<float>({0, 0, 0, 1, 0, 0, 0, 1, 0, h, 0, h, h, 0, h, h, 0, h}));
  const Mesh mesh = load(write("instanced.gltf", kInstancedGltf));
  ASSERT_EQ(mesh.triangle_count(), 3u);

  // Mesh 0 through both translations; no normals in the file, so the flat glTF normal.
  EXPECT_TRUE(near(corner(mesh, 0, 0), {10, 0, 5}, 0));
  EXPECT_TRUE(near(corner(mesh, 0, 1), {11, 0, 5}, 0));
  EXPECT_TRUE(near(corner(mesh, 0, 2), {10, 1, 5}, 0));
  for (int k = 0; k < 3; ++k) EXPECT_TRUE(near(normal(mesh, mesh.indices[k]), {0, 0, 1}, 1e-6));

  // Mesh 0 mirrored in x: the winding is reversed, so the front face still faces +z.
  EXPECT_TRUE(near(corner(mesh, 1, 0), {0, 0, 0}, 0));
  EXPECT_TRUE(near(corner(mesh, 1, 1), {0, 1, 0}, 0));
  EXPECT_TRUE(near(corner(mesh, 1, 2), {-1, 0, 0}, 0));
  for (int k = 3; k < 6; ++k) EXPECT_TRUE(near(normal(mesh, mesh.indices[k]), {0, 0, 1}, 1e-6));

  // Mesh 1 scaled: normals by the inverse transpose, (0.5, 0, 1) normalized, not (2, 0, 1).
  EXPECT_TRUE(near(corner(mesh, 2, 1), {2, 0, 0}, 0));
  const double length = std::sqrt(1.25);
  for (int k = 6; k < 9; ++k) EXPECT_TRUE(near(normal(mesh, mesh.indices[k]), {0.5 / length, 0, 1 / length}, 1e-6));
}

TEST(LoadModel, GltfWithoutNormalsGetsFlatNormals) {
  // An indexed quad without normals: every triangle gets its own three vertices.
  const fs::path path = kModels / "glTF2/glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_13.gltf";
  ASSERT_FALSE(gltf_document(path)["meshes"][0]["primitives"][0]["attributes"].contains("NORMAL"));
  const Mesh mesh = load(path);
  ASSERT_EQ(mesh.triangle_count(), gltf_triangles(path));
  EXPECT_EQ(mesh.vertex_count(), 3 * mesh.triangle_count());
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    const glm::dvec3 expected = glm::normalize(face_cross(mesh, t));
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(mesh.indices[3 * t + k], 3 * t + k);
      EXPECT_TRUE(near(normal(mesh, mesh.indices[3 * t + k]), expected, 1e-6));
    }
  }
}

// The box [0,1] x [0,2] x [0,3] as twelve triangles, each face split along the diagonal that
// misses corner 8, (1,2,3). So corner 8 is in one triangle of each of its three faces, corner 1 in
// two; either way each face adds its area times its normal: (6, 3, 2) with signs, over 7.
constexpr const char* kBoxObj = R"(v 0 0 0
v 1 0 0
v 0 2 0
v 1 2 0
v 0 0 3
v 1 0 3
v 0 2 3
v 1 2 3
f 5 6 7
f 6 8 7
f 2 4 6
f 4 8 6
f 3 7 4
f 7 8 4
f 1 3 4
f 1 4 2
f 1 5 7
f 1 7 3
f 1 2 6
f 1 6 5
)";

TEST_F(CraftedModel, ObjWithoutNormalsIsSmoothedAcrossFacesByArea) {
  const Mesh mesh = load(write("box.obj", kBoxObj));
  ASSERT_EQ(mesh.triangle_count(), 12u);
  // assimp gives every face corner its own vertex: the smoothing goes by position.
  EXPECT_EQ(mesh.vertex_count(), 36u);
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
    const glm::dvec3 p = position(mesh, v);
    const double sx = p.x > 0.5 ? 1 : -1, sy = p.y > 1 ? 1 : -1, sz = p.z > 1.5 ? 1 : -1;
    EXPECT_TRUE(near(normal(mesh, v), {6 * sx / 7, 3 * sy / 7, 2 * sz / 7}, 1e-6)) << "vertex " << v;
  }
}

TEST_F(CraftedModel, StlWithZeroNormalsIsSmoothed) {
  const Mesh mesh = load(write("zero.stl", R"(solid zero
facet normal 0 0 0
outer loop
vertex 0 0 0
vertex 1 0 0
vertex 0 1 0
endloop
endfacet
endsolid zero
)"));
  ASSERT_EQ(mesh.triangle_count(), 1u);
  for (std::uint32_t v = 0; v < 3; ++v) EXPECT_TRUE(near(normal(mesh, v), {0, 0, 1}, 1e-6));
}

TEST_F(CraftedModel, NonFiniteCoordinatesAreKept) {
  // The first triangle has a NaN corner; the second is finite and shares two positions with it.
  const Mesh mesh = load(write("nan.obj", "v nan 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n"));
  ASSERT_EQ(mesh.triangle_count(), 2u);
  EXPECT_TRUE(std::isnan(corner(mesh, 0, 0).x));
  // The NaN triangle's normal is left out of its neighbours' sums.
  for (int k = 0; k < 3; ++k) EXPECT_TRUE(near(normal(mesh, mesh.indices[3 + k]), {0, 0, 1}, 1e-6));

  const Mesh infinite = load(write("inf.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 inf 0\n3 0 1 2\n"));
  ASSERT_EQ(infinite.triangle_count(), 1u);
  EXPECT_TRUE(std::isinf(corner(infinite, 0, 2).y));
}

TEST(LoadModel, GltfWithInfinitiesLoads) {
  const Mesh mesh = load(kModels / "glTF2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb");
  EXPECT_EQ(mesh.triangle_count(), 12u);
  EXPECT_TRUE(std::any_of(mesh.positions.begin(), mesh.positions.end(), [](float x) { return !std::isfinite(x); }));
}

// ---- Errors --------------------------------------------------------------------------------------

TEST_F(CraftedModel, IndicesOfVerticesThatDoNotExistAreErrors) {
  // Each reader meets these differently: OBJ and PLY fail outright, OFF clamps the index and says
  // so only in assimp's log.
  const std::string ply_header =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
  const std::string binary_ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n" +
      bytes_of<float>({0, 0, 0, 1, 0, 0, 0, 1, 0}) + std::string(1, '\3') + bytes_of<std::int32_t>({0, 1, 9});
  const fs::path files[] = {
      write("past_end.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n"),
      write("negative.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -5\n"),
      write("past_end.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n"),
      write("past_end.ply", ply_header + "3 0 1 9\n"),
      write("negative.ply", ply_header + "3 0 1 -1\n"),
      write("past_end_binary.ply", binary_ply),
  };
  for (const fs::path& file : files) {
    SCOPED_TRACE(file);
    load_error(file);
  }
  EXPECT_NE(load_error(files[2]).find("vertices that do not exist"), std::string::npos);
}

TEST_F(CraftedModel, ReferencesThatAssimpMisreadsAreErrors) {
  // assimp reads each of these without an error: negative and 32-bit-wrapping indices as other
  // vertices, missing ones as 0, floating-point ones cut to integers, strips as one triangle each,
  // and references to normals or texture coordinates that do not exist by dropping them all.
  const std::string off = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n";
  const std::string ply_vertices =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
  const std::string ply_data = "end_header\n0 0 0\n1 0 0\n0 1 0\n";
  const std::string ply = ply_vertices + "element face 1\nproperty list uchar uint vertex_indices\n" + ply_data;
  const std::string float_ply =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar float vertex_indices\nend_header\n" +
      bytes_of<float>({0, 0, 0, 1, 0, 0, 0, 1, 0}) + std::string(1, '\3') + bytes_of<float>({0, 1, 4294967296.0f});
  const std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n";
  const std::string no_vertex = "faces reference vertices that do not exist: ";
  const std::string no_normal = "faces reference normals that do not exist: ";
  struct Case {
    const char* file;
    std::string content;
    std::string reason;
  };
  const Case cases[] = {
      {"negative.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 -1\n",
       no_vertex + "line 7 refers to vertex '-1' of 4"},
      {"wrapping.off", off + "3 0 1 4294967297\n", no_vertex + "line 6 refers to vertex '4294967297' of 3"},
      {"short.off", off + "3 0 1\n", "line 6 ends before its face does"},
      // assimp picks the OFF reader by the content.
      {"wrapping_off", off + "3 0 1 4294967297\n", no_vertex + "line 6 refers to vertex '4294967297' of 3"},
      {"wrapping.ply", ply + "3 0 1 4294967297\n", no_vertex + "line 13 refers to vertex '4294967297' of 3"},
      {"negative_unsigned.ply", ply + "3 0 -1 2\n", no_vertex + "line 13 refers to vertex '-1' of 3"},
      {"short.ply", ply + "3 0 1\n", "line 13 ends before its face does"},
      {"missing_face.ply",
       ply_vertices + "element face 2\nproperty list uchar uint vertex_indices\n" + ply_data + "3 0 1 2\n",
       "the file ends before its last face"},
      {"float_indices.ply", float_ply, "line 8 declares vertex indices of type float, which assimp rounds and wraps"},
      {"strips.ply",
       ply_vertices + "element tristrips 1\nproperty list int int vertex_indices\n" + ply_data + "3 0 1 2\n",
       "line 7 declares triangle strips, of which assimp keeps one triangle each"},
      {"missing_normal.obj", obj + "f 1//9 2//9 3//9\n", no_normal + "line 6 refers to normal '9' of 1"},
      {"wrapping_normal.obj", obj + "f 1//1 2//1 3//4294967297\n",
       no_normal + "line 6 refers to normal '4294967297' of 1"},
      {"normal_before_the_start.obj", obj + "f 1//-1 2//-1 3//-2\n", no_normal + "line 6 refers to normal '-2' of 1"},
      {"missing_texture_coordinate.obj", obj + "f 1/1 2/1 3/2\n",
       "faces reference texture coordinates that do not exist: line 6 refers to texture coordinate '2' of 1"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    const std::string message = load_error(write(c.file, c.content));
    EXPECT_NE(message.find("': " + c.reason), std::string::npos) << message;
  }
}

TEST_F(CraftedModel, ReferencesThatAssimpReadsRightLoad) {
  struct Case {
    const char* file;
    std::string content;
  };
  const Case cases[] = {
      // Comments and blank lines, the counts after the keyword, colours after the indices.
      {"comments.off", "# a triangle\nOFF 3 1 0 # no edges\n\n0 0 0\n1 0 0\n\n\n0 1 0\n3 0 1 2 255 0 0\n"},
      {"normals.off", "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n"},
      // A comment, values before and after the indices, one blank line, which assimp skips.
      {"values.ply",
       "ply\nformat ascii 1.0\ncomment by hand\nelement vertex 3\nproperty float x\nproperty float y\n"
       "property float z\nelement face 1\nproperty uchar flags\nproperty list uchar int vertex_indices\n"
       "property list uchar float texcoord\nend_header\n0 0 0\n1 0 0\n0 1 0\n\n7 3 0 1 2 6 0 0 1 0 0 1\n"},
      {"crlf.ply",
       "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty float x\r\nproperty float y\r\n"
       "property float z\r\nelement face 1\r\nproperty list uchar int vertex_index\r\nend_header\r\n"
       "0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n"},
      // References back from the latest, a continued line, a reference to a later normal.
      {"references.obj",
       "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf -3/-1/-1 -2/-1/-1 \\\n-1/-1/-1\nf 1//2 2//2 3//2\n"
       "vn 0 0 1\n"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.file);
    const Mesh mesh = load(write(c.file, c.content));
    ASSERT_GE(mesh.triangle_count(), 1u);
    EXPECT_TRUE(near(face_cross(mesh, 0), {0, 0, 1}, 0));
  }
}

TEST_F(CraftedModel, ConcurrentLoadsEachSeeTheirOwnRepairs) {
  // The repair, dropped faces, shows only in assimp's process-wide log: a load must neither miss
  // its own warning nor fail on another thread's.
  const fs::path good = write("good.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  const fs::path bad = kModels / "glTF2/IndexOutOfRange/IndexOutOfRange.gltf";
  std::atomic<int> loaded = 0, refused = 0;
  std::vector<std::thread> threads;
  for (int t = 0; t < 4; ++t) {
    threads.emplace_back([&] {
      for (int i = 0; i < 20; ++i) {
        std::vector<std::string> warnings;
        loaded += load_model(good.string(), warnings).triangle_count() == 1;
        try {
          load_model(bad.string(), warnings);
        } catch (const InvalidArgument&) {
          ++refused;
        }
      }
    });
  }
  for (std::thread& thread : threads) thread.join();
  EXPECT_EQ(loaded, 80);
  EXPECT_EQ(refused, 80);
}

TEST(LoadModel, LeavesTheApplicationsLoggerInPlace) {
  Assimp::DefaultLogger::create(nullptr, Assimp::Logger::NORMAL, 0);
  const Assimp::Logger* installed = Assimp::DefaultLogger::get();
  load(kModels / "OBJ/box.obj");
  EXPECT_EQ(Assimp::DefaultLogger::get(), installed);
  Assimp::DefaultLogger::kill();
}

TEST(LoadModel, GltfIndicesOutOfRangeAreErrors) {
  // assimp drops those faces with a warning; a partial model must not be drawn. Without any faces
  // left, assimp fails too, saying only that the mesh has no faces.
  for (const char* file : {"IndexOutOfRange.gltf", "AllIndicesOutOfRange.gltf"}) {
    SCOPED_TRACE(file);
    const std::string message = load_error(kModels / "glTF2/IndexOutOfRange" / file);
    EXPECT_NE(message.find("vertices that do not exist"), std::string::npos) << message;
  }
}

TEST(LoadModel, MalformedGltfFilesAreErrors) {
  for (const char* directory : {"glTF2/wrongTypes", "glTF2/SchemaFailures"}) {
    for (const auto& entry : fs::directory_iterator(kModels / directory)) {
      if (entry.path().extension() != ".gltf") continue;
      SCOPED_TRACE(entry.path());
      const std::string message = load_error(entry.path());
      EXPECT_NE(message.find("was not of type"), std::string::npos) << message;
    }
  }
}

TEST(LoadModel, FilesWithoutTrianglesAreErrors) {
  EXPECT_NE(load_error(kModels / "OBJ/testpoints.obj").find("no triangles in the file (skipped 24 point primitives)"),
            std::string::npos);
  EXPECT_NE(load_error(kModels / "OBJ/testline.obj").find("no triangles in the file (skipped 18 line primitives)"),
            std::string::npos);
  load_error(kModels / "OBJ/point_cloud.obj");  // refused by assimp's validation
  load_error(kModels / "glTF2/TestNoRootNode/SceneWithoutNodes.gltf");
}

TEST(LoadModel, UnparsableFilesAreErrors) {
  for (const auto& entry : fs::directory_iterator(kModels / "invalid")) {
    // malformed2.obj only has an empty face, which assimp ignores. OutOfMemory.off claims 3.5e11
    // vertices, which assimp allocates before failing: an error too, but after 13 s.
    if (entry.path().filename() == "malformed2.obj" || entry.path().filename() == "OutOfMemory.off") continue;
    SCOPED_TRACE(entry.path());
    load_error(entry.path());
  }
  load_error(kModels / "glTF2/MissingBin/BoxTextured.gltf");
  load_error(kModels / "glTF2/RecursiveNodes/RecursiveNodes.gltf");
}

TEST_F(CraftedModel, MissingFilesAndDirectoriesAreErrors) {
  EXPECT_NE(load_error(directory_ / "missing.obj").find("No such file or directory"), std::string::npos);
  EXPECT_NE(load_error(directory_).find("is a directory"), std::string::npos);
}

TEST_F(CraftedModel, UnopenableFilesAreErrorsWithTheSystemsReason) {
  // A path through a regular file cannot be opened by anyone, root included (permission bits
  // would not stop root).
  const fs::path file = write("box.obj", kBoxObj);
  EXPECT_NE(load_error(file / "model.obj").find("Not a directory"), std::string::npos);
}

// ---- bounding_sphere -----------------------------------------------------------------------------

TEST(BoundingSphere, CentresOnTheBoxOfFiniteVertices) {
  Mesh mesh;
  mesh.positions = {0, 0, 0, 2, 4, 6, 1, 1, 1, NAN, 100, 100, 1e30f, INFINITY, 0};
  const BoundingSphere sphere = bounding_sphere(mesh);
  EXPECT_FLOAT_EQ(sphere.center.x, 1);
  EXPECT_FLOAT_EQ(sphere.center.y, 2);
  EXPECT_FLOAT_EQ(sphere.center.z, 3);
  EXPECT_FLOAT_EQ(sphere.radius, std::sqrt(14.0f));
  EXPECT_GE(double{sphere.radius}, std::sqrt(14.0));
}

TEST(BoundingSphere, DegenerateMeshes) {
  Mesh point;
  point.positions = {1, 2, 3, NAN, 0, 0};
  const BoundingSphere single = bounding_sphere(point);
  EXPECT_EQ(single.center.x, 1);
  EXPECT_EQ(single.center.y, 2);
  EXPECT_EQ(single.center.z, 3);
  EXPECT_EQ(single.radius, 0);

  Mesh no_finite;
  no_finite.positions = {NAN, 0, 0};
  const BoundingSphere none = bounding_sphere(no_finite);
  EXPECT_EQ(none.center.x, 0);
  EXPECT_EQ(none.radius, 0);
  EXPECT_EQ(bounding_sphere(Mesh{}).radius, 0);
}

TEST(BoundingSphere, ContainsEveryVertexOfARealModel) {
  const Mesh mesh = load(kModels / "OBJ/spider.obj");
  const BoundingSphere sphere = bounding_sphere(mesh);
  for (std::uint32_t v = 0; v < mesh.vertex_count(); ++v) {
    const glm::dvec3 center(sphere.center.x, sphere.center.y, sphere.center.z);
    ASSERT_LE(glm::distance(position(mesh, v), center), sphere.radius) << "vertex " << v;
  }
}

}  // namespace
}  // namespace clraster::io
