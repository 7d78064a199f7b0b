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
#include <functional>
#include <memory>
#include <optional>
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
  // The limits the pipeline's sizes are chosen within (OpenCL 1.2 promises only 32 KiB of local
  // memory, 64 KiB of constant memory, 1 KiB of kernel arguments, work-groups of one work-item, and
  // buffers of a quarter of the memory). What a device cannot run is an InvalidArgument naming the
  // limit, never a driver failure.
  std::size_t local_memory_bytes = 0;    // CL_DEVICE_LOCAL_MEM_SIZE
  std::size_t work_group_items = 0;      // CL_DEVICE_MAX_WORK_GROUP_SIZE
  std::size_t buffer_bytes = 0;          // CL_DEVICE_MAX_MEM_ALLOC_SIZE: one buffer at most
  std::size_t constant_buffer_bytes = 0; // CL_DEVICE_MAX_CONSTANT_BUFFER_SIZE: a program's uniforms at most
  std::size_t parameter_bytes = 0;       // CL_DEVICE_MAX_PARAMETER_SIZE: all of a kernel's arguments
  unsigned address_bits = 0;             // CL_DEVICE_ADDRESS_BITS
};

// Every OpenCL device of every platform, in a stable order. Throws DeviceError when the machine has
// no OpenCL platform at all (the message names pocl-opencl-icd, the CPU implementation on Debian).
std::vector<DeviceInfo> list_devices();

inline constexpr std::size_t kDefaultMemoryCap = std::size_t{256} << 20;
inline constexpr std::size_t kMinMemoryCap = std::size_t{4} << 20;
// ContextOptions::tile_size: kDeviceTileSize lets the context pick from the work-group shapes it
// takes (see WorkGroupShape). Where a work-group loops over its tile (CPUs), 32x32 pixels: against
// 16x16, a quarter of the tiles and half the bin entries of triangles larger than a tile, which
// the few work-items walk anyway (clraster bench on PoCL, medians of three runs in turn: the
// 50k-triangle model 1.14 times faster, the fill-rate scene 1.12, the terrains and the one-pixel
// triangles 1.02 to 1.04; docs/performance.md, step 36).
// Where a work-item takes a pixel of the tile (GPUs), 16x16 pixels: 256 work-items, and the tile
// in the local memory of small GPUs; against 8x8, a quarter of the bin entries and tile loads for
// triangles larger than a tile. Smaller where the device needs it: in the GPU shapes, a tile's
// pixels must fit in one work-group; and a program whose stages need more local memory than the
// device has at the context's size (a tile's attachments: 32 KiB, OpenCL's minimum, holds a 32x32
// tile of one RGBA colour attachment but not the triangles staged beside it) is built for the
// largest smaller one that fits.
inline constexpr int kDeviceTileSize = 0;
inline constexpr int kCpuShapeTileSize = 32;
inline constexpr int kGpuShapeTileSize = 16;
inline constexpr std::array<int, 3> kTileSizes = {8, 16, 32};  // ContextOptions::tile_size, or kDeviceTileSize

// How many work-items the pipeline's kernels put in a work-group. Device: the device's own shapes
// (on GPUs a work-item per pixel of a tile and 256 per block of a scan or sort; on CPUs one
// work-item looping over them, which PoCL runs faster). Wide: the GPU shapes on any device, to test
// them on a CPU, or for a CPU OpenCL whose compiler vectorizes across work-items. Both draw the
// same pictures, bit for bit.
enum class WorkGroupShape { Device, Wide };

