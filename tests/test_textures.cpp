// Unit tests of textures: texel loads, stores and quantization for every format; sampling against
// values worked out by hand and against a small reference written from OpenGL 4.6's formulas
// (sections 8.14 and 8.15); mipmap generation; image files; and every bad input. Device code runs
// through small test kernels compiled with the pipeline's sources.
#include "api/impl.hpp"
#include "runtime/kernel_sources.hpp"
#include "runtime/launch.hpp"
#include "support/test_support.hpp"

#include <stb/stb_image_write.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace clraster::test {
namespace {

const char* const kTestKernels = R"CLC(
/* Texel i <- values[i], then what loading it back and quantizing values[i] give. */
__kernel void test_store_load_float(int format, __global const float4* values, __global uchar* texels,
                                    __global float4* loaded, __global float4* quantized) {
  const uint i = get_global_id(0);
  clr_store_texel_float(format, texels, i, values[i]);
  loaded[i] = clr_load_texel_float(format, texels, i);
  quantized[i] = clr_quantize_float(format, values[i]);
}

__kernel void test_store_load_int(int format, __global const int4* values, __global uchar* texels,
                                  __global int4* loaded_int, __global uint4* loaded_uint) {
  const uint i = get_global_id(0);
  clr_store_texel_int(format, texels, i, values[i]);
  loaded_int[i] = clr_load_texel_int(format, texels, i);
  loaded_uint[i] = clr_load_texel_uint(format, texels, i);
}

__kernel void test_store_uint(int format, __global const uint4* values, __global uchar* texels) {
  clr_store_texel_uint(format, texels, get_global_id(0), values[get_global_id(0)]);
}

/* Per query, 8 floats: s, t, lod, unused, ds/dx, dt/dx, ds/dy, dt/dy. */
__kernel void test_sample(__global const uchar* data, __constant const TextureDesc* desc,
                          __global const float* queries, int gradients, __global float4* out) {
  const uint i = get_global_id(0);
  const clr_texture t = {data, desc};
  __global const float* q = queries + 8 * i;
  const float2 uv = (float2)(q[0], q[1]);
  out[i] = gradients ? clr_sample_grad(t, uv, (float2)(q[4], q[5]), (float2)(q[6], q[7])) : clr_sample_lod(t, uv, q[2]);
}

/* Per query: x, y, level. */
__kernel void test_fetch(__global const uchar* data, __constant const TextureDesc* desc, __global const int* queries,
                         __global float4* as_float, __global int4* as_int, __global uint4* as_uint,
                         __global int* sizes) {
  const uint i = get_global_id(0);
  const clr_texture t = {data, desc};
  const int2 texel = (int2)(queries[3 * i], queries[3 * i + 1]);
  const int level = queries[3 * i + 2];
  as_float[i] = clr_texel_fetch(t, texel, level);
  as_int[i] = clr_texel_fetch_int(t, texel, level);
  as_uint[i] = clr_texel_fetch_uint(t, texel, level);
  const int2 size = clr_texture_size(t, level);
  sizes[3 * i] = size.x;
  sizes[3 * i + 1] = size.y;
  sizes[3 * i + 2] = clr_texture_levels(t);
}
)CLC";

using Texel = std::array<float, 4>;

std::vector<std::byte> bytes_of(const void* data, std::size_t size) {
  const auto* begin = static_cast<const std::byte*>(data);
  return {begin, begin + size};
}
template <typename T>
std::vector<std::byte> bytes_of(const std::vector<T>& values) {
  return bytes_of(values.data(), values.size() * sizeof(T));
}

// What `action` throws as InvalidArgument, or a note that it threw nothing.
template <typename Action>
std::string error_of(Action&& action) {
  try {
    action();
  } catch (const InvalidArgument& error) {
    return error.what();
  }
  return "(no InvalidArgument)";
}

class TextureTest : public ::testing::Test {
 protected:
  void SetUp() override {
    program_ = build_test_program("texture unit tests", runtime::sources::core_program() + kTestKernels);
  }

  static ContextState& state() { return *shared_context().impl().state; }

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

  // One work-item per element.
  template <typename... Args>
  void run(const char* name, std::size_t count, const Args&... args) {
    cl::Kernel kernel(program_, name);
    runtime::set_args(kernel, args...);
    state().queue.get().enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(count));
    state().queue.get().finish();
  }

  struct StoreLoad {
    std::vector<std::uint8_t> bytes;  // the texels as stored, in a buffer first filled with 0xAA
    std::vector<Texel> loaded;
    std::vector<Texel> quantized;
  };
  StoreLoad store_load(Format format, const std::vector<Texel>& values) {
    const std::size_t bytes = values.size() * 16;  // room for the widest format
    cl::Buffer texels = buffer(std::vector<std::uint8_t>(bytes, 0xAA));
    cl::Buffer loaded = buffer(std::vector<Texel>(values.size()));
    cl::Buffer quantized = buffer(std::vector<Texel>(values.size()));
    run("test_store_load_float", values.size(), cl_int(format), buffer(values), texels, loaded, quantized);
    return {read<std::uint8_t>(texels, bytes), read<Texel>(loaded, values.size()),
            read<Texel>(quantized, values.size())};
  }

  cl::Buffer desc_buffer(const Texture& texture, const Sampler& sampler) {
    return buffer(std::vector<TextureDesc>{texture.impl().describe(sampler)});
  }

  // Texel fetches of every kind, and the size and level count queries, at (x, y, level) triples.
  struct Fetched {
    std::vector<Texel> floats;
    std::vector<cl_int4> ints;
    std::vector<cl_uint4> uints;
    std::vector<cl_int> sizes;  // width, height at the level, and the level count, per query
  };
  Fetched fetch(const Texture& texture, const std::vector<cl_int>& queries) {
    const std::size_t count = queries.size() / 3;
    cl::Buffer floats = buffer(std::vector<Texel>(count));
    cl::Buffer ints = buffer(std::vector<cl_int4>(count)), uints = buffer(std::vector<cl_uint4>(count));
    cl::Buffer sizes = buffer(std::vector<cl_int>(3 * count));
    run("test_fetch", count, texture.impl().data, desc_buffer(texture, {}), buffer(queries), floats, ints, uints,
        sizes);
    return {read<Texel>(floats, count), read<cl_int4>(ints, count), read<cl_uint4>(uints, count),
            read<cl_int>(sizes, 3 * count)};
  }

  struct Query {
    float s = 0, t = 0, lod = 0;
    std::array<float, 2> dx{0, 0}, dy{0, 0};
  };
  std::vector<Texel> sample(const Texture& texture, const Sampler& sampler, const std::vector<Query>& queries,
                            bool gradients) {
    std::vector<float> packed;
    for (const Query& q : queries)
      packed.insert(packed.end(), {q.s, q.t, q.lod, 0, q.dx[0], q.dx[1], q.dy[0], q.dy[1]});
    cl::Buffer out = buffer(std::vector<Texel>(queries.size()));
    run("test_sample", queries.size(), texture.impl().data, desc_buffer(texture, sampler), buffer(packed),
        cl_int{gradients}, out);
    return read<Texel>(out, queries.size());
  }
  Texel sample_lod(const Texture& texture, const Sampler& sampler, float s, float t, float lod) {
    return sample(texture, sampler, {Query{s, t, lod}}, false)[0];
  }

  cl::Program program_;
};

Texture float_texture(int width, int height, const std::vector<Texel>& texels, Format format = Format::RGBA32F) {
  return Texture(shared_context(), width, height, format, bytes_of(texels), false);
}

::testing::AssertionResult near(const Texel& actual, const Texel& expected, float tolerance = 1e-5f) {
  for (int c = 0; c < 4; ++c) {
    if (!(std::abs(actual[c] - expected[c]) <= tolerance)) {
      return ::testing::AssertionFailure()
             << "(" << actual[0] << ", " << actual[1] << ", " << actual[2] << ", " << actual[3] << ") is not ("
             << expected[0] << ", " << expected[1] << ", " << expected[2] << ", " << expected[3] << ")";
    }
  }
  return ::testing::AssertionSuccess();
}

// ---- Formats: stores, loads and quantization -----------------------------------------------------------

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr float kInf = std::numeric_limits<float>::infinity();

