// Unit tests of the pipeline's device code: primitive assembly, clipping, snapping, the tie-breaking
// rule, and the scan and radix sort that binning stands on. Each test runs the real kernel functions
// through a small test kernel compiled together with the pipeline's sources.
#include "api/impl.hpp"
#include "parallel/radix_sort.hpp"
#include "pipeline/draw_state.hpp"
#include "program/generator.hpp"
#include "program/interface.hpp"
#include "runtime/kernel_sources.hpp"
#include "runtime/launch.hpp"
#include "shared/clr_limits.h"
#include "support/test_support.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numeric>
#include <random>

namespace clraster::test {
namespace {

const char* const kTestKernels = R"CLC(
__kernel void test_stream_positions(int topology, uint count, __global uint* out) {
  for (uint p = 0; p < count; ++p) vstore3(primitive_stream_positions(topology, p), p, out);
}

/* in: 3 vertices of 7 floats (x, y, z, w, three varyings). out: up to 9 vertices. */
__kernel void test_clip(__global const float* in, float2 guard_min, float2 guard_max, __global float* out,
                        __global int* count) {
  ClipVertex poly[CLR_MAX_CLIP_VERTICES];
  for (int i = 0; i < 3; ++i) {
    poly[i].position = vload4(0, in + 7 * i);
    for (int k = 0; k < 3; ++k) poly[i].varyings[k] = in[7 * i + 4 + k];
  }
  /* The decision set-up takes from the vertices' clip codes (setup.cl), restated: rejected when all
   * are outside one plane, clipped against the planes any is outside, else kept as it is. These
   * tests check the codes and clip_polygon; set-up's own decision is checked end to end, against
   * OpenGL, by the conformance tests' scenes that cross and lie behind the near plane. */
  uint any_outside = 0, all_outside = ~0u;
  for (int i = 0; i < 3; ++i) {
    const PositionLanes lanes = position_in_every_lane(poly[i].position);
    const vertex_lanes_int codes = clip_outcode_lanes(&lanes, guard_min, guard_max);
    const uint code = (uint)CLR_VERTEX_LANE(int, codes, 0);
    any_outside |= code;
    all_outside &= code;
  }
  const int n = all_outside ? 0 : any_outside ? clip_polygon(poly, 3, any_outside, guard_min, guard_max) : 3;
  for (int i = 0; i < n; ++i) {
    vstore4(poly[i].position, 0, out + 7 * i);
    for (int k = 0; k < 3; ++k) out[7 * i + 4 + k] = poly[i].varyings[k];
  }
  *count = n;
}

__kernel void test_project(__global const float4* clip, uint count, __constant const DrawUniforms* u,
                           __global int* out) {
  for (uint i = 0; i < count; ++i) {
    ClipVertex v;
    v.position = clip[i];
    WindowVertex w;
    const bool ok = project_vertex(&v, u, &w);
    out[3 * i] = ok;
    out[3 * i + 1] = ok ? w.fixed.x : 0;
    out[3 * i + 2] = ok ? w.fixed.y : 0;
  }
}

/* edges: ax, ay, bx, by per edge */
__kernel void test_edge_rule(__global const int* edges, uint count, __global int* out) {
  for (uint i = 0; i < count; ++i) {
    out[i] = edge_includes_centres((int2)(edges[4 * i], edges[4 * i + 1]), (int2)(edges[4 * i + 2], edges[4 * i + 3]));
  }
}
)CLC";

class KernelTest : public ::testing::Test {
 protected:
  void SetUp() override { program_ = build_test_program("kernel unit tests", builtin_stage_program() + kTestKernels); }

  virtual ContextState& state() { return *shared_context().impl().state; }

  // A device copy of `data`, padded to at least 16 bytes.
  template <typename T>
  cl::Buffer buffer(std::vector<T> data) {
    data.resize(std::max<std::size_t>(data.size(), (16 + sizeof(T) - 1) / sizeof(T)));
    return cl::Buffer(state().context, CL_MEM_READ_WRITE | CL_MEM_COPY_HOST_PTR, data.size() * sizeof(T), data.data());
  }

  template <typename T>
  std::vector<T> read(const cl::Buffer& buffer, std::size_t count) {
    std::vector<T> data(count);
    state().queue.get().enqueueReadBuffer(buffer, CL_TRUE, 0, count * sizeof(T), data.data());
    return data;
  }

