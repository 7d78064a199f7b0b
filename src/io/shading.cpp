#include "io/shading.hpp"

namespace clraster::io {

DrawState shading_state(BuiltinShading shading, const Camera& camera, float aspect) {
  return shading_state(shading, to_mat4(view_matrix(camera)), to_mat4(projection_matrix(camera, aspect)),
                       {camera.near_plane, camera.far_plane});
}

DrawState shading_state(BuiltinShading shading, const Mat4& model_view, const Mat4& projection,
                        std::array<float, 2> depth_range) {
  DrawState state;
  state.model_view = model_view;
  state.projection = projection;
  switch (shading) {
    case BuiltinShading::Normal: state.shading = Shading::Normal; break;
    case BuiltinShading::Lambert:
      state.shading = Shading::Lambert;
      state.base_color = {0.85f, 0.85f, 0.85f, 1.0f};
      break;
    case BuiltinShading::Depth:
      state.shading = Shading::Depth;
      state.depth_shading_range = depth_range;
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
