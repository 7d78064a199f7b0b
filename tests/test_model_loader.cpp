// Model loading: triangle counts checked against the files themselves, node transforms and
// instancing, the three normal rules, and a one-line error for every broken file.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <assimp/DefaultLogger.hpp>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <numeric>
#include <ostream>
#include <sstream>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include "clraster/clraster.hpp"
#include "support/mesh_inspection.hpp"
#include "io/mesh.hpp"
#include "io/isolated_loader.hpp"
#include "io/model_loader.hpp"
#include "support/hostile_models.hpp"

namespace clraster::io {

// For gtest's messages; found by argument-dependent lookup, so in ModelPart's namespace.
void PrintTo(const ModelPart& part, std::ostream* out) {
  *out << "{first_index " << part.first_index << ", index_count " << part.index_count << ", material "
       << part.material << "}";
}

namespace {

using test::corner;
using test::face_cross;
using test::normal;
using test::position;
using test::texcoord;

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

Model load(const fs::path& path) {
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

// Chunk `index` of a .glb file: a 12-byte header, then chunks of their length, their type and
// their bytes; the JSON chunk first, then the binary one.
std::string glb_chunk(const std::string& bytes, int index) {
  std::size_t at = 12;
  for (int chunk = 0;; ++chunk) {
    std::uint32_t length = 0;
    std::memcpy(&length, bytes.data() + at, sizeof length);
    if (chunk == index) return bytes.substr(at + 8, length);
    at += 8 + std::size_t{length};
  }
}

nlohmann::json gltf_document(const fs::path& path) {
  const std::string bytes = read_text(path);
  return nlohmann::json::parse(path.extension() == ".glb" ? glb_chunk(bytes, 0) : bytes);
}

// One triangle primitive of one mesh instance of the default scene, in the order load_model
// visits them: depth first, a node's mesh before its children.
struct GltfDraw {
  const nlohmann::json* primitive;  // in the document
  std::size_t triangles;            // by primitive mode
};

std::vector<GltfDraw> gltf_draws(const nlohmann::json& document) {
  const auto& accessors = document["accessors"];
  std::vector<GltfDraw> draws;
  std::function<void(std::size_t)> visit = [&](std::size_t index) {
    const auto& node = document["nodes"][index];
    if (node.contains("mesh")) {
      for (const auto& primitive : document["meshes"][node["mesh"].get<std::size_t>()]["primitives"]) {
        // Corners: the index count, or the vertex count when the primitive has no indices.
        const auto& corner_accessor =
            primitive.contains("indices") ? primitive["indices"] : primitive["attributes"]["POSITION"];
        const auto corners = accessors[corner_accessor.get<std::size_t>()]["count"].get<std::size_t>();
        const int mode = primitive.value("mode", 4);
        if (mode == 4) draws.push_back({&primitive, corners / 3});
        if (mode == 5 || mode == 6) draws.push_back({&primitive, corners - 2});
      }
    }
    for (const auto& child : node.value("children", nlohmann::json::array())) visit(child);
  };
  for (const auto& root : document["scenes"][document.value("scene", 0)]["nodes"]) visit(root);
  return draws;
}

std::size_t gltf_triangles(const fs::path& path) {
  const nlohmann::json document = gltf_document(path);
  std::size_t triangles = 0;
  for (const GltfDraw& draw : gltf_draws(document)) triangles += draw.triangles;
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

// A scan as depth sensors write it: vertex 1 is NaN and vertex 5 infinite, so faces 1 and 3 go,
// and with them the vertices only they use, 1, 5 and (finite) 6.
constexpr const char* kScanPly = R"(ply
format ascii 1.0
element vertex 7
property float x
property float y
property float z
element face 4
property list uchar int vertex_indices
end_header
0 0 0
nan nan nan
1 0 0
0 1 0
1 1 0
2 0 inf
4 4 0
3 0 2 3
3 1 2 4
3 2 4 3
3 4 5 6
)";

TEST_F(CraftedModel, NonFinitePositionsDropTheirTrianglesAndTheVerticesOnlyTheyUse) {
  const Model model = load(write("scan.ply", kScanPly));
  EXPECT_EQ(model.triangles_dropped, 2u);
  // Vertices 0, 2, 3 and 4, numbered anew in order.
  EXPECT_EQ(model.positions, (std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0}));
  EXPECT_EQ(model.indices, (std::vector<std::uint32_t>{0, 1, 2, 1, 3, 2}));
  EXPECT_EQ(model.parts, (std::vector<ModelPart>{{0, 6, 0}}));
  // Smoothed over the kept faces alone: a dropped one would have made vertices 2 and 4 zero.
  for (std::uint32_t v = 0; v < model.vertex_count(); ++v) {
    EXPECT_TRUE(near(normal(model, v), {0, 0, 1}, 1e-6)) << "vertex " << v;
  }
  // Vertex 6, (4, 4, 0), would have moved it.
  const BoundingSphere sphere = bounding_sphere(model);
  EXPECT_TRUE(near({sphere.center.x, sphere.center.y, sphere.center.z}, {0.5, 0.5, 0}, 0));
}

TEST_F(CraftedModel, NonFinitePositionsAndNormalsDropTheirTrianglesInEveryFormat) {
  // assimp's OBJ reader gives every face corner a vertex of its own: the kept face's three.
  const Model nan_obj = load(write("nan.obj", "v 1 0 0\nv nan 0 0\nv 0 1 0\nv 1 1 0\nf 1 4 3\nf 1 2 3\n"));
  EXPECT_EQ(nan_obj.triangles_dropped, 1u);
  EXPECT_EQ(nan_obj.positions, (std::vector<float>{1, 0, 0, 1, 1, 0, 0, 1, 0}));
  EXPECT_EQ(nan_obj.indices, (std::vector<std::uint32_t>{0, 1, 2}));

  const Model inf_off = load(write("inf.off", "OFF\n5 3 0\n0 0 0\n1 0 0\n0 inf 0\n0 1 0\n-inf 0 0\n"
                                              "3 0 1 2\n3 0 1 3\n3 4 0 3\n"));
  EXPECT_EQ(inf_off.triangles_dropped, 2u);
  ASSERT_EQ(inf_off.triangle_count(), 1u);
  EXPECT_TRUE(near(corner(inf_off, 0, 0), {0, 0, 0}, 0));
  EXPECT_TRUE(near(corner(inf_off, 0, 1), {1, 0, 0}, 0));
  EXPECT_TRUE(near(corner(inf_off, 0, 2), {0, 1, 0}, 0));
  EXPECT_EQ(inf_off.vertex_count(), 3u);

  // A normal that is not finite would shade its triangle with undefined values.
  const Model normal_obj = load(write("normal.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\nvn 0 -inf 1\n"
                                                    "f 1//1 2//1 3//1\nf 2//1 4//2 3//1\n"));
  EXPECT_EQ(normal_obj.triangles_dropped, 1u);
  EXPECT_EQ(normal_obj.positions, (std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0}));
  EXPECT_EQ(normal_obj.normals, (std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1}));
}

