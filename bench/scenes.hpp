// The scenes of `clraster bench`: fixed procedural meshes, each drawn in one draw with one of the
// command line's built-in shadings from a fixed camera. They are made for 1920x1080, the
// benchmark's default size; at another size the same view is drawn, its projection following the
// aspect.
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
//               a pixel (trilinear), drawn as `render --shading material` draws models: the
//               material program (programs/material.cl), its texture times a headlight; depth test
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "clraster/clraster.hpp"
#include "io/camera.hpp"
#include "io/mesh.hpp"
#include "io/model_loader.hpp"
#include "io/shading.hpp"

namespace clraster::bench {

struct Scene {
  std::string name;
  io::Mesh mesh;
  io::Camera camera;
  io::BuiltinShading shading = io::BuiltinShading::Normal;
  // A textured scene's material: the mesh, one part, is drawn with the material program as the
  // command line draws models (cli/model_draws.hpp) instead of with `shading`.
  std::optional<io::Material> material;

  // The one draw's state for a width x height picture.
  DrawState state(int width, int height) const;
};

// Every scene's name, in the order the benchmark runs them, and the same as one "a, b, c" text.
const std::vector<std::string>& scene_names();
std::string scene_names_text();

// The scenes of a comma-separated list of names, in its order; an empty list is every scene.
// Throws InvalidArgument for a name that is not a scene's (the message lists the scenes), before
// any scene is built.
std::vector<std::string> parse_scene_list(const std::string& list);

// Builds the named scene: deterministic, the same bytes on every run; the largest take seconds.
// Throws InvalidArgument for a name that is not a scene's.
Scene make_scene(const std::string& name);

}  // namespace clraster::bench
