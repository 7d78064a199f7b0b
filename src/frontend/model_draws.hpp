// A model drawn part by part with a program that follows the command line's contract
// (program_contract.hpp): each part with its material's base colour factor and texture. One class
// per backend: clraster with any such program (the built-in material program or a --program file),
// and the OpenGL oracle with the GLSL equivalent of the material program. Used by the command line
// (`render --shading material`, `--program`) and the benchmark's scenes of materials.
#pragma once

#include "clraster/clraster.hpp"
#include "frontend/material_textures.hpp"
#include "frontend/program_contract.hpp"
#include "io/model_loader.hpp"
#include "oracle/gl_renderer.hpp"
#include "oracle/gl_scene.hpp"

#include <optional>
#include <string>
#include <vector>

namespace clraster::frontend {

// The GLSL equivalent of programs/material.cl (uniforms mvp, normal_matrix, light_direction,
// base_color; sampler base_color_texture): what GlMaterialDraws draws with.
extern const char* const kGlMaterialVertexShader;
extern const char* const kGlMaterialFragmentShader;

class ClrasterModelDraws {
 public:
  // Binds what `program`, which follows the contract (check_contract), declares: `view`'s uniforms,
  // each part's base colour factor, and, when it declares base_color_texture, each part's texture
  // (materials' images that cannot be used add a line to `warnings`, as MaterialTextures says).
  ClrasterModelDraws(Context& context, Program program, const io::Model& model, const ProgramInputs& view,
                     std::vector<std::string>& warnings);

  // One draw per part of the model, whose positions, normals and indices are `vertices` and
  // `indices`, with `state`'s fixed-function state. The draws refer to this object.
  std::vector<DrawCall> calls(const VertexBuffer& vertices, const IndexBuffer& indices, const DrawState& state) const;

 private:
  Program program_;
  std::vector<io::ModelPart> parts_;
  std::optional<Buffer> uvs_;                          // when the program declares them
  std::optional<MaterialTextures<Texture>> textures_;  // when the program declares base_color_texture
  std::vector<Bindings> bindings_;                     // per part
};

class GlMaterialDraws {
 public:
  // The GLSL material program with `view`'s uniforms, and the materials' textures (warnings as
  // MaterialTextures says). `model` must outlive this object.
  GlMaterialDraws(const io::Model& model, const ProgramInputs& view, std::vector<std::string>& warnings);

  // Draws every part, in order, with `state`'s fixed-function state.
  void draw(oracle::GlRenderer& target, const DrawState& state);

  std::size_t draw_count() const { return model_.parts.size(); }

 private:
  const io::Model& model_;
  oracle::GlProgram program_;
  oracle::GlVertexInput vertex_input_;  // the model's vertices and indices, uploaded once for every part
  MaterialTextures<oracle::GlTexture> textures_;
};

// One frame of a model on the OpenGL oracle, as `render --backend gl` and the benchmark draw it:
// clears to (0, 0, 0, 1) and depth 1, draws every part with `material_draws` when it holds them,
// else `mesh` in one draw (a built-in shading), with `state`'s fixed-function state, and waits for
// the rendering (glFinish). One of the two must hold a value.
void draw_gl_frame(oracle::GlRenderer& target, const DrawState& state, const std::optional<oracle::GlMesh>& mesh,
                   std::optional<GlMaterialDraws>& material_draws);

}  // namespace clraster::frontend