TEST_F(CraftedModel, NonFiniteVerticesNoTriangleUsesAreIgnored) {
  // Also after the node's transform, which moves every vertex.
  const Model model = load(write("unused.off", "OFF\n4 1 0\n0 0 0\n1 0 0\n0 1 0\nnan 5 5\n3 0 1 2\n"));
  EXPECT_EQ(model.triangle_count(), 1u);
  EXPECT_EQ(model.triangles_dropped, 0u);
}

TEST(LoadModel, GltfWhoseEveryTriangleIsDroppedIsAnError) {
  // Every position has an infinite x: nothing is left to draw or to frame.
  const fs::path path = kModels / "glTF2/BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb";
  const std::string message = load_error(path);
  EXPECT_NE(message.find(": no triangles left: 12 triangles dropped: a corner's position, normal or texture "
                         "coordinate is NaN or infinite"),
            std::string::npos)
      << message;
}

TEST_F(CraftedModel, LargeScalesKeepUnitNormals) {
  // Positions up to 1e20 are floats; the normals' cofactors, 1e40, are not.
  write("data.bin", bytes_of<float>({0, 0, 0, 1, 0, 0, 0, 1, 0}) + bytes_of<float>({0, 0, 1, 0, 0, 1, 0, 0, 1}));
  const Mesh mesh = load(write("scaled.gltf", R"({
  "asset": {"version": "2.0"},
  "buffers": [{"uri": "data.bin", "byteLength": 72}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}, {"buffer": 0, "byteOffset": 36, "byteLength": 36}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC3"}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1}}]}],
  "nodes": [{"mesh": 0, "scale": [1e20, 1e20, 1e20]}],
  "scenes": [{"nodes": [0]}],
  "scene": 0
})"));
  ASSERT_EQ(mesh.triangle_count(), 1u);
  EXPECT_TRUE(near(corner(mesh, 0, 1), {1e20, 0, 0}, 1e13));
  for (std::uint32_t v = 0; v < 3; ++v) EXPECT_TRUE(near(normal(mesh, v), {0, 0, 1}, 1e-6));
}

// The triangle (0,0,0) (1,0,0) (0,1,0), instanced by node 1, whose scale with its parent's carries
// x = 1 to 3e38 * 2e38, and by node 2 as it is.
constexpr const char* kScaledBeyondFloatRangeGltf = R"({
  "asset": {"version": "2.0"},
  "buffers": [{"uri": "data.bin", "byteLength": 36}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 1, 0]}],
  "meshes": [{"name": "huge", "primitives": [{"attributes": {"POSITION": 0}}]}],
  "nodes": [{"scale": [3e38, 3e38, 3e38], "children": [1]}, {"mesh": 0, "scale": [2e38, 2e38, 2e38]},
            {"mesh": 0}],
  "scenes": [{"nodes": [0, 2]}],
  "scene": 0
})";

TEST_F(CraftedModel, PositionsMovedBeyondFloatRangeDropTheirTriangles) {
  write("data.bin", bytes_of<float>({0, 0, 0, 1, 0, 0, 0, 1, 0}));
  const Model model = load(write("huge.gltf", kScaledBeyondFloatRangeGltf));
  EXPECT_EQ(model.triangles_dropped, 1u);
  // Node 2's instance alone, with its flat normal.
  EXPECT_EQ(model.positions, (std::vector<float>{0, 0, 0, 1, 0, 0, 0, 1, 0}));
  EXPECT_EQ(model.normals, (std::vector<float>{0, 0, 1, 0, 0, 1, 0, 0, 1}));

  std::string only_huge = kScaledBeyondFloatRangeGltf;
  only_huge.replace(only_huge.find("[0, 2]"), 6, "[0]");
  const std::string message = load_error(write("only_huge.gltf", only_huge));
  EXPECT_NE(message.find(": no triangles left: 1 triangle dropped: a corner's position, normal or texture coordinate "
                         "is NaN or infinite"),
            std::string::npos)
      << message;
}

// ---- Texture coordinates, materials and parts ----------------------------------------------------

std::string as_string(const std::vector<std::byte>& bytes) {
  return {reinterpret_cast<const char*>(bytes.data()), bytes.size()};
}

std::string base64_decoded(std::string_view text) {
  constexpr std::string_view kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string bytes;
  std::uint32_t bits = 0;
  int bit_count = 0;
  for (char c : text) {
    const std::size_t value = kAlphabet.find(c);
    if (value == std::string_view::npos) continue;  // '=' padding
    bits = bits << 6 | static_cast<std::uint32_t>(value);
    bit_count += 6;
    if (bit_count >= 8) {
      bit_count -= 8;
      bytes += static_cast<char>(bits >> bit_count & 0xff);
    }
  }
  return bytes;
}

// The bytes of a base64 data: URI ("data:image/png;base64,...").
std::string data_uri_bytes(std::string_view uri) { return base64_decoded(uri.substr(uri.find(',') + 1)); }

// Buffer `index` of a glTF file: a file beside it, a data: URI, or a .glb's binary chunk.
std::string gltf_buffer(const fs::path& path, const nlohmann::json& document, std::size_t index) {
  const auto& buffer = document["buffers"][index];
  if (!buffer.contains("uri")) return glb_chunk(read_text(path), 1);
  const std::string uri = buffer["uri"];
  return uri.starts_with("data:") ? data_uri_bytes(uri) : read_text(path.parent_path() / uri);
}

std::string gltf_buffer_view(const fs::path& path, const nlohmann::json& document, std::size_t index) {
  const auto& view = document["bufferViews"][index];
  return gltf_buffer(path, document, view["buffer"])
      .substr(view.value("byteOffset", std::size_t{0}), view["byteLength"].get<std::size_t>());
}

