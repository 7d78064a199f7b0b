// Model files that crashed, hung or exhausted the process before they were checked (issue 38), made
// by the tests as small files, each with the reason the model loader gives for refusing it. Shared by
// the loader's tests and the command line's.
#pragma once

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>
#include <vector>

namespace clraster::test {

struct HostileModel {
  const char* name;  // for test names
  const char* file_name;
  std::string contents;
  // After "cannot load model 'PATH': ".
  std::string reason;
  // A file the model names (a material library), written beside it; none when file_name is null.
  struct Companion {
    const char* file_name = nullptr;
    std::string contents;
  } companion;
};

template <typename T>
std::string binary_values(std::initializer_list<T> values) {
  std::string bytes(values.size() * sizeof(T), '\0');
  std::memcpy(bytes.data(), std::data(values), bytes.size());
  return bytes;
}

// `directory`: where the files are written (material libraries are named by their path in messages).
inline std::vector<HostileModel> hostile_models(const std::filesystem::path& directory) {
  const std::string vertices =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n";
  const auto ascii_faces = [&](int count) {
    return vertices + "element face " + std::to_string(count) +
           "\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n";
  };
  const auto binary_faces = [](std::uint32_t count) {
    return "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
           "property float z\nelement face " +
           std::to_string(count) + "\nproperty list uchar int vertex_indices\nend_header\n" +
           binary_values<float>({0, 0, 0, 1, 0, 0, 0, 1, 0});
  };
  const std::string triangle = std::string(1, '\3') + binary_values<std::int32_t>({0, 1, 2});
  const std::string json = R"({"asset":{"version":"2.0"}})";  // 27 bytes
  const std::string glb = "glTF" + binary_values<std::uint32_t>({2, static_cast<std::uint32_t>(20 + json.size())}) +
                          binary_values<std::uint32_t>({0xFFFFFFFE}) + "JSON" + json;
  const std::string library = (directory / "early_map.mtl").string();
  return {
      // assimp: SIGABRT, an assertion in its triangulation.
      {"PlyFaceWithoutIndices", "zero_face.ply", ascii_faces(1) + "0\n", "line 13 is a face without vertex indices"},
      // assimp: SIGBUS, a wild write in SortByPType.
      {"PlyFacesOf1And4And0Indices", "mixed_faces.ply", ascii_faces(4) + "1 0\n4 0 1 2 0\n0\n3 0 1 2\n",
       "line 15 is a face without vertex indices"},
      {"BinaryPlyFaceWithoutIndices", "zero_face_binary.ply", binary_faces(2) + triangle + std::string(1, '\0'),
       "face 1 has no vertex indices"},
      // assimp: loops forever. 20 bytes.
      {"PlyHeaderWithoutEndHeader", "no_end_header.ply", "ply\nformat ascii 1.0",
       "its PLY header has no end_header line"},
      // assimp: grows past 4.6 GB. 188 bytes.
      {"PlyDeclaring100MillionFaces", "hundred_million_faces.ply", ascii_faces(100000000) + "3 0 1 2\n",
       "line 7 declares 100000000 'face' elements, more than the 26 bytes after the header hold"},
      {"BinaryPlyDeclaring100MillionFaces", "hundred_million_faces_binary.ply", binary_faces(100000000) + triangle,
       "line 7 declares 100000000 'face' elements, more than the 49 bytes after the header hold"},
      // assimp: allocates 4.2 GB, then finds no reader.
      {"GlbWithAJsonChunkOf4GB", "huge_json_chunk.glb", glb,
       "GLB chunk 0 (JSON) declares 4294967294 bytes, but the file has 27 for it"},
      // assimp: allocates for them (its own test file OutOfMemory.off, 3.5e11 vertices: 13 s).
      {"OffDeclaring100MillionVertices", "hundred_million_vertices.off", "OFF\n100000000 1 0\n0 0 0\n3 0 0 0\n",
       "line 2 declares 100000000 vertices and 1 faces, more than the 14 bytes after it hold"},
      // assimp: SIGSEGV.
      {"MtlTextureBeforeNewmtl", "early_map.obj", "mtllib early_map.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl m\nf 1 2 3\n",
       "material library '" + library + "' line 2 has 'map_Kd' before any 'newmtl': it belongs to no material",
       {"early_map.mtl", "# textured\nmap_Kd texture.png\nnewmtl m\nKd 1 0 0\n"}},
  };
}

// A GLB file that instances one mesh of `triangles` triangles from `instances` nodes: a few hundred
// KB that the loader, which gives each instance its own triangles, makes into gigabytes (with the
// defaults, 2000 triangles 10000 times: 255 KB, 20 million triangles).
inline std::string instancing_glb(std::uint32_t triangles = 2000, std::uint32_t instances = 10000) {
  std::string positions;
  for (std::uint32_t t = 0; t < triangles; ++t) {
    const float x = static_cast<float>(t);
    positions += binary_values<float>({x, 0, 0, x + 1, 0, 0, x, 1, 0});
  }
  std::string children, nodes;
  for (std::uint32_t n = 1; n <= instances; ++n) {
    children += (n == 1 ? "" : ",") + std::to_string(n);
    nodes += R"(,{"mesh":0})";
  }
  std::string json = R"({"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"children":[)" +
                     children + "]}" + nodes +
                     R"(],"meshes":[{"primitives":[{"attributes":{"POSITION":0}}]}],"accessors":[{"bufferView":0,)"
                     R"("componentType":5126,"count":)" +
                     std::to_string(3 * triangles) + R"(,"type":"VEC3","min":[0,0,0],"max":[)" +
                     std::to_string(triangles + 1) + R"(,1,0]}],"bufferViews":[{"buffer":0,"byteLength":)" +
                     std::to_string(positions.size()) + R"(}],"buffers":[{"byteLength":)" +
                     std::to_string(positions.size()) + "}]}";
  json.resize((json.size() + 3) / 4 * 4, ' ');  // chunks are 4-byte aligned
  const auto length = [](const std::string& chunk) { return static_cast<std::uint32_t>(chunk.size()); };
  return "glTF" + binary_values<std::uint32_t>({2, 12 + 8 + length(json) + 8 + length(positions)}) +
         binary_values<std::uint32_t>({length(json)}) + "JSON" + json + binary_values<std::uint32_t>({length(positions)}) +
         std::string("BIN\0", 4) + positions;
}

// Writes `model` (and its companion) into `directory`; returns the model's path.
inline std::filesystem::path write_hostile_model(const HostileModel& model, const std::filesystem::path& directory) {
  if (model.companion.file_name != nullptr) {
    std::ofstream(directory / model.companion.file_name, std::ios::binary) << model.companion.contents;
  }
  const std::filesystem::path path = directory / model.file_name;
  std::ofstream(path, std::ios::binary) << model.contents;
  return path;
}

}  // namespace clraster::test
