// What a clraster.Context does: a clraster::Context with the meshes it has uploaded, and batches of
// views drawn into layered framebuffers, a chunk of layers per submission.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "clraster/clraster.hpp"
#include "frontend/model_draws.hpp"
#include "io/shading.hpp"
#include "mesh.hpp"

namespace clraster::python {

// Pictures of `count` views, each `width` x `height`: the caller's arrays, rows from the top.
struct Pictures {
  int width = 0;
  int height = 0;
  std::size_t count = 0;
};

// What a clraster.Program binds of its own, beyond the contract's names that the renderer binds
// (frontend/program_contract.hpp): each uniform's bytes, one value for every view or one per view
// one after the other, and textures.
struct OwnValues {
  struct Uniform {
    std::string name;
    std::vector<std::byte> bytes;
    bool per_view = false;
  };
  std::vector<Uniform> uniforms;
  std::vector<std::pair<std::string, std::shared_ptr<const Texture>>> textures;
};

// Where a visibility buffer goes: per picture and pixel (rows from the top) a triangle, two
// barycentrics and a depth.
struct VisibilityOutputs {
  std::int32_t* triangles;
  float* barycentrics;
  float* depths;
};

// Called after each chunk of a batch with the pictures done and the batch's count.
using Progress = std::function<void(std::size_t done, std::size_t total)>;

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
                       std::uint8_t* rgba, const Progress& progress);

  // The same, drawn part by part with `program` (the material program, or a clraster.Program
  // checked against the contract) and the parts' materials, and `own`'s values. The first draw of
  // a mesh with a program appends its materials' warnings to `warnings`.
  std::uint64_t render(const std::shared_ptr<const MeshData>& mesh, std::span<const Mat4> views, const Mat4& projection,
                       const std::shared_ptr<const Program>& program, const OwnValues& own, const Pictures& pictures,
                       std::uint8_t* rgba, const Progress& progress, std::vector<std::string>& warnings);

  // A program of the user's: checked against the contract (frontend::kPythonPackage) before it is
  // compiled, as the command line checks --program files.
  std::shared_ptr<const Program> compile(const std::string& source, const std::string& file_name);
  std::shared_ptr<const Program> material_program();

  // A texture of `texels` (rows from the top, tightly packed), with mipmaps, rows turned so that
  // the top row is at t = 1, as the materials' images are.
  std::shared_ptr<const Texture> texture(int width, int height, Format format, std::span<const std::byte> texels);

  // The visibility buffer of `mesh` for each view: per pixel the mesh triangle drawn there (-1 for
  // none), its perspective-correct barycentrics (2 floats) and its window depth (1 where empty).
  std::uint64_t rasterize(const std::shared_ptr<const MeshData>& mesh, std::span<const Mat4> views,
                          const Mat4& projection, const Pictures& pictures, const VisibilityOutputs& out,
                          const Progress& progress);
  // The same of triangles `indices` (three per triangle, each below vertex_count) given in clip
  // space: pictures.count views of vertex_count positions (x, y, z, w) each.
  std::uint64_t rasterize(std::span<const float> clip_positions, std::size_t vertex_count,
                          std::span<const std::uint32_t> indices, const Pictures& pictures,
                          const VisibilityOutputs& out, const Progress& progress);

 private:
  struct MeshBuffers;
  struct VisibilityTarget;
  struct ModelDraws;
  // What one view of a visibility buffer draws: clip positions = mvp * positions (float4 each).
  struct VisibilityView {
    const Buffer* positions;
    Mat4 mvp;
  };
  // Draws `count` visibility buffers in chunks of layers; `chunk_views(first, layers)` gives the
  // views of a chunk (what they point to must last until the next call).
  std::uint64_t draw_visibility(std::size_t count, const IndexBuffer& indices, const Buffer& corners,
                                const Pictures& pictures, const VisibilityOutputs& out, const Progress& progress,
                                const std::function<std::vector<VisibilityView>(std::size_t first, int layers)>& chunk_views);
  // Draws `count` pictures in chunks of layers of the picture target: `draw_chunk(framebuffer,
  // first, layers)` draws views first .. first + layers - 1 into the cleared framebuffer.
  std::uint64_t draw_pictures(std::size_t count, const Pictures& pictures, std::uint8_t* rgba,
                              const Progress& progress,
                              const std::function<DrawStats(Framebuffer&, std::size_t, int)>& draw_chunk);
  ModelDraws& model_draws(const std::shared_ptr<const MeshData>& mesh, const std::shared_ptr<const Program>& program,
                          std::vector<std::string>& warnings);
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
  std::shared_ptr<const Program> material_program_;
  std::vector<std::unique_ptr<ModelDraws>> model_draws_;  // per mesh and program drawn, while both live
};

}  // namespace clraster::python