// The bytes of an image file that a glTF file embeds, in a buffer view or a data: URI.
std::string gltf_embedded_image(const fs::path& path, const nlohmann::json& document, const nlohmann::json& image) {
  if (image.contains("bufferView")) return gltf_buffer_view(path, document, image["bufferView"]);
  return data_uri_bytes(image["uri"].get<std::string>());
}

// A glTF accessor's elements: component c of element i starts at byte offset + i * stride +
// c * sizeof(T) of the buffer view.
struct GltfAccessor {
  std::string view;  // the accessor's buffer view
  std::size_t offset;
  std::size_t stride;
  int component_type;

  template <typename T>
  T component(std::size_t i, int c) const {
    T value;
    std::memcpy(&value, view.data() + offset + i * stride + c * sizeof(T), sizeof value);
    return value;
  }
  std::size_t index(std::size_t i) const {
    switch (component_type) {
      case 5121: return component<std::uint8_t>(i, 0);
      case 5123: return component<std::uint16_t>(i, 0);
      default: return component<std::uint32_t>(i, 0);
    }
  }
};

GltfAccessor gltf_accessor(const fs::path& path, const nlohmann::json& document, std::size_t index) {
  const auto& accessor = document["accessors"][index];
  const int component_type = accessor["componentType"];
  const std::size_t component_size = component_type == 5121 ? 1 : component_type == 5123 ? 2 : 4;
  const std::string type = accessor["type"];
  const std::size_t components = type == "SCALAR" ? 1 : type == "VEC2" ? 2 : type == "VEC3" ? 3 : 4;
  const auto& view = document["bufferViews"][accessor["bufferView"].get<std::size_t>()];
  return {gltf_buffer_view(path, document, accessor["bufferView"]), accessor.value("byteOffset", std::size_t{0}),
          view.value("byteStride", components * component_size), component_type};
}

// The texture coordinates that load_model gives a glTF file's model, read from the file: each
// draw's TEXCOORD_0 (floats) with v turned up, vertex by vertex, or corner by corner for
// primitives without normals, which get flat normals; (0, 0) for draws without them, and none at
// all when no draw has them.
std::vector<float> gltf_texcoords(const fs::path& path) {
  const nlohmann::json document = gltf_document(path);
  std::vector<float> texcoords;
  bool any = false;
  for (const GltfDraw& draw : gltf_draws(document)) {
    const nlohmann::json& primitive = *draw.primitive;
    const auto& attributes = primitive["attributes"];
    EXPECT_EQ(primitive.value("mode", 4), 4) << "only triangle lists are read here";
    std::vector<std::size_t> vertices(
        document["accessors"][attributes["POSITION"].get<std::size_t>()]["count"].get<std::size_t>());
    std::iota(vertices.begin(), vertices.end(), std::size_t{0});
    if (!attributes.contains("NORMAL") && primitive.contains("indices")) {
      const GltfAccessor indices = gltf_accessor(path, document, primitive["indices"]);
      vertices.resize(3 * draw.triangles);
      for (std::size_t corner = 0; corner < vertices.size(); ++corner) vertices[corner] = indices.index(corner);
    }
    if (!attributes.contains("TEXCOORD_0")) {
      texcoords.resize(texcoords.size() + 2 * vertices.size(), 0.0f);
      continue;
    }
    any = true;
    const GltfAccessor uv = gltf_accessor(path, document, attributes["TEXCOORD_0"]);
    EXPECT_EQ(uv.component_type, 5126);
    for (std::size_t v : vertices) {
      texcoords.insert(texcoords.end(), {uv.component<float>(v, 0), 1.0f - uv.component<float>(v, 1)});
    }
  }
  return any ? texcoords : std::vector<float>{};
}

// glTF samples with materials, most with textures: in files of their own, in a .glb's binary chunk
// and in data: URIs.
constexpr const char* kGltfWithMaterials[] = {
    "glTF2/BoxTextured-glTF/BoxTextured.gltf",
    "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb",
    "glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf",
    "glTF2/BoxTexcoords-glTF/boxTexcoords.gltf",
    "glTF2/ClearCoat-glTF/ClearCoatTest.gltf",
    "glTF2/textureTransform/TextureTransformTest.gltf",
    "glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb",
};

TEST(LoadModel, GltfTexcoordsAreTheFilesWithVUp) {
  for (const char* file : kGltfWithMaterials) {
    SCOPED_TRACE(file);
    const fs::path path = kModels / file;
    const Model model = load(path);
    const std::vector<float> expected = gltf_texcoords(path);
    EXPECT_EQ(model.texcoords.size(), expected.empty() ? 0 : 2 * model.vertex_count());
    EXPECT_EQ(model.texcoords, expected);
  }
  // The first vertices of BoxTextured0.bin: (6, 0) and (6, 0.99999988), so v turned up is 1 and
  // 1 - 0.99999988.
  const Model box = load(kModels / "glTF2/BoxTextured-glTF/BoxTextured.gltf");
  ASSERT_EQ(box.texcoords.size(), 2 * 24u);
  EXPECT_EQ(texcoord(box, 0), glm::dvec2(6, 1));
  EXPECT_EQ(texcoord(box, 2), glm::dvec2(6, 1.0f - 0.99999988f));
}