  template <typename... Args>
  void run_single(const char* name, const Args&... args) {
    cl::Kernel kernel(program_, name);
    runtime::set_args(kernel, args...);
    state().queue.get().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(1), cl::NDRange(1));
    state().queue.get().finish();
  }

  cl::Program program_;
};

// ---- Primitive assembly ---------------------------------------------------------------------------

TEST_F(KernelTest, ListsTakeThreeConsecutiveVertices) {
  cl::Buffer out = buffer(std::vector<cl_uint>(12));
  run_single("test_stream_positions", cl_int{0}, cl_uint{3}, out);
  EXPECT_EQ(read<cl_uint>(out, 9), (std::vector<cl_uint>{0, 1, 2, 3, 4, 5, 6, 7, 8}));
}

TEST_F(KernelTest, StripsSwapTheFirstTwoVerticesOfOddTriangles) {
  // OpenGL 4.6 section 10.1.3: triangle i of a strip is (i, i+1, i+2) for even i, (i+1, i, i+2) for odd i.
  cl::Buffer out = buffer(std::vector<cl_uint>(12));
  run_single("test_stream_positions", cl_int{1}, cl_uint{4}, out);
  EXPECT_EQ(read<cl_uint>(out, 12), (std::vector<cl_uint>{0, 1, 2, 2, 1, 3, 2, 3, 4, 4, 3, 5}));
}

TEST_F(KernelTest, FansShareTheFirstVertex) {
  cl::Buffer out = buffer(std::vector<cl_uint>(9));
  run_single("test_stream_positions", cl_int{2}, cl_uint{3}, out);
  EXPECT_EQ(read<cl_uint>(out, 9), (std::vector<cl_uint>{0, 1, 2, 0, 2, 3, 0, 3, 4}));
}

// ---- Block culling's index ranges --------------------------------------------------------------------

// The elements (positions from the draw's first) of primitive p: OpenGL's order, as above.
std::array<std::uint32_t, 3> primitive_elements(int topology, std::uint32_t p) {
  if (topology == CLR_TOPOLOGY_LIST) return {3 * p, 3 * p + 1, 3 * p + 2};
  if (topology == CLR_TOPOLOGY_STRIP) return {p, p + 1, p + 2};
  return {0, p + 1, p + 2};
}

// Each block's two ranges (block_index_ranges, for block culling) are its smallest and largest
// index split at their midpoint, each side shrunk to the indices it has: for lists, strips and fans,
// 16- and 32-bit indices, from an element past the buffer's first, on indices in two clusters as a
// grid's rows are, with outliers (a fan's centre among them).
TEST_F(KernelTest, BlockIndexRangesAreTheTwoHalvesOfTheirBlocksIndices) {
  std::mt19937 random(17);
  std::vector<std::uint32_t> indices(1003);
  for (std::size_t i = 0; i < indices.size(); ++i) {
    indices[i] = static_cast<std::uint32_t>(i % 2 ? 40000 + random() % 300 : 100 + random() % 300);
    if (random() % 50 == 0) indices[i] = static_cast<std::uint32_t>(random() % 60000);
  }
  const std::uint32_t first = 3;
  cl::Kernel kernel(state().core_program(), "block_index_ranges");
  for (int topology : {CLR_TOPOLOGY_LIST, CLR_TOPOLOGY_STRIP, CLR_TOPOLOGY_FAN}) {
    for (int index_size : {2, 4}) {
      const std::uint32_t elements = static_cast<std::uint32_t>(indices.size()) - first;
      const std::uint32_t primitives = topology == CLR_TOPOLOGY_LIST ? elements / 3 : elements - 2;
      const std::size_t blocks = runtime::divide_round_up(primitives, CLR_CULL_BLOCK_PRIMITIVES);
      cl::Buffer index_buffer = index_size == 4 ? buffer(indices)
                                                : buffer(std::vector<cl_ushort>(indices.begin(), indices.end()));
      cl::Buffer ranges = buffer(std::vector<cl_uint4>(blocks));
      runtime::set_args(kernel, index_buffer, cl_int{index_size}, first, primitives, cl_int{topology}, ranges);
      state().queue.get().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(blocks), cl::NullRange);
      const std::vector<cl_uint4> result = read<cl_uint4>(ranges, blocks);
      for (std::uint32_t b = 0; b < blocks; ++b) {
        std::vector<std::uint32_t> used;
        for (std::uint32_t p = b * CLR_CULL_BLOCK_PRIMITIVES; p < std::min(primitives, (b + 1) * CLR_CULL_BLOCK_PRIMITIVES); ++p) {
          for (std::uint32_t e : primitive_elements(topology, p)) used.push_back(indices[first + e]);
        }
        const auto [lowest, highest] = std::minmax_element(used.begin(), used.end());
        const std::uint32_t middle = *lowest + (*highest - *lowest) / 2;
        std::uint32_t lower_last = *lowest, upper_first = *highest;
        for (std::uint32_t index : used) {
          if (index <= middle) lower_last = std::max(lower_last, index);
          else upper_first = std::min(upper_first, index);
        }
        EXPECT_EQ((std::array<cl_uint, 4>{result[b].s[0], result[b].s[1], result[b].s[2], result[b].s[3]}),
                  (std::array<cl_uint, 4>{*lowest, lower_last, upper_first, *highest}))
            << "topology " << topology << ", " << index_size << "-byte indices, block " << b;
      }
    }
  }
}

