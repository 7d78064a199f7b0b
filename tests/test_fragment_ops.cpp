// Unit tests of the per-fragment operations (raster/fragment_ops.cl) and of the advanced blend
// modes (program/library/blend_modes.cl). Small test kernels call the real functions, compiled with
// the pipeline's sources; the expected values come from references written here, independently,
// from the formulas of OpenGL 4.6 (17.3.3 stencil, 17.3.4 depth, 17.3.6 blending), of llvmpipe's
// 8-bit fixed-point blend (in integers) and of KHR_blend_equation_advanced.
#include "api/impl.hpp"
#include "runtime/kernel_sources.hpp"
#include "runtime/launch.hpp"
#include "shared/types.h"
#include "support/test_support.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace clraster::test {
namespace {

const char* const kTestKernels = R"CLC(
/* The operations work on spans of pixels (fragment_ops.cl): each case is given to every lane of a
 * span, and the result is lane 0's. */
int lane_0(clr_span_int mask) { return CLR_SPAN_LANE(int, mask, 0) != 0; }
uint lane_0_uint(clr_span_uint value) { return CLR_SPAN_LANE(uint, value, 0); }

__kernel void test_compare(__global const int* funcs, __global const float2* operands, __global int* passed) {
  const size_t i = get_global_id(0);
  passed[i] = lane_0(clr_compare(funcs[i], (clr_span_float)(operands[i].x), (clr_span_float)(operands[i].y)));
}

__kernel void test_stencil_test(__global const StencilUniforms* states, __global const uint* stored,
                                __global int* passed) {
  const size_t i = get_global_id(0);
  passed[i] = lane_0(clr_stencil_test(states[i], (clr_span_uint)(stored[i])));
}

/* Applies each state's depth_pass op. */
__kernel void test_stencil_update(__global const StencilUniforms* states, __global const uint* stored,
                                  __global uint* updated) {
  const size_t i = get_global_id(0);
  updated[i] = lane_0_uint(clr_stencil_update(states[i], states[i].depth_pass, (clr_span_uint)(stored[i])));
}

/* outcomes: bit 0 stencil passed, bit 1 depth passed. */
__kernel void test_stencil_after_tests(StencilUniforms s, uint stored, __global const int* outcomes,
                                       __global uint* updated) {
  const size_t i = get_global_id(0);
  const clr_span_int stencil_passed = (clr_span_int)(outcomes[i] & 1) != 0;
  const clr_span_int depth_passed = (clr_span_int)(outcomes[i] & 2) != 0;
  updated[i] = lane_0_uint(clr_stencil_after_tests(s, stencil_passed, depth_passed, (clr_span_uint)(stored)));
}

/* Case i blends colour combination i % combos under state i / combos, for an attachment of `kind`
 * (Attachment in the test). */
__kernel void test_blend(__global const BlendUniforms* states, __global const float4* sources,
                         __global const float4* destinations, __global const float4* constants, uint combos,
                         int kind, __global float4* blended) {
  const size_t i = get_global_id(0);
  const size_t c = i % combos;
  const BlendUniforms b = states[i / combos];
  const clr_span_color s = CLR_SPAN_COLOR_SPLAT(sources[c]);
  const clr_span_color d = CLR_SPAN_COLOR_SPLAT(destinations[c]);
  const clr_span_color k = CLR_SPAN_COLOR_SPLAT(constants[c]);
  clr_span_color result;
  if (kind == 2) clr_blend_unorm8(b, s, d, k, 4, false, &result);
  else clr_blend(b, s, d, k, kind == 1, 4, &result);
  blended[i] = clr_span_color_lane(result, 0);
}

__kernel void test_write_mask(__global const uint* masks, float4 value, float4 destination, __global float4* out) {
  const size_t i = get_global_id(0);
  clr_span_bits masked = CLR_SPAN_COLOR_BITS(CLR_SPAN_COLOR_SPLAT(value));
  clr_apply_write_mask(masks[i], &masked, CLR_SPAN_COLOR_BITS(CLR_SPAN_COLOR_SPLAT(destination)));
  out[i] = clr_span_color_lane(CLR_SPAN_BITS_COLOR(masked), 0);
}

/* mode: the position in KHR_blend_equation_advanced's tables X.1 then X.2. */
__kernel void test_advanced(int mode, __global const float4* sources, __global const float4* destinations,
                            __global float4* blended) {
  const size_t i = get_global_id(0);
  const float4 s = sources[i];
  const float4 d = destinations[i];
  float4 result;
  switch (mode) {
    case 0: result = clr_blend_multiply(s, d); break;
    case 1: result = clr_blend_screen(s, d); break;
    case 2: result = clr_blend_overlay(s, d); break;
    case 3: result = clr_blend_darken(s, d); break;
    case 4: result = clr_blend_lighten(s, d); break;
    case 5: result = clr_blend_colordodge(s, d); break;
    case 6: result = clr_blend_colorburn(s, d); break;
    case 7: result = clr_blend_hardlight(s, d); break;
    case 8: result = clr_blend_softlight(s, d); break;
    case 9: result = clr_blend_difference(s, d); break;
    case 10: result = clr_blend_exclusion(s, d); break;
    case 11: result = clr_blend_hsl_hue(s, d); break;
    case 12: result = clr_blend_hsl_saturation(s, d); break;
    case 13: result = clr_blend_hsl_color(s, d); break;
    default: result = clr_blend_hsl_luminosity(s, d); break;
  }
  blended[i] = result;
}
)CLC";

