// A model drawn part by part with a program that follows the front ends' contract
// (program_contract.hpp): each part with its material's base colour factor and texture, in one view
// or in one view per layer of a layered framebuffer. Used by the command line (`render --shading
// material`, `--program`), the benchmark's scenes of materials and the Python package; needs no
// OpenGL (gl_model_draws.hpp draws the same on the OpenGL oracle).
#pragma once

#include "clraster/clraster.hpp"
#include "frontend/material_textures.hpp"
#include "frontend/program_contract.hpp"
#include "io/model_loader.hpp"

#include <optional>
#include <span>
#include <string>
#include <vector>

namespace clraster::frontend {

class ClrasterModelDraws {
 public:
  // Makes what `program`, which follows the contract (check_contract), declares of the model: its
  // texture coordinates as the attribute uv, and, when it declares base_color_texture, each
  // material's texture (materials' images that cannot be used add a line to `warnings`, as
  // MaterialTextures says). Keeps the model's parts, not the model; `program` must outlive the
  // draws made with this object.
  ClrasterModelDraws(Context& context, const Program& program, const io::Model& model,
                     std::vector<std::string>& warnings);

  // Binds, for each of `views` and each part, the contract's uniforms the program declares (the
  // view's, and the part's base colour factor) and the part's texture, over `own[view]`: bindings
  // of the program's other uniforms and textures, which the caller gives (empty: there are none).
  void bind(std::span<const ProgramInputs> views, std::span<const Bindings> own = {});

  // One draw per part of the model, whose positions, normals and indices are `vertices` and
  // `indices`, with `state`'s fixed-function state; with more than one bound view, view k of each
  // draw goes to layer k. The draws refer to this object, and hold until the next bind.
  std::vector<DrawCall> calls(const VertexBuffer& vertices, const IndexBuffer& indices, const DrawState& state) const;

 private:
  const Program* program_;
  std::vector<io::ModelPart> parts_;
  std::vector<std::array<float, 4>> base_colors_;       // per material
  std::optional<Buffer> uvs_;                          // when the program declares them
  std::optional<MaterialTextures<Texture>> textures_;  // when the program declares base_color_texture
  std::size_t view_count_ = 0;
  std::vector<Bindings> bindings_;                     // per part, then per view
};

}  // namespace clraster::frontend