TEST_F(TextureTest, UnormStoresClampAndRoundToNearestAndReadBackOver255) {
  // 0.5 * 255 = 127.5 -> 128 (the even neighbour); 0.25 * 255 = 63.75 -> 64; 0.998 * 255 = 254.49 -> 254; NaN -> 0.
  const std::vector<Texel> values = {{1, 0.5f, 0.25f, 0}, {-1, 2, kNaN, kInf}, {0.998f, 0.002f, 1.0f / 255, -kInf}};
  const StoreLoad r = store_load(Format::RGBA8, values);
  EXPECT_EQ(std::vector<std::uint8_t>(r.bytes.begin(), r.bytes.begin() + 12),
            (std::vector<std::uint8_t>{255, 128, 64, 0, 0, 255, 0, 255, 254, 1, 1, 0}));
  EXPECT_EQ(r.bytes[12], 0xAA);
  EXPECT_EQ(r.loaded[0], (Texel{1, 128 / 255.0f, 64 / 255.0f, 0}));
  EXPECT_EQ(r.loaded[1], (Texel{0, 1, 0, 1}));
  EXPECT_EQ(r.loaded[2], (Texel{254 / 255.0f, 1 / 255.0f, 1 / 255.0f, 0}));
}

// Ties go to the even byte, as llvmpipe rounds them (OpenGL leaves the direction open): in float,
// 0.3f * 255 is exactly 76.5, and (i + 0.5f) / 255 * 255 is exactly i + 0.5 for these i.
TEST_F(TextureTest, UnormStoresRoundTiesToEvenAsLlvmpipe) {
  const StoreLoad r = store_load(Format::RGBA8, {{0.3f, 1.5f / 255, 2.5f / 255, 0.5f / 255}, {200.5f / 255, 0, 0, 0}});
  EXPECT_EQ(std::vector<std::uint8_t>(r.bytes.begin(), r.bytes.begin() + 5), (std::vector<std::uint8_t>{76, 2, 2, 0, 200}));
}

TEST_F(TextureTest, FormatsWithFewerChannelsWriteOnlyTheirBytesAndReadZeroAndOpaqueAlpha) {
  const std::vector<Texel> values = {{0.2f, 0.4f, 0.6f, 0.8f}, {1, 0, 1, 0}};
  const StoreLoad r8 = store_load(Format::R8, values);
  EXPECT_EQ(std::vector<std::uint8_t>(r8.bytes.begin(), r8.bytes.begin() + 3),
            (std::vector<std::uint8_t>{51, 255, 0xAA}));
  EXPECT_EQ(r8.loaded[0], (Texel{51 / 255.0f, 0, 0, 1}));
  const StoreLoad rg8 = store_load(Format::RG8, values);
  EXPECT_EQ(std::vector<std::uint8_t>(rg8.bytes.begin(), rg8.bytes.begin() + 5),
            (std::vector<std::uint8_t>{51, 102, 255, 0, 0xAA}));
  EXPECT_EQ(rg8.loaded[1], (Texel{1, 0, 0, 1}));
  const StoreLoad r32f = store_load(Format::R32F, values);
  EXPECT_EQ(r32f.loaded[0], (Texel{0.2f, 0, 0, 1}));
  EXPECT_EQ(r32f.bytes[8], 0xAA);
  const StoreLoad rg32f = store_load(Format::RG32F, values);
  EXPECT_EQ(rg32f.loaded[0], (Texel{0.2f, 0.4f, 0, 1}));
  EXPECT_EQ(rg32f.bytes[16], 0xAA);
}

TEST_F(TextureTest, FloatFormatsStoreExactlyAndDepthReadsAsDepthZeroZeroOne) {
  const std::vector<Texel> values = {{0.1f, -3e38f, kInf, 1e-42f}, {0.25f, 7, 8, 9}};
  EXPECT_EQ(store_load(Format::RGBA32F, values).loaded[0], values[0]);
  for (const Format depth : {Format::Depth32F, Format::Depth32FStencil8}) {
    const StoreLoad r = store_load(depth, values);
    EXPECT_EQ(r.loaded[1], (Texel{0.25f, 0, 0, 1}));
    float stored = 0;
    std::memcpy(&stored, r.bytes.data() + 4, 4);
    EXPECT_EQ(stored, 0.25f);
    EXPECT_EQ(r.bytes[8], 0xAA);
  }
}

// llvmpipe converts floats to half rounding toward zero, in clears, fragment stores and blending
// alike (OpenGL leaves the rounding open): finite values beyond half's range become 65504.
TEST_F(TextureTest, HalfFloatsRoundTowardZeroAsLlvmpipe) {
  // Half has 10 mantissa bits: its step just above 1 is 2^-10, and 2^-24 is its smallest subnormal.
  const float one_and_half_step = 1 + 0x1p-11f, one_and_three_half_steps = 1 + 3 * 0x1p-11f;
  const std::vector<Texel> values = {
      {1.0f / 3, one_and_half_step, one_and_three_half_steps, 65519},  // 0x3555, 1, 1 + 2^-10, 65504
      {65520, 0x1p-25f, 3 * 0x1p-25f, -0.0f},                          // 65504, 0, 2^-24, -0
      {1e-10f, -2.5f, 1.0f, kNaN},
      {1e9f, -0.35f, kInf, -kInf}};  // 65504, -1433 * 2^-12 (not -1434 * 2^-12, the nearer)
  const StoreLoad r = store_load(Format::RGBA16F, values);
  EXPECT_EQ(r.loaded[0], (Texel{0.333251953125f, 1.0f, 1 + 0x1p-10f, 65504}));
  EXPECT_EQ(r.loaded[1][0], 65504.0f);
  EXPECT_EQ(r.loaded[1][1], 0.0f);
  EXPECT_EQ(r.loaded[1][2], 0x1p-24f);
  EXPECT_TRUE(std::signbit(r.loaded[1][3]));
  EXPECT_EQ(r.loaded[2][0], 0.0f);
  EXPECT_EQ(r.loaded[2][1], -2.5f);
  EXPECT_TRUE(std::isnan(r.loaded[2][3]));
  EXPECT_EQ(r.loaded[3], (Texel{65504, -1433 * 0x1p-12f, kInf, -kInf}));
  std::uint16_t one = 0;
  std::memcpy(&one, r.bytes.data() + 8 * 2 + 4, 2);  // texel 2, channel b
  EXPECT_EQ(one, 0x3C00);
}

// sRGB byte c to linear, OpenGL 4.6 section 8.24, in double precision.
double srgb_to_linear(int c) {
  const double s = c / 255.0;
  return s <= 0.04045 ? s / 12.92 : std::pow((s + 0.055) / 1.055, 2.4);
}

// Linear to the unscaled sRGB value before rounding (section 17.3), in double precision.
double linear_to_srgb(double linear) {
  if (linear <= 0) return 0;
  if (linear >= 1) return 1;
  return linear < 0.0031308 ? 12.92 * linear : 1.055 * std::pow(linear, 1 / 2.4) - 0.055;
}

TEST_F(TextureTest, SrgbDecodesEveryByteExactlyAndAlphaLinearly) {
  std::vector<std::uint8_t> texels;
  for (int c = 0; c < 256; ++c)
    texels.insert(texels.end(), {std::uint8_t(c), 0, std::uint8_t(255 - c), std::uint8_t(c)});
  const Texture texture(shared_context(), 256, 1, Format::SRGB8_A8, bytes_of(texels), false);
  std::vector<cl_int> queries;
  for (int c = 0; c < 256; ++c) queries.insert(queries.end(), {c, 0, 0});
  const std::vector<Texel> decoded = fetch(texture, queries).floats;
  for (int c = 0; c < 256; ++c) {
    EXPECT_EQ(decoded[c][0], static_cast<float>(srgb_to_linear(c))) << "byte " << c;
    EXPECT_EQ(decoded[c][2], static_cast<float>(srgb_to_linear(255 - c))) << "byte " << 255 - c;
    EXPECT_EQ(decoded[c][3], c / 255.0f) << "alpha " << c;
  }
}

// Every byte decodes to the float nearest c / 255 (clr_unorm8_to_float computes it without a division).
TEST_F(TextureTest, UnormDecodesEveryByteToItsQuotientBy255) {
  std::vector<std::uint8_t> texels;
  for (int c = 0; c < 256; ++c)
    texels.insert(texels.end(), {std::uint8_t(c), std::uint8_t(255 - c), std::uint8_t(c ^ 0x55), std::uint8_t(c)});
  const Texture texture(shared_context(), 256, 1, Format::RGBA8, bytes_of(texels), false);
  std::vector<cl_int> queries;
  for (int c = 0; c < 256; ++c) queries.insert(queries.end(), {c, 0, 0});
  const std::vector<Texel> decoded = fetch(texture, queries).floats;
  for (int c = 0; c < 256; ++c) {
    EXPECT_EQ(decoded[c], (Texel{c / 255.0f, (255 - c) / 255.0f, (c ^ 0x55) / 255.0f, c / 255.0f})) << "byte " << c;
  }
}