using Rgba = std::array<float, 4>;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInfinity = std::numeric_limits<float>::infinity();

std::string describe(const Rgba& c) {
  std::ostringstream out;
  out << "(" << c[0] << ", " << c[1] << ", " << c[2] << ", " << c[3] << ")";
  return out.str();
}

class FragmentOpsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    program_ = build_test_program("fragment op unit tests", builtin_stage_program() + kTestKernels);
  }

  ContextState& state() { return *shared_context().impl().state; }

  template <typename T>
  cl::Buffer buffer(const std::vector<T>& data) {
    return cl::Buffer(state().context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, data.size() * sizeof(T),
                      const_cast<T*>(data.data()));
  }

  template <typename T>
  cl::Buffer output(std::size_t count) {
    return cl::Buffer(state().context, CL_MEM_READ_WRITE, count * sizeof(T));
  }

  template <typename T>
  std::vector<T> read(const cl::Buffer& buffer, std::size_t count) {
    std::vector<T> data(count);
    state().queue.get().enqueueReadBuffer(buffer, CL_TRUE, 0, count * sizeof(T), data.data());
    return data;
  }

  // One work-item per element.
  template <typename... Args>
  void run(const char* name, std::size_t items, const Args&... args) {
    cl::Kernel kernel(program_, name);
    runtime::set_args(kernel, args...);
    state().queue.get().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(items), cl::NullRange);
    state().queue.get().finish();
  }

  cl::Program program_;
};

// ---- Comparisons ------------------------------------------------------------------------------------

// GL 4.6 17.3.4: the test passes when "fragment func stored".
bool reference_compare(int func, float fragment, float stored) {
  switch (func) {
    case CLR_COMPARE_NEVER: return false;
    case CLR_COMPARE_LESS: return fragment < stored;
    case CLR_COMPARE_EQUAL: return fragment == stored;
    case CLR_COMPARE_LEQUAL: return fragment <= stored;
    case CLR_COMPARE_GREATER: return fragment > stored;
    case CLR_COMPARE_NOTEQUAL: return fragment != stored;
    case CLR_COMPARE_GEQUAL: return fragment >= stored;
    default: return true;
  }
}

TEST_F(FragmentOpsTest, CompareFunctionsFollowIeeeForNaNInfinitiesAndSignedZeros) {
  const std::vector<float> values = {kNaN, -kInfinity, -1.0f, -0.0f, 0.0f, 0.25f, 0.5f, 1.0f, kInfinity};
  std::vector<cl_int> funcs;
  std::vector<cl_float2> operands;
  for (int func = CLR_COMPARE_NEVER; func <= CLR_COMPARE_ALWAYS; ++func) {
    for (float fragment : values) {
      for (float stored : values) {
        funcs.push_back(func);
        operands.push_back({{fragment, stored}});
      }
    }
  }
  cl::Buffer passed = output<cl_int>(funcs.size());
  run("test_compare", funcs.size(), buffer(funcs), buffer(operands), passed);
  const std::vector<cl_int> result = read<cl_int>(passed, funcs.size());
  for (std::size_t i = 0; i < funcs.size(); ++i) {
    EXPECT_EQ(result[i] != 0, reference_compare(funcs[i], operands[i].s[0], operands[i].s[1]))
        << "func " << funcs[i] << ", fragment " << operands[i].s[0] << ", stored " << operands[i].s[1];
  }
}

TEST_F(FragmentOpsTest, CompareTakesTheFragmentAsLeftOperandAndZerosAsEqual) {
  const std::vector<cl_int> funcs = {CLR_COMPARE_LESS, CLR_COMPARE_LESS, CLR_COMPARE_EQUAL, CLR_COMPARE_NOTEQUAL,
                                     CLR_COMPARE_NOTEQUAL};
  const std::vector<cl_float2> operands = {{{0.25f, 0.5f}}, {{0.5f, 0.25f}}, {{-0.0f, 0.0f}}, {{kNaN, kNaN}},
                                           {{0.5f, 0.5f}}};
  cl::Buffer passed = output<cl_int>(funcs.size());
  run("test_compare", funcs.size(), buffer(funcs), buffer(operands), passed);
  EXPECT_EQ(read<cl_int>(passed, funcs.size()), (std::vector<cl_int>{1, 0, 1, 1, 0}));
}

// ---- Stencil ------------------------------------------------------------------------------------------

StencilUniforms stencil_state(int func, std::uint32_t reference, std::uint32_t read_mask, std::uint32_t write_mask,
                              int op = CLR_STENCIL_KEEP) {
  StencilUniforms s{};
  s.func = func;
  s.reference = reference;
  s.read_mask = read_mask;
  s.write_mask = write_mask;
  s.stencil_fail = CLR_STENCIL_KEEP;
  s.depth_fail = CLR_STENCIL_KEEP;
  s.depth_pass = op;
  return s;
}

// GL 4.6 17.3.3 with 8-bit stencil: ops saturate at 0 and 2^8 - 1 or wrap modulo 2^8, and only the
// bits set in the write mask change.
std::uint32_t reference_stencil_update(int op, std::uint32_t reference, std::uint32_t write_mask,
                                       std::uint32_t stored) {
  std::uint32_t value = stored;
  switch (op) {
    case CLR_STENCIL_ZERO: value = 0; break;
    case CLR_STENCIL_REPLACE: value = reference; break;
    case CLR_STENCIL_INCR: value = stored == 255 ? 255 : stored + 1; break;
    case CLR_STENCIL_INCR_WRAP: value = (stored + 1) % 256; break;
    case CLR_STENCIL_DECR: value = stored == 0 ? 0 : stored - 1; break;
    case CLR_STENCIL_DECR_WRAP: value = (stored + 255) % 256; break;
    case CLR_STENCIL_INVERT: value = 255 - stored; break;
    default: break;
  }
  return ((value & write_mask) | (stored & ~write_mask)) & 255;
}

