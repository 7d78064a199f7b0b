#include "oracle/gl_state.hpp"

#include <limits>

namespace clraster::oracle::gl {
namespace {

GLenum compare_func(CompareFunc func, const char* what) {
  switch (func) {
    case CompareFunc::Never: return GL_NEVER;
    case CompareFunc::Less: return GL_LESS;
    case CompareFunc::Equal: return GL_EQUAL;
    case CompareFunc::LessEqual: return GL_LEQUAL;
    case CompareFunc::Greater: return GL_GREATER;
    case CompareFunc::NotEqual: return GL_NOTEQUAL;
    case CompareFunc::GreaterEqual: return GL_GEQUAL;
    case CompareFunc::Always: return GL_ALWAYS;
    case CompareFunc::Program:
      throw InvalidArgument(std::string(what) + " CompareFunc::Program has no OpenGL equivalent");
  }
  throw InvalidArgument(std::string("unknown ") + what + " " + std::to_string(static_cast<int>(func)));
}

GLenum stencil_op(StencilOp op) {
  switch (op) {
    case StencilOp::Keep: return GL_KEEP;
    case StencilOp::Zero: return GL_ZERO;
    case StencilOp::Replace: return GL_REPLACE;
    case StencilOp::Increment: return GL_INCR;
    case StencilOp::IncrementWrap: return GL_INCR_WRAP;
    case StencilOp::Decrement: return GL_DECR;
    case StencilOp::DecrementWrap: return GL_DECR_WRAP;
    case StencilOp::Invert: return GL_INVERT;
  }
  throw InvalidArgument("unknown stencil operation " + std::to_string(static_cast<int>(op)));
}

GLenum blend_equation(BlendEquation equation, int attachment) {
  switch (equation) {
    case BlendEquation::Add: return GL_FUNC_ADD;
    case BlendEquation::Subtract: return GL_FUNC_SUBTRACT;
    case BlendEquation::ReverseSubtract: return GL_FUNC_REVERSE_SUBTRACT;
    case BlendEquation::Min: return GL_MIN;
    case BlendEquation::Max: return GL_MAX;
    case BlendEquation::Program:
      throw InvalidArgument("blend[" + std::to_string(attachment) +
                            "]: BlendEquation::Program has no OpenGL equivalent");
  }
  throw InvalidArgument("unknown blend equation " + std::to_string(static_cast<int>(equation)));
}

GLenum blend_factor(BlendFactor factor) {
  switch (factor) {
    case BlendFactor::Zero: return GL_ZERO;
    case BlendFactor::One: return GL_ONE;
    case BlendFactor::SrcColor: return GL_SRC_COLOR;
    case BlendFactor::OneMinusSrcColor: return GL_ONE_MINUS_SRC_COLOR;
    case BlendFactor::DstColor: return GL_DST_COLOR;
    case BlendFactor::OneMinusDstColor: return GL_ONE_MINUS_DST_COLOR;
    case BlendFactor::SrcAlpha: return GL_SRC_ALPHA;
    case BlendFactor::OneMinusSrcAlpha: return GL_ONE_MINUS_SRC_ALPHA;
    case BlendFactor::DstAlpha: return GL_DST_ALPHA;
    case BlendFactor::OneMinusDstAlpha: return GL_ONE_MINUS_DST_ALPHA;
    case BlendFactor::ConstantColor: return GL_CONSTANT_COLOR;
    case BlendFactor::OneMinusConstantColor: return GL_ONE_MINUS_CONSTANT_COLOR;
    case BlendFactor::ConstantAlpha: return GL_CONSTANT_ALPHA;
    case BlendFactor::OneMinusConstantAlpha: return GL_ONE_MINUS_CONSTANT_ALPHA;
    case BlendFactor::SrcAlphaSaturate: return GL_SRC_ALPHA_SATURATE;
  }
  throw InvalidArgument("unknown blend factor " + std::to_string(static_cast<int>(factor)));
}

void set_enabled(GLenum capability, bool enabled) { enabled ? glEnable(capability) : glDisable(capability); }

void apply_stencil_face(GLenum face, const StencilFace& stencil, const char* what) {
  glStencilFuncSeparate(face, compare_func(stencil.func, what), stencil.reference, stencil.read_mask);
  glStencilOpSeparate(face, stencil_op(stencil.stencil_fail), stencil_op(stencil.depth_fail),
                      stencil_op(stencil.depth_pass));
  glStencilMaskSeparate(face, stencil.write_mask);
}

}  // namespace

GLenum topology(Topology topology) {
  switch (topology) {
    case Topology::TriangleList: return GL_TRIANGLES;
    case Topology::TriangleStrip: return GL_TRIANGLE_STRIP;
    case Topology::TriangleFan: return GL_TRIANGLE_FAN;
  }
  throw InvalidArgument("unknown topology " + std::to_string(static_cast<int>(topology)));
}

void apply_draw_state(const DrawState& state, int width, int height) {
  if (state.viewport.width == 0 || state.viewport.height == 0) {
    glViewport(0, 0, width, height);
  } else {
    glViewport(state.viewport.x, state.viewport.y, state.viewport.width, state.viewport.height);
  }
  set_enabled(GL_SCISSOR_TEST, state.scissor_test);
  if (state.scissor_test) glScissor(state.scissor.x, state.scissor.y, state.scissor.width, state.scissor.height);

  set_enabled(GL_CULL_FACE, state.cull != CullMode::None);
  glCullFace(state.cull == CullMode::Front ? GL_FRONT : GL_BACK);
  glFrontFace(state.front_face == FrontFace::CounterClockwise ? GL_CCW : GL_CW);

  set_enabled(GL_DEPTH_TEST, state.depth_test);
  glDepthFunc(compare_func(state.depth_func, "depth function"));
  glDepthMask(state.depth_write ? GL_TRUE : GL_FALSE);

  set_enabled(GL_STENCIL_TEST, state.stencil_test);
  apply_stencil_face(GL_FRONT, state.stencil_front, "front stencil function");
  apply_stencil_face(GL_BACK, state.stencil_back, "back stencil function");

  for (int i = 0; i < kMaxColorAttachments; ++i) {
    const BlendState& blend = state.blend[std::size_t(i)];
    const auto buffer = GLuint(i);
    blend.enabled ? glEnablei(GL_BLEND, buffer) : glDisablei(GL_BLEND, buffer);
    glBlendEquationSeparatei(buffer, blend_equation(blend.rgb_equation, i), blend_equation(blend.alpha_equation, i));
    glBlendFuncSeparatei(buffer, blend_factor(blend.src_rgb), blend_factor(blend.dst_rgb),
                         blend_factor(blend.src_alpha), blend_factor(blend.dst_alpha));
    const auto& mask = blend.write_mask;
    glColorMaski(buffer, mask[0], mask[1], mask[2], mask[3]);
  }
  const auto& [r, g, b, a] = state.blend_color;
  glBlendColor(r, g, b, a);
}

void prepare_clear() {
  glDisable(GL_SCISSOR_TEST);
  for (int i = 0; i < kMaxColorAttachments; ++i) glColorMaski(GLuint(i), GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
  glStencilMask(0xff);
}

std::uint32_t draw_range(std::uint32_t first, std::uint32_t count, std::uint64_t available, const std::string& what) {
  if (first > available) {
    throw InvalidArgument("draw starts at element " + std::to_string(first) + " of " + what + "'s " +
                          std::to_string(available));
  }
  const std::uint64_t elements = count == kAllElements ? available - first : count;
  if (first + elements > available) {
    throw InvalidArgument("draw of " + std::to_string(elements) + " elements from " + std::to_string(first) +
                          " runs past " + what + "'s " + std::to_string(available));
  }
  constexpr std::uint64_t kMaxGlCount = std::numeric_limits<GLint>::max();
  if (first > kMaxGlCount || elements > kMaxGlCount) {
    throw InvalidArgument("draw of " + std::to_string(elements) + " elements from " + std::to_string(first) +
                          " exceeds OpenGL's 32-bit signed counts");
  }
  return static_cast<std::uint32_t>(elements);
}

}  // namespace clraster::oracle::gl