TEST_F(TextureTest, SrgbEncodesWithTheGLFormulaThenRoundsAndRoundTripsEveryByte) {
  // Hand-checked: 0.5 -> 187.516 -> 188; 0.2 -> 123.555 -> 124; 0.001 -> 3.29 -> 3; alpha 0.5 -> 128.
  const StoreLoad exact = store_load(Format::SRGB8_A8, {{0.5f, 0.2f, 0.001f, 0.5f}, {-1, 2, kNaN, 1}});
  EXPECT_EQ(std::vector<std::uint8_t>(exact.bytes.begin(), exact.bytes.begin() + 8),
            (std::vector<std::uint8_t>{188, 124, 3, 128, 0, 255, 0, 255}));

  // Every byte's linear value encodes back to the byte.
  std::vector<Texel> values;
  for (int c = 0; c < 256; ++c) values.push_back({static_cast<float>(srgb_to_linear(c)), 0, 0, c / 255.0f});
  const StoreLoad round_trip = store_load(Format::SRGB8_A8, values);
  for (int c = 0; c < 256; ++c) {
    EXPECT_EQ(round_trip.bytes[4 * c], c) << "colour " << c;
    EXPECT_EQ(round_trip.bytes[4 * c + 3], c) << "alpha " << c;
  }

  // A sweep of linear values against the formula in double precision, except within float error of
  // a rounding tie.
  values.clear();
  for (int i = 0; i <= 4000; ++i) values.push_back({i / 4000.0f, 0, 0, 1});
  const StoreLoad sweep = store_load(Format::SRGB8_A8, values);
  int checked = 0;
  for (int i = 0; i <= 4000; ++i) {
    const double scaled = linear_to_srgb(values[i][0]) * 255;
    if (std::abs(scaled - std::floor(scaled) - 0.5) < 1e-4) continue;
    EXPECT_EQ(sweep.bytes[4 * i], static_cast<int>(std::floor(scaled + 0.5))) << "linear " << values[i][0];
    ++checked;
  }
  EXPECT_GT(checked, 3900);
}

TEST_F(TextureTest, QuantizationEqualsAStoreFollowedByALoadForEveryFloatFormat) {
  std::mt19937 random(7);
  std::uniform_real_distribution<float> value(-0.2f, 1.2f);
  std::vector<Texel> values = {{kNaN, kInf, -kInf, -0.0f}, {0.5f, 1.0f / 3, 65520, 1e-9f}};
  for (int i = 0; i < 500; ++i) values.push_back({value(random), value(random), value(random), value(random)});
  for (const Format format : {Format::R8, Format::RG8, Format::RGBA8, Format::SRGB8_A8, Format::R32F, Format::RG32F,
                              Format::RGBA16F, Format::RGBA32F, Format::Depth32F, Format::Depth32FStencil8}) {
    const StoreLoad r = store_load(format, values);
    for (std::size_t i = 0; i < values.size(); ++i) {
      // Bitwise, so NaN equals NaN.
      EXPECT_EQ(std::memcmp(r.quantized[i].data(), r.loaded[i].data(), sizeof(Texel)), 0)
          << format_info(format).name << " value " << i;
    }
  }
}

TEST_F(TextureTest, IntegerFormatsStoreWordsAndReadMissingChannelsAsZeroAndOne) {
  const std::vector<cl_int4> values = {{{-5, 7, -8, 2147483647}}, {{-2147483647 - 1, 1, 2, 3}}};
  for (const Format format : {Format::R32I, Format::R32UI, Format::RGBA32I, Format::RGBA32UI}) {
    const int channels = format_info(format).channels;
    cl::Buffer texels = buffer(std::vector<std::uint8_t>(64, 0xAA));
    cl::Buffer as_int = buffer(std::vector<cl_int4>(2)), as_uint = buffer(std::vector<cl_uint4>(2));
    run("test_store_load_int", 2, cl_int(format), buffer(values), texels, as_int, as_uint);
    const std::vector<cl_int4> loaded = read<cl_int4>(as_int, 2);
    const std::vector<cl_uint4> loaded_uint = read<cl_uint4>(as_uint, 2);
    for (int i = 0; i < 2; ++i) {
      for (int c = 0; c < 4; ++c) {
        const int expected = c < channels ? values[i].s[c] : (c == 3 ? 1 : 0);
        EXPECT_EQ(loaded[i].s[c], expected) << format_info(format).name << " texel " << i << " channel " << c;
        EXPECT_EQ(loaded_uint[i].s[c], static_cast<cl_uint>(expected));
      }
    }
    EXPECT_EQ(read<std::uint8_t>(texels, 64)[8 * channels], 0xAA) << "wrote past texel 1";
  }
  // Unsigned stores keep all 32 bits.
  cl::Buffer texels = buffer(std::vector<std::uint8_t>(16));
  run("test_store_uint", 1, cl_int(Format::RGBA32UI), buffer(std::vector<cl_uint4>{{{0xffffffffu, 1, 2, 0x80000000u}}}),
      texels);
  EXPECT_EQ(read<cl_uint>(texels, 4), (std::vector<cl_uint>{0xffffffffu, 1, 2, 0x80000000u}));
}

TEST_F(TextureTest, MismatchedAccessesWriteNothingAndReadZeroZeroZeroOne) {
  // A float store into an integer format, and an integer store into a float format.
  const StoreLoad r = store_load(Format::RGBA32I, {{1, 2, 3, 4}});
  EXPECT_EQ(std::vector<std::uint8_t>(r.bytes.begin(), r.bytes.begin() + 16), std::vector<std::uint8_t>(16, 0xAA));
  EXPECT_EQ(r.loaded[0], (Texel{0, 0, 0, 1}));
  EXPECT_EQ(r.quantized[0], (Texel{0, 0, 0, 1}));
  cl::Buffer texels = buffer(std::vector<std::uint8_t>(16, 0xAA));
  cl::Buffer as_int = buffer(std::vector<cl_int4>(1)), as_uint = buffer(std::vector<cl_uint4>(1));
  run("test_store_load_int", 1, cl_int(Format::RGBA8), buffer(std::vector<cl_int4>{{{1, 2, 3, 4}}}), texels, as_int,
      as_uint);
  EXPECT_EQ(read<std::uint8_t>(texels, 16), std::vector<std::uint8_t>(16, 0xAA));
  EXPECT_EQ(read<cl_int4>(as_int, 1)[0].s[3], 1);
}

TEST(TextureFormats, FormatInfoDescribesEveryFormat) {
  EXPECT_EQ(format_info(Format::RGBA8).bytes_per_texel, 4);
  EXPECT_EQ(format_info(Format::RG8).bytes_per_texel, 2);
  EXPECT_EQ(format_info(Format::RGBA16F).bytes_per_texel, 8);
  EXPECT_EQ(format_info(Format::RGBA32UI).bytes_per_texel, 16);
  EXPECT_EQ(format_info(Format::Depth32FStencil8).bytes_per_texel, 4);
  EXPECT_TRUE(format_info(Format::R32I).integer && format_info(Format::R32I).is_signed);
  EXPECT_TRUE(format_info(Format::R32UI).integer && !format_info(Format::R32UI).is_signed);
  EXPECT_TRUE(format_info(Format::Depth32F).depth && !format_info(Format::Depth32F).stencil);
  EXPECT_TRUE(format_info(Format::Depth32FStencil8).stencil);
  EXPECT_FALSE(format_info(Format::SRGB8_A8).integer || format_info(Format::SRGB8_A8).depth);
  EXPECT_STREQ(format_info(Format::SRGB8_A8).name, "SRGB8_A8");
  EXPECT_EQ(format_info(Format::RG32F).channels, 2);
}

TEST(TextureLayout, LevelsFollowEachOtherAndTheStencilPlaneFollowsLevelZero) {
  Context& context = shared_context();
  const Texture texture(context, 5, 3, Format::RGBA16F, kFullMipChain);  // 5x3, 2x1, 1x1
  Sampler sampler;
  sampler.wrap_s = Wrap::MirroredRepeat;
  sampler.min_filter = Filter::Nearest;
  sampler.lod_bias = 0.5f;
  const TextureDesc desc = texture.impl().describe(sampler);
  EXPECT_EQ(desc.format, CLR_FORMAT_RGBA16F);
  EXPECT_EQ(desc.levels, 3);
  EXPECT_EQ((std::array<clr_uint, 3>{desc.level_offset[0], desc.level_offset[1], desc.level_offset[2]}),
            (std::array<clr_uint, 3>{0, 15, 17}));
  EXPECT_EQ(desc.wrap_s, CLR_WRAP_MIRRORED_REPEAT);
  EXPECT_EQ(desc.wrap_t, CLR_WRAP_REPEAT);
  EXPECT_EQ(desc.min_filter, CLR_FILTER_NEAREST);
  EXPECT_EQ(desc.mip_filter, CLR_MIP_LINEAR);
  EXPECT_EQ(desc.lod_bias, 0.5f);
  EXPECT_EQ(texture.impl().level_offset_bytes(2), 17u * 8);
  EXPECT_EQ(texture.impl().level_bytes(1), 2u * 8);
  EXPECT_EQ(texture.read(0), std::vector<std::byte>(15 * 8));  // new textures are zeros
  const Texture depth_stencil(context, 3, 2, Format::Depth32FStencil8);
  EXPECT_EQ(depth_stencil.impl().describe().stencil_offset, 3u * 2 * 4);
}