// ---- Clipping ---------------------------------------------------------------------------------------

struct ClipResult {
  int count = 0;
  std::vector<float> vertices;  // 7 floats per vertex
};

class ClipTest : public KernelTest {
 protected:
  ClipResult clip(const std::vector<float>& triangle, float guard = 1000.0f) {
    cl::Buffer in = buffer(triangle);
    cl::Buffer out = buffer(std::vector<float>(7 * CLR_MAX_CLIP_VERTICES));
    cl::Buffer count = buffer(std::vector<cl_int>(1));
    run_single("test_clip", in, cl_float2{{-guard, -guard}}, cl_float2{{guard, guard}}, out, count);
    ClipResult result;
    result.count = read<cl_int>(count, 1)[0];
    result.vertices = read<float>(out, 7 * CLR_MAX_CLIP_VERTICES);
    result.vertices.resize(7 * std::max(result.count, 0));
    return result;
  }
};

TEST_F(ClipTest, TrianglesInsideAreReturnedBitForBit) {
  const std::vector<float> triangle = {-0.5f, -0.5f, 0.1f, 1, 1, 2, 3, 0.5f, -0.5f, 0.2f, 1, 4, 5, 6,
                                       0, 0.5f, -0.3f, 1.5f, 7, 8, 9};
  const ClipResult result = clip(triangle);
  ASSERT_EQ(result.count, 3);
  EXPECT_EQ(result.vertices, triangle);
}

TEST_F(ClipTest, TrianglesBehindTheNearPlaneVanish) {
  EXPECT_EQ(clip({0, 0, -2, 1, 0, 0, 0, 1, 0, -3, 1, 0, 0, 0, 0, 1, -2.5f, 1, 0, 0, 0}).count, 0);
}

TEST_F(ClipTest, TrianglesBeyondTheFarPlaneVanish) {
  EXPECT_EQ(clip({0, 0, 2, 1, 0, 0, 0, 1, 0, 3, 1, 0, 0, 0, 0, 1, 2.5f, 1, 0, 0, 0}).count, 0);
}

TEST_F(ClipTest, OneVertexBehindTheNearPlaneGivesAQuadOnThePlane) {
  // Vertex 0 at z = -3 (w = 1) is behind near (z >= -w). Edges 0-1 and 2-0 cross z = -1 a third of
  // the way from their inside end (distances 1 inside, -2 outside).
  const ClipResult r = clip({0, 0, -3, 1, 10, 0, 0, 1, 0, 0, 1, 40, 0, 0, 0, 1, 0, 1, 70, 0, 0});
  ASSERT_EQ(r.count, 4);
  int on_plane = 0;
  for (int i = 0; i < r.count; ++i) {
    const float* v = &r.vertices[7 * i];
    EXPECT_GE(v[2] + v[3], -1e-6f) << "vertex " << i << " is behind the near plane";
    if (std::abs(v[2] + v[3]) < 1e-6f) {
      ++on_plane;
      // The varying is interpolated with the position: from 40 (or 70) a third of the way to 10.
      EXPECT_TRUE(std::abs(v[4] - 30.0f) < 1e-4f || std::abs(v[4] - 50.0f) < 1e-4f) << v[4];
    }
  }
  EXPECT_EQ(on_plane, 2);
}