TEST_F(FragmentOpsTest, StencilTestComparesMaskedReferenceWithMaskedStoredValue) {
  const std::vector<std::uint32_t> references = {0x00, 0x01, 0x7f, 0x80, 0xa5, 0xfe, 0xff};
  const std::vector<std::uint32_t> read_masks = {0xff, 0x0f, 0xf0, 0x81, 0x00};
  std::vector<StencilUniforms> states;
  std::vector<cl_uint> stored;
  for (int func = CLR_COMPARE_NEVER; func <= CLR_COMPARE_ALWAYS; ++func) {
    for (std::uint32_t reference : references) {
      for (std::uint32_t mask : read_masks) {
        for (std::uint32_t value = 0; value < 256; ++value) {
          states.push_back(stencil_state(func, reference, mask, 0xff));
          stored.push_back(value);
        }
      }
    }
  }
  cl::Buffer passed = output<cl_int>(states.size());
  run("test_stencil_test", states.size(), buffer(states), buffer(stored), passed);
  const std::vector<cl_int> result = read<cl_int>(passed, states.size());
  int failures = 0;
  for (std::size_t i = 0; i < states.size() && failures < 10; ++i) {
    const StencilUniforms& s = states[i];
    const std::uint32_t ref = s.reference & s.read_mask;
    const std::uint32_t value = stored[i] & s.read_mask;
    const bool expected = s.func == CLR_COMPARE_NEVER     ? false
                          : s.func == CLR_COMPARE_LESS     ? ref < value
                          : s.func == CLR_COMPARE_EQUAL    ? ref == value
                          : s.func == CLR_COMPARE_LEQUAL   ? ref <= value
                          : s.func == CLR_COMPARE_GREATER  ? ref > value
                          : s.func == CLR_COMPARE_NOTEQUAL ? ref != value
                          : s.func == CLR_COMPARE_GEQUAL   ? ref >= value
                                                           : true;
    if ((result[i] != 0) != expected) {
      ++failures;
      ADD_FAILURE() << "func " << s.func << ", reference " << s.reference << ", read mask " << s.read_mask
                    << ", stored " << stored[i] << ": expected " << expected;
    }
  }
}

TEST_F(FragmentOpsTest, StencilOpsSaturateOrWrapAndRespectTheWriteMask) {
  const std::vector<std::uint32_t> references = {0x00, 0x5a, 0xff};
  const std::vector<std::uint32_t> write_masks = {0xff, 0x00, 0x0f, 0xf0, 0x01, 0x80};
  std::vector<StencilUniforms> states;
  std::vector<cl_uint> stored;
  for (int op = CLR_STENCIL_KEEP; op <= CLR_STENCIL_INVERT; ++op) {
    for (std::uint32_t reference : references) {
      for (std::uint32_t mask : write_masks) {
        for (std::uint32_t value = 0; value < 256; ++value) {
          states.push_back(stencil_state(CLR_COMPARE_ALWAYS, reference, 0xff, mask, op));
          stored.push_back(value);
        }
      }
    }
  }
  cl::Buffer updated = output<cl_uint>(states.size());
  run("test_stencil_update", states.size(), buffer(states), buffer(stored), updated);
  const std::vector<cl_uint> result = read<cl_uint>(updated, states.size());
  int failures = 0;
  for (std::size_t i = 0; i < states.size() && failures < 10; ++i) {
    const StencilUniforms& s = states[i];
    const std::uint32_t expected = reference_stencil_update(s.depth_pass, s.reference, s.write_mask, stored[i]);
    if (result[i] != expected) {
      ++failures;
      ADD_FAILURE() << "op " << s.depth_pass << ", reference " << s.reference << ", write mask " << s.write_mask
                    << ", stored " << stored[i] << ": " << result[i] << " instead of " << expected;
    }
  }
}

TEST_F(FragmentOpsTest, StencilOpsAtTheirEdges) {
  const std::vector<StencilUniforms> states = {
      stencil_state(CLR_COMPARE_ALWAYS, 0, 0xff, 0xff, CLR_STENCIL_INCR),
      stencil_state(CLR_COMPARE_ALWAYS, 0, 0xff, 0xff, CLR_STENCIL_INCR_WRAP),
      stencil_state(CLR_COMPARE_ALWAYS, 0, 0xff, 0xff, CLR_STENCIL_DECR),
      stencil_state(CLR_COMPARE_ALWAYS, 0, 0xff, 0xff, CLR_STENCIL_DECR_WRAP),
      stencil_state(CLR_COMPARE_ALWAYS, 0, 0xff, 0x0f, CLR_STENCIL_INVERT),
      stencil_state(CLR_COMPARE_ALWAYS, 0xab, 0xff, 0xf0, CLR_STENCIL_REPLACE),
  };
  const std::vector<cl_uint> stored = {255, 255, 0, 0, 0x35, 0x12};
  cl::Buffer updated = output<cl_uint>(states.size());
  run("test_stencil_update", states.size(), buffer(states), buffer(stored), updated);
  EXPECT_EQ(read<cl_uint>(updated, states.size()), (std::vector<cl_uint>{255, 0, 0, 255, 0x3a, 0xa2}));
}