// ---- Texel fetches ----------------------------------------------------------------------------------------

TEST_F(TextureTest, TexelFetchesReadExactTexelsAndZerosOutsideTheTexture) {
  // A 3x2 RGBA32I texture with 2 levels: texel (x, y) of level l holds (x, y, l, -1).
  Texture texture(shared_context(), 3, 2, Format::RGBA32I, 2);
  std::vector<cl_int> level0, level1 = {0, 0, 1, -1};
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < 3; ++x) level0.insert(level0.end(), {x, y, 0, -1});
  }
  texture.upload(0, bytes_of(level0));
  texture.upload(1, bytes_of(level1));
  // Inside level 0 and level 1; then outside: x = 3, y = -1, texel (1, 0) of level 1, level 2, level -1.
  const std::vector<cl_int> queries = {2, 1, 0, 0, 0, 1, 3, 0, 0, 0, -1, 0, 1, 0, 1, 0, 0, 2, 0, 0, -1};
  const Fetched r = fetch(texture, queries);
  const auto texel = [&](std::size_t i) {
    return std::array<int, 4>{r.ints[i].s[0], r.ints[i].s[1], r.ints[i].s[2], r.ints[i].s[3]};
  };
  EXPECT_EQ(texel(0), (std::array<int, 4>{2, 1, 0, -1}));
  EXPECT_EQ(texel(1), (std::array<int, 4>{0, 0, 1, -1}));
  for (std::size_t i = 2; i < r.ints.size(); ++i) {
    EXPECT_EQ(texel(i), (std::array<int, 4>{0, 0, 0, 0})) << "query " << i;
    EXPECT_EQ(r.uints[i].s[3], 0u) << "query " << i;
  }
  EXPECT_EQ(r.uints[0].s[3], 0xffffffffu);
  // A float fetch of an integer format reads (0, 0, 0, 1); outside, zeros.
  EXPECT_EQ(r.floats[0], (Texel{0, 0, 0, 1}));
  EXPECT_EQ(r.floats[2], (Texel{0, 0, 0, 0}));
  // Sizes per level; (0, 0) for levels the texture does not have.
  EXPECT_EQ(std::vector<cl_int>(r.sizes.begin(), r.sizes.begin() + 6), (std::vector<cl_int>{3, 2, 2, 1, 1, 2}));
  EXPECT_EQ(std::vector<cl_int>(r.sizes.begin() + 15, r.sizes.end()), (std::vector<cl_int>{0, 0, 2, 0, 0, 2}));
}

// ---- Sampling: texel selection and wrapping, worked out by hand -------------------------------------------

// A 4x2 texture whose texel (i, j) is (i, j, 0, 1).
Texture coordinate_texture() {
  std::vector<Texel> texels;
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 4; ++i) texels.push_back({float(i), float(j), 0, 1});
  }
  return float_texture(4, 2, texels);
}

Sampler nearest_sampler(Wrap wrap) {
  Sampler sampler;
  sampler.mag_filter = sampler.min_filter = Filter::Nearest;
  sampler.mip_filter = MipFilter::None;
  sampler.wrap_s = sampler.wrap_t = wrap;
  return sampler;
}

TEST_F(TextureTest, NearestFilteringSelectsFloorOfUTimesWidthWrapped) {
  const Texture texture = coordinate_texture();
  struct Case {
    Wrap wrap;
    float s;
    int i;  // by hand: u = 4 s, i = wrap(floor(u))
  };
  const std::vector<Case> cases = {
      {Wrap::Repeat, 0.1f, 0},           // u = 0.4
      {Wrap::Repeat, 0.99f, 3},          // 3.96
      {Wrap::Repeat, 1.0f, 0},           // 4 -> 0
      {Wrap::Repeat, -0.1f, 3},          // -0.4 -> -1 -> 3
      {Wrap::Repeat, -1.3f, 2},          // -5.2 -> -6 -> 2
      {Wrap::Repeat, 2.6f, 2},           // 10.4 -> 10 -> 2
      {Wrap::ClampToEdge, -0.5f, 0},     // -2 -> 0
      {Wrap::ClampToEdge, 1.2f, 3},      // 4.8 -> 4 -> 3
      {Wrap::ClampToEdge, 0.6f, 2},      // 2.4
      {Wrap::MirroredRepeat, 0.3f, 1},   // 1.2
      {Wrap::MirroredRepeat, -0.1f, 0},  // -1 mirrors to 0
      {Wrap::MirroredRepeat, 1.1f, 3},   // 4 mirrors to 3
      {Wrap::MirroredRepeat, 1.3f, 2},   // 5 mirrors to 2
      {Wrap::MirroredRepeat, -0.6f, 2},  // -2.4 -> -3 mirrors to 2
      {Wrap::MirroredRepeat, 2.2f, 0},   // 8.8 -> 8: the period is 8 texels
  };
  for (const Case& c : cases) {
    // t = 0.75 -> v = 1.5 -> row 1 in every mode.
    EXPECT_EQ(sample_lod(texture, nearest_sampler(c.wrap), c.s, 0.75f, 0), (Texel{float(c.i), 1, 0, 1}))
        << "wrap " << int(c.wrap) << " s " << c.s;
  }
}

TEST_F(TextureTest, BilinearFilteringWeighsTheFourTexelsAroundUMinusAHalf) {
  // A 4x1 texture holding 10, 20, 40, 80 in red. With t = 0.5, v - 1/2 = 0: row 0 alone.
  const Texture texture = float_texture(4, 1, {{10, 0, 0, 1}, {20, 0, 0, 1}, {40, 0, 0, 1}, {80, 0, 0, 1}});
  Sampler sampler;
  sampler.mip_filter = MipFilter::None;
  struct Case {
    Wrap wrap;
    float s;
    float expected;  // by hand: u - 1/2 = 4 s - 1/2, i0 = wrap(floor), i1 = wrap(floor + 1), alpha = frac
  };
  const std::vector<Case> cases = {
      {Wrap::Repeat, 0.125f, 10},                                // u - 1/2 = 0: texel 0 alone
      {Wrap::Repeat, 0.25f, 15},                                 // 0.5: half 10, half 20
      {Wrap::Repeat, 0.0625f, 0.25f * 80 + 0.75f * 10},          // -0.25: i0 = -1 -> 3 (80), i1 = 0, alpha 0.75
      {Wrap::Repeat, 1.0f, 0.5f * 80 + 0.5f * 10},               // 3.5: i0 = 3, i1 = 4 -> 0
      {Wrap::ClampToEdge, 0.0625f, 10},                          // i0 = -1 -> 0, i1 = 0
      {Wrap::ClampToEdge, 0.96875f, 80},                         // 3.375: i0 = 3, i1 = 4 -> 3
      {Wrap::ClampToEdge, 0.6875f, 0.75f * 40 + 0.25f * 80},     // 2.25: i0 = 2, alpha 0.25
      {Wrap::MirroredRepeat, 0.0625f, 10},                       // i0 = -1 mirrors to 0, i1 = 0
      {Wrap::MirroredRepeat, 1.0f, 80},                          // i0 = 3, i1 = 4 mirrors to 3
      {Wrap::MirroredRepeat, 1.1875f, 0.75f * 80 + 0.25f * 40},  // 4.25: i0 = 4 -> 3, i1 = 5 -> 2
  };
  for (const Case& c : cases) {
    sampler.wrap_s = sampler.wrap_t = c.wrap;
    EXPECT_TRUE(near(sample_lod(texture, sampler, c.s, 0.5f, 0), {c.expected, 0, 0, 1}, 1e-4f))
        << "wrap " << int(c.wrap) << " s " << c.s;
  }
}

