// The scenes of `clraster bench`, each drawn from a fixed camera: fixed procedural meshes drawn in
// one draw with one of the command line's built-in shadings, and models drawn part by part with the
// material program, one draw per part, as `render --shading material` draws models
// (frontend/model_draws.hpp). They are made for 1920x1080, the benchmark's default size; at another
// size the same view is drawn, its projection following the aspect.
//
//   model-50k   a trefoil knot of 50,000 triangles, smooth and closed, over 37% of the picture,
//               crossing itself in depth; normal shading, depth test
//   terrain-1m  a landscape of 708 x 708 cells (1,002,528 triangles) seen from above at 45 degrees,
//               filling the picture; normal shading, depth test
//   terrain-4m  the same landscape of 1415 x 1415 cells (4,004,450 triangles)
//   fill-16     16 stacked quads covering the picture (32 triangles), added up without depth test:
//               16 fragments per pixel, the command line's overdraw shading
//   tiny-1m     a plane facing the camera of 1024 x 512 cells of 0.7 pixel (1,048,576 triangles of
//               a quarter of a pixel each), in the middle of the picture; normal shading, depth test
//   textured-50k  model-50k's knot and view with a 1024x1024 texture mapped from above, 3 to 4 texels
//               a pixel (trilinear): one part, the material program, its texture times a headlight;
//               depth test
//   materials-256  model-50k's knot and view in 256 parts of consecutive triangles (195 or 196
//               each), each with a material colour of its own: 256 draws, depth test
//   engine-glb  assimp's 2CylinderEngine.glb (package assimp-testmodels; 121,496 triangles in 108
//               parts, one per mesh and node), framed as `render` frames a model by default at
//               1920x1080; material colours, depth test
//   instanced-4k  a sphere of 1,280 triangles drawn 4,096 times in one instanced draw (5,242,880
//               triangles), a 64 x 64 grid of them seen from above at an angle, each placed and
//               sized by a per-instance attribute; normal shading, depth test
//   views-64    model-50k's knot from 64 cameras around it (8 elevations by 8 azimuths), each view
//               256x256 whatever the benchmark's size (64x256x256): one draw of 64 views into a
//               layered framebuffer; llvmpipe draws the 64 into one picture of the layers side
//               by side, a draw per view into its viewport; normal shading, depth test
#pragma once

#include <string>
#include <vector>

#include "clraster/clraster.hpp"
#include "io/camera.hpp"
#include "io/mesh.hpp"
#include "io/model_loader.hpp"
#include "io/shading.hpp"

namespace clraster::bench {

// The side of each view of a scene of views, in pixels.
inline constexpr int kViewSide = 256;

struct Scene {
  std::string name;
  // The triangles; a scene of materials has its materials and its parts as well.
  io::Model model;
  io::Camera camera{};
  // How a scene without parts is drawn, in one draw.
  io::BuiltinShading shading = io::BuiltinShading::Normal;
  // An instanced scene's placements, four floats an instance: x, y, z and a scale. Its model is
  // drawn once, instanced, with the instancing program (kInstancedProgram: normal shading of the
  // placed mesh).
  std::vector<float> instances{};
  // A scene of views' cameras: its model drawn once from each, with `shading`, in one draw, view k
  // into layer k of kViewSide x kViewSide pixels (its `camera` is the first view's).
  std::vector<io::Camera> views{};

  // A scene with parts is drawn with the material program instead of with `shading`, a draw per
  // part.
  bool draws_materials() const { return !model.parts.empty(); }
  std::size_t draw_count() const { return draws_materials() ? model.parts.size() : 1; }
  std::uint32_t instance_count() const { return instances.empty() ? 1 : static_cast<std::uint32_t>(instances.size() / 4); }
  bool draws_views() const { return !views.empty(); }
  int layer_count() const { return draws_views() ? static_cast<int>(views.size()) : 1; }
  std::uint64_t triangle_count() const { return model.triangle_count() * instance_count() * layer_count(); }

  // A layer's size when the benchmark runs at width x height: a scene of views' are kViewSide
  // square at any size, every other scene is one layer of that size.
  int layer_width(int width) const;
  int layer_height(int height) const;
  // The layers of layer_width x layer_height side by side in one picture, as a layered Framebuffer
  // holds them: layer l at column l % layer_columns(), row l / layer_columns(), from the bottom
  // left (Framebuffer::layer_rect). OpenGL draws a scene of views into such a picture.
  int layer_columns() const;
  int layer_rows() const;
  Rect layer_rect(int layer, int layer_width, int layer_height) const;

  // The views as clraster takes them, each camera's matrices for a square layer.
  std::vector<View> view_matrices() const;
  // The views as OpenGL draws them, a draw each: `state` with the view's matrices, its viewport
  // the view's layer_rect for layers of width x height. None for a scene without views.
  std::vector<DrawState> view_states(const DrawState& state, int width, int height) const;

  // The fixed-function state of every draw for layers of width x height pixels (its camera's
  // matrices, which a scene of views' views replace).
  DrawState state(int width, int height) const;
};

// The instancing program of instanced scenes, in OpenCL C for clraster and in GLSL for OpenGL:
// attributes position, normal and the per-instance placement (vec4: x, y, z offset, scale), uniform
// mvp; the colour is normal shading's, normalize(normal) * 0.5 + 0.5.
extern const char* const kInstancedProgram;
extern const char* const kGlInstancedVertexShader;
extern const char* const kGlInstancedFragmentShader;

// Every scene's name, in the order the benchmark runs them, and the same as one "a, b, c" text.
const std::vector<std::string>& scene_names();
std::string scene_names_text();

// The scenes of a comma-separated list of names, in its order; an empty list is every scene.
// Throws InvalidArgument for a name that is not a scene's (the message lists the scenes), and
// clraster::Error naming the file and its package when a chosen scene's model file is missing,
// before any scene is built.
std::vector<std::string> parse_scene_list(const std::string& list);

// Builds the named scene: deterministic, the same bytes on every run; the largest take seconds.
// Throws InvalidArgument for a name that is not a scene's, and clraster::Error when its model file
// is missing (as parse_scene_list) or loads with warnings.
Scene make_scene(const std::string& name);

}  // namespace clraster::bench