// Checks a glTF file's model against the file: the parts are the runs of draws, in file order,
// with the same glTF material (or none, which assimp gives a default material); the materials are
// numbered in the order of their first part and have the name, baseColorFactor and
// baseColorTexture of the glTF material.
void expect_gltf_materials_and_parts(const fs::path& path, const Model& model) {
  const nlohmann::json document = gltf_document(path);
  std::vector<ModelPart> parts;
  std::vector<int> gltf_materials;  // of each model material
  std::uint32_t first_index = 0;
  for (const GltfDraw& draw : gltf_draws(document)) {
    const int gltf_material = draw.primitive->value("material", -1);
    const auto found = std::find(gltf_materials.begin(), gltf_materials.end(), gltf_material);
    const auto material = static_cast<std::uint32_t>(found - gltf_materials.begin());
    if (found == gltf_materials.end()) gltf_materials.push_back(gltf_material);
    const auto index_count = static_cast<std::uint32_t>(3 * draw.triangles);
    if (!parts.empty() && parts.back().material == material) {
      parts.back().index_count += index_count;
    } else {
      parts.push_back({first_index, index_count, material});
    }
    first_index += index_count;
  }
  EXPECT_EQ(model.parts, parts);
  ASSERT_EQ(model.materials.size(), gltf_materials.size());

  for (std::size_t m = 0; m < gltf_materials.size(); ++m) {
    SCOPED_TRACE("material " + std::to_string(m));
    const Material& material = model.materials[m];
    const nlohmann::json source =
        gltf_materials[m] < 0 ? nlohmann::json::object() : document["materials"][gltf_materials[m]];
    EXPECT_EQ(material.name, source.value("name", ""));
    const nlohmann::json pbr = source.value("pbrMetallicRoughness", nlohmann::json::object());
    const auto factor = pbr.value("baseColorFactor", std::vector<double>{1, 1, 1, 1});
    for (int c = 0; c < 4; ++c) EXPECT_EQ(material.base_color_factor[c], static_cast<float>(factor[c]));
    if (!pbr.contains("baseColorTexture")) {
      EXPECT_FALSE(material.base_color_texture);
      continue;
    }
    ASSERT_TRUE(material.base_color_texture);
    const MaterialTexture& texture = *material.base_color_texture;
    const auto& info = pbr["baseColorTexture"];
    EXPECT_EQ(texture.uv_channel, info.value("texCoord", 0u));
    const auto& gltf_texture = document["textures"][info["index"].get<std::size_t>()];
    const auto& image = document["images"][gltf_texture["source"].get<std::size_t>()];
    const std::string uri = image.value("uri", "");
    if (uri.empty() || uri.starts_with("data:")) {
      EXPECT_TRUE(texture.embedded());
      EXPECT_EQ(as_string(texture.encoded), gltf_embedded_image(path, document, image));
      EXPECT_EQ(texture.format_hint, image["mimeType"] == "image/jpeg" ? "jpg" : "png");
    } else {
      EXPECT_EQ(texture.reference, uri);
      EXPECT_EQ(texture.file, (path.parent_path() / uri).string());
      EXPECT_TRUE(texture.encoded.empty());
    }
  }
}

TEST(LoadModel, GltfMaterialsAndPartsMatchTheFiles) {
  for (const char* file : kGltfWithMaterials) {
    SCOPED_TRACE(file);
    const fs::path path = kModels / file;
    expect_gltf_materials_and_parts(path, load(path));
  }
}

TEST(LoadModel, GltfBaseColourTexturesInFilesAndEmbedded) {
  // One box, one part, its texture (2433 bytes of PNG) beside the file, in the .glb's binary chunk
  // and in a data: URI.
  const fs::path directory = kModels / "glTF2/BoxTextured-glTF";
  const std::string png = read_text(directory / "CesiumLogoFlat.png");
  ASSERT_EQ(png.size(), 2433u);
  for (const char* file : {"BoxTextured-glTF/BoxTextured.gltf", "BoxTextured-glTF-Binary/BoxTextured.glb",
                           "BoxTextured-glTF-Embedded/BoxTextured.gltf"}) {
    SCOPED_TRACE(file);
    std::vector<std::string> warnings;
    const Model model = load_model((kModels / "glTF2" / file).string(), warnings);
    EXPECT_TRUE(warnings.empty());
    EXPECT_TRUE(model.material_warnings.empty());
    EXPECT_EQ(model.parts, (std::vector<ModelPart>{{0, 36, 0}}));
    ASSERT_EQ(model.materials.size(), 1u);
    const Material& material = model.materials[0];
    EXPECT_EQ(material.name, "Texture");
    EXPECT_EQ(material.base_color_factor, (std::array<float, 4>{1, 1, 1, 1}));
    ASSERT_TRUE(material.base_color_texture);
    const MaterialTexture& texture = *material.base_color_texture;
    EXPECT_EQ(texture.uv_channel, 0u);
    if (std::string_view(file).starts_with("BoxTextured-glTF/")) {
      EXPECT_FALSE(texture.embedded());
      EXPECT_EQ(texture.reference, "CesiumLogoFlat.png");
      EXPECT_EQ(texture.file, (directory / "CesiumLogoFlat.png").string());
    } else {
      EXPECT_TRUE(texture.embedded());
      EXPECT_EQ(texture.reference, "*0");
      EXPECT_EQ(as_string(texture.encoded), png);
      EXPECT_EQ(texture.format_hint, "png");
    }
  }
}

// Materials of an MTL file by name.
struct MtlMaterial {
  std::array<float, 4> diffuse{};
  std::string diffuse_map;  // the rest of the map_Kd line
};

std::map<std::string, MtlMaterial> mtl_materials(const fs::path& path) {
  std::map<std::string, MtlMaterial> materials;
  MtlMaterial* current = nullptr;
  std::istringstream lines(read_text(path));
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "newmtl") {
      std::string name;
      words >> name;
      current = &materials[name];
    } else if (keyword == "Kd") {
      words >> current->diffuse[0] >> current->diffuse[1] >> current->diffuse[2];
      current->diffuse[3] = 1;
    } else if (keyword == "map_Kd") {
      words >> std::ws;
      std::getline(words, current->diffuse_map);
    }
  }
  return materials;
}

