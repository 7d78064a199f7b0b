// A model drawn part by part with its materials on the OpenGL oracle: the GLSL equivalent of the
// material program, as `render --backend gl` and the benchmark draw models. Links with OpenGL,
// which model_draws.hpp (clraster's side) does not need.
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