TEST_F(TextureTest, SrgbTexturesAreFilteredAfterDecoding) {
  // Black and white side by side; halfway between them is linear 0.5, not the decoded midpoint byte.
  const std::vector<std::uint8_t> texels = {0, 0, 0, 0, 255, 255, 255, 255};
  const Texture texture(shared_context(), 2, 1, Format::SRGB8_A8, bytes_of(texels), false);
  Sampler sampler;
  sampler.wrap_s = sampler.wrap_t = Wrap::ClampToEdge;
  EXPECT_TRUE(near(sample_lod(texture, sampler, 0.5f, 0.5f, 0), {0.5f, 0.5f, 0.5f, 0.5f}, 1e-6f));
}

TEST_F(TextureTest, DepthTexturesSampleAsDepthZeroZeroOne) {
  const std::vector<float> depths = {0.25f, 0.75f};
  const Texture texture(shared_context(), 2, 1, Format::Depth32F, bytes_of(depths), false);
  Sampler sampler;
  sampler.wrap_s = Wrap::ClampToEdge;
  EXPECT_TRUE(near(sample_lod(texture, sampler, 0.5f, 0.5f, 0), {0.5f, 0, 0, 1}));
  EXPECT_EQ(sample_lod(texture, nearest_sampler(Wrap::Repeat), 0.9f, 0.5f, 0), (Texel{0.75f, 0, 0, 1}));
}

// ---- Level of detail and mipmapping, by hand ------------------------------------------------------------

// An 8x8 texture with 4 levels, every texel of level l holding (l, l, l, 1): a sample reads which
// level (or which blend of levels) it came from.
Texture level_texture() {
  Texture texture(shared_context(), 8, 8, Format::RGBA32F, kFullMipChain);
  for (int level = 0; level < texture.levels(); ++level) {
    const std::size_t texels = std::size_t(texture.width(level)) * texture.height(level);
    texture.upload(level, bytes_of(std::vector<Texel>(texels, Texel{float(level), float(level), float(level), 1})));
  }
  return texture;
}

Sampler mip_sampler(MipFilter mip) {
  Sampler sampler;
  sampler.mip_filter = mip;
  return sampler;
}

TEST_F(TextureTest, NearestMipmapRoundsLambdaWithTiesGoingToTheFinerLevel) {
  const Texture texture = level_texture();
  ASSERT_EQ(texture.levels(), 4);
  // d = 0 for lambda <= 1/2, ceil(lambda + 1/2) - 1 up to q + 1/2, q = 3 beyond.
  const std::vector<std::pair<float, float>> cases = {{-1, 0},    {0.3f, 0}, {0.5f, 0}, {0.51f, 1}, {1.5f, 1},
                                                      {1.51f, 2}, {3.4f, 3}, {3.5f, 3}, {9, 3}};
  for (const auto& [lod, level] : cases) {
    EXPECT_EQ(sample_lod(texture, mip_sampler(MipFilter::Nearest), 0.3f, 0.6f, lod)[0], level) << "lod " << lod;
  }
}

TEST_F(TextureTest, LinearMipmapBlendsTheTwoLevelsAroundLambda) {
  const Texture texture = level_texture();
  // (1 - frac) * level floor(lambda) + frac * the next; the last level beyond q; level 0 when magnified.
  const std::vector<std::pair<float, float>> cases = {{-2, 0},      {0.25f, 0.25f}, {1.0f, 1.0f}, {1.75f, 1.75f},
                                                      {2.5f, 2.5f}, {3, 3},         {7.5f, 3}};
  for (const auto& [lod, expected] : cases) {
    EXPECT_NEAR(sample_lod(texture, mip_sampler(MipFilter::Linear), 0.3f, 0.6f, lod)[0], expected, 1e-6f)
        << "lod " << lod;
  }
  // Without mipmapping, level 0 whatever lambda.
  EXPECT_EQ(sample_lod(texture, mip_sampler(MipFilter::None), 0.3f, 0.6f, 2.5f)[0], 0.0f);
}

TEST_F(TextureTest, BiasAndLodRangeApplyToExplicitLevelsOfDetail) {
  const Texture texture = level_texture();
  Sampler sampler = mip_sampler(MipFilter::Linear);
  sampler.lod_bias = 1.0f;
  EXPECT_NEAR(sample_lod(texture, sampler, 0.5f, 0.5f, 0.25f)[0], 1.25f, 1e-6f);
  sampler.lod_bias = -100.0f;  // clamped to -16, then to min_lod
  sampler.min_lod = 0.5f;
  EXPECT_NEAR(sample_lod(texture, sampler, 0.5f, 0.5f, 15.0f)[0], 0.5f, 1e-6f);
  sampler.lod_bias = 0;
  sampler.min_lod = -1000;
  sampler.max_lod = 1.5f;
  EXPECT_NEAR(sample_lod(texture, sampler, 0.5f, 0.5f, 3.0f)[0], 1.5f, 1e-6f);
  sampler.max_lod = 2.25f;
  sampler.lod_bias = 100.0f;  // clamped to 16: still beyond max_lod
  EXPECT_NEAR(sample_lod(texture, sampler, 0.5f, 0.5f, -10.0f)[0], 2.25f, 1e-6f);
  sampler.lod_bias = 0;
  sampler.min_lod = sampler.max_lod = 2;
  EXPECT_NEAR(sample_lod(texture, sampler, 0.5f, 0.5f, -5.0f)[0], 2.0f, 1e-6f);  // min_lod 2 minifies
}

TEST_F(TextureTest, GradientsGiveLambdaAsLog2OfTheLongerFootprintInTexels) {
  // log2 is llvmpipe's: exact at powers of two, linear between them (checked against llvmpipe's
  // textureGrad: 2.28125 for rho = 5, 0.5625 for rho = 1.5).
  const Texture texture = level_texture();  // 8x8
  const Sampler sampler = mip_sampler(MipFilter::Linear);
  const float eighth = 1.0f / 8;
  const std::vector<std::pair<Query, float>> cases = {
      {Query{0.5f, 0.5f, 0, {2 * eighth, 0}, {0, eighth}}, 1.0f},            // rho = max(2, 1)
      {Query{0.5f, 0.5f, 0, {0, eighth}, {0, 4 * eighth}}, 2.0f},            // rho = max(1, 4)
      {Query{0.5f, 0.5f, 0, {eighth, eighth}, {0, 0}}, 0.5f},                // rho^2 = 2
      {Query{0.5f, 0.5f, 0, {3 * eighth, 4 * eighth}, {0, 0}}, 2.28125f},    // rho^2 = 25 = 1.5625 * 16
      {Query{0.5f, 0.5f, 0, {1.5f * eighth, 0}, {0, 0}}, 0.5625f},           // rho^2 = 2.25 = 1.125 * 2
      {Query{0.5f, 0.5f, 0, {0.5f * eighth, 0}, {0, 0.5f * eighth}}, 0.0f},  // magnified
      {Query{0.5f, 0.5f, 0, {0, 0}, {0, 0}}, 0.0f},                          // rho 0: lambda -inf
      {Query{0.5f, 0.5f, 0, {kNaN, 0}, {0, 0}}, 0.0f},                       // lambda NaN: min_lod
      {Query{0.5f, 0.5f, 0, {1e30f, 0}, {0, 0}}, 3.0f},                      // the last level
  };
  std::vector<Query> queries;
  for (const auto& c : cases) queries.push_back(c.first);
  const std::vector<Texel> results = sample(texture, sampler, queries, true);
  for (std::size_t i = 0; i < cases.size(); ++i) EXPECT_NEAR(results[i][0], cases[i].second, 1e-5f) << "case " << i;
}

TEST_F(TextureTest, MagnificationUsesTheMagFilterAndMinificationTheMinFilter) {
  // Level 0: 0 and 1 alternating columns (4x1); at s = 0.25 nearest reads column 1, linear blends 0.5.
  const Texture texture = float_texture(4, 1, {{0, 0, 0, 1}, {1, 0, 0, 1}, {0, 0, 0, 1}, {1, 0, 0, 1}});
  Sampler sampler;
  sampler.mag_filter = Filter::Nearest;
  sampler.min_filter = Filter::Linear;
  sampler.mip_filter = MipFilter::None;
  EXPECT_EQ(sample_lod(texture, sampler, 0.25f, 0.5f, 0.0f)[0], 1.0f);    // lambda 0: magnified
  EXPECT_EQ(sample_lod(texture, sampler, 0.25f, 0.5f, 0.001f)[0], 0.5f);  // minified
  sampler.mag_filter = Filter::Linear;
  sampler.min_filter = Filter::Nearest;
  EXPECT_EQ(sample_lod(texture, sampler, 0.25f, 0.5f, -1.0f)[0], 0.5f);
  EXPECT_EQ(sample_lod(texture, sampler, 0.25f, 0.5f, 1.0f)[0], 1.0f);
}

// ---- Sampling against a reference written from the spec -------------------------------------------------