TEST(LoadModel, ObjMaterialsPartsAndTexcoordsMatchTheFiles) {
  // spider.obj: 'usemtl' runs of faces; spider.mtl: Kd and map_Kd, with Windows paths (".\x.jpg").
  const fs::path path = kModels / "OBJ/spider.obj";
  struct Run {
    std::string material;
    std::size_t triangles;
  };
  std::vector<Run> runs;
  std::vector<glm::dvec3> file_positions;
  std::vector<glm::dvec2> file_texcoords;
  std::vector<std::string> first_face;
  std::istringstream lines(read_text(path));
  std::string material;
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "v") {
      glm::dvec3& p = file_positions.emplace_back();
      words >> p.x >> p.y >> p.z;
    }
    if (keyword == "vt") {
      glm::dvec2& uv = file_texcoords.emplace_back();
      words >> uv.x >> uv.y;
    }
    if (keyword == "usemtl") words >> material;
    if (keyword != "f") continue;
    std::vector<std::string> corners{std::istream_iterator<std::string>(words), {}};
    if (first_face.empty()) first_face = corners;
    if (runs.empty() || runs.back().material != material) runs.push_back({material, 0});
    runs.back().triangles += corners.size() - 2;
  }
  const std::map<std::string, MtlMaterial> mtl = mtl_materials(kModels / "OBJ/spider.mtl");

  std::vector<std::string> warnings;
  const Model model = load_model(path.string(), warnings);
  EXPECT_TRUE(warnings.empty());
  EXPECT_TRUE(model.material_warnings.empty());
  ASSERT_EQ(model.parts.size(), runs.size());
  std::uint32_t first_index = 0;
  for (std::size_t p = 0; p < runs.size(); ++p) {
    SCOPED_TRACE("part " + std::to_string(p) + ", " + runs[p].material);
    const ModelPart& part = model.parts[p];
    EXPECT_EQ(part.first_index, first_index);
    EXPECT_EQ(part.index_count, 3 * runs[p].triangles);
    first_index += part.index_count;
    ASSERT_LT(part.material, model.materials.size());
    const Material& loaded = model.materials[part.material];
    EXPECT_EQ(loaded.name, runs[p].material);
    const MtlMaterial& expected = mtl.at(runs[p].material);
    for (int c = 0; c < 4; ++c) EXPECT_FLOAT_EQ(loaded.base_color_factor[c], expected.diffuse[c]);
    ASSERT_TRUE(loaded.base_color_texture);
    const MaterialTexture& texture = *loaded.base_color_texture;
    EXPECT_EQ(texture.reference, expected.diffuse_map);
    std::string with_slashes = expected.diffuse_map;
    std::replace(with_slashes.begin(), with_slashes.end(), '\\', '/');
    EXPECT_EQ(texture.file, (kModels / "OBJ" / with_slashes).string());
    EXPECT_TRUE(fs::is_regular_file(texture.file));
  }
  EXPECT_EQ(first_index, model.indices.size());
  // Materials in the order of their first part; the file's unused ones (Brusttex, assimp's
  // DefaultMaterial) are left out.
  std::uint32_t next_new_material = 0;
  for (const ModelPart& part : model.parts) {
    EXPECT_LE(part.material, next_new_material);
    next_new_material += part.material == next_new_material;
  }
  EXPECT_EQ(next_new_material, model.materials.size());
  EXPECT_EQ(model.materials.size(), 4u);

  // The first face, "f 1/1/1 2/2/2 3/3/3": assimp gives each corner its own vertex, in order.
  ASSERT_EQ(model.texcoords.size(), 2 * model.vertex_count());
  ASSERT_EQ(first_face.size(), 3u);
  for (std::uint32_t k = 0; k < 3; ++k) {
    const std::size_t reference = std::stoul(first_face[k]) - 1;  // v/vt/vn, the same number thrice
    EXPECT_TRUE(near(position(model, k), file_positions[reference], 1e-5));
    EXPECT_TRUE(near(glm::dvec3(texcoord(model, k), 0), glm::dvec3(file_texcoords[reference], 0), 1e-6));
  }
}

TEST(LoadModel, ColladaDuckHasItsTextureBesideIt) {
  const fs::path path = kModels / "Collada/duck.dae";
  const Model model = load(path);
  EXPECT_EQ(model.texcoords.size(), 2 * model.vertex_count());
  EXPECT_EQ(model.parts, (std::vector<ModelPart>{{0, static_cast<std::uint32_t>(model.indices.size()), 0}}));
  ASSERT_EQ(model.materials.size(), 1u);
  // <diffuse><texture texture="file2-sampler"/></diffuse>, the sampler's image "./duckCM.tga".
  EXPECT_EQ(model.materials[0].base_color_factor, (std::array<float, 4>{1, 1, 1, 1}));
  ASSERT_TRUE(model.materials[0].base_color_texture);
  EXPECT_EQ(model.materials[0].base_color_texture->reference, "./duckCM.tga");
  EXPECT_TRUE(fs::is_regular_file(model.materials[0].base_color_texture->file));
}

TEST(LoadModel, TexturesEmbeddedAsRawTexelsAreLeftOutWithAWarning) {
  // Half-Life MDL skins: raw texels, which materials name by their file names.
  std::vector<std::string> warnings;
  const Model model = load_model((kModels / "MDL/MDL (HL1)/man.mdl").string(), warnings);
  EXPECT_TRUE(warnings.empty());  // those are about the geometry
  const std::vector<std::string>& material_warnings = model.material_warnings;
  ASSERT_EQ(model.materials.size(), 3u);  // man.mdl's three skins
  ASSERT_EQ(material_warnings.size(), model.materials.size());
  for (std::size_t m = 0; m < model.materials.size(); ++m) {
    const Material& material = model.materials[m];
    EXPECT_EQ(material.name, "");
    EXPECT_EQ(material.base_color_factor, (std::array<float, 4>{1, 1, 1, 1}));  // no colour in the file
    EXPECT_FALSE(material.base_color_texture);
    const std::string& warning = material_warnings[m];
    EXPECT_TRUE(warning.starts_with("material " + std::to_string(m) + ": its base colour texture '")) << warning;
    EXPECT_TRUE(warning.ends_with(".bmp' is embedded as raw texels, which are not loaded")) << warning;
  }
}

TEST(LoadModel, ModelsWithoutTexcoordsHaveNone) {
  const Model model = load(kModels / "OBJ/box.obj");
  EXPECT_TRUE(model.texcoords.empty());
  EXPECT_EQ(model.parts, (std::vector<ModelPart>{{0, 36, 0}}));
  ASSERT_EQ(model.materials.size(), 1u);
  EXPECT_EQ(model.materials[0].name, "Default");
  // No material file: assimp's default diffuse colour.
  EXPECT_EQ(model.materials[0].base_color_factor, (std::array<float, 4>{0.6f, 0.6f, 0.6f, 1}));
  EXPECT_FALSE(model.materials[0].base_color_texture);
}

// A quad of two triangles with texture coordinates and a third triangle without, in three
// 'usemtl' runs: "painted", "plain", "painted" again.
constexpr const char* kTexturedObj = R"(mtllib materials.mtl
v 0 0 0
v 1 0 0
v 0 1 0
v 1 1 0
vt 0.25 0.5
vt 1 0
vt 0 0.75
vt 1 1
usemtl painted
f 1/1 2/2 3/3
f 2/2 4/4 3/3
usemtl plain
f 1 2 4
usemtl painted
f 1/4 2/1 3/2
)";