TEST_F(ClipTest, TriangleSpanningNearAndFarIsCutByBoth) {
  // One vertex behind near, one beyond far, one inside: the inside vertex plus two points on each
  // plane, a pentagon.
  const ClipResult r = clip({-1, 0, -3, 1, 0, 0, 0, 1, 0, 3, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 0});
  ASSERT_EQ(r.count, 5);
  int on_near = 0, on_far = 0;
  for (int i = 0; i < r.count; ++i) {
    const float* v = &r.vertices[7 * i];
    EXPECT_GE(v[2] + v[3], -1e-6f);
    EXPECT_GE(v[3] - v[2], -1e-6f);
    on_near += std::abs(v[2] + v[3]) < 1e-6f;
    on_far += std::abs(v[3] - v[2]) < 1e-6f;
  }
  EXPECT_EQ(on_near, 2);
  EXPECT_EQ(on_far, 2);
}

TEST_F(ClipTest, TrianglesCrossingWZeroKeepOnlyTheirPositiveWPart) {
  // Guard-band planes x >= -g w and x <= g w together imply w >= 0.
  const ClipResult r = clip({0, 0, 0, 1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 0}, 10.0f);
  ASSERT_GE(r.count, 3);
  for (int i = 0; i < r.count; ++i) EXPECT_GE(r.vertices[7 * i + 3], 0.0f);
}

TEST_F(ClipTest, SharedEdgesAreClippedToBitIdenticalPoints) {
  // Two triangles sharing the edge a-b that crosses the near plane, listed in opposite directions.
  const std::vector<float> a = {0.3f, 0.1f, -2.7f, 1.1f, 0, 0, 0};
  const std::vector<float> b = {-0.2f, 0.4f, 0.3f, 0.9f, 0, 0, 0};
  const std::vector<float> c = {0.5f, 0.6f, 0.2f, 1.0f, 0, 0, 0};
  const std::vector<float> d = {-0.6f, -0.3f, 0.1f, 1.2f, 0, 0, 0};
  auto concat = [](std::vector<float> x, const std::vector<float>& y, const std::vector<float>& z) {
    x.insert(x.end(), y.begin(), y.end());
    x.insert(x.end(), z.begin(), z.end());
    return x;
  };
  const ClipResult first = clip(concat(a, b, c));
  const ClipResult second = clip(concat(b, a, d));
  auto near_points = [](const ClipResult& r) {
    std::vector<std::vector<float>> points;
    for (int i = 0; i < r.count; ++i) {
      const float* v = &r.vertices[7 * i];
      if (v[2] + v[3] == 0.0f || std::abs(v[2] + v[3]) < 1e-6f) points.push_back({v[0], v[1], v[2], v[3]});
    }
    return points;
  };
  // The point where a-b crosses the plane appears in both, bit for bit.
  int shared = 0;
  for (const auto& p : near_points(first)) {
    for (const auto& q : near_points(second)) shared += p == q;
  }
  EXPECT_EQ(shared, 1);
}

// ---- Snapping and the tie-breaking rule ---------------------------------------------------------------

