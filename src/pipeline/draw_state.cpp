#include "pipeline/draw_state.hpp"

#include "shared/clr_limits.h"

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

template <typename Enum>
int checked(Enum value, Enum last, const char* what) {
  const int index = static_cast<int>(value);
  if (index < 0 || index > static_cast<int>(last)) {
    throw InvalidArgument(std::string(what) + " has the invalid value " + std::to_string(index));
  }
  return index;
}

// The public enums are in the order of the kernels' CLR_* constants (static_asserts below).
void set_fragment_operations(const DrawState& s, const RenderTarget& target, const program::ParsedProgram& program,
                             DrawUniforms& u) {
  const bool has_depth = target.depth_stencil() != nullptr;
  u.depth_test = s.depth_test && has_depth;
  u.depth_func = checked(s.depth_func, CompareFunc::Program, "depth_func");
  u.depth_write = s.depth_write;
  if (s.depth_test && s.depth_func == CompareFunc::Program && !program.interface.has_depth_test) {
    throw InvalidArgument("depth_func is Program but the program defines no bool depth_test(clr_fragment* f, "
                          "float fragment_depth, float stored_depth)");
  }
  u.stencil_test = s.stencil_test && target.has_stencil;
  const StencilFace* faces[2] = {&s.stencil_front, &s.stencil_back};
  for (int i = 0; i < 2; ++i) {
    const StencilFace& face = *faces[i];
    const char* name = i == 0 ? "stencil_front" : "stencil_back";
    StencilUniforms& out = u.stencil[i];
    out.func = checked(face.func, CompareFunc::Always, (std::string(name) + ".func (Program is for depth only)").c_str());
    out.reference = face.reference;
    out.read_mask = face.read_mask;
    out.write_mask = face.write_mask;
    out.stencil_fail = checked(face.stencil_fail, StencilOp::Invert, name);
    out.depth_fail = checked(face.depth_fail, StencilOp::Invert, name);
    out.depth_pass = checked(face.depth_pass, StencilOp::Invert, name);
  }
  std::copy(s.blend_color.begin(), s.blend_color.end(), u.blend_color);
  for (int k = 0; k < CLR_MAX_COLOR_ATTACHMENTS; ++k) {
    const BlendState& b = s.blend[static_cast<std::size_t>(k)];
    BlendUniforms& out = u.blend[k];
    const std::string name = "blend[" + std::to_string(k) + "]";
    out.enabled = b.enabled;
    out.rgb_equation = checked(b.rgb_equation, BlendEquation::Program, name.c_str());
    out.alpha_equation = checked(b.alpha_equation, BlendEquation::Program, name.c_str());
    out.src_rgb = checked(b.src_rgb, BlendFactor::SrcAlphaSaturate, name.c_str());
    out.dst_rgb = checked(b.dst_rgb, BlendFactor::SrcAlphaSaturate, name.c_str());
    out.src_alpha = checked(b.src_alpha, BlendFactor::SrcAlphaSaturate, name.c_str());
    out.dst_alpha = checked(b.dst_alpha, BlendFactor::SrcAlphaSaturate, name.c_str());
    out.write_mask = 0;
    for (unsigned c = 0; c < 4; ++c) out.write_mask |= b.write_mask[c] ? 1u << c : 0u;
    const bool programmed = b.rgb_equation == BlendEquation::Program || b.alpha_equation == BlendEquation::Program;
    if (b.enabled && programmed && !program.interface.has_blend) {
      throw InvalidArgument(name + " uses BlendEquation::Program but the program defines no float4 blend(clr_fragment* f, "
                            "uint target, float4 source, float4 destination)");
    }
    u.target_format[k] = k < static_cast<int>(target.formats.size()) ? target.formats[static_cast<std::size_t>(k)] : -1;
    out.common = common_blend(out, u.target_format[k]);
  }
}

}  // namespace

int common_blend(const BlendUniforms& b, int format) {
  if (!b.enabled || format != CLR_FORMAT_RGBA8 || b.rgb_equation != b.alpha_equation || b.src_rgb != b.src_alpha ||
      b.dst_rgb != b.dst_alpha) {
    return CLR_NOT_COMMON_BLEND;
  }
#define CLR_MATCH_COMMON_BLEND(index, equation, source_factor, destination_factor)                     \
  if (b.rgb_equation == (equation) && b.src_rgb == (source_factor) && b.dst_rgb == (destination_factor)) { \
    return index;                                                                                        \
  }
  CLR_COMMON_BLENDS(CLR_MATCH_COMMON_BLEND)
#undef CLR_MATCH_COMMON_BLEND
  return CLR_NOT_COMMON_BLEND;
}

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