TEST_F(FragmentOpsTest, StencilOpIsChosenByTheStencilThenTheDepthOutcome) {
  StencilUniforms s = stencil_state(CLR_COMPARE_ALWAYS, 0, 0xff, 0xff);
  s.stencil_fail = CLR_STENCIL_ZERO;
  s.depth_fail = CLR_STENCIL_INVERT;
  s.depth_pass = CLR_STENCIL_INCR;
  const std::vector<cl_int> outcomes = {0, 2, 1, 3};  // bit 0: stencil passed, bit 1: depth passed
  const cl_uint stored = 0x35;
  cl::Buffer updated = output<cl_uint>(outcomes.size());
  run("test_stencil_after_tests", outcomes.size(), s, stored, buffer(outcomes), updated);
  // ZERO where the stencil test failed, whatever the depth test did; INVERT, INCR after it.
  EXPECT_EQ(read<cl_uint>(updated, outcomes.size()), (std::vector<cl_uint>{0x00, 0x00, 0xca, 0x36}));
}

// ---- Blending -------------------------------------------------------------------------------------------

BlendUniforms blend_state(int rgb_equation, int src_rgb, int dst_rgb, int alpha_equation, int src_alpha,
                          int dst_alpha) {
  BlendUniforms b{};
  b.enabled = 1;
  b.rgb_equation = rgb_equation;
  b.alpha_equation = alpha_equation;
  b.src_rgb = src_rgb;
  b.dst_rgb = dst_rgb;
  b.src_alpha = src_alpha;
  b.dst_alpha = dst_alpha;
  b.write_mask = 0xf;
  return b;
}

using Rgbad = std::array<double, 4>;

// Table 17.2 of GL 4.6, for channel c (3 is alpha), with colours in units where `one` is 1 (or 255
// for 8-bit values).
double reference_factor(int factor, int c, const Rgbad& s, const Rgbad& d, const Rgbad& k, double one) {
  const bool alpha = c == 3;
  switch (factor) {
    case CLR_FACTOR_ZERO: return 0;
    case CLR_FACTOR_ONE: return one;
    case CLR_FACTOR_SRC_COLOR: return s[c];
    case CLR_FACTOR_ONE_MINUS_SRC_COLOR: return one - s[c];
    case CLR_FACTOR_DST_COLOR: return d[c];
    case CLR_FACTOR_ONE_MINUS_DST_COLOR: return one - d[c];
    case CLR_FACTOR_SRC_ALPHA: return s[3];
    case CLR_FACTOR_ONE_MINUS_SRC_ALPHA: return one - s[3];
    case CLR_FACTOR_DST_ALPHA: return d[3];
    case CLR_FACTOR_ONE_MINUS_DST_ALPHA: return one - d[3];
    case CLR_FACTOR_CONSTANT_COLOR: return k[c];
    case CLR_FACTOR_ONE_MINUS_CONSTANT_COLOR: return one - k[c];
    case CLR_FACTOR_CONSTANT_ALPHA: return k[3];
    case CLR_FACTOR_ONE_MINUS_CONSTANT_ALPHA: return one - k[3];
    default: return alpha ? one : std::min(s[3], one - d[3]);  // SRC_ALPHA_SATURATE
  }
}

// Table 17.1 of GL 4.6 for channel c, in the same units, with products taken by `multiply`.
template <typename Multiply>
double reference_equation(const BlendUniforms& b, int c, const Rgbad& s, const Rgbad& d, const Rgbad& k, double one,
                          Multiply multiply) {
  const bool alpha = c == 3;
  const int equation = alpha ? b.alpha_equation : b.rgb_equation;
  if (equation == CLR_BLEND_MIN) return std::min(s[c], d[c]);
  if (equation == CLR_BLEND_MAX) return std::max(s[c], d[c]);
  const double source_term = multiply(s[c], reference_factor(alpha ? b.src_alpha : b.src_rgb, c, s, d, k, one));
  const double destination_term = multiply(d[c], reference_factor(alpha ? b.dst_alpha : b.dst_rgb, c, s, d, k, one));
  switch (equation) {
    case CLR_BLEND_SUBTRACT: return source_term - destination_term;
    case CLR_BLEND_REVERSE_SUBTRACT: return destination_term - source_term;
    default: return source_term + destination_term;  // CLR_BLEND_ADD
  }
}

// The product of two 8-bit values in llvmpipe (Mesa's lp_build_mul_norm for 8-bit unorm).
double llvmpipe_mul_unorm8(double a, double b) {
  const int ab = static_cast<int>(a) * static_cast<int>(b);
  return (ab + (ab >> 8) + 128) >> 8;
}

// The attachment kinds of test_blend.
enum class Attachment { Float = 0, Normalized = 1, Unorm8 = 2 };
const char* name(Attachment kind) {
  return kind == Attachment::Float ? "float" : kind == Attachment::Normalized ? "normalized" : "8-bit";
}

struct BlendCase {
  Rgba source, destination, constant;
};

float to_unorm8(float v) { return std::nearbyint(std::clamp(v, 0.0f, 1.0f) * 255.0f); }