// OpenGL 4.6 sections 8.14-8.15 for a texture whose levels are given as decoded texels, in the
// spec's own terms: table 8.20 for wrapping, equations for lambda, d, d1 and d2.
struct ReferenceTexture {
  int width = 0, height = 0;
  std::vector<std::vector<Texel>> levels;

  int level_width(int level) const { return std::max(1, width >> level); }
  int level_height(int level) const { return std::max(1, height >> level); }
};

int reference_wrap(Wrap wrap, int coordinate, int size) {
  const auto fmod_positive = [](int a, int b) { return ((a % b) + b) % b; };
  const auto mirror = [](int a) { return a >= 0 ? a : -(1 + a); };
  switch (wrap) {
    case Wrap::Repeat:
      return fmod_positive(coordinate, size);
    case Wrap::ClampToEdge:
      return std::clamp(coordinate, 0, size - 1);
    case Wrap::MirroredRepeat:
      return (size - 1) - mirror(fmod_positive(coordinate, 2 * size) - size);
  }
  return 0;
}

Texel reference_filter(const ReferenceTexture& texture, const Sampler& sampler, int level, float s, float t,
                       Filter filter) {
  const int w = texture.level_width(level), h = texture.level_height(level);
  const float u = s * float(w), v = t * float(h);
  const auto at = [&](int i, int j) {
    return texture
        .levels[level][std::size_t(reference_wrap(sampler.wrap_t, j, h)) * w + reference_wrap(sampler.wrap_s, i, w)];
  };
  if (filter == Filter::Nearest) return at(int(std::floor(u)), int(std::floor(v)));
  const int i0 = int(std::floor(u - 0.5f)), j0 = int(std::floor(v - 0.5f));
  const float alpha = (u - 0.5f) - std::floor(u - 0.5f), beta = (v - 0.5f) - std::floor(v - 0.5f);
  Texel result{};
  for (int c = 0; c < 4; ++c) {
    result[c] = (1 - alpha) * (1 - beta) * at(i0, j0)[c] + alpha * (1 - beta) * at(i0 + 1, j0)[c] +
                (1 - alpha) * beta * at(i0, j0 + 1)[c] + alpha * beta * at(i0 + 1, j0 + 1)[c];
  }
  return result;
}

// llvmpipe's log2 of a level of detail: e + m - 1 for x = m 2^e, m in [1, 2).
double piecewise_linear_log2(double x) {
  if (!(x > 0) || std::isinf(x)) return std::log2(x);
  int exponent = 0;
  const double mantissa = 2 * std::frexp(x, &exponent);
  return exponent - 1 + mantissa - 1;
}

double reference_lambda(const Sampler& sampler, double lambda_base) {
  const double lambda = lambda_base + std::clamp(double(sampler.lod_bias), -16.0, 16.0);
  return std::clamp(lambda, double(sampler.min_lod), double(sampler.max_lod));
}

Texel reference_sample(const ReferenceTexture& texture, const Sampler& sampler, float s, float t, double lambda) {
  if (lambda <= 0) return reference_filter(texture, sampler, 0, s, t, sampler.mag_filter);
  const int q = int(texture.levels.size()) - 1;
  if (sampler.mip_filter == MipFilter::None) return reference_filter(texture, sampler, 0, s, t, sampler.min_filter);
  if (sampler.mip_filter == MipFilter::Nearest) {
    const int d = lambda <= 0.5 ? 0 : lambda <= q + 0.5 ? int(std::ceil(lambda + 0.5)) - 1 : q;
    return reference_filter(texture, sampler, d, s, t, sampler.min_filter);
  }
  if (lambda >= q) return reference_filter(texture, sampler, q, s, t, sampler.min_filter);
  const int d1 = int(std::floor(lambda));
  const double weight = lambda - d1;
  const Texel a = reference_filter(texture, sampler, d1, s, t, sampler.min_filter);
  const Texel b = reference_filter(texture, sampler, d1 + 1, s, t, sampler.min_filter);
  Texel result{};
  for (int c = 0; c < 4; ++c) result[c] = float((1 - weight) * a[c] + weight * b[c]);
  return result;
}

// Whether lambda is so close to, but not on, a point where the choice of level jumps (0 between
// magnification and minification; k + 1/2 between nearest levels) that the device's float and the
// reference's double evaluations may fall on different sides.
bool near_lambda_boundary(const Sampler& sampler, double lambda) {
  const auto near_but_not_on = [](double distance) { return distance != 0 && std::abs(distance) < 1e-3; };
  return near_but_not_on(lambda) ||
         (sampler.mip_filter == MipFilter::Nearest && near_but_not_on(lambda - std::floor(lambda) - 0.5));
}

// A 16x8 texture with 5 levels of random texels (not generated from each other), and a 12x5 one with
// 4, whose sides are not powers of two (wrapping them takes a division).
TEST_F(TextureTest, EverySamplerMatchesTheReferenceAtRandomCoordinatesAndGradients) {
  for (const auto [width, height] : {std::pair{16, 8}, std::pair{12, 5}}) {
    std::mt19937 random(11);
    std::uniform_real_distribution<float> unit(0, 1);
    Texture texture(shared_context(), width, height, Format::RGBA32F, kFullMipChain);
    ReferenceTexture reference{width, height, {}};
    for (int level = 0; level < texture.levels(); ++level) {
      std::vector<Texel> texels(std::size_t(texture.width(level)) * texture.height(level));
      for (Texel& texel : texels) texel = {unit(random), unit(random), unit(random), unit(random)};
      texture.upload(level, bytes_of(texels));
      reference.levels.push_back(texels);
    }
    // Coordinates over several periods, on both sides of 0; footprints from 1/8 to 64 texels.
    std::uniform_real_distribution<float> coordinate(-2.5f, 3.5f), log_footprint(-3, 6), angle(0, 6.2831853f);
    std::vector<Query> queries;
    for (int i = 0; i < 200; ++i) {
      const float a = angle(random), b = angle(random);
      const float x_texels = std::exp2(log_footprint(random)), y_texels = std::exp2(log_footprint(random));
      queries.push_back(Query{coordinate(random),
                              coordinate(random),
                              log_footprint(random) - 1,
                              {x_texels * std::cos(a) / width, x_texels * std::sin(a) / height},
                              {y_texels * std::cos(b) / width, y_texels * std::sin(b) / height}});
    }
    // Texel centres and edges exactly, where selection rules differ most.
    for (int i = -4; i <= 20; ++i) {
      queries.push_back(Query{i / float(width), (i + 0.5f) / float(height), 0.5f * float(i % 3)});
    }

    int checked = 0;
    for (const Filter mag : {Filter::Nearest, Filter::Linear}) {
      for (const Filter min : {Filter::Nearest, Filter::Linear}) {
        for (const MipFilter mip : {MipFilter::None, MipFilter::Nearest, MipFilter::Linear}) {
          for (const Wrap wrap_s : {Wrap::Repeat, Wrap::ClampToEdge, Wrap::MirroredRepeat}) {
            for (const Wrap wrap_t : {Wrap::Repeat, Wrap::ClampToEdge, Wrap::MirroredRepeat}) {
              // A third of the samplers with a bias and a narrower lod range.
              Sampler sampler{mag, min, mip, wrap_s, wrap_t, 0.0f, -1000.0f, 1000.0f};
              if (wrap_s == Wrap::MirroredRepeat) sampler = {mag, min, mip, wrap_s, wrap_t, 0.5f, 0.25f, 3.5f};
              for (const bool gradients : {false, true}) {
                const std::vector<Texel> results = sample(texture, sampler, queries, gradients);
                for (std::size_t i = 0; i < queries.size(); ++i) {
                  const Query& q = queries[i];
                  const auto squared = [&](std::array<float, 2> d) {
                    return std::pow(double(d[0]) * width, 2) + std::pow(double(d[1]) * height, 2);
                  };
                  const double lambda_base =
                      gradients ? 0.5 * piecewise_linear_log2(std::max(squared(q.dx), squared(q.dy))) : q.lod;
                  const double lambda = reference_lambda(sampler, lambda_base);
                  if (near_lambda_boundary(sampler, lambda)) continue;
                  EXPECT_TRUE(near(results[i], reference_sample(reference, sampler, q.s, q.t, lambda), 1e-4f))
                      << "mag " << int(mag) << " min " << int(min) << " mip " << int(mip) << " wrap " << int(wrap_s)
                      << "/" << int(wrap_t) << (gradients ? " gradients" : " lod") << " query " << i << " s " << q.s
                      << " t " << q.t << " lambda " << lambda << " size " << width << "x" << height;
                  ++checked;
                }
              }
            }
          }
        }
      }
    }
    EXPECT_GT(checked, 48000) << width << "x" << height;  // of 108 samplers x 2 x 225 queries, few are near a boundary
  }
}

