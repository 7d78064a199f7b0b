// A triangle mesh as the Python package holds it: arrays of its own (Python reads them as
// read-only numpy arrays), the triangles that are drawn, and an identity for the upload caches.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "io/model_loader.hpp"

namespace clraster::python {

struct MeshData {
  // Normals always present (computed when not given); texcoords may be empty. A mesh from arrays
  // is one part with a white material, over the drawn triangles.
  io::Model model;
  // The triangles drawn: those without a NaN or infinite position, normal or texture coordinate
  // at a corner, as the command line draws a model. Empty: every triangle of `mesh`.
  std::vector<std::uint32_t> drawn_indices;
  std::vector<std::int32_t> drawn_triangles;  // the mesh triangle of each drawn one, with drawn_indices
  std::uint64_t triangles_dropped = 0;
  std::uint64_t id = 0;  // unique in the process: what a context's upload cache knows the mesh by

  std::span<const std::uint32_t> indices_drawn() const {
    return drawn_indices.empty() && triangles_dropped == 0 ? std::span<const std::uint32_t>(model.indices)
                                                           : std::span<const std::uint32_t>(drawn_indices);
  }
};

// Throws InvalidArgument naming the first triangle with an index of `vertex_count` or more.
void check_indices(std::span<const std::uint32_t> indices, std::size_t vertex_count);

// A mesh from arrays of `vertex_count` vertices: positions and normals 3 floats each, uvs 2,
// indices 3 per triangle. Throws InvalidArgument for an index out of range or arrays whose sizes
// disagree. Without normals, every vertex gets the area-weighted normal of the faces around its
// position, as load_model gives files without normals.
std::shared_ptr<const MeshData> make_mesh(std::vector<float> positions, std::vector<std::uint32_t> indices,
                                          std::optional<std::vector<float>> normals,
                                          std::optional<std::vector<float>> uvs);

// A model file, as the command line loads it; its warnings (skipped primitives, triangles dropped)
// are appended to `warnings`. Those of its materials come when they are drawn, as the command line
// prints them with --shading material only.
std::shared_ptr<const MeshData> load_mesh(const std::string& path, std::vector<std::string>& warnings);

}  // namespace clraster::python