// What the device must return for channel c, within `tolerance` (float rounding of the products and
// the sum). For 8-bit attachments, in bytes: llvmpipe's fixed-point blend of the inputs converted to
// bytes, with its products, the result saturated.
struct Expected {
  double value;
  double tolerance;
};
Expected reference_blend(const BlendUniforms& b, int c, const BlendCase& colors, Attachment kind) {
  Rgbad s, d, k;
  for (int i = 0; i < 4; ++i) {
    const auto prepare = [&](float v) {
      switch (kind) {
        case Attachment::Float: return double{v};
        case Attachment::Normalized: return std::clamp(double{v}, 0.0, 1.0);  // 17.3.6
        default: return double{to_unorm8(v)};
      }
    };
    s[i] = prepare(colors.source[i]);
    d[i] = prepare(colors.destination[i]);
    k[i] = prepare(colors.constant[i]);
  }
  if (kind == Attachment::Unorm8) {
    return {std::clamp(reference_equation(b, c, s, d, k, 255, llvmpipe_mul_unorm8), 0.0, 255.0), 0};
  }
  double largest = 0;
  for (int i = 0; i < 4; ++i) largest = std::max({largest, std::abs(s[i]), std::abs(d[i]), std::abs(k[i])});
  const auto multiply = [](double a, double b) { return a * b; };
  return {reference_equation(b, c, s, d, k, 1, multiply), 1e-6 * (1 + largest) * (1 + largest)};
}

class BlendTest : public FragmentOpsTest {
 protected:
  std::vector<Rgba> blend(const std::vector<BlendUniforms>& states, const std::vector<BlendCase>& cases,
                          Attachment kind) {
    std::vector<Rgba> sources, destinations, constants;
    for (const BlendCase& c : cases) {
      sources.push_back(c.source);
      destinations.push_back(c.destination);
      constants.push_back(c.constant);
    }
    const std::size_t count = states.size() * cases.size();
    cl::Buffer blended = output<Rgba>(count);
    run("test_blend", count, buffer(states), buffer(sources), buffer(destinations), buffer(constants),
        cl_uint(cases.size()), cl_int(kind), blended);
    return read<Rgba>(blended, count);
  }

  Rgba blend(const BlendUniforms& state, const BlendCase& c, Attachment kind) {
    return blend(std::vector<BlendUniforms>{state}, std::vector<BlendCase>{c}, kind)[0];
  }

  // Every state on every colour case; checks each channel against reference_blend.
  void expect_reference(const std::vector<BlendUniforms>& states, const std::vector<BlendCase>& cases,
                        Attachment kind) {
    const std::vector<Rgba> result = blend(states, cases, kind);
    int failures = 0;
    for (std::size_t i = 0; i < result.size() && failures < 10; ++i) {
      const BlendUniforms& b = states[i / cases.size()];
      const BlendCase& c = cases[i % cases.size()];
      for (int channel = 0; channel < 4; ++channel) {
        const Expected expected = reference_blend(b, channel, c, kind);
        const double actual = kind == Attachment::Unorm8 ? to_unorm8(result[i][channel]) : result[i][channel];
        if (!(std::abs(actual - expected.value) <= expected.tolerance)) {
          ++failures;
          ADD_FAILURE() << name(kind) << " rgb " << b.rgb_equation << "(" << b.src_rgb << ", " << b.dst_rgb
                        << "), alpha " << b.alpha_equation << "(" << b.src_alpha << ", " << b.dst_alpha
                        << "), source " << describe(c.source) << ", destination " << describe(c.destination)
                        << ", constant " << describe(c.constant) << ": channel " << channel << " is " << actual
                        << " instead of " << expected.value;
        }
      }
    }
  }
};

// Every equation with every pair of factors for rgb, and, in the same states, every equation with
// every pair of factors for alpha (a different equation and the factors swapped, so a mix-up of the
// rgb and alpha state shows).
std::vector<BlendUniforms> every_equation_and_factor_pair() {
  std::vector<BlendUniforms> states;
  for (int equation = CLR_BLEND_ADD; equation <= CLR_BLEND_MAX; ++equation) {
    for (int src = CLR_FACTOR_ZERO; src <= CLR_FACTOR_SRC_ALPHA_SATURATE; ++src) {
      for (int dst = CLR_FACTOR_ZERO; dst <= CLR_FACTOR_SRC_ALPHA_SATURATE; ++dst) {
        states.push_back(blend_state(equation, src, dst, (equation + 2) % 5, dst, src));
      }
    }
  }
  return states;
}

// Colours whose channels all differ, so that a factor taken from the wrong channel shows.
std::vector<BlendCase> colour_grid(const std::vector<Rgba>& sources, const std::vector<Rgba>& destinations,
                                   const std::vector<Rgba>& constants) {
  std::vector<BlendCase> cases;
  for (const Rgba& s : sources) {
    for (const Rgba& d : destinations) {
      for (const Rgba& k : constants) cases.push_back({s, d, k});
    }
  }
  return cases;
}

TEST_F(BlendTest, NormalizedAttachmentsClampInputsThenBlendAsGL) {
  const std::vector<BlendCase> cases = colour_grid(
      {{0.2f, 0.5f, 0.9f, 0.6f}, {0.0f, 1.0f, 0.75f, 0.0f}, {0.1f, 0.4f, 0.7f, 1.0f}, {1.5f, -0.25f, 0.3f, 1.25f},
       {-1.0f, 2.0f, 0.55f, -0.5f}},
      {{0.3f, 0.8f, 0.15f, 0.45f}, {1.0f, 0.0f, 0.5f, 1.0f}, {0.65f, 0.35f, 0.95f, 0.0f}, {1.75f, -0.5f, 0.25f, 3.0f}},
      {{0.3f, 0.6f, 0.9f, 0.45f}, {-0.5f, 1.5f, 0.25f, 1.2f}});
  expect_reference(every_equation_and_factor_pair(), cases, Attachment::Normalized);
}

