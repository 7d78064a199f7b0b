// The command line's built-in shadings (`render --shading normal|lambert|depth|overdraw`) as the
// draw state that draws them, so that the command line and the benchmarks draw them alike.
#pragma once

#include "clraster/clraster.hpp"
#include "io/camera.hpp"

namespace clraster::io {

enum class BuiltinShading {
  Normal,    // Shading::Normal: the object-space normal as colour
  Lambert,   // Shading::Lambert: light grey lit by a headlight
  Depth,     // Shading::Depth: view distance as grey over the camera's near..far
  Overdraw,  // Shading::Constant adding 1/255 per fragment without depth test: red counts fragments
};

// The camera's view and projection (aspect = width / height) and the shading's inputs; the rest
// of the state is DrawState's defaults (depth test less, no blending, no culling) but for
// Overdraw's blending and depth test.
DrawState shading_state(BuiltinShading shading, const Camera& camera, float aspect);

// The same from the matrices themselves (column-major) and the view distances Depth draws white
// and black, for front ends that take matrices rather than a camera (the Python package).
DrawState shading_state(BuiltinShading shading, const Mat4& model_view, const Mat4& projection,
                        std::array<float, 2> depth_range);

}  // namespace clraster::io