struct ContextOptions {
  // Index into list_devices(). -1 takes the CLRASTER_DEVICE environment variable when it is set,
  // else device 0.
  int device = -1;
  // Upper bound, in bytes, on the pipeline's intermediate buffers (transformed vertices, set-up
  // triangles, bin lists). Draws that need more are processed in chunks; nothing is dropped.
  // At least kMinMemoryCap.
  std::size_t memory_cap = kDefaultMemoryCap;
  // Side of the square screen tile that one work-group rasterizes: 8, 16 or 32 pixels, or
  // kDeviceTileSize for the context's choice (Context::options() then says which it took; a program
  // that does not fit the device at that size takes a smaller one). A program that does not fit the
  // device at a size given here is refused (InvalidArgument naming the limit).
  int tile_size = kDeviceTileSize;
  // Where built program binaries are kept between runs. Empty: $CLRASTER_CACHE_DIR, else
  // $XDG_CACHE_HOME/clraster, else ~/.cache/clraster. "off" (here or in $CLRASTER_CACHE_DIR)
  // disables the on-disk cache. It keeps at most 512 MiB, removing the least recently used first.
  std::string cache_dir;
  // Measure each pipeline stage's device time (DrawStats::stage_times). Costs a little per command.
  bool profile = false;
  // Hears, one line each, what the context recovered from by itself: a program-cache entry that was
  // damaged (or that the driver rejected) and was rebuilt. Unset: written to stderr as
  // "clraster: warning: ...".
  std::function<void(const std::string& message)> on_warning;
  // Unset: $CLRASTER_WORK_GROUP_SHAPE ("device" or "wide"), else Device (Context::options() then
  // says which it took).
  std::optional<WorkGroupShape> work_group_shape;
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
// Buffers.

// Raw bytes on the device: vertex attributes, and user buffers that programs read or write.
class Buffer {
 public:
  Buffer(Context& context, std::size_t bytes);                       // zero-filled
  Buffer(Context& context, std::span<const std::byte> data);
  template <typename T>
  Buffer(Context& context, std::span<const T> data) : Buffer(context, std::as_bytes(data)) {}
  template <typename T>
  Buffer(Context& context, const std::vector<T>& data) : Buffer(context, std::span<const T>(data)) {}
  ~Buffer();
  Buffer(Buffer&&) noexcept;
  Buffer& operator=(Buffer&&) noexcept;

  std::size_t size_bytes() const;
  void write(std::size_t offset, std::span<const std::byte> data);
  std::vector<std::byte> read() const;

  struct Impl;
  Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

// Vertex positions and (optionally) normals, three floats each: the attributes "position" and
// "normal" (float3) that the built-in programs read, and that user programs may declare too.
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

// 16- or 32-bit vertex indices. Indices are checked against the vertex attributes when drawing: a
// draw that references a vertex that does not exist throws InvalidArgument before anything is rendered.
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

// ---------------------------------------------------------------------------------------------
// Textures: 2D images with a mipmap chain, sampled in software by programs and rendered into as
// framebuffer attachments. Texel row 0 is t = 0 (the bottom of a rendered image, the first row of
// uploaded data), as in OpenGL.

enum class Format {
  R8, RG8, RGBA8,          // unsigned normalized: sampled and rendered as floats in [0, 1]
  SRGB8_A8,                // RGBA8 whose colour channels are sRGB-encoded (decoded when sampled, encoded when written)
  R32F, RG32F, RGBA16F, RGBA32F,
  R32I, R32UI, RGBA32I, RGBA32UI,  // integer: rendered as int4/uint4 outputs, read with texel fetches
  Depth32F,                // depth attachment; sampled as a float in .x
  Depth32FStencil8,        // depth and 8-bit stencil attachment; sampled as its depth
};

struct FormatInfo {
  int bytes_per_texel;   // of one plane; Depth32FStencil8 adds one stencil byte per texel in a second plane
  int channels;
  bool integer;          // R32I .. RGBA32UI
  bool is_signed;        // R32I, RGBA32I
  bool depth;
  bool stencil;
  const char* name;      // "RGBA8", ...
};
const FormatInfo& format_info(Format format);

enum class Filter { Nearest, Linear };
enum class MipFilter { None, Nearest, Linear };  // None: level 0 only
enum class Wrap { Repeat, ClampToEdge, MirroredRepeat };

// How a program samples a texture (OpenGL's sampler object state).
struct Sampler {
  Filter mag_filter = Filter::Linear;
  Filter min_filter = Filter::Linear;
  MipFilter mip_filter = MipFilter::Linear;  // GL_LINEAR_MIPMAP_LINEAR with the defaults: trilinear
  Wrap wrap_s = Wrap::Repeat;
  Wrap wrap_t = Wrap::Repeat;
  float lod_bias = 0.0f;
  float min_lod = -1000.0f;
  float max_lod = 1000.0f;
};

inline constexpr int kMaxTextureSize = 16384;
inline constexpr int kMaxFramebufferSize = 16384;  // pixels per side of a framebuffer (its attachments' level 0)
inline constexpr int kFullMipChain = 0;

class Texture {
 public:
  // Uninitialized (zero) texture. levels: 1..full chain, or kFullMipChain for down to 1x1.
  Texture(Context& context, int width, int height, Format format, int levels = 1);
  // Texture holding `level0` (rows of width texels, first row t = 0, tightly packed in the format's
  // layout), with its mipmaps generated when `mipmaps`.
  Texture(Context& context, int width, int height, Format format, std::span<const std::byte> level0,
          bool mipmaps = true);
  // A PNG or JPEG file (anything stb_image reads), as RGBA8 or SRGB8_A8, with mipmaps. The file's
  // first row becomes t = 0 unless flip_vertically (then its last row does, as OpenGL apps often want).
  static Texture load(Context& context, const std::string& path, bool srgb = true, bool flip_vertically = false);
  // The same from an encoded file in memory (e.g. embedded in a glTF binary).
  static Texture decode(Context& context, std::span<const std::byte> encoded, bool srgb = true,
                        bool flip_vertically = false, const std::string& name = "image");
  ~Texture();
  Texture(Texture&&) noexcept;
  Texture& operator=(Texture&&) noexcept;