TEST_F(BlendTest, FloatAttachmentsBlendOutOfRangeValuesUnclamped) {
  const std::vector<BlendCase> cases = colour_grid(
      {{0.2f, 0.5f, 0.9f, 0.6f}, {3.5f, -2.0f, 0.25f, 1.75f}, {-0.5f, 10.0f, 1.0f, -0.25f}, {0.0f, 1.0f, 0.3f, 0.0f}},
      {{0.3f, 0.8f, 0.15f, 0.45f}, {-1.5f, 4.0f, 0.5f, 2.5f}, {1.25f, 0.0f, -3.0f, -0.75f}},
      {{0.3f, 0.6f, 0.9f, 0.45f}, {-0.5f, 1.5f, 2.25f, 1.2f}});
  expect_reference(every_equation_and_factor_pair(), cases, Attachment::Float);
}

TEST_F(BlendTest, EightBitAttachmentsBlendInFixedPointAsLlvmpipe) {
  // Fragment and constant colours off the 8-bit grid, on its rounding ties and out of range.
  const std::vector<BlendCase> cases = colour_grid(
      {{0.2f, 0.5f, 0.9f, 0.6f}, {0.0f, 1.0f, 0.7513f, 0.0f}, {0.1f, 0.4f, 0.7f, 1.0f}, {1.5f, -0.25f, 0.3f, 1.25f},
       {0.5f / 255.0f, 1.5f / 255.0f, 0.33f, 0.91f}},
      {{77.0f / 255.0f, 204.0f / 255.0f, 38.0f / 255.0f, 115.0f / 255.0f}, {1.0f, 0.0f, 128.0f / 255.0f, 1.0f},
       {166.0f / 255.0f, 89.0f / 255.0f, 242.0f / 255.0f, 0.0f}},
      {{0.3f, 0.6f, 0.9f, 0.45f}, {-0.5f, 1.5f, 0.25f, 0.7f}});
  expect_reference(every_equation_and_factor_pair(), cases, Attachment::Unorm8);
}

TEST_F(BlendTest, EightBitAttachmentsRoundEachProductNotTheSum) {
  // SRC_ALPHA, ONE_MINUS_SRC_ALPHA with 51 over 153, alpha 51: 10.2 + 122.4 blends to 10 + 122 = 132
  // (llvmpipe), not round(132.6) = 133.
  const BlendUniforms over = blend_state(CLR_BLEND_ADD, CLR_FACTOR_SRC_ALPHA, CLR_FACTOR_ONE_MINUS_SRC_ALPHA,
                                         CLR_BLEND_ADD, CLR_FACTOR_ONE, CLR_FACTOR_ZERO);
  const float grey = 51.0f / 255.0f;
  const Rgba result = blend(over, {{grey, grey, grey, grey}, {0.6f, 0.6f, 0.6f, 1.0f}, {}}, Attachment::Unorm8);
  EXPECT_EQ(to_unorm8(result[0]), 132.0f);
}

TEST_F(BlendTest, EightBitProductsJustAboveAHalfRoundDownAsInLlvmpipe) {
  // 152 * 229 / 255 = 136.502: llvmpipe's (ab + (ab >> 8) + 128) >> 8 gives 136.
  const BlendUniforms modulate = blend_state(CLR_BLEND_ADD, CLR_FACTOR_DST_COLOR, CLR_FACTOR_ZERO, CLR_BLEND_ADD,
                                             CLR_FACTOR_ONE, CLR_FACTOR_ZERO);
  const Rgba result =
      blend(modulate, {{152.0f / 255.0f, 0, 0, 1}, {229.0f / 255.0f, 0, 0, 1}, {}}, Attachment::Unorm8);
  EXPECT_EQ(to_unorm8(result[0]), 136.0f);
}

TEST_F(BlendTest, SrcAlphaSaturateIsTheSmallerOfSourceAlphaAndOneMinusDestinationAlphaAndOneForAlpha) {
  const BlendUniforms saturate = blend_state(CLR_BLEND_ADD, CLR_FACTOR_SRC_ALPHA_SATURATE, CLR_FACTOR_ZERO,
                                             CLR_BLEND_ADD, CLR_FACTOR_SRC_ALPHA_SATURATE, CLR_FACTOR_ZERO);
  const Rgba result = blend(saturate, {{0.8f, 0.4f, 0.2f, 0.75f}, {0.0f, 0.0f, 0.0f, 0.5f}, {}}, Attachment::Normalized);
  EXPECT_FLOAT_EQ(result[0], 0.8f * 0.5f);
  EXPECT_FLOAT_EQ(result[1], 0.4f * 0.5f);
  EXPECT_FLOAT_EQ(result[2], 0.2f * 0.5f);
  EXPECT_FLOAT_EQ(result[3], 0.75f);
}