TEST_F(KernelTest, WindowCoordinatesSnapToOneTwoHundredFiftySixthOfAPixelAroundPixelCentres) {
  DrawState state;
  pipeline::RenderTarget target;
  target.width = target.height = target.layer_width = target.layer_height = 256;
  const std::string builtin = runtime::sources::text("program/builtin/normal.cl");
  DrawUniforms u = pipeline::make_uniforms(state, target, program::parse_program(builtin, "normal.cl"), 0);  // NDC x -> (x + 1) * 128
  cl::Buffer uniforms = buffer(std::vector<DrawUniforms>{u});
  // Window x = 10.5 (a pixel centre) -> fixed 10 * 256; x = 10.5 + 1/256 -> 2561; x = 0 -> -128;
  // halfway between two 1/256 steps rounds to even; w = 0 cannot be projected.
  const auto ndc = [](double window) { return static_cast<float>(window / 128.0 - 1.0); };
  const std::vector<cl_float4> clip = {{{ndc(10.5), ndc(20.5), 0, 1}},
                                       {{ndc(10.5 + 1.0 / 256), ndc(0), 0, 1}},
                                       {{ndc(10.5 + 0.5 / 256), ndc(10.5 + 1.5 / 256), 0, 1}},
                                       {{0, 0, 0, 0}}};
  cl::Buffer in = buffer(clip);
  cl::Buffer out = buffer(std::vector<cl_int>(3 * clip.size()));
  run_single("test_project", in, cl_uint(clip.size()), uniforms, out);
  const std::vector<cl_int> r = read<cl_int>(out, 3 * clip.size());
  EXPECT_EQ((std::vector<cl_int>(r.begin(), r.begin() + 9)), (std::vector<cl_int>{1, 2560, 5120, 1, 2561, -128, 1, 2560, 2562}));
  EXPECT_EQ(r[9], 0);
}

TEST_F(KernelTest, CentresOnLeftAndBottomEdgesBelongToTheTriangle) {
  // Edges of counter-clockwise triangles in y-up window coordinates: going down is a left edge,
  // going right horizontally a bottom edge; up, and left horizontally, are right and top edges.
  const std::vector<cl_int> edges = {0, 100, 0, 0,     // down: left edge
                                     0, 0, 100, 0,     // right: bottom edge
                                     100, 0, 0, 100,   // up-left: right edge
                                     100, 100, 0, 100, // left: top edge
                                     0, 0, 0, 100,     // up: right edge
                                     50, 100, 0, 0};   // down-left: left edge
  cl::Buffer in = buffer(edges);
  cl::Buffer out = buffer(std::vector<cl_int>(6));
  run_single("test_edge_rule", in, cl_uint{6}, out);
  EXPECT_EQ(read<cl_int>(out, 6), (std::vector<cl_int>{1, 1, 0, 0, 0, 1}));
}

// ---- Record layouts -----------------------------------------------------------------------------------

// The host sizes the vertex slots and set-up records it allocates with program::shaded_vertex_bytes
// and program::setup_triangle_bytes; the kernels index them with the compiler's layout. Programs
// with few and many varying floats must agree.
TEST_F(KernelTest, HostRecordSizesMatchTheCompilersForEveryVaryingCount) {
  const std::string few = "clr_varying(float, a)\nclr_output(float4, color)\n"
                          "void vertex(clr_vertex* v) { v->out.a = 1.0f; }\n"
                          "void fragment(clr_fragment* f) { f->out.color = (float4)(f->in.a); }\n";
  const std::string many = "clr_varying(float4, a)\nclr_varying(float3, b)\nclr_varying_flat(int2, c)\n"
                           "clr_output(float4, color)\n"
                           "void vertex(clr_vertex* v) { v->out.a = 1.0f; v->out.b = 2.0f; v->out.c = 3; }\n"
                           "void fragment(clr_fragment* f) { f->out.color = f->in.a; }\n";
  const char* const sizes_kernel = R"CLC(
__kernel void test_record_sizes(__global uint* out) {
  out[0] = sizeof(SetupTriangle);
  out[1] = CLR_SHADED_VERTEX_FLOAT4S * sizeof(float4);
  out[2] = CLR_NUM_VARYINGS;
}
)CLC";
  for (const std::string& source : {few, many}) {
    const program::ParsedProgram parsed = program::parse_program(source, "layout.cl");
    program_ = build_test_program("record layout",
                                  program::generate_stage_program(parsed, source, "layout.cl") + sizes_kernel);
    cl::Buffer out = buffer(std::vector<cl_uint>(3));
    run_single("test_record_sizes", out);
    const std::vector<cl_uint> sizes = read<cl_uint>(out, 3);
    SCOPED_TRACE(std::to_string(sizes[2]) + " varying floats");
    EXPECT_EQ(sizes[0], program::setup_triangle_bytes(parsed));
    EXPECT_EQ(sizes[1], program::shaded_vertex_bytes(parsed));
  }
}

