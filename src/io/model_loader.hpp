// Model files (through assimp) into one triangle list.
#pragma once

#include <string>
#include <vector>

#include "io/mesh.hpp"

namespace clraster::io {

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
// - non-finite coordinates are kept as they are (the pipeline drops such triangles).
// Throws clraster::InvalidArgument with one line naming the file when the file is missing or
// unreadable, assimp cannot parse it, it has no triangles, faces reference vertices, normals or
// texture coordinates that do not exist (also when assimp would repair that by dropping the faces,
// normals or texture coordinates, or by clamping or wrapping the indices), or a PLY file has what
// assimp reads wrongly: triangle strips or floating-point vertex indices.
// Loads from several threads take turns: assimp's logger, which this watches, is process-wide.
Mesh load_model(const std::string& path, std::vector<std::string>& warnings);

}  // namespace clraster::io
