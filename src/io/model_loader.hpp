// Model files (through assimp) into one triangle list, with the materials its parts are drawn with.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "io/mesh.hpp"

namespace clraster::io {

// The image a material's base colour texture comes from, as the model file names it. Nothing has
// been opened or decoded: a file that is missing or unreadable is for the renderer to report.
struct MaterialTexture {
  // As the file names it: a path, or assimp's "*N" for the file's embedded image N.
  std::string reference;
  // An image in a file of its own: `reference` resolved against the model file's directory, with
  // backslashes read as directory separators (Windows tools write them into OBJ material files).
  // Empty when the image is embedded.
  std::string file;
  // An embedded image (a .glb buffer view or a data: URI): the bytes of its image file, and
  // assimp's hint of their format ("png", "jpg"; can be empty).
  std::vector<std::byte> encoded;
  std::string format_hint;
  // The texture coordinate set that maps the image. Only set 0 is loaded (Mesh::texcoords); a
  // texture mapped by another comes with a line in Model::material_warnings.
  unsigned uv_channel = 0;

  bool embedded() const { return file.empty(); }
};

struct Material {
  std::string name;  // as in the file; can be empty
  // Linear RGBA: glTF's baseColorFactor, or else the diffuse colour (OBJ's Kd), or else white.
  std::array<float, 4> base_color_factor{1, 1, 1, 1};
  // glTF's baseColorTexture, or else the diffuse texture (OBJ's map_Kd).
  std::optional<MaterialTexture> base_color_texture;
};

// How warnings name model material `index`: "material 'Body'", or "material 3" when it has no name.
std::string material_label(const Material& material, std::size_t index);

// Consecutive triangles drawn with one material: indices [first_index, first_index + index_count)
// of the model, as DrawCall::first and DrawCall::count.
struct ModelPart {
  std::uint32_t first_index = 0;
  std::uint32_t index_count = 0;
  std::uint32_t material = 0;  // into Model::materials

  bool operator==(const ModelPart&) const = default;
};

// A loaded model: its triangles as one Mesh, cut into parts by material.
struct Model : Mesh {
  std::vector<Material> materials;  // the materials the parts use, in the order of their first part
  std::vector<ModelPart> parts;     // in index order, together covering every triangle once
  // What of the materials is not drawn as the file means it, one line each, such as "material
  // 'Body': its base colour texture is mapped by texture coordinate set 1, which is not loaded
  // (only set 0 is)": for renderers that draw with the materials to pass on.
  std::vector<std::string> material_warnings;
  // Triangles of the file left out for a NaN or infinite value at a corner (load_model), for front
  // ends to report (describe_triangles_dropped) and to count with what the pipeline drops.
  std::uint64_t triangles_dropped = 0;
};

// "3 triangles dropped: a corner's position, normal or texture coordinate is NaN or infinite": what
// Model::triangles_dropped counts, for warnings.
std::string describe_triangles_dropped(std::uint64_t count);

// Sets every vertex normal of `meshes` to the normalized sum of the area-weighted normals of the
// triangles, across all of them, that have a corner at the vertex's position (what load_model
// gives files without normals, but glTF's).
void smooth_normals(std::span<Mesh* const> meshes);

// "cannot load model 'PATH': REASON": how the errors of a model load read.
std::string describe_load_error(const std::string& path, const std::string& reason);

// Loads the triangles of a model file in any format assimp reads (OBJ, glTF 2.0 .gltf/.glb, PLY,
// STL, OFF, ...) into one triangle list in the file's object space:
// - each mesh appears once per node that instances it, moved by the node's accumulated transform;
//   normals by its inverse transpose, renormalized; a mirroring transform also reverses the
//   winding, so that front faces stay counter-clockwise;
// - point and line primitives are skipped, each kind with a line in `warnings` such as
//   "skipped 12 line primitives";
// - normals come from the file when it has them (a mesh whose normals are all zero, as some STL
//   writers leave them, has none); otherwise glTF files get flat normals, as the glTF 2.0
//   specification says (every triangle its own three vertices, with the face normal); otherwise
//   every vertex gets the normalized sum of the normals cross(v1 - v0, v2 - v0), unnormalized so
//   that they are weighted by area, of the faces around it. Vertices at bit-identical positions
//   count as one, so faces that meet are smoothed together even when the file gives each face its
//   own vertices. A zero sum stays a zero normal;
// - texture coordinates are the file's first set (assimp's channel 0); a mesh instance without
//   them gets (0, 0) when others have them, and a model without any has none;
// - each mesh instance is drawn with its mesh's material; instances that follow each other with the
//   same material make one part;
// - a triangle with a NaN or infinite position, normal or texture coordinate at a corner, in the
//   file or (a position) after its node's transform, is left out and counted in
//   Model::triangles_dropped: scans carry such vertices and OpenGL draws the rest, but a non-finite
//   normal or texture coordinate would colour the triangle with undefined values. The vertices
//   that only such triangles use are left out with them, so that bounding spheres and smoothed
//   normals see only what is drawn; vertices no triangle uses stay as they are;
// - texture files are neither opened nor checked. A base colour texture that names no image, or
//   that the file embeds as raw texels rather than as an image file (Quake and Half-Life MDL), is
//   left out, and one mapped by a texture coordinate set other than the first is kept, each with a
//   line in Model::material_warnings.
// Throws clraster::InvalidArgument with one line naming the file when the file is missing or
// unreadable, assimp cannot parse it, it has no triangles (also when every one was left out for a
// NaN or infinite value: there is nothing to draw or to frame), faces reference vertices,
// normals or texture coordinates that do not exist (also when assimp would repair that by dropping
// the faces, normals or texture coordinates, or by clamping or wrapping the indices), or a PLY file
// has what assimp reads wrongly: triangle strips or floating-point vertex indices; and, before assimp
// reads the file, when it has what assimp would crash on, spin on or allocate without bound for (a
// PLY header without end_header or declaring more than the file holds, a PLY face without vertex
// indices, a GLB chunk longer than the file, an OBJ material library with a texture before its
// first newmtl). For files from untrusted sources, load_model_isolated (isolated_loader.hpp) also
// survives what nobody foresaw.
// Loads from several threads take turns: assimp's logger, which this watches, is process-wide.
Model load_model(const std::string& path, std::vector<std::string>& warnings);

}  // namespace clraster::io