  int width(int level = 0) const;
  int height(int level = 0) const;
  int levels() const;
  Format format() const;
  // The device memory the texture holds: every level (and a stencil plane).
  std::size_t memory_bytes() const;

  // Replaces a level's texels (tightly packed, rows from t = 0).
  void upload(int level, std::span<const std::byte> texels);
  // Recomputes levels 1.. from level 0, e.g. after rendering into level 0: each level samples the
  // one before bilinearly at its texel centres, as Mesa's glGenerateMipmap does (a 2x2 box filter
  // where a side halves exactly), in linear space for sRGB. Not for integer or depth formats.
  void generate_mipmaps();
  // A level's texels, tightly packed, rows from t = 0 (for Depth32FStencil8: the depth plane).
  std::vector<std::byte> read(int level = 0) const;
  std::vector<std::uint8_t> read_stencil() const;  // Depth32FStencil8 only, rows from t = 0

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

// ---------------------------------------------------------------------------------------------
// Programs: vertex and fragment programs written in OpenCL C, compiled at run time into the
// pipeline's kernels. docs/programs.md describes the language; in short, a program declares its
// interface at file scope and defines `void vertex(clr_vertex* v)` and `void fragment(clr_fragment* f)`:
//
//   clr_attribute(float3, position)
//   clr_attribute(float2, uv)
//   clr_varying(float2, uv)
//   clr_uniform(float16, mvp)
//   clr_texture(albedo)
//   clr_output(float4, color)
//
//   void vertex(clr_vertex* v) {
//     v->position = clr_mul(v->uniforms->mvp, (float4)(v->in.position, 1.0f));
//     v->out.uv = v->in.uv;
//   }
//   void fragment(clr_fragment* f) { f->out.color = clr_sample(f, f->textures.albedo, f->in.uv); }

// One declaration of a program's interface, in declaration order.
struct ProgramVariable {
  std::string name;
  std::string type;          // OpenCL C type as written: "float3", "uint", "float16", ...
  int array_size = 0;        // uniforms only: 0 for a single value, else the number of elements
  int line = 0;              // in the program's source
  std::size_t offset = 0;    // uniforms: byte offset in the uniform block
  std::size_t bytes = 0;     // uniforms: size in bytes (with the array)
  std::string interpolation; // varyings: "smooth", "flat" or "noperspective"
  bool writable = false;     // buffers: declared without const
};

struct ProgramInterface {
  std::vector<ProgramVariable> attributes;
  std::vector<ProgramVariable> varyings;
  std::vector<ProgramVariable> uniforms;
  std::vector<ProgramVariable> textures;
  std::vector<ProgramVariable> buffers;
  std::vector<ProgramVariable> outputs;  // output k goes to colour attachment k
  std::size_t uniform_bytes = 0;
  bool has_depth_test = false;           // defines bool depth_test(...)
  bool has_blend = false;                // defines float4 blend(...)
  bool uses_derivatives = false;         // shaded in 2x2 quads
  bool has_fragment_span = false;        // its fragment program is void fragment_span(...), a span at a time
};

class Program {
 public:
  // Compiles `source`; `file_name` is what errors call it. Throws BuildError whose what() carries the
  // compiler's messages as "file_name:LINE:COLUMN: error: ..." lines, or InvalidArgument for a
  // malformed interface declaration.
  Program(Context& context, std::string source, std::string file_name = "program.cl");
  static Program load(Context& context, const std::string& path);
  // The text of the program file at `path`, as load reads it. Throws InvalidArgument when it cannot
  // be opened or read.
  static std::string read_source(const std::string& path);
  // What `source` declares, read without compiling it (a build takes seconds; this, microseconds),
  // for tools that check a program before they build it. Throws InvalidArgument for a malformed
  // declaration, as the constructor does.
  static ProgramInterface read_interface(const std::string& source, const std::string& file_name = "program.cl");
  ~Program();
  Program(Program&&) noexcept;
  Program& operator=(Program&&) noexcept;