// The structs the host fills and the kernels read (types.h): the device compiler's sizes, and the
// offsets of the fields after the nested arrays of structs, are the host's.
TEST_F(KernelTest, SharedStructsHaveTheHostsLayout) {
  const char* const layouts_kernel = R"CLC(
__kernel void test_shared_layouts(__global uint* out) {
  out[0] = sizeof(TextureDesc);
  out[1] = sizeof(BlendUniforms);
  out[2] = sizeof(StencilUniforms);
  out[3] = sizeof(DrawUniforms);
  out[4] = sizeof(AttributeDesc);
  out[5] = sizeof(SlotMap);
  out[6] = __builtin_offsetof(DrawUniforms, blend);
  out[7] = __builtin_offsetof(DrawUniforms, stencil);
  out[8] = __builtin_offsetof(DrawUniforms, clear_color);
  out[9] = __builtin_offsetof(DrawUniforms, streaming_stores);
}
)CLC";
  program_ = build_test_program("shared layouts", builtin_stage_program() + layouts_kernel);
  cl::Buffer out = buffer(std::vector<cl_uint>(10));
  run_single("test_shared_layouts", out);
  EXPECT_EQ(read<cl_uint>(out, 10),
            (std::vector<cl_uint>{sizeof(TextureDesc), sizeof(BlendUniforms), sizeof(StencilUniforms),
                                  sizeof(DrawUniforms), sizeof(AttributeDesc), sizeof(SlotMap),
                                  offsetof(DrawUniforms, blend), offsetof(DrawUniforms, stencil),
                                  offsetof(DrawUniforms, clear_color), offsetof(DrawUniforms, streaming_stores)}));
}

TEST(Rasterization, PixelCentresOnEdgesFollowTheLeftBottomRule) {
  // A right triangle whose legs run through pixel centres: window (0.5, 0.5), (8.5, 0.5), (0.5, 8.5)
  // in a 16x16 framebuffer. Its bottom edge (y = 0.5) and left edge (x = 0.5) include their
  // centres; the hypotenuse (a right/top edge) excludes the centres on it (x + y = 9).
  const auto ndc = [](double window) { return static_cast<float>(window / 8.0 - 1.0); };
  io::Mesh mesh;
  mesh.positions = {ndc(0.5), ndc(0.5), 0, ndc(8.5), ndc(0.5), 0, ndc(0.5), ndc(8.5), 0};
  mesh.normals = {0, 0, 1, 0, 0, 1, 0, 0, 1};
  mesh.indices = {0, 1, 2};
  DrawState state;
  state.shading = Shading::Constant;
  const Image image = render_clraster(shared_context(), mesh, state, 16, 16).image;
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 16; ++x) {
      const bool covered = image.rgba[(static_cast<std::size_t>(15 - y) * 16 + x) * 4] != 0;
      // Centre (x + 0.5, y + 0.5) is inside when x >= 0, y >= 0 and (x + 0.5) + (y + 0.5) < 9.
      EXPECT_EQ(covered, x + y + 1 < 9) << "pixel " << x << ", " << y;
    }
  }
}

// ---- Scan and radix sort ----------------------------------------------------------------------------

// The scans and the sort in both work-group shapes: the device's (one work-item per block on a CPU)
// and the GPU's (256 per block).
class ParallelTest : public KernelTest, public ::testing::WithParamInterface<WorkGroupShape> {
 protected:
  ContextState& state() override { return *shared_context(GetParam()).impl().state; }
};

INSTANTIATE_TEST_SUITE_P(Shapes, ParallelTest, ::testing::Values(WorkGroupShape::Device, WorkGroupShape::Wide),
                         [](const auto& info) { return info.param == WorkGroupShape::Device ? "Device" : "Wide"; });