TEST_F(CraftedModel, ObjMaterialFactorsTexturePathsAndTexcoords) {
  // Texture paths as the file gives them: none of these files exist, which is the renderer's to
  // report.
  write("materials.mtl", "newmtl painted\nKd 0.5 0.25 0.125\nmap_Kd textures\\wood.png\n"
                         "newmtl plain\nKd 0.1 0.2 0.3\nmap_Kd ../elsewhere/missing.png\n");
  std::vector<std::string> warnings;
  const Model model = load_model(write("model.obj", kTexturedObj).string(), warnings);
  EXPECT_TRUE(warnings.empty());
  EXPECT_TRUE(model.material_warnings.empty());
  ASSERT_EQ(model.triangle_count(), 4u);
  EXPECT_EQ(model.parts, (std::vector<ModelPart>{{0, 6, 0}, {6, 3, 1}, {9, 3, 0}}));

  ASSERT_EQ(model.materials.size(), 2u);
  const Material& painted = model.materials[0];
  EXPECT_EQ(painted.name, "painted");
  EXPECT_EQ(painted.base_color_factor, (std::array<float, 4>{0.5f, 0.25f, 0.125f, 1}));
  ASSERT_TRUE(painted.base_color_texture);
  EXPECT_EQ(painted.base_color_texture->reference, "textures\\wood.png");
  EXPECT_EQ(painted.base_color_texture->file, (directory_ / "textures/wood.png").string());
  EXPECT_FALSE(painted.base_color_texture->embedded());
  const Material& plain = model.materials[1];
  EXPECT_EQ(plain.name, "plain");
  EXPECT_EQ(plain.base_color_factor, (std::array<float, 4>{0.1f, 0.2f, 0.3f, 1}));
  ASSERT_TRUE(plain.base_color_texture);
  EXPECT_EQ(plain.base_color_texture->reference, "../elsewhere/missing.png");
  EXPECT_EQ(plain.base_color_texture->file, (directory_ / "../elsewhere/missing.png").string());

  // Each face corner its own vertex, in order; the triangle without texture coordinates gets (0, 0).
  const std::vector<float> expected = {0.25f, 0.5f, 1, 0, 0, 0.75f,  1, 0, 1, 1, 0, 0.75f,
                                       0, 0, 0, 0, 0, 0,             1, 1, 0.25f, 0.5f, 1, 0};
  EXPECT_EQ(model.texcoords, expected);
}

// Mesh 0: a triangle without normals (so flat normals, every corner its own vertex) with two
// texture coordinate sets; its material takes the base colour texture from the second. Mesh 1:
// the same triangle without texture coordinates, and without a material.
constexpr const char* kTwoSetsGltf = R"({
  "asset": {"version": "2.0"},
  "buffers": [{"uri": "data.bin", "byteLength": 66}],
  "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 36},
                  {"buffer": 0, "byteOffset": 36, "byteLength": 24},
                  {"buffer": 0, "byteOffset": 60, "byteLength": 6}],
  "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 1, 0]},
                {"bufferView": 1, "componentType": 5126, "count": 3, "type": "VEC2"},
                {"bufferView": 2, "componentType": 5123, "count": 3, "type": "SCALAR"}],
  "images": [{"uri": "../images/albedo.png"}],
  "textures": [{"source": 0}],
  "materials": [{"name": "second set",
                 "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.25, 1, 0.75],
                                          "baseColorTexture": {"index": 0, "texCoord": 1}}}],
  "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1, "TEXCOORD_1": 1},
                              "indices": 2, "material": 0}]},
             {"primitives": [{"attributes": {"POSITION": 0}}]}],
  "nodes": [{"mesh": 0}, {"mesh": 1}],
  "scenes": [{"nodes": [0, 1]}],
  "scene": 0
})";