  const std::string& file_name() const;
  const ProgramInterface& interface() const;

  struct Impl;
  Impl& impl() const { return *impl_; }
  explicit Program(std::unique_ptr<Impl> impl);  // for the library's built-in program

 private:
  std::unique_ptr<Impl> impl_;
};

// Values and resources bound to a program's declared names. Each setter checks the name and the
// size or kind against the program and throws InvalidArgument naming what is wrong; a draw throws
// if a declared name was left unbound.
class Bindings {
 public:
  explicit Bindings(const Program& program);
  ~Bindings();
  Bindings(const Bindings&);
  Bindings& operator=(const Bindings&);
  Bindings(Bindings&&) noexcept;
  Bindings& operator=(Bindings&&) noexcept;

  // A uniform's bytes, in the declared type's layout (float3 takes 12 bytes and is padded to 16 in
  // arrays, float16 is a column-major 4x4 matrix). `element` starts at that array element.
  Bindings& set_bytes(const std::string& name, std::span<const std::byte> bytes, int element = 0);
  Bindings& set(const std::string& name, float value);
  Bindings& set(const std::string& name, std::int32_t value);
  Bindings& set(const std::string& name, std::uint32_t value);
  template <std::size_t N>
  Bindings& set(const std::string& name, const std::array<float, N>& value) {
    return set_bytes(name, std::as_bytes(std::span<const float>(value)));
  }
  template <std::size_t N>
  Bindings& set(const std::string& name, const std::array<std::int32_t, N>& value) {
    return set_bytes(name, std::as_bytes(std::span<const std::int32_t>(value)));
  }
  Bindings& set(const std::string& name, const std::vector<float>& values) {
    return set_bytes(name, std::as_bytes(std::span<const float>(values)));
  }
  Bindings& set_texture(const std::string& name, const Texture& texture, const Sampler& sampler = {});
  // Bound textures and buffers must outlive the draws that use them.
  Bindings& set_buffer(const std::string& name, const Buffer& buffer);

  struct Impl;
  Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

// ---------------------------------------------------------------------------------------------
// Draw state.

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
// OpenGL's comparison functions (fragment op stored). Program: the program's depth_test function
// decides (depth only).
enum class CompareFunc { Never, Less, Equal, LessEqual, Greater, NotEqual, GreaterEqual, Always, Program };
enum class StencilOp { Keep, Zero, Replace, Increment, IncrementWrap, Decrement, DecrementWrap, Invert };

struct StencilFace {
  CompareFunc func = CompareFunc::Always;
  std::uint8_t reference = 0;
  std::uint8_t read_mask = 0xff;
  std::uint8_t write_mask = 0xff;
  StencilOp stencil_fail = StencilOp::Keep;
  StencilOp depth_fail = StencilOp::Keep;
  StencilOp depth_pass = StencilOp::Keep;
};

// OpenGL's blend equations. Program: the program's blend function gives the result.
enum class BlendEquation { Add, Subtract, ReverseSubtract, Min, Max, Program };
enum class BlendFactor {
  Zero, One, SrcColor, OneMinusSrcColor, DstColor, OneMinusDstColor, SrcAlpha, OneMinusSrcAlpha,
  DstAlpha, OneMinusDstAlpha, ConstantColor, OneMinusConstantColor, ConstantAlpha, OneMinusConstantAlpha,
  SrcAlphaSaturate,
};

// Blending and write mask of one colour attachment. Blending applies to normalized and float
// attachments (never to integer ones, as in OpenGL).
struct BlendState {
  bool enabled = false;
  BlendEquation rgb_equation = BlendEquation::Add;
  BlendEquation alpha_equation = BlendEquation::Add;
  BlendFactor src_rgb = BlendFactor::One;
  BlendFactor dst_rgb = BlendFactor::Zero;
  BlendFactor src_alpha = BlendFactor::One;
  BlendFactor dst_alpha = BlendFactor::Zero;
  std::array<bool, 4> write_mask{true, true, true, true};
};
// glBlendFunc(GL_ONE, GL_ONE): an additive blend (an overdraw counter with Shading::Constant).
inline constexpr BlendState kAdditiveBlend{true,
                                           BlendEquation::Add,
                                           BlendEquation::Add,
                                           BlendFactor::One,
                                           BlendFactor::One,
                                           BlendFactor::One,
                                           BlendFactor::One,
                                           {true, true, true, true}};
// The program's blend function on every channel.
inline constexpr BlendState kProgramBlend{true,
                                          BlendEquation::Program,
                                          BlendEquation::Program,
                                          BlendFactor::One,
                                          BlendFactor::Zero,
                                          BlendFactor::One,
                                          BlendFactor::Zero,
                                          {true, true, true, true}};

inline constexpr int kMaxColorAttachments = 8;

// The built-in programs, used when a draw names no Program. Every mode transforms the attribute
// "position" by projection * model_view and interpolates its varyings perspective-correctly.
enum class Shading {
  Normal,    // colour = normalize(object-space normal) * 0.5 + 0.5, alpha 1
  Lambert,   // colour = base_color * (0.1 + 0.9 * |n_eye . z|): a headlight at the camera, two-sided
  Depth,     // grey = 1 - (view distance - near) / (far - near) over depth_shading_range, clamped
  Constant,  // colour = base_color (with kAdditiveBlend and no depth test: an overdraw counter)
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
  bool stencil_test = false;
  StencilFace stencil_front{};
  StencilFace stencil_back{};

