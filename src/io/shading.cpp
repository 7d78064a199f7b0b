#include "io/shading.hpp"

namespace clraster::io {

DrawState shading_state(BuiltinShading shading, const Camera& camera, float aspect) {
  DrawState state;
  state.model_view = to_mat4(view_matrix(camera));
  state.projection = to_mat4(projection_matrix(camera, aspect));
  switch (shading) {
    case BuiltinShading::Normal: state.shading = Shading::Normal; break;
    case BuiltinShading::Lambert:
      state.shading = Shading::Lambert;
      state.base_color = {0.85f, 0.85f, 0.85f, 1.0f};
      break;
    case BuiltinShading::Depth:
      state.shading = Shading::Depth;
      state.depth_shading_range = {camera.near_plane, camera.far_plane};
      break;
    case BuiltinShading::Overdraw:
      // Every fragment adds 1/255: the red channel counts the fragments of each pixel.
      state.shading = Shading::Constant;
      state.base_color = {1.0f / 255, 1.0f / 255, 1.0f / 255, 1.0f / 255};
      state.blend[0] = kAdditiveBlend;
      state.depth_test = false;
      break;
  }
  return state;
}

}  // namespace clraster::io