TEST_F(CraftedModel, GltfTextureOfAnotherSetFlatNormalsAndNoMaterial) {
  write("data.bin", bytes_of<float>({0, 0, 0, 1, 0, 0, 0, 1, 0}) + bytes_of<float>({0.25f, 0.5f, 1, 0, 0, 0.75f}) +
                        bytes_of<std::uint16_t>({2, 0, 1}));
  const fs::path path = write("two_sets.gltf", kTwoSetsGltf);
  std::vector<std::string> warnings;
  const Model model = load_model(path.string(), warnings);
  EXPECT_TRUE(warnings.empty());
  EXPECT_EQ(model.material_warnings,
            std::vector<std::string>{"material 'second set': its base colour texture is mapped by texture "
                                     "coordinate set 1, which is not loaded (only set 0 is)"});
  // Corner by corner (indices 2, 0, 1), v turned up; then mesh 1's three vertices at (0, 0).
  EXPECT_EQ(model.texcoords, (std::vector<float>{0, 0.25f, 0.25f, 0.5f, 1, 1, 0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(model.texcoords, gltf_texcoords(path));
  EXPECT_EQ(model.parts, (std::vector<ModelPart>{{0, 3, 0}, {3, 3, 1}}));
  expect_gltf_materials_and_parts(path, model);

  ASSERT_EQ(model.materials.size(), 2u);
  EXPECT_EQ(model.materials[0].base_color_factor, (std::array<float, 4>{0.5f, 0.25f, 1, 0.75f}));
  const MaterialTexture& texture = model.materials[0].base_color_texture.value();
  EXPECT_EQ(texture.uv_channel, 1u);
  EXPECT_EQ(texture.file, (directory_ / "../images/albedo.png").string());
  // assimp's default material for primitives without one: no name, white, no texture.
  EXPECT_EQ(model.materials[1].name, "");
  EXPECT_EQ(model.materials[1].base_color_factor, (std::array<float, 4>{1, 1, 1, 1}));
  EXPECT_FALSE(model.materials[1].base_color_texture);
}

TEST_F(CraftedModel, TextureWithoutAnImageNameIsLeftOut) {
  write("data.bin", std::string(66, '\0'));
  std::string gltf = kTwoSetsGltf;
  gltf.replace(gltf.find("../images/albedo.png"), std::strlen("../images/albedo.png"), "");
  const Model model = load(write("no_name.gltf", gltf));
  EXPECT_FALSE(model.materials.at(0).base_color_texture);
  EXPECT_EQ(model.material_warnings,
            std::vector<std::string>{"material 'second set': its base colour texture names no image"});
}

TEST_F(CraftedModel, NonFiniteTexcoordsDropTheirTriangles) {
  write("data.bin", bytes_of<float>({0, 0, 0, 1, 0, 0, 0, 1, 0}) +
                        bytes_of<float>({0.25f, 0.5f, INFINITY, 0.5f, 0, 0.75f}) +
                        bytes_of<std::uint16_t>({0, 1, 2}));
  // Mesh 0's triangle has vertex 1's (inf, 0.5): only mesh 1's is left, and with it neither the
  // material nor the texture coordinates of mesh 0.
  const Model model = load(write("two_sets.gltf", kTwoSetsGltf));
  EXPECT_EQ(model.triangles_dropped, 1u);
  EXPECT_EQ(model.triangle_count(), 1u);
  EXPECT_TRUE(model.texcoords.empty());
  ASSERT_EQ(model.materials.size(), 1u);
  EXPECT_EQ(model.materials[0].name, "");
  EXPECT_EQ(model.parts, (std::vector<ModelPart>{{0, 3, 0}}));
  EXPECT_TRUE(model.material_warnings.empty());

  // assimp's OBJ reader itself reads non-finite texture coordinates as 0.
  const Model obj =
      load(write("nan.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt nan 0.5\nvt 0.5 inf\nvt 1 -inf\nf 1/1 2/2 3/3\n"));
  EXPECT_EQ(obj.texcoords, (std::vector<float>{0, 0.5f, 0.5f, 0, 1, 0}));
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
    // malformed2.obj only has an empty face, which assimp ignores.
    if (entry.path().filename() == "malformed2.obj") continue;
    SCOPED_TRACE(entry.path());
    load_error(entry.path());
  }
  // It claims 3.5e11 vertices, which assimp allocated before it failed, after 13 s: refused before.
  EXPECT_EQ(load_error(kModels / "invalid/OutOfMemory.off"),
            "cannot load model '" + (kModels / "invalid/OutOfMemory.off").string() +
                "': line 2 has '353535235358' where a count belongs");
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

// ---- Hostile files and the isolated loader --------------------------------------------------------

// Far more than each case takes (milliseconds, a few MiB), far less than what it took before it was
// checked (forever, gigabytes): a check that stopped working shows as another message.
const ModelLoadLimits kHostileLimits{std::size_t{256} << 20, std::chrono::seconds(10)};
constexpr auto kPromptly = std::chrono::seconds(5);

// The message load_model_isolated throws for `path`, after checking that it is InvalidArgument (or
// `Exception`, derived from it).
template <typename Exception = InvalidArgument>
std::string isolated_load_error(const fs::path& path, const ModelLoadLimits& limits) {
  std::vector<std::string> warnings;
  try {
    load_model_isolated(path.string(), warnings, limits);
  } catch (const Exception& error) {
    return error.what();
  } catch (const std::exception& error) {
    ADD_FAILURE() << path << " threw " << typeid(error).name() << ": " << error.what();
    return {};
  }
  ADD_FAILURE() << path << " loaded without an error";
  return {};
}

TEST_F(CraftedModel, HostileFilesAreRefusedBeforeAssimpReadsThem) {
  for (const test::HostileModel& hostile : test::hostile_models(directory_)) {
    SCOPED_TRACE(hostile.name);
    const fs::path path = test::write_hostile_model(hostile, directory_);
    const auto start = std::chrono::steady_clock::now();
    EXPECT_EQ(isolated_load_error(path, kHostileLimits), "cannot load model '" + path.string() + "': " + hostile.reason);
    EXPECT_LT(std::chrono::steady_clock::now() - start, kPromptly);
  }
  // The two whose size is part of the story.
  EXPECT_EQ(read_text(directory_ / "no_end_header.ply").size(), 20u);
  EXPECT_EQ(read_text(directory_ / "hundred_million_faces.ply").size(), 188u);
}

TEST_F(CraftedModel, WhatTheFuzzerFoundIsRefused) {
  // scripts/fuzz.sh's findings, reduced. In the checks before assimp: a binary format declared after
  // a property of a type whose size is unknown (read as null in check_declared_counts).
  const fs::path late_format = write("late_format.ply",
                                     "ply\nformat ascii 1.0\nelement vertex 3\nproperty foo x\n"
                                     "format binary_little_endian 1.0\nend_header\n");
  EXPECT_EQ(load_error(late_format),
            "cannot load model '" + late_format.string() + "': line 4 declares a property of unknown type 'foo'");
  // assimp corrupts its heap ("malloc(): corrupted top size") on a second vertex element.
  std::string second_vertices = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float y\nelement vertex 24\n"
                                "property float z\nend_header\n";
  for (int line = 0; line < 27; ++line) second_vertices += "0\n";
  const fs::path duplicate = write("second_vertices.ply", second_vertices);
  EXPECT_EQ(isolated_load_error(duplicate, kHostileLimits),
            "cannot load model '" + duplicate.string() + "': line 5 declares a second 'vertex' element");
}

TEST_F(CraftedModel, AParserCrashIsAnErrorNamingTheSignal) {
  // assimp crashes on both: the first is assimp's own test model with one character changed (found
  // by scripts/fuzz.sh); in the second, without an extension, assimp picks its OBJ reader by the
  // content, past the check of .obj files' material libraries, and meets a texture before any
  // material.
  std::string gltf = read_text(kModels / "glTF2/BoxTextured-glTF-Embedded/BoxTextured.gltf");
  const std::size_t mime = gltf.find("data:image/png;");
  ASSERT_NE(mime, std::string::npos);
  gltf[mime + 10] = ' ';  // "data:image png;"
  write("early.mtl", "map_Kd texture.png\nnewmtl m\n");
  const fs::path files[] = {
      write("mime_type.gltf", gltf),
      write("early_map", "mtllib early.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n"),
  };
  for (const fs::path& path : files) {
    SCOPED_TRACE(path);
    const std::string message = isolated_load_error(path, kHostileLimits);
    const std::string crashed = "cannot load model '" + path.string() + "': the model loader ";
    if (kBuiltWithAddressSanitizer) {
      EXPECT_TRUE(message.starts_with(crashed)) << message;  // AddressSanitizer's report, and its exit code
    } else {
      EXPECT_EQ(message, crashed + "crashed (SIGSEGV, Segmentation fault)");
    }
  }
}

TEST_F(CraftedModel, ALoadBeyondItsTimeIsKilled) {
  // A named pipe nobody writes: opening it blocks, as a parser that spins would.
  const fs::path path = directory_ / "pipe.obj";
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
  const auto start = std::chrono::steady_clock::now();
  const std::string message =
      isolated_load_error<ModelLoadLimitExceeded>(path, {std::nullopt, std::chrono::milliseconds(500)});
  const auto elapsed = std::chrono::steady_clock::now() - start;
  EXPECT_EQ(message, "cannot load model '" + path.string() + "': the model loader ran longer than its time limit of 0.5 s");
  EXPECT_GE(elapsed, std::chrono::milliseconds(500));
  EXPECT_LT(elapsed, kPromptly);
}

// A binary PLY grid of side x side vertices, two triangles per cell.
std::string ply_grid(std::uint32_t side) {
  std::string vertices, faces;
  for (std::uint32_t y = 0; y < side; ++y) {
    for (std::uint32_t x = 0; x < side; ++x) vertices += bytes_of<float>({float(x), float(y), float((x * y) % 7)});
  }
  for (std::uint32_t y = 0; y + 1 < side; ++y) {
    for (std::uint32_t x = 0; x + 1 < side; ++x) {
      const std::uint32_t a = y * side + x;
      faces += std::string(1, '\3') + bytes_of<std::uint32_t>({a, a + 1, a + side});
      faces += std::string(1, '\3') + bytes_of<std::uint32_t>({a + 1, a + side + 1, a + side});
    }
  }
  return "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(side * side) +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " +
         std::to_string(2 * (side - 1) * (side - 1)) + "\nproperty list uchar uint vertex_indices\nend_header\n" +
         vertices + faces;
}

TEST_F(CraftedModel, ALoadBeyondItsMemoryIsRefused) {
  if (kBuiltWithAddressSanitizer) GTEST_SKIP() << "no memory limit under AddressSanitizer";
  // 13 MB, which takes over 100 MiB to load: within the default limit, not within 16 MiB and the
  // few tens of MiB that this test process holds free (which the child can reuse).
  const fs::path grid = write("grid.ply", ply_grid(600));
  std::vector<std::string> warnings;
  EXPECT_EQ(load_model_isolated(grid.string(), warnings).triangle_count(), 2u * 599 * 599);
  EXPECT_EQ(isolated_load_error<ModelLoadLimitExceeded>(grid, {std::size_t{16} << 20, std::nullopt}),
            "cannot load model '" + grid.string() + "': the model loader needed more than its memory limit of 16 MiB");

  // 255 KB of one mesh instanced 10000 times, 20 million triangles once each instance has its own:
  // beyond the default limit for such a file, refused within seconds.
  const fs::path instances = write("instances.glb", test::instancing_glb());
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(isolated_load_error<ModelLoadLimitExceeded>(instances, {}),
            "cannot load model '" + instances.string() + "': the model loader needed more than its memory limit of " +
                std::to_string(kLoadMemoryFloor >> 20) + " MiB");
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
  // A smaller one loads, and with its instances.
  const fs::path few = write("few_instances.glb", test::instancing_glb(20, 30));
  EXPECT_EQ(load_model_isolated(few.string(), warnings).triangle_count(), 20u * 30);
}

TEST(IsolatedLoad, DefaultLimitsGrowWithTheFile) {
  const ResolvedLoadLimits small = resolve_load_limits({}, 1000);
  EXPECT_EQ(small.memory_bytes, kLoadMemoryFloor);
  EXPECT_EQ(small.time, kLoadTimeFloor);
  const ResolvedLoadLimits large = resolve_load_limits({}, std::uintmax_t{100} << 20);
  EXPECT_EQ(large.memory_bytes, kLoadMemoryPerFileByte * (std::size_t{100} << 20));
  EXPECT_EQ(large.time, std::max<std::chrono::milliseconds>(kLoadTimeFloor, 100 * kLoadTimePerMiB));
  const ResolvedLoadLimits given = resolve_load_limits({std::size_t{5} << 20, std::chrono::seconds(3)}, 1000);
  EXPECT_EQ(given.memory_bytes, std::size_t{5} << 20);
  EXPECT_EQ(given.time, std::chrono::seconds(3));
}

void expect_same_texture(const std::optional<MaterialTexture>& a, const std::optional<MaterialTexture>& b) {
  ASSERT_EQ(a.has_value(), b.has_value());
  if (!a) return;
  EXPECT_EQ(a->reference, b->reference);
  EXPECT_EQ(a->file, b->file);
  EXPECT_EQ(a->encoded, b->encoded);
  EXPECT_EQ(a->format_hint, b->format_hint);
  EXPECT_EQ(a->uv_channel, b->uv_channel);
}

TEST_F(CraftedModel, IsolatedLoadsPassBackWhatLoadModelGives) {
  const fs::path files[] = {
      kModels / "glTF2/BoxTextured-glTF-Binary/BoxTextured.glb",  // an embedded texture
      kModels / "OBJ/spider.obj",                                  // textures in files, several materials
      kModels / "OBJ/testmixed.obj",                               // warnings: points and lines skipped
      kModels / "MDL/MDL (HL1)/man.mdl",                           // material warnings
      write("scan.ply", kScanPly),                                 // triangles dropped
  };
  for (const fs::path& file : files) {
    SCOPED_TRACE(file);
    std::vector<std::string> warnings, isolated_warnings;
    const Model model = load_model(file.string(), warnings);
    const Model isolated = load_model_isolated(file.string(), isolated_warnings);
    EXPECT_EQ(isolated_warnings, warnings);
    EXPECT_EQ(isolated.positions, model.positions);
    EXPECT_EQ(isolated.normals, model.normals);
    EXPECT_EQ(isolated.texcoords, model.texcoords);
    EXPECT_EQ(isolated.indices, model.indices);
    EXPECT_EQ(isolated.parts, model.parts);
    EXPECT_EQ(isolated.material_warnings, model.material_warnings);
    EXPECT_EQ(isolated.triangles_dropped, model.triangles_dropped);
    ASSERT_EQ(isolated.materials.size(), model.materials.size());
    for (std::size_t m = 0; m < model.materials.size(); ++m) {
      EXPECT_EQ(isolated.materials[m].name, model.materials[m].name);
      EXPECT_EQ(isolated.materials[m].base_color_factor, model.materials[m].base_color_factor);
      expect_same_texture(isolated.materials[m].base_color_texture, model.materials[m].base_color_texture);
    }
  }
  EXPECT_FALSE(load(files[0]).materials.at(0).base_color_texture->encoded.empty());
}

TEST_F(CraftedModel, IsolatedLoadsThrowWhatLoadModelThrows) {
  const fs::path files[] = {directory_ / "missing.obj", kModels / "glTF2/IndexOutOfRange/IndexOutOfRange.gltf",
                            write("past_end.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99\n")};
  for (const fs::path& file : files) {
    SCOPED_TRACE(file);
    EXPECT_EQ(isolated_load_error(file, {}), load_error(file));
  }
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