TEST_P(ParallelTest, ExclusiveScanMatchesTheHostAcrossBlockBoundaries) {
  ContextState& s = state();
  parallel::Scan scan(state().core_program());
  cl::Buffer counters = buffer(std::vector<cl_uint>(CLR_COUNTER_COUNT));
  for (std::size_t n : {std::size_t{1}, std::size_t{CLR_SCAN_BLOCK - 1}, std::size_t{CLR_SCAN_BLOCK + 1},
                        std::size_t{CLR_SCAN_BLOCK * (CLR_SCAN_GPU_ITEMS + 1) + 77}}) {
    // The last: more blocks than a GPU-shaped scan_block_sums takes in one round.
    std::vector<cl_uint> data(n);
    std::mt19937 random(static_cast<unsigned>(n));
    for (cl_uint& v : data) v = random() % 9;
    cl::Buffer device = buffer(data);
    cl::Buffer block_sums(s.context, CL_MEM_READ_WRITE, parallel::Scan::scratch_bytes(n));
    scan.exclusive(s.queue, device, n, block_sums, counters);
    std::vector<cl_uint> expected(n);
    std::exclusive_scan(data.begin(), data.end(), expected.begin(), cl_uint{0});
    EXPECT_EQ(read<cl_uint>(device, n), expected) << "n = " << n;
    EXPECT_EQ(read<cl_uint>(counters, 1)[CLR_COUNTER_SCAN_TOTAL], std::accumulate(data.begin(), data.end(), cl_uint{0}));
  }
}

TEST_P(ParallelTest, ExclusiveScanSaturatesInsteadOfWrapping) {
  // Bin pair counts can add up past 2^32: offsets must stay monotone so the host can split there.
  ContextState& s = state();
  parallel::Scan scan(state().core_program());
  cl::Buffer counters = buffer(std::vector<cl_uint>(CLR_COUNTER_COUNT));
  const std::size_t n = 2 * CLR_SCAN_BLOCK + 5;
  std::vector<cl_uint> data(n, 1u << 22);  // 2^22 * 4101 > 2^32 after 1024 elements
  cl::Buffer device = buffer(data);
  cl::Buffer block_sums(s.context, CL_MEM_READ_WRITE, parallel::Scan::scratch_bytes(n));
  scan.exclusive(s.queue, device, n, block_sums, counters);
  const std::vector<cl_uint> result = read<cl_uint>(device, n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint64_t exact = std::uint64_t{i} << 22;
    ASSERT_EQ(result[i], std::min<std::uint64_t>(exact, 0xffffffffu)) << i;
  }
  EXPECT_EQ(read<cl_uint>(counters, 1)[CLR_COUNTER_SCAN_TOTAL], 0xffffffffu);
}

TEST_P(ParallelTest, RadixSortIsStable) {
  ContextState& s = state();
  parallel::Scan scan(state().core_program());
  parallel::RadixSort sort(state().core_program(), scan);
  // Several blocks of either shape, and keys of 13 bits: more than one pass of either digit size.
  const std::size_t n = 3 * std::max(CLR_RADIX_CPU_BLOCK, CLR_RADIX_GPU_BLOCK) + 123;
  std::vector<cl_uint> keys(n), values(n);
  std::mt19937 random(7);
  for (std::size_t i = 0; i < n; ++i) {
    keys[i] = random() % 5000;  // many equal keys: stability shows
    values[i] = static_cast<cl_uint>(i);
  }
  const cl::Buffer key_buffers[2] = {buffer(keys), buffer(std::vector<cl_uint>(n))};
  const cl::Buffer value_buffers[2] = {buffer(values), buffer(std::vector<cl_uint>(n))};
  cl::Buffer histogram(s.context, CL_MEM_READ_WRITE, parallel::RadixSort::histogram_bytes(n));
  cl::Buffer block_sums(s.context, CL_MEM_READ_WRITE, parallel::RadixSort::scan_scratch_bytes(n));
  cl::Buffer counters = buffer(std::vector<cl_uint>(CLR_COUNTER_COUNT));
  const int result = sort.sort(s.queue, key_buffers, value_buffers, n, 13, histogram, block_sums, counters);

  std::vector<std::pair<cl_uint, cl_uint>> expected(n);
  for (std::size_t i = 0; i < n; ++i) expected[i] = {keys[i], values[i]};
  std::stable_sort(expected.begin(), expected.end(), [](auto& a, auto& b) { return a.first < b.first; });
  const std::vector<cl_uint> sorted_keys = read<cl_uint>(key_buffers[result], n);
  const std::vector<cl_uint> sorted_values = read<cl_uint>(value_buffers[result], n);
  for (std::size_t i = 0; i < n; ++i) {
    ASSERT_EQ(sorted_keys[i], expected[i].first) << i;
    ASSERT_EQ(sorted_values[i], expected[i].second) << i;
  }
}

}  // namespace
}  // namespace clraster::test
