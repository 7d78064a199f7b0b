// What a clraster.Context does: a clraster::Context with the meshes it has uploaded, and batches of
// views drawn into layered framebuffers, a chunk of layers per submission.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>

#include "clraster/clraster.hpp"
#include "io/shading.hpp"
#include "mesh.hpp"

namespace clraster::python {

// Pictures of `count` views, each `width` x `height`: the caller's arrays, rows from the top.
struct Pictures {
  int width = 0;
  int height = 0;
  std::size_t count = 0;
};

class Renderer {
 public:
  Renderer(int device, std::size_t memory_cap);
  ~Renderer();
  const DeviceInfo& device() const { return context_.device(); }

  // Draws `mesh` once per view (model-view matrices, column-major) with the command line's
  // shading into `rgba` (count * height * width * 4 bytes). Returns the triangles the pipeline
  // dropped for a NaN or infinite clip coordinate, over all views. Thread-safe (one at a time).
  std::uint64_t render(const std::shared_ptr<const MeshData>& mesh, std::span<const Mat4> views, const Mat4& projection,
                       io::BuiltinShading shading, std::array<float, 2> depth_range, const Pictures& pictures,
                       std::uint8_t* rgba);

  // The visibility buffer of `mesh` for each view: per pixel the mesh triangle drawn there (-1 for
  // none), its perspective-correct barycentrics (2 floats) and its window depth (1 where empty).
  std::uint64_t rasterize(const std::shared_ptr<const MeshData>& mesh, std::span<const Mat4> views,
                          const Mat4& projection, const Pictures& pictures, std::int32_t* triangles,
                          float* barycentrics, float* depths);

 private:
  struct MeshBuffers;
  struct VisibilityTarget;
  MeshBuffers& buffers(const std::shared_ptr<const MeshData>& mesh);
  Framebuffer& picture_target(int width, int height, int layers);
  VisibilityTarget& visibility_target(int width, int height, int layers);
  const Program& visibility_program();

  std::mutex mutex_;
  Context context_;
  std::map<std::uint64_t, std::unique_ptr<MeshBuffers>> uploads_;  // by MeshData::id
  std::optional<Framebuffer> picture_target_;                      // the last batch's, reused
  std::unique_ptr<VisibilityTarget> visibility_target_;
  std::optional<Program> visibility_program_;
};

}  // namespace clraster::python
