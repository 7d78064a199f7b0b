// clraster: a programmable graphics pipeline written as OpenCL kernels.
//
// The whole public API is this header. A typical frame:
//
//   clraster::Context context;                          // picks a device (CLRASTER_DEVICE or the first)
//   clraster::VertexBuffer vertices(context, positions, normals);
//   clraster::IndexBuffer indices(context, triangle_indices);
//   clraster::Framebuffer target(context, 1920, 1080);
//   target.clear({0, 0, 0, 1}, 1.0f);
//   clraster::DrawCall call{&vertices, &indices};
//   call.state.model_view = ...; call.state.projection = ...;   // column-major, as OpenGL
//   clraster::DrawStats stats = target.draw(call);
//   clraster::Image picture = target.read_color();      // RGBA8, top row first
//
// Conventions follow OpenGL: clip space x, y, z in [-w, w]; window coordinates with y up; pixel
// centres at (i + 0.5, j + 0.5); counter-clockwise front faces; depth cleared to 1 and tested LESS.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace clraster {

// The library version ("major.minor.patch").
const char* version();

// ---------------------------------------------------------------------------------------------
// Errors. Every failure is reported by throwing one of these; messages are one line and say what
// was wrong and with which value.

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// No OpenCL platform or device, or a device index that does not exist.
class DeviceError : public Error {
 public:
  using Error::Error;
};

// An OpenCL program failed to build. what() names the program; log() is the compiler's output.
class BuildError : public Error {
 public:
  BuildError(const std::string& message, std::string log) : Error(message), log_(std::move(log)) {}
  const std::string& log() const { return log_; }

 private:
  std::string log_;
};

// An argument or input the library cannot accept (sizes, states, indices, memory caps).
class InvalidArgument : public Error {
 public:
  using Error::Error;
};

// ---------------------------------------------------------------------------------------------
// Devices and the context.

struct DeviceInfo {
  int index = 0;               // position in list_devices(), across all platforms
  std::string name;            // CL_DEVICE_NAME
  std::string platform;        // CL_PLATFORM_NAME
  std::string version;         // CL_DEVICE_VERSION
  std::string driver_version;  // CL_DRIVER_VERSION
  std::string type;            // "CPU", "GPU", "accelerator" or "other"
  int compute_units = 0;
};

// Every OpenCL device of every platform, in a stable order. Throws DeviceError when the machine has
// no OpenCL platform at all (the message names pocl-opencl-icd, the CPU implementation on Debian).
std::vector<DeviceInfo> list_devices();

inline constexpr std::size_t kDefaultMemoryCap = std::size_t{256} << 20;
inline constexpr std::size_t kMinMemoryCap = std::size_t{4} << 20;
// 8x8-pixel tiles: small triangles are tested against few pixels, and a tile is one 64-wide
// work-group, the shape both GPUs and PoCL's vectorizer like.
inline constexpr int kDefaultTileSize = 8;

struct ContextOptions {
  // Index into list_devices(). -1 takes the CLRASTER_DEVICE environment variable when it is set,
  // else device 0.
  int device = -1;
  // Upper bound, in bytes, on the pipeline's intermediate buffers (transformed vertices, set-up
  // triangles, bin lists). Draws that need more are processed in chunks; nothing is dropped.
  // At least kMinMemoryCap.
  std::size_t memory_cap = kDefaultMemoryCap;
  // Side of the square screen tile that one work-group rasterizes: 8, 16 or 32 pixels.
  int tile_size = kDefaultTileSize;
  // Where built program binaries are kept between runs. Empty: $CLRASTER_CACHE_DIR, else
  // $XDG_CACHE_HOME/clraster, else ~/.cache/clraster. "off" (here or in $CLRASTER_CACHE_DIR)
  // disables the on-disk cache.
  std::string cache_dir;
  // Measure each pipeline stage's device time (DrawStats::stage_times). Costs a little per command.
  bool profile = false;
};

// A device, its command queue, the built pipeline programs and the pipeline's scratch memory.
// Not thread-safe: use one context per thread.
class Context {
 public:
  explicit Context(const ContextOptions& options = {});
  ~Context();
  Context(Context&&) noexcept;
  Context& operator=(Context&&) noexcept;
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  const DeviceInfo& device() const;
  const ContextOptions& options() const;
  // Blocks until all work submitted to the device is done.
  void finish();

  struct Impl;
  Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

// ---------------------------------------------------------------------------------------------
// Resources.

// Vertex positions and (optionally) normals, three floats each, uploaded to the device.
class VertexBuffer {
 public:
  // positions: x, y, z per vertex. normals: empty (all normals are zero) or one x, y, z per vertex.
  VertexBuffer(Context& context, std::span<const float> positions, std::span<const float> normals = {});
  ~VertexBuffer();
  VertexBuffer(VertexBuffer&&) noexcept;
  VertexBuffer& operator=(VertexBuffer&&) noexcept;

  std::size_t size() const;  // number of vertices