DrawUniforms make_uniforms(const DrawState& s, const RenderTarget& target, const program::ParsedProgram& program,
                           std::uint32_t view) {
  DrawUniforms u{};
  const int width = target.layer_width;
  const int height = target.layer_height;
  // The layer's origin in the attachments: viewport and scissor move with it.
  const int layer_x = static_cast<int>(view) % target.layer_columns * width;
  const int layer_y = static_cast<int>(view) / target.layer_columns * height;
  check_rect("viewport", s.viewport, CLR_MAX_FRAMEBUFFER_SIZE, CLR_MAX_VIEWPORT_OFFSET);
  Rect viewport = (s.viewport.width == 0 || s.viewport.height == 0) ? Rect{0, 0, width, height} : s.viewport;
  viewport.x += layer_x;
  viewport.y += layer_y;
  u.viewport_scale[0] = static_cast<float>(viewport.width) * 0.5f;
  u.viewport_scale[1] = static_cast<float>(viewport.height) * 0.5f;
  u.viewport_offset[0] = static_cast<float>(viewport.x) + u.viewport_scale[0];
  u.viewport_offset[1] = static_cast<float>(viewport.y) + u.viewport_scale[1];
  for (int axis = 0; axis < 2; ++axis) {
    // Planes in NDC whose window coordinates are -+CLR_GUARD_BAND_PIXELS.
    u.guard_min[axis] = (-CLR_GUARD_BAND_PIXELS - u.viewport_offset[axis]) / u.viewport_scale[axis];
    u.guard_max[axis] = (CLR_GUARD_BAND_PIXELS - u.viewport_offset[axis]) / u.viewport_scale[axis];
  }

  int x0 = std::max(layer_x, viewport.x), y0 = std::max(layer_y, viewport.y);
  int x1 = std::min(layer_x + width, viewport.x + viewport.width);
  int y1 = std::min(layer_y + height, viewport.y + viewport.height);
  if (s.scissor_test) {
    check_rect("scissor", s.scissor, CLR_MAX_FRAMEBUFFER_SIZE, CLR_MAX_VIEWPORT_OFFSET);
    x0 = std::max(x0, layer_x + s.scissor.x);
    y0 = std::max(y0, layer_y + s.scissor.y);
    x1 = std::min(x1, layer_x + s.scissor.x + s.scissor.width);
    y1 = std::min(y1, layer_y + s.scissor.y + s.scissor.height);
  }
  u.clip_rect[0] = x0;
  u.clip_rect[1] = y0;
  u.clip_rect[2] = std::max(x0, x1);
  u.clip_rect[3] = std::max(y0, y1);
  u.framebuffer_size[0] = target.width;
  u.framebuffer_size[1] = target.height;
  u.streaming_stores = std::int64_t{target.width} * target.height >= CLR_STREAMING_STORE_PIXELS;
  u.view = view;
  u.layer_size[0] = width;
  u.layer_size[1] = height;
  u.layer_columns = target.layer_columns;

  u.topology = s.topology == Topology::TriangleList    ? CLR_TOPOLOGY_LIST
               : s.topology == Topology::TriangleStrip ? CLR_TOPOLOGY_STRIP
                                                       : CLR_TOPOLOGY_FAN;
  u.cull = s.cull == CullMode::None ? CLR_CULL_NONE : s.cull == CullMode::Back ? CLR_CULL_BACK : CLR_CULL_FRONT;
  u.front_face_ccw = s.front_face == FrontFace::CounterClockwise;
  set_fragment_operations(s, target, program, u);
  return u;
}

}  // namespace clraster::pipeline

static_assert(static_cast<int>(clraster::CompareFunc::Less) == CLR_COMPARE_LESS);
static_assert(static_cast<int>(clraster::CompareFunc::Program) == CLR_COMPARE_PROGRAM);
static_assert(static_cast<int>(clraster::StencilOp::Invert) == CLR_STENCIL_INVERT);
static_assert(static_cast<int>(clraster::BlendEquation::Program) == CLR_BLEND_PROGRAM);
static_assert(static_cast<int>(clraster::BlendFactor::SrcAlphaSaturate) == CLR_FACTOR_SRC_ALPHA_SATURATE);
static_assert(static_cast<int>(clraster::Format::Depth32FStencil8) == CLR_FORMAT_DEPTH32F_STENCIL8);
static_assert(static_cast<int>(clraster::Wrap::MirroredRepeat) == CLR_WRAP_MIRRORED_REPEAT);
static_assert(static_cast<int>(clraster::MipFilter::Linear) == CLR_MIP_LINEAR);
static_assert(clraster::kMaxColorAttachments == CLR_MAX_COLOR_ATTACHMENTS);
static_assert(clraster::kMaxTextureSize == CLR_MAX_TEXTURE_SIZE);
static_assert(clraster::kMaxFramebufferSize == CLR_MAX_FRAMEBUFFER_SIZE);