TEST_F(BlendTest, ConstantColourIsClampedOnlyForNormalizedAttachments) {
  const BlendUniforms constant = blend_state(CLR_BLEND_ADD, CLR_FACTOR_CONSTANT_COLOR, CLR_FACTOR_ZERO,
                                             CLR_BLEND_ADD, CLR_FACTOR_CONSTANT_ALPHA, CLR_FACTOR_ZERO);
  const BlendCase c{{0.5f, 0.5f, 0.5f, 0.5f}, {}, {2.0f, -1.0f, 0.5f, 3.0f}};
  EXPECT_EQ(blend(constant, c, Attachment::Normalized), (Rgba{0.5f, 0.0f, 0.25f, 0.5f}));
  EXPECT_EQ(blend(constant, c, Attachment::Float), (Rgba{1.0f, -0.5f, 0.25f, 1.5f}));
}

TEST_F(BlendTest, MinAndMaxIgnoreTheFactors) {
  const BlendUniforms min_max = blend_state(CLR_BLEND_MIN, CLR_FACTOR_ZERO, CLR_FACTOR_ZERO, CLR_BLEND_MAX,
                                            CLR_FACTOR_ZERO, CLR_FACTOR_ZERO);
  EXPECT_EQ(blend(min_max, {{0.25f, 0.75f, 0.5f, 0.25f}, {0.5f, 0.5f, 0.5f, 0.5f}, {}}, Attachment::Normalized),
            (Rgba{0.25f, 0.5f, 0.5f, 0.5f}));
}

TEST_F(BlendTest, SubtractionIsNotClampedBeforeTheConversionToTheAttachment) {
  const BlendUniforms subtract = blend_state(CLR_BLEND_SUBTRACT, CLR_FACTOR_ONE, CLR_FACTOR_ONE,
                                             CLR_BLEND_REVERSE_SUBTRACT, CLR_FACTOR_ONE, CLR_FACTOR_ONE);
  EXPECT_EQ(blend(subtract, {{0.25f, 1.0f, 0.5f, 0.75f}, {0.5f, 0.25f, 0.5f, 0.25f}, {}}, Attachment::Normalized),
            (Rgba{-0.25f, 0.75f, 0.0f, -0.5f}));
}

TEST_F(FragmentOpsTest, WriteMaskKeepsTheDestinationInMaskedChannels) {
  std::vector<cl_uint> masks(16);
  for (cl_uint m = 0; m < 16; ++m) masks[m] = m;
  const cl_float4 value{{1, 2, 3, 4}};
  const cl_float4 destination{{-1, -2, -3, -4}};
  cl::Buffer out = output<Rgba>(masks.size());
  run("test_write_mask", masks.size(), buffer(masks), value, destination, out);
  const std::vector<Rgba> result = read<Rgba>(out, masks.size());
  for (cl_uint m = 0; m < 16; ++m) {
    for (int c = 0; c < 4; ++c) {
      EXPECT_EQ(result[m][c], (m >> c) & 1 ? value.s[c] : destination.s[c]) << "mask " << m << " channel " << c;
    }
  }
}

// ---- Advanced blend modes (KHR_blend_equation_advanced) ------------------------------------------------

using Rgbd = std::array<double, 3>;

double lum(const Rgbd& c) { return 0.30 * c[0] + 0.59 * c[1] + 0.11 * c[2]; }
double min3(const Rgbd& c) { return std::min({c[0], c[1], c[2]}); }
double max3(const Rgbd& c) { return std::max({c[0], c[1], c[2]}); }

Rgbd clip_color(Rgbd c) {
  const double l = lum(c);
  const double lo = min3(c);
  const double hi = max3(c);
  if (lo < 0) {
    for (double& x : c) x = l + (x - l) * l / (l - lo);
  }
  if (hi > 1) {
    for (double& x : c) x = l + (x - l) * (1 - l) / (hi - l);
  }
  return c;
}

Rgbd set_lum(Rgbd base, const Rgbd& with_lum) {
  const double difference = lum(with_lum) - lum(base);
  for (double& x : base) x += difference;
  return clip_color(base);
}

Rgbd set_lum_sat(const Rgbd& base, const Rgbd& with_sat, const Rgbd& with_lum) {
  const double base_sat = max3(base) - min3(base);
  Rgbd c{0, 0, 0};
  if (base_sat > 0) {
    for (int i = 0; i < 3; ++i) c[i] = (base[i] - min3(base)) * (max3(with_sat) - min3(with_sat)) / base_sat;
  }
  return set_lum(c, with_lum);
}

// f(Cs, Cd) of tables X.1 (per channel) and X.2 (whole colours), in the order of test_advanced.
Rgbd reference_f(int mode, const Rgbd& cs, const Rgbd& cd) {
  switch (mode) {
    case 11: return set_lum_sat(cs, cd, cd);
    case 12: return set_lum_sat(cd, cs, cd);
    case 13: return set_lum(cs, cd);
    case 14: return set_lum(cd, cs);
    default: break;
  }
  Rgbd f;
  for (int i = 0; i < 3; ++i) {
    const double s = cs[i];
    const double d = cd[i];
    switch (mode) {
      case 0: f[i] = s * d; break;
      case 1: f[i] = s + d - s * d; break;
      case 2: f[i] = d <= 0.5 ? 2 * s * d : 1 - 2 * (1 - s) * (1 - d); break;
      case 3: f[i] = std::min(s, d); break;
      case 4: f[i] = std::max(s, d); break;
      case 5: f[i] = d <= 0 ? 0 : s < 1 ? std::min(1.0, d / (1 - s)) : 1; break;
      case 6: f[i] = d >= 1 ? 1 : s > 0 ? 1 - std::min(1.0, (1 - d) / s) : 0; break;
      case 7: f[i] = s <= 0.5 ? 2 * s * d : 1 - 2 * (1 - s) * (1 - d); break;
      case 8:
        f[i] = s <= 0.5    ? d - (1 - 2 * s) * d * (1 - d)
               : d <= 0.25 ? d + (2 * s - 1) * d * ((16 * d - 12) * d + 3)
                           : d + (2 * s - 1) * (std::sqrt(d) - d);
        break;
      case 9: f[i] = std::abs(d - s); break;
      default: f[i] = s + d - 2 * s * d; break;  // EXCLUSION
    }
  }
  return f;
}