  struct Impl;
  Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

// 16- or 32-bit vertex indices. Indices are checked against the vertex buffer when drawing: a draw
// that references a vertex that does not exist throws InvalidArgument before anything is rendered.
class IndexBuffer {
 public:
  IndexBuffer(Context& context, std::span<const std::uint32_t> indices);
  IndexBuffer(Context& context, std::span<const std::uint16_t> indices);
  ~IndexBuffer();
  IndexBuffer(IndexBuffer&&) noexcept;
  IndexBuffer& operator=(IndexBuffer&&) noexcept;

  std::size_t size() const;        // number of indices
  int index_size() const;          // bytes per index: 2 or 4

  struct Impl;
  Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

// An RGBA8 picture in memory, rows from top to bottom, 4 bytes per pixel.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> rgba;
};

// Column-major 4x4 matrix, as OpenGL's glUniformMatrix4fv with transpose = GL_FALSE.
using Mat4 = std::array<float, 16>;
inline constexpr Mat4 kIdentity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

// A rectangle in window coordinates (origin at the bottom-left pixel, y up).
struct Rect {
  int x = 0;
  int y = 0;
  int width = 0;
  int height = 0;
};

enum class Topology { TriangleList, TriangleStrip, TriangleFan };
enum class CullMode { None, Back, Front };
enum class FrontFace { CounterClockwise, Clockwise };
enum class CompareFunc { Never, Less, Equal, LessEqual, Greater, NotEqual, GreaterEqual, Always };
enum class BlendMode {
  Replace,   // destination = source
  Additive,  // destination = min(source + destination, 1), per channel (glBlendFunc(GL_ONE, GL_ONE))
};

// The built-in vertex and fragment program. Every mode transforms positions by
// projection * model_view and interpolates its varyings perspective-correctly.
enum class Shading {
  Normal,    // colour = normalize(object-space normal) * 0.5 + 0.5, alpha 1
  Lambert,   // colour = base_color * (0.1 + 0.9 * |n_eye . z|): a headlight at the camera, two-sided
  Depth,     // grey = 1 - (view distance - near) / (far - near) over depth_shading_range, clamped
  Constant,  // colour = base_color (with Additive blending and no depth test: an overdraw counter)
};

struct DrawState {
  Topology topology = Topology::TriangleList;
  Rect viewport{};                  // width or height 0: the whole framebuffer
  bool scissor_test = false;
  Rect scissor{};
  CullMode cull = CullMode::None;
  FrontFace front_face = FrontFace::CounterClockwise;
  bool depth_test = true;
  CompareFunc depth_func = CompareFunc::Less;
  bool depth_write = true;
  BlendMode blend = BlendMode::Replace;

  Shading shading = Shading::Normal;
  Mat4 model_view = kIdentity;
  Mat4 projection = kIdentity;
  std::array<float, 4> base_color{1, 1, 1, 1};
  std::array<float, 2> depth_shading_range{0.1f, 100.0f};  // view distances drawn white and black
};

inline constexpr std::uint32_t kAllElements = 0xffffffffu;

// One draw: which buffers, which part of them, and the state. Plain data, cheap to copy.
struct DrawCall {
  const VertexBuffer* vertices = nullptr;
  const IndexBuffer* indices = nullptr;  // null: non-indexed, vertices taken in order
  std::uint32_t first = 0;               // first index (or vertex, when non-indexed)
  std::uint32_t count = kAllElements;    // number of indices (or vertices); kAllElements: to the end
  DrawState state{};
};

// Device time spent in each stage of a draw, in milliseconds (zero unless ContextOptions::profile).
struct StageTimes {
  double vertex_ms = 0;     // vertex program
  double setup_ms = 0;      // assembly, clipping, culling, triangle set-up, and the scans that place them
  double binning_ms = 0;    // bin pairs, radix sort by tile, tile ranges
  double raster_ms = 0;     // rasterization, depth test, interpolation, shading, blending
  double other_ms = 0;      // index validation, clears and transfers
};

struct DrawStats {
  std::uint64_t triangles = 0;            // primitives assembled from the input
  std::uint64_t triangles_dropped = 0;    // of those, dropped for non-finite clip coordinates
  std::uint64_t chunks = 0;               // pieces the draw was split into to stay under the memory cap
  std::uint64_t tile_triangle_pairs = 0;  // (tile, triangle) bin entries rasterized
  std::uint64_t peak_memory_bytes = 0;    // largest total of intermediate buffers held, so far, by the context
  StageTimes stage_times;
};

// A colour (RGBA8) and a depth (32-bit float) attachment of 1..16384 pixels per side.
class Framebuffer {
 public:
  Framebuffer(Context& context, int width, int height);
  ~Framebuffer();
  Framebuffer(Framebuffer&&) noexcept;
  Framebuffer& operator=(Framebuffer&&) noexcept;

  int width() const;
  int height() const;

  void clear(std::array<float, 4> color, float depth = 1.0f);
  void clear_color(std::array<float, 4> color);
  void clear_depth(float depth);

  // Renders one draw call into this framebuffer. Draws are applied in the order they are made.
  DrawStats draw(const DrawCall& call);

  Image read_color() const;              // rows top to bottom
  std::vector<float> read_depth() const; // rows top to bottom, width * height values

  struct Impl;
  Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace clraster