TEST_F(TextureTest, HugeAndNonFiniteCoordinatesSampleSomeTexelOfTheTexture) {
  const Texture texture = level_texture();
  for (const Wrap wrap : {Wrap::Repeat, Wrap::ClampToEdge, Wrap::MirroredRepeat}) {
    Sampler sampler = mip_sampler(MipFilter::Linear);
    sampler.wrap_s = sampler.wrap_t = wrap;
    for (const float s : {kNaN, kInf, -kInf, 3e38f, -3e38f, 1e9f}) {
      const std::vector<Texel> results = sample(texture, sampler, {Query{s, 0.5f, 1.5f}, Query{0.5f, s, kNaN}}, false);
      for (const Texel& result : results) {
        EXPECT_GE(result[0], 0.0f) << s;
        EXPECT_LE(result[0], 3.0f) << s;
      }
    }
  }
}

// ---- Mipmap generation -------------------------------------------------------------------------------------

// A level's texels as values of type T.
template <typename T>
std::vector<T> level_values(const Texture& texture, int level) {
  const std::vector<std::byte> bytes = texture.read(level);
  std::vector<T> values(bytes.size() / sizeof(T));
  std::memcpy(values.data(), bytes.data(), bytes.size());
  return values;
}

TEST_F(TextureTest, MipmapsOfSidesThatHalveAverageTwoByTwoBlocks) {
  // 4x2: level 1 (2x1) averages columns {0, 1} and {2, 3} of both rows; level 2 (1x1) averages
  // level 1's two texels (its one row taken alone).
  std::vector<Texel> level0;
  for (int j = 0; j < 2; ++j) {
    for (int i = 0; i < 4; ++i) level0.push_back({float(i + 4 * j), float(1 << i), 0, 1});
  }
  const Texture texture(shared_context(), 4, 2, Format::RGBA32F, bytes_of(level0));
  ASSERT_EQ(texture.levels(), 3);
  EXPECT_EQ(level_values<Texel>(texture, 1), (std::vector<Texel>{{2.5f, 1.5f, 0, 1}, {4.5f, 6, 0, 1}}));
  EXPECT_EQ(level_values<Texel>(texture, 2), (std::vector<Texel>{{3.5f, 3.75f, 0, 1}}));
}

TEST_F(TextureTest, MipmapsOfOddSidesSampleTheLevelAboveAtTheirTexelCentres) {
  // As Mesa's glGenerateMipmap (these are llvmpipe's results): destination texel x of a side going
  // from 5 to 2 texels has its centre at (x + 1/2) * 5/2 = 1.25, 3.75 source texels, between
  // texels 0 and 1 (weights 3/4 on 1) and 3 and 4 (3/4 on 3); a side going from 3 to 1 takes the
  // middle texel, a side going from 7 to 3 the centres 7/6, 7/2 and 35/6.
  std::vector<float> grid;  // 5x3, x + 10 y
  for (int y = 0; y < 3; ++y) {
    for (int x = 0; x < 5; ++x) grid.push_back(float(x + 10 * y));
  }
  const Texture texture(shared_context(), 5, 3, Format::R32F, bytes_of(grid));
  ASSERT_EQ(texture.levels(), 3);
  EXPECT_EQ(level_values<float>(texture, 1), (std::vector<float>{10.75f, 13.25f}));
  EXPECT_EQ(level_values<float>(texture, 2), (std::vector<float>{12.0f}));  // halfway between them

  const std::vector<float> squares = {0, 1, 4, 9, 16, 25, 36};  // 7x1
  const Texture row(shared_context(), 7, 1, Format::R32F, bytes_of(squares));
  const std::vector<float> level1 = level_values<float>(row, 1);
  ASSERT_EQ(level1.size(), 3u);
  EXPECT_NEAR(level1[0], 2.0f / 3, 1e-6f);        // 2/3 of the way from 0 to 1
  EXPECT_EQ(level1[1], 9.0f);                     // texel 3 alone
  EXPECT_NEAR(level1[2], 25 + 11.0f / 3, 1e-5f);  // a third of the way from 25 to 36
  EXPECT_EQ(level_values<float>(row, 2), (std::vector<float>{9.0f}));
}

TEST_F(TextureTest, SrgbMipmapsAverageInLinearSpace) {
  // Two black and two white texels: linear mean 0.5 encodes to 188 (a byte mean would give 128;
  // llvmpipe, whose sRGB encoding is approximate, gives 187); alpha averages as it is: 127.5 -> 128.
  const std::vector<std::uint8_t> texels = {0, 0, 0, 0, 255, 255, 255, 255, 255, 255, 255, 255, 0, 0, 0, 0};
  const Texture texture(shared_context(), 2, 2, Format::SRGB8_A8, bytes_of(texels));
  EXPECT_EQ(texture.read(1), bytes_of(std::vector<std::uint8_t>{188, 188, 188, 128}));
}

TEST_F(TextureTest, EveryFilterableColourFormatGeneratesMipmaps) {
  // 2x2 texels 0, 64, 128, 255 (over 255 for the normalized formats): the mean is 111.75, which
  // 8-bit formats round to 112 and the float ones (half included) hold exactly.
  const std::vector<std::pair<Format, float>> formats = {
      {Format::R8, 112 / 255.0f}, {Format::RG8, 112 / 255.0f}, {Format::RGBA8, 112 / 255.0f}, {Format::R32F, 111.75f},
      {Format::RG32F, 111.75f},   {Format::RGBA16F, 111.75f},  {Format::RGBA32F, 111.75f}};
  for (const auto& [format, mean] : formats) {
    const float scale = mean < 1 ? 1.0f / 255 : 1.0f;
    std::vector<Texel> values;
    for (const float v : {0.0f, 64.0f, 128.0f, 255.0f}) values.push_back({v * scale, v * scale, v * scale, v * scale});
    // Level 0's bytes, made by the device's own stores (tested above).
    const StoreLoad stored = store_load(format, values);
    const std::size_t bytes = 4 * std::size_t(format_info(format).bytes_per_texel);
    const Texture texture(shared_context(), 2, 2, format,
                          bytes_of(std::vector<std::uint8_t>(stored.bytes.begin(), stored.bytes.begin() + bytes)));
    EXPECT_EQ(fetch(texture, {0, 0, 1}).floats[0][0], mean) << format_info(format).name;
  }
}

// ---- Image files ------------------------------------------------------------------------------------------

