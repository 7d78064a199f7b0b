#include "mesh.hpp"

#include <atomic>
#include <cmath>

#include "clraster/clraster.hpp"

namespace clraster::python {
namespace {

std::uint64_t next_id() {
  static std::atomic<std::uint64_t> counter{0};
  return ++counter;
}

bool finite_at(const std::vector<float>& values, std::size_t components, std::uint32_t vertex) {
  for (std::size_t k = 0; k < components; ++k) {
    if (!std::isfinite(values[components * vertex + k])) return false;
  }
  return true;
}

}  // namespace

void check_indices(std::span<const std::uint32_t> indices, std::size_t vertex_count) {
  for (std::size_t i = 0; i < indices.size(); ++i) {
    if (indices[i] >= vertex_count) {
      throw InvalidArgument("indices: triangle " + std::to_string(i / 3) + " has index " + std::to_string(indices[i]) +
                            ", out of range for " + std::to_string(vertex_count) + " vertices");
    }
  }
}

std::shared_ptr<const MeshData> make_mesh(std::vector<float> positions, std::vector<std::uint32_t> indices,
                                          std::optional<std::vector<float>> normals,
                                          std::optional<std::vector<float>> uvs) {
  if (positions.size() % 3 != 0 || indices.size() % 3 != 0) {
    throw InvalidArgument("a mesh takes three floats per position and three indices per triangle");
  }
  const std::size_t vertex_count = positions.size() / 3;
  if (normals && normals->size() != positions.size()) {
    throw InvalidArgument("normals: " + std::to_string(normals->size() / 3) + " given for " +
                          std::to_string(vertex_count) + " vertices");
  }
  if (uvs && uvs->size() != 2 * vertex_count) {
    throw InvalidArgument("uvs: " + std::to_string(uvs->size() / 2) + " given for " + std::to_string(vertex_count) +
                          " vertices");
  }
  check_indices(indices, vertex_count);

  auto data = std::make_shared<MeshData>();
  io::Model& model = data->model;
  model.positions = std::move(positions);
  model.indices = std::move(indices);
  if (uvs) model.texcoords = std::move(*uvs);
  data->id = next_id();

  const auto finite_vertex = [&](std::uint32_t v) {
    return finite_at(model.positions, 3, v) && (!normals || finite_at(*normals, 3, v)) &&
           (model.texcoords.empty() || finite_at(model.texcoords, 2, v));
  };
  for (std::size_t t = 0; t < model.triangle_count(); ++t) {
    const std::uint32_t* corners = &model.indices[3 * t];
    if (finite_vertex(corners[0]) && finite_vertex(corners[1]) && finite_vertex(corners[2])) {
      data->drawn_indices.insert(data->drawn_indices.end(), corners, corners + 3);
      data->drawn_triangles.push_back(static_cast<std::int32_t>(t));
    } else {
      ++data->triangles_dropped;
    }
  }
  // As the command line refuses a model left without triangles: there is nothing to draw.
  if (data->drawn_triangles.empty()) {
    throw InvalidArgument(data->triangles_dropped == 0
                              ? std::string("a mesh needs at least one triangle")
                              : "no triangles left: " + io::describe_triangles_dropped(data->triangles_dropped));
  }
  if (data->triangles_dropped == 0) {  // drawn as given: no copy of the indices, no renumbering
    data->drawn_indices.clear();
    data->drawn_triangles.clear();
  }

  model.materials.emplace_back();  // white
  model.parts.push_back({0, static_cast<std::uint32_t>(data->indices_drawn().size()), 0});

  if (normals) {
    model.normals = std::move(*normals);
  } else {
    // Smoothed over the drawn triangles only, as the loader smooths what it keeps.
    io::Mesh drawn;
    drawn.positions = model.positions;
    drawn.indices.assign(data->indices_drawn().begin(), data->indices_drawn().end());
    drawn.normals.resize(drawn.positions.size());
    io::Mesh* meshes[] = {&drawn};
    io::smooth_normals(meshes);
    model.normals = std::move(drawn.normals);
  }
  return data;
}

std::shared_ptr<const MeshData> load_mesh(const std::string& path, std::vector<std::string>& warnings) {
  io::Model model = io::load_model(path, warnings);
  if (model.triangles_dropped > 0) warnings.push_back(path + ": " + io::describe_triangles_dropped(model.triangles_dropped));
  auto data = std::make_shared<MeshData>();
  data->model = std::move(model);
  data->id = next_id();
  return data;
}

}  // namespace clraster::python