  std::array<BlendState, kMaxColorAttachments> blend{};  // per colour attachment
  std::array<float, 4> blend_color{0, 0, 0, 0};           // GL_CONSTANT_COLOR

  // Inputs of the built-in programs (ignored when the draw has a Program).
  Shading shading = Shading::Normal;
  Mat4 model_view = kIdentity;
  Mat4 projection = kIdentity;
  std::array<float, 4> base_color{1, 1, 1, 1};
  std::array<float, 2> depth_shading_range{0.1f, 100.0f};  // view distances drawn white and black
};

enum class AttributeType {
  Float, Float2, Float3, Float4,
  Int, Int2, Int3, Int4,
  UInt, UInt2, UInt3, UInt4,
};

// Where one attribute a program declares comes from: element i (vertex, or instance when
// per_instance) is at byte offset + i * stride of the buffer.
struct VertexAttribute {
  std::string name;
  const Buffer* buffer = nullptr;
  AttributeType type = AttributeType::Float3;
  std::size_t offset = 0;
  std::size_t stride = 0;      // 0: tightly packed
  bool per_instance = false;   // advances once per instance (divisor 1), not per vertex
};

inline constexpr std::uint32_t kAllElements = 0xffffffffu;

// What one view of a draw into a layered framebuffer changes: the camera of the built-in programs,
// or a Program's uniforms. View k is drawn into layer k, and programs see k as view_id.
struct View {
  Mat4 model_view = kIdentity;         // built-in programs: in place of DrawState::model_view ...
  Mat4 projection = kIdentity;         // ... and DrawState::projection (ignored with a Program)
  const Bindings* bindings = nullptr;  // a Program's bindings for this view (null: the draw's own)
};

// One draw: which program, buffers and bindings, which part of the buffers, and the state.
struct DrawCall {
  const VertexBuffer* vertices = nullptr;  // supplies the attributes "position" and "normal"
  const IndexBuffer* indices = nullptr;    // null: non-indexed, vertices taken in order
  std::uint32_t first = 0;                 // first index (or vertex, when non-indexed)
  // Number of indices (or vertices). kAllElements: to the end of the index buffer, or of the
  // per-vertex attributes; a non-indexed draw with no per-vertex attribute must give it.
  std::uint32_t count = kAllElements;
  DrawState state{};
  const Program* program = nullptr;        // null: the built-in program for state.shading
  const Bindings* bindings = nullptr;      // the program's uniforms, textures and buffers
  std::vector<VertexAttribute> attributes; // further attributes (or all of them, without `vertices`)
  std::uint32_t instance_count = 1;
  // One per layer of the framebuffer, or none: then every layer is drawn with the draw's own state
  // and bindings (view_id still counts the layers). The viewport and scissor are within each layer.
  std::vector<View> views;
};

// Device time spent in each stage of a draw, in milliseconds (zero unless ContextOptions::profile).
struct StageTimes {
  double vertex_ms = 0;     // vertex program
  double setup_ms = 0;      // assembly, clipping, culling, triangle set-up, and the scans that place them
  double binning_ms = 0;    // bin pairs, radix sort by tile, tile ranges
  double raster_ms = 0;     // rasterization, fragment program, depth/stencil tests, blending
  double other_ms = 0;      // index validation, clears and transfers
};

struct DrawStats {
  std::uint64_t triangles = 0;            // primitives assembled from the input (all instances)
  std::uint64_t triangles_dropped = 0;    // of those, dropped for non-finite clip coordinates
  std::uint64_t chunks = 0;               // passes of draws through the stages, and chunks of draws too large for one
  std::uint64_t tile_triangle_pairs = 0;  // (tile, triangle) bin entries rasterized
  // Largest total of the pipeline's intermediate buffers held, so far, by the context: what
  // ContextOptions::memory_cap bounds. Framebuffers, textures and vertex buffers are besides.
  std::uint64_t peak_memory_bytes = 0;
  StageTimes stage_times;
};

// ---------------------------------------------------------------------------------------------
// Framebuffers: up to kMaxColorAttachments colour textures and an optional depth (or depth-stencil)
// texture, all of one size, rendered at their level 0.

class Framebuffer {
 public:
  // Owns an RGBA8 colour and a Depth32FStencil8 attachment of 1..16384 pixels per side, cleared to
  // (0, 0, 0, 1), depth 1 and stencil 0.
  Framebuffer(Context& context, int width, int height);
  // Renders into textures the caller owns (they must outlive the framebuffer). Any colour count
  // 0..8, formats may differ; depth_stencil may be null (then depth and stencil tests pass and
  // write nothing).
  Framebuffer(Context& context, std::vector<Texture*> colors, Texture* depth_stencil);
  // A layered framebuffer: `layers` (1..4096) pictures of width x height pixels, which a
  // draw renders together, one view each (DrawCall::views). Its RGBA8 and Depth32FStencil8
  // attachments hold the layers side by side: layer l at layer_rect(l), in rows of layer_columns()
  // (the smallest square grid), each side of the attachment at most 16384 pixels.
  Framebuffer(Context& context, int width, int height, int layers);
  ~Framebuffer();
  Framebuffer(Framebuffer&&) noexcept;
  Framebuffer& operator=(Framebuffer&&) noexcept;

