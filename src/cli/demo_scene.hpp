// The built-in demo scene that `clraster render` draws when it is given no model file.
#pragma once

#include "io/camera.hpp"
#include "io/mesh.hpp"

namespace clraster::cli {

// A landscape with a torus, spheres and boxes standing on it: procedural, no files needed, a few
// hundred thousand triangles of every size from sub-pixel to screen-filling.
io::Mesh make_demo_scene();

// A view of the demo scene from above its edge, closer than a fit to its bounding sphere (the flat
// landscape would leave most of the picture empty).
io::Camera demo_camera(float fov_degrees);

}  // namespace clraster::cli