class TextureFiles : public TextureTest {
 protected:
  void SetUp() override {
    directory_ =
        std::filesystem::temp_directory_path() / ("clraster_textures_" + std::to_string(::getpid()) + "_" +
                                                  ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(directory_);
  }
  void TearDown() override { std::filesystem::remove_all(directory_); }

  std::string path(const std::string& name) const { return (directory_ / name).string(); }

  // A 3x2 RGBA picture: row 0 (the file's first) red, green, blue; row 1 white, black, half-grey.
  static std::vector<std::uint8_t> picture() {
    return {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255, 0, 0, 0, 255, 128, 128, 128, 128};
  }

  std::filesystem::path directory_;
};

TEST_F(TextureFiles, PngFilesLoadWithTheirFirstRowAtTZeroUnlessFlipped) {
  const std::vector<std::uint8_t> rgba = picture();
  ASSERT_TRUE(stbi_write_png(path("picture.png").c_str(), 3, 2, 4, rgba.data(), 3 * 4));
  const Texture texture = Texture::load(shared_context(), path("picture.png"), false);
  EXPECT_EQ(texture.format(), Format::RGBA8);
  EXPECT_EQ(texture.width(), 3);
  EXPECT_EQ(texture.height(), 2);
  EXPECT_EQ(texture.levels(), 2);  // 3x2, 1x1
  EXPECT_EQ(texture.read(0), bytes_of(rgba));

  const Texture flipped = Texture::load(shared_context(), path("picture.png"), true, true);
  EXPECT_EQ(flipped.format(), Format::SRGB8_A8);
  std::vector<std::uint8_t> bottom_up(rgba.begin() + 12, rgba.end());
  bottom_up.insert(bottom_up.end(), rgba.begin(), rgba.begin() + 12);
  EXPECT_EQ(flipped.read(0), bytes_of(bottom_up));
}

TEST_F(TextureFiles, EncodedImagesInMemoryAndJpegsDecode) {
  std::vector<std::uint8_t> encoded;
  const auto append = [](void* context, void* data, int size) {
    auto& out = *static_cast<std::vector<std::uint8_t>*>(context);
    out.insert(out.end(), static_cast<std::uint8_t*>(data), static_cast<std::uint8_t*>(data) + size);
  };
  const std::vector<std::uint8_t> rgba = picture();
  ASSERT_TRUE(stbi_write_png_to_func(append, &encoded, 3, 2, 4, rgba.data(), 3 * 4));
  EXPECT_EQ(Texture::decode(shared_context(), bytes_of(encoded), false).read(0), bytes_of(rgba));

  // A flat orange 16x16 JPEG: lossy, but a flat colour survives within a step or two; alpha is 255.
  std::vector<std::uint8_t> orange;
  for (int i = 0; i < 16 * 16; ++i) orange.insert(orange.end(), {230, 120, 20});
  ASSERT_TRUE(stbi_write_jpg(path("orange.jpg").c_str(), 16, 16, 3, orange.data(), 100));
  const Texture jpeg = Texture::load(shared_context(), path("orange.jpg"));
  EXPECT_EQ(jpeg.levels(), 5);
  const std::vector<std::byte> texels = jpeg.read(4);  // the 1x1 level
  ASSERT_EQ(texels.size(), 4u);
  EXPECT_NEAR(std::to_integer<int>(texels[0]), 230, 3);
  EXPECT_NEAR(std::to_integer<int>(texels[1]), 120, 3);
  EXPECT_NEAR(std::to_integer<int>(texels[2]), 20, 3);
  EXPECT_EQ(std::to_integer<int>(texels[3]), 255);
}

// ---- Bad input ------------------------------------------------------------------------------------------

TEST(TextureErrors, SizesOutsideOneTo16384AreRejected) {
  Context& context = shared_context();
  EXPECT_EQ(error_of([&] { Texture(context, 0, 5, Format::RGBA8); }),
            "texture size 0x5 is out of range: each side must be 1..16384");
  EXPECT_EQ(error_of([&] { Texture(context, 16385, 1, Format::R8); }),
            "texture size 16385x1 is out of range: each side must be 1..16384");
  EXPECT_EQ(error_of([&] { Texture(context, 4, -3, Format::R8, std::span<const std::byte>{}); }),
            "texture size 4x-3 is out of range: each side must be 1..16384");
}

TEST(TextureErrors, LevelCountsBeyondTheFullChainAreRejected) {
  Context& context = shared_context();
  EXPECT_EQ(error_of([&] { Texture(context, 16, 4, Format::RGBA8, 6); }),
            "6 mip levels requested for a 16x4 texture: it has 1..5 (or kFullMipChain)");
  EXPECT_EQ(error_of([&] { Texture(context, 16, 4, Format::RGBA8, -1); }),
            "-1 mip levels requested for a 16x4 texture: it has 1..5 (or kFullMipChain)");
  EXPECT_EQ(error_of([&] { Texture(context, 16, 4, Format::Depth32FStencil8, 2); }),
            "Depth32FStencil8 textures have one level; 2 requested");
  EXPECT_EQ(Texture(context, 16, 4, Format::RGBA8, kFullMipChain).levels(), 5);
  EXPECT_EQ(Texture(context, 1, 1, Format::RGBA8, kFullMipChain).levels(), 1);
}

TEST(TextureErrors, UnknownFormatsAndSamplerModesAreRejected) {
  Context& context = shared_context();
  EXPECT_EQ(error_of([&] { Texture(context, 4, 4, static_cast<Format>(14)); }), "unknown texture format 14");
  EXPECT_EQ(error_of([&] { format_info(static_cast<Format>(-1)); }), "unknown texture format -1");
  const Texture texture(context, 4, 4, Format::RGBA8);
  Sampler sampler;
  sampler.wrap_t = static_cast<Wrap>(3);
  EXPECT_EQ(error_of([&] { texture.impl().describe(sampler); }),
            "sampler has a filter or wrap mode that does not exist");
}

TEST(TextureErrors, DataOfTheWrongSizeIsRejected) {
  Context& context = shared_context();
  const std::vector<std::byte> bytes(1000);
  EXPECT_EQ(error_of([&] { Texture(context, 16, 16, Format::RGBA8, bytes); }),
            "level 0 of the 16x16 RGBA8 texture is 16x16 texels, 1024 bytes; got 1000 bytes");
  Texture texture(context, 16, 8, Format::RG32F, 3);
  EXPECT_EQ(error_of([&] { texture.upload(2, bytes); }),
            "level 2 of the 16x8 RG32F texture is 4x2 texels, 64 bytes; got 1000 bytes");
  EXPECT_EQ(error_of([&] { texture.upload(3, bytes); }), "texture level 3 does not exist: the texture has 3 levels");
  EXPECT_EQ(error_of([&] { texture.read(-1); }), "texture level -1 does not exist: the texture has 3 levels");
  EXPECT_EQ(error_of([&] { texture.width(7); }), "texture level 7 does not exist: the texture has 3 levels");
}

TEST(TextureErrors, MipmapsOfIntegerAndDepthFormatsAreRejected) {
  Context& context = shared_context();
  const std::vector<std::byte> bytes(16 * 4);
  EXPECT_EQ(error_of([&] { Texture(context, 4, 4, Format::R32UI, bytes); }),
            "cannot generate mipmaps for R32UI textures: integer formats cannot be filtered");
  EXPECT_EQ(error_of([&] { Texture(context, 4, 4, Format::Depth32F, bytes); }),
            "cannot generate mipmaps for Depth32F textures: depth formats cannot be filtered");
  Texture texture(context, 4, 4, Format::RGBA32I, 3);
  EXPECT_EQ(error_of([&] { texture.generate_mipmaps(); }),
            "cannot generate mipmaps for RGBA32I textures: integer formats cannot be filtered");
  EXPECT_EQ(Texture(context, 4, 4, Format::R32UI, bytes, false).levels(), 1);
}

TEST(TextureErrors, StencilIsReadOnlyFromStencilFormats) {
  Context& context = shared_context();
  EXPECT_EQ(error_of([&] { Texture(context, 2, 2, Format::Depth32F).read_stencil(); }),
            "read_stencil needs a texture with stencil; this one is Depth32F");
  const Texture depth_stencil(context, 3, 2, Format::Depth32FStencil8);
  EXPECT_EQ(depth_stencil.read_stencil(), std::vector<std::uint8_t>(6, 0));
  EXPECT_EQ(depth_stencil.read().size(), 24u);
}

TEST(TextureErrors, MissingAndUndecodableFilesAreRejectedWithTheirNamesAndReasons) {
  Context& context = shared_context();
  EXPECT_EQ(error_of([&] { Texture::load(context, "/nonexistent/picture.png"); }),
            "cannot read /nonexistent/picture.png: No such file or directory");
  const std::string directory = std::filesystem::temp_directory_path().string();
  EXPECT_EQ(error_of([&] { Texture::load(context, directory); }), "cannot read " + directory + ": Is a directory");
  const std::string garbage = "not a picture at all";
  EXPECT_EQ(
      error_of([&] { Texture::decode(context, bytes_of(garbage.data(), garbage.size()), true, false, "garbage.bin"); }),
      "cannot decode garbage.bin: unknown image type");
  EXPECT_EQ(error_of([&] { Texture::decode(context, {}); }), "cannot decode image: unknown image type");

  // A PNG cut short after its header: the header says what it is, the data is missing.
  std::vector<std::uint8_t> encoded;
  const auto append = [](void* out, void* data, int size) {
    static_cast<std::vector<std::uint8_t>*>(out)->insert(static_cast<std::vector<std::uint8_t>*>(out)->end(),
                                                         static_cast<std::uint8_t*>(data),
                                                         static_cast<std::uint8_t*>(data) + size);
  };
  const std::vector<std::uint8_t> rgba(8 * 8 * 4, 77);
  ASSERT_TRUE(stbi_write_png_to_func(append, &encoded, 8, 8, 4, rgba.data(), 8 * 4));
  encoded.resize(40);
  const std::string message = error_of([&] { Texture::decode(context, bytes_of(encoded), true, false, "cut.png"); });
  EXPECT_EQ(message.rfind("cannot decode cut.png: ", 0), 0u) << message;

  // A picture wider than a texture can be is refused from its header, before decoding.
  encoded.clear();
  const std::vector<std::uint8_t> row(20000 * 4, 0);
  ASSERT_TRUE(stbi_write_png_to_func(append, &encoded, 20000, 1, 4, row.data(), 20000 * 4));
  EXPECT_EQ(error_of([&] { Texture::decode(context, bytes_of(encoded), true, false, "wide.png"); }),
            "cannot load wide.png: its 20000x1 pixels exceed the texture size limit of 16384 per side");
}

}  // namespace
}  // namespace clraster::test