// The extension's blend of premultiplied colours with (X, Y, Z) = (1, 1, 1).
Rgbad reference_advanced(int mode, const Rgba& source, const Rgba& destination) {
  const double as = source[3];
  const double ad = destination[3];
  Rgbd cs, cd;
  for (int i = 0; i < 3; ++i) {
    cs[i] = as == 0 ? 0 : source[i] / as;
    cd[i] = ad == 0 ? 0 : destination[i] / ad;
  }
  const double p0 = as * ad;
  const double p1 = as * (1 - ad);
  const double p2 = ad * (1 - as);
  const Rgbd f = reference_f(mode, cs, cd);
  Rgbad result;
  for (int i = 0; i < 3; ++i) result[i] = f[i] * p0 + cs[i] * p1 + cd[i] * p2;
  result[3] = p0 + p1 + p2;
  return result;
}

constexpr const char* kAdvancedModes[] = {"multiply",   "screen",    "overlay",    "darken",     "lighten",
                                          "colordodge", "colorburn", "hardlight",  "softlight",  "difference",
                                          "exclusion",  "hsl_hue",   "hsl_saturation", "hsl_color", "hsl_luminosity"};

class AdvancedBlendTest : public FragmentOpsTest {
 protected:
  std::vector<Rgba> run_mode(int mode, const std::vector<Rgba>& sources, const std::vector<Rgba>& destinations) {
    cl::Buffer blended = output<Rgba>(sources.size());
    run("test_advanced", sources.size(), cl_int{mode}, buffer(sources), buffer(destinations), blended);
    return read<Rgba>(blended, sources.size());
  }
};

Rgba premultiplied(const Rgba& straight, float alpha) {
  return {straight[0] * alpha, straight[1] * alpha, straight[2] * alpha, alpha};
}

TEST_F(AdvancedBlendTest, EveryModeMatchesTheExtensionOnPremultipliedColours) {
  // Straight colours on the modes' branch points (0, 0.25, 0.5, 1), greys (no saturation) and
  // saturated colours whose HSL mixes leave [0, 1] and need ClipColor; alphas 0, partial and 1.
  const std::vector<Rgba> straight = {{0.0f, 0.0f, 0.0f, 0},     {1.0f, 1.0f, 1.0f, 0},  {0.5f, 0.5f, 0.5f, 0},
                                      {0.25f, 0.5f, 1.0f, 0},    {1.0f, 0.25f, 0.0f, 0}, {0.1f, 0.7f, 0.3f, 0},
                                      {0.9f, 0.2f, 0.6f, 0},     {0.0f, 1.0f, 0.75f, 0}, {0.35f, 0.05f, 0.95f, 0},
                                      {0.6f, 0.6f, 0.2f, 0}};
  const std::vector<float> alphas = {0.0f, 0.4f, 1.0f};
  std::vector<Rgba> sources, destinations;
  for (const Rgba& s : straight) {
    for (float as : alphas) {
      for (const Rgba& d : straight) {
        for (float ad : alphas) {
          sources.push_back(premultiplied(s, as));
          destinations.push_back(premultiplied(d, ad));
        }
      }
    }
  }
  for (int mode = 0; mode < 15; ++mode) {
    const std::vector<Rgba> result = run_mode(mode, sources, destinations);
    int failures = 0;
    for (std::size_t i = 0; i < sources.size() && failures < 5; ++i) {
      const Rgbad expected = reference_advanced(mode, sources[i], destinations[i]);
      for (int c = 0; c < 4; ++c) {
        if (!(std::abs(result[i][c] - expected[c]) <= 1e-5)) {
          ++failures;
          ADD_FAILURE() << kAdvancedModes[mode] << ", source " << describe(sources[i]) << ", destination "
                        << describe(destinations[i]) << ": channel " << c << " is " << result[i][c] << " instead of "
                        << expected[c];
        }
      }
    }
  }
}

TEST_F(AdvancedBlendTest, OpaqueColoursGiveFAndTransparentOnesLeaveTheOther) {
  const Rgba red{1.0f, 0.0f, 0.0f, 1.0f};
  const Rgba grey{0.5f, 0.5f, 0.5f, 1.0f};
  const Rgba clear{0.0f, 0.0f, 0.0f, 0.0f};
  const Rgba half_blue = premultiplied({0.0f, 0.0f, 1.0f, 0}, 0.5f);
  // MULTIPLY of opaque colours is their product; over a transparent destination the source is kept
  // (p1 = As), and a transparent source keeps the destination (p2 = Ad).
  EXPECT_EQ(run_mode(0, {red, red, clear}, {grey, clear, half_blue}),
            (std::vector<Rgba>{{0.5f, 0.0f, 0.0f, 1.0f}, red, half_blue}));
}

}  // namespace
}  // namespace clraster::test
