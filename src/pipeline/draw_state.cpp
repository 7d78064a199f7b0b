#include "pipeline/draw_state.hpp"

#include "clr_limits.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace clraster::pipeline {
namespace {

std::string rect_text(const Rect& r) {
  return "(" + std::to_string(r.x) + ", " + std::to_string(r.y) + ", " + std::to_string(r.width) + ", " +
         std::to_string(r.height) + ")";
}

void check_rect(const char* what, const Rect& r, int max_size, int max_offset) {
  if (r.width < 0 || r.height < 0 || r.width > max_size || r.height > max_size || std::abs(r.x) > max_offset ||
      std::abs(r.y) > max_offset) {
    throw InvalidArgument(std::string(what) + " " + rect_text(r) + " is out of range: sizes must be 0.." +
                          std::to_string(max_size) + " and offsets within +-" + std::to_string(max_offset));
  }
}

}  // namespace

Mat4 model_view_projection(const DrawState& state) {
  Mat4 product{};
  for (int column = 0; column < 4; ++column) {
    for (int row = 0; row < 4; ++row) {
      double sum = 0;
      for (int k = 0; k < 4; ++k) sum += double{state.projection[k * 4 + row]} * double{state.model_view[column * 4 + k]};
      product[column * 4 + row] = static_cast<float>(sum);
    }
  }
  return product;
}

std::array<float, 9> normal_matrix(const Mat4& m) {
  const auto a = [&](int row, int column) { return double{m[column * 4 + row]}; };
  double cofactor[3][3];
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      const int r1 = (r + 1) % 3, r2 = (r + 2) % 3, c1 = (c + 1) % 3, c2 = (c + 2) % 3;
      cofactor[r][c] = a(r1, c1) * a(r2, c2) - a(r1, c2) * a(r2, c1);
    }
  }
  const double det = a(0, 0) * cofactor[0][0] + a(0, 1) * cofactor[0][1] + a(0, 2) * cofactor[0][2];
  const double scale = det != 0.0 ? 1.0 / det : 1.0;
  // inverse = transpose(cofactor) / det, so inverse transpose = cofactor / det.
  std::array<float, 9> result{};
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) result[c * 3 + r] = static_cast<float>(cofactor[r][c] * scale);
  }
  return result;
}

DrawUniforms make_uniforms(const DrawState& s, int width, int height) {
  DrawUniforms u{};
  const Mat4 mvp = model_view_projection(s);
  std::copy(mvp.begin(), mvp.end(), u.mvp);
  std::copy(s.model_view.begin(), s.model_view.end(), u.model_view);
  const std::array<float, 9> normals = normal_matrix(s.model_view);
  std::copy(normals.begin(), normals.end(), u.normal_matrix);
  std::copy(s.base_color.begin(), s.base_color.end(), u.base_color);

  if (s.shading == Shading::Depth &&
      !(std::isfinite(s.depth_shading_range[0]) && std::isfinite(s.depth_shading_range[1]) &&
        s.depth_shading_range[1] > s.depth_shading_range[0])) {
    throw InvalidArgument("depth shading range [" + std::to_string(s.depth_shading_range[0]) + ", " +
                          std::to_string(s.depth_shading_range[1]) + "] must be finite with near < far");
  }
  u.depth_shading_range[0] = s.depth_shading_range[0];
  u.depth_shading_range[1] = s.depth_shading_range[1];

  check_rect("viewport", s.viewport, CLR_MAX_FRAMEBUFFER_SIZE, CLR_MAX_VIEWPORT_OFFSET);
  const Rect viewport = (s.viewport.width == 0 || s.viewport.height == 0) ? Rect{0, 0, width, height} : s.viewport;
  u.viewport_scale[0] = static_cast<float>(viewport.width) * 0.5f;
  u.viewport_scale[1] = static_cast<float>(viewport.height) * 0.5f;
  u.viewport_offset[0] = static_cast<float>(viewport.x) + u.viewport_scale[0];
  u.viewport_offset[1] = static_cast<float>(viewport.y) + u.viewport_scale[1];
  for (int axis = 0; axis < 2; ++axis) {
    // Planes in NDC whose window coordinates are -+CLR_GUARD_BAND_PIXELS.
    u.guard_min[axis] = (-CLR_GUARD_BAND_PIXELS - u.viewport_offset[axis]) / u.viewport_scale[axis];
    u.guard_max[axis] = (CLR_GUARD_BAND_PIXELS - u.viewport_offset[axis]) / u.viewport_scale[axis];
  }

  int x0 = std::max(0, viewport.x), y0 = std::max(0, viewport.y);
  int x1 = std::min(width, viewport.x + viewport.width), y1 = std::min(height, viewport.y + viewport.height);
  if (s.scissor_test) {
    check_rect("scissor", s.scissor, CLR_MAX_FRAMEBUFFER_SIZE, CLR_MAX_VIEWPORT_OFFSET);
    x0 = std::max(x0, s.scissor.x);
    y0 = std::max(y0, s.scissor.y);
    x1 = std::min(x1, s.scissor.x + s.scissor.width);
    y1 = std::min(y1, s.scissor.y + s.scissor.height);
  }
  u.clip_rect[0] = x0;
  u.clip_rect[1] = y0;
  u.clip_rect[2] = std::max(x0, x1);
  u.clip_rect[3] = std::max(y0, y1);

  u.topology = s.topology == Topology::TriangleList    ? CLR_TOPOLOGY_LIST
               : s.topology == Topology::TriangleStrip ? CLR_TOPOLOGY_STRIP
                                                       : CLR_TOPOLOGY_FAN;
  u.cull = s.cull == CullMode::None ? CLR_CULL_NONE : s.cull == CullMode::Back ? CLR_CULL_BACK : CLR_CULL_FRONT;
  u.front_face_ccw = s.front_face == FrontFace::CounterClockwise;
  u.shading = static_cast<int>(s.shading);  // same order as CLR_SHADING_*
  u.depth_test = s.depth_test;
  u.depth_func = static_cast<int>(s.depth_func);  // same order as CLR_COMPARE_*
  u.depth_write = s.depth_write;
  u.blend = s.blend[0].enabled ? CLR_BLEND_ADDITIVE : CLR_BLEND_REPLACE;
  return u;
}

bool writable_rect_empty(const DrawUniforms& u) { return u.clip_rect[0] >= u.clip_rect[2] || u.clip_rect[1] >= u.clip_rect[3]; }

}  // namespace clraster::pipeline

static_assert(static_cast<int>(clraster::Shading::Constant) == CLR_SHADING_CONSTANT);
static_assert(static_cast<int>(clraster::CompareFunc::Less) == CLR_COMPARE_LESS);
static_assert(static_cast<int>(clraster::CompareFunc::Always) == CLR_COMPARE_ALWAYS);