  int width() const;   // of a layer
  int height() const;
  int layers() const;  // 1 unless layered
  int layer_columns() const;
  Rect layer_rect(int layer) const;     // where a layer is in the attachments, window coordinates
  int color_count() const;
  Texture& color(int index = 0);        // the attachment itself (render-to-texture), every layer
  Texture* depth_stencil();             // null when there is none

  // Clears every colour attachment (normalized and float ones to `color`; integer ones to the
  // values truncated toward zero and saturated to the format's range, NaN as 0), depth (clamped to
  // [0, 1]) and stencil.
  void clear(std::array<float, 4> color, float depth = 1.0f, std::uint8_t stencil = 0);
  void clear_color(std::array<float, 4> color);                        // every colour attachment
  void clear_color(int index, std::array<float, 4> color);
  void clear_color_int(int index, std::array<std::int32_t, 4> value);  // integer attachments
  void clear_color_uint(int index, std::array<std::uint32_t, 4> value);
  void clear_depth(float depth);
  void clear_stencil(std::uint8_t stencil);

  // Renders one draw call into this framebuffer. Draws are applied in the order they are made.
  DrawStats draw(const DrawCall& call);
  // Renders a frame: the calls in order, as if drawn one after the other, every one checked before
  // any renders. Consecutive calls (and each call's instances and views) that share a program, its
  // textures and buffers, and the state rasterization reads (depth, stencil, blending; not the
  // viewport or scissor) are binned together and rasterized in one pass over the tiles, so that many
  // small draws cost about what one draw of all their triangles costs. The statistics are the frame's.
  DrawStats draw(std::span<const DrawCall> calls);

  // Colour attachment `index` of `layer` converted to RGBA8 (normalized formats only; missing
  // channels read as 0, alpha as 1), rows top to bottom.
  Image read_color(int index = 0, int layer = 0) const;
  std::vector<float> read_depth(int layer = 0) const;           // rows top to bottom, width * height values
  std::vector<std::uint8_t> read_stencil(int layer = 0) const;  // rows top to bottom

  struct Impl;
  Impl& impl() const { return *impl_; }

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace clraster
