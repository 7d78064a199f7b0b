#include "renderer.hpp"

#include <algorithm>
#include <cstring>

#include "pipeline/draw_state.hpp"
#include "shared/clr_limits.h"

namespace clraster::python {

extern const char* const kVisibilityProgram;  // visibility.cl, embedded by CMake

namespace {

// What the attachments of one batch's framebuffer may take: batches larger than this are drawn in
// chunks of layers, so that memory does not grow with the batch.
constexpr std::size_t kAttachmentBudget = std::size_t{256} << 20;

// The library's layout of a layered framebuffer (Framebuffer(context, width, height, layers)):
// the smallest square grid, layer l at column l % columns of row l / columns.
struct LayerGrid {
  int columns = 1;
  int rows = 1;

  explicit LayerGrid(int layers) {
    while (columns * columns < layers) ++columns;
    rows = (layers + columns - 1) / columns;
  }
  Rect layer_rect(int layer, int width, int height) const {
    return {layer % columns * width, layer / columns * height, width, height};
  }
};

// How many of the pictures one framebuffer takes: all of them, within the library's layer limit,
// the largest attachment side, kAttachmentBudget for all attachments (pixel_bytes a pixel) and the
// device's largest buffer for the largest one (texel_bytes a pixel).
int layers_per_pass(const Pictures& pictures, std::size_t pixel_bytes, std::size_t texel_bytes,
                    std::size_t buffer_bytes) {
  int layers = static_cast<int>(std::min<std::size_t>(pictures.count, CLR_MAX_LAYERS));
  for (; layers > 1; --layers) {
    const LayerGrid grid(layers);
    const std::int64_t width = std::int64_t{pictures.width} * grid.columns;
    const std::int64_t height = std::int64_t{pictures.height} * grid.rows;
    const auto pixels = static_cast<std::size_t>(width * height);
    if (width <= kMaxFramebufferSize && height <= kMaxFramebufferSize && pixels * pixel_bytes <= kAttachmentBudget &&
        pixels * texel_bytes <= buffer_bytes) {
      break;
    }
  }
  return layers;
}

// Copies each layer of a grid of them (rows from the bottom, as textures hold them) into
// consecutive pictures whose rows run from the top.
void copy_layers(const std::vector<std::byte>& grid, int layers, const Pictures& pictures, std::size_t pixel_bytes,
                 void* first_picture) {
  const LayerGrid layout(layers);
  const std::size_t row_bytes = std::size_t(pictures.width) * pixel_bytes;
  const std::size_t grid_row_bytes = row_bytes * std::size_t(layout.columns);
  auto* out = static_cast<std::byte*>(first_picture);
  for (int layer = 0; layer < layers; ++layer) {
    const Rect rect = layout.layer_rect(layer, pictures.width, pictures.height);
    for (int y = 0; y < pictures.height; ++y) {
      const std::byte* source = grid.data() + std::size_t(rect.y + y) * grid_row_bytes + std::size_t(rect.x) * pixel_bytes;
      std::byte* target = out + (std::size_t(layer) * std::size_t(pictures.height) + std::size_t(pictures.height - 1 - y)) * row_bytes;
      std::memcpy(target, source, row_bytes);
    }
  }
}

// The bytes of one value of each of `own`'s uniforms, as the program declares them. Throws
// InvalidArgument for a uniform it does not declare, or bytes that are not one value or one per
// view (the package checks values first; this keeps the draws within the bytes given).
std::vector<std::size_t> own_value_bytes(const ProgramInterface& interface, const OwnValues& own, std::size_t views) {
  std::vector<std::size_t> sizes;
  for (const OwnValues::Uniform& uniform : own.uniforms) {
    const auto declared = std::find_if(interface.uniforms.begin(), interface.uniforms.end(),
                                       [&](const ProgramVariable& v) { return v.name == uniform.name; });
    if (declared == interface.uniforms.end()) throw InvalidArgument("the program has no uniform '" + uniform.name + "'");
    if (uniform.bytes.size() != declared->bytes * (uniform.per_view ? views : 1)) {
      throw InvalidArgument("uniform '" + uniform.name + "': " + std::to_string(uniform.bytes.size()) +
                            " bytes, not " + (uniform.per_view ? "one value of " + std::to_string(declared->bytes) +
                            " bytes per view" : "one value of " + std::to_string(declared->bytes) + " bytes"));
    }
    sizes.push_back(declared->bytes);
  }
  return sizes;
}

ContextOptions context_options(int device, std::size_t memory_cap) {
  ContextOptions options;
  options.device = device;
  options.memory_cap = memory_cap;
  return options;
}

}  // namespace

struct Renderer::MeshBuffers {
  std::weak_ptr<const MeshData> mesh;
  VertexBuffer vertices;
  IndexBuffer indices;
  // For the visibility buffer, made by the first rasterize: the positions as an attribute and for
  // the fragment program, which reads a triangle's corners (with the indices) to weigh them.
  std::optional<Buffer> positions;
  std::optional<Buffer> corners;
};

// A mesh's draws with a program, made once (textures loaded, texture coordinates uploaded); left
// out of the cache, unused, once the mesh or the program is gone.
struct Renderer::ModelDraws {
  std::weak_ptr<const MeshData> mesh;
  std::weak_ptr<const Program> program;
  frontend::ClrasterModelDraws draws;
};

struct Renderer::VisibilityTarget {
  static constexpr std::size_t kPixelBytes = 4 + 8 + 4;  // triangle (R32I), barycentrics (RG32F), depth
  static constexpr std::size_t kLargestTexelBytes = 8;

  int width;
  int height;
  int layers;
  Texture triangles;
  Texture barycentrics;
  Texture depths;
  Framebuffer framebuffer;

  VisibilityTarget(Context& context, int width, int height, int layers)
      : width(width),
        height(height),
        layers(layers),
        triangles(context, width * LayerGrid(layers).columns, height * LayerGrid(layers).rows, Format::R32I),
        barycentrics(context, triangles.width(), triangles.height(), Format::RG32F),
        depths(context, triangles.width(), triangles.height(), Format::Depth32F),
        framebuffer(context, {&triangles, &barycentrics}, &depths) {}
};

Renderer::Renderer(int device, std::size_t memory_cap) : context_(context_options(device, memory_cap)) {}
Renderer::~Renderer() = default;

Renderer::MeshBuffers& Renderer::buffers(const std::shared_ptr<const MeshData>& mesh) {
  std::erase_if(uploads_, [](const auto& entry) { return entry.second->mesh.expired(); });
  std::unique_ptr<MeshBuffers>& entry = uploads_[mesh->id];
  if (!entry) {
    entry.reset(new MeshBuffers{mesh, VertexBuffer(context_, mesh->model.positions, mesh->model.normals),
                                IndexBuffer(context_, mesh->indices_drawn()), std::nullopt, std::nullopt});
  }
  return *entry;
}

Renderer::ModelDraws& Renderer::model_draws(const std::shared_ptr<const MeshData>& mesh,
                                            const std::shared_ptr<const Program>& program,
                                            std::vector<std::string>& warnings) {
  std::erase_if(model_draws_, [](const auto& entry) { return entry->mesh.expired() || entry->program.expired(); });
  for (const auto& entry : model_draws_) {
    if (entry->mesh.lock() == mesh && entry->program.lock() == program) return *entry;
  }
  return *model_draws_.emplace_back(
      new ModelDraws{mesh, program, frontend::ClrasterModelDraws(context_, *program, mesh->model, warnings)});
}

Framebuffer& Renderer::picture_target(int width, int height, int layers) {
  if (!picture_target_ || picture_target_->width() != width || picture_target_->height() != height ||
      picture_target_->layers() != layers) {
    picture_target_.reset();  // its memory free before the next one takes its own
    picture_target_.emplace(context_, width, height, layers);
  }
  return *picture_target_;
}

Renderer::VisibilityTarget& Renderer::visibility_target(int width, int height, int layers) {
  if (!visibility_target_ || visibility_target_->width != width || visibility_target_->height != height ||
      visibility_target_->layers != layers) {
    visibility_target_.reset();
    visibility_target_ = std::make_unique<VisibilityTarget>(context_, width, height, layers);
  }
  return *visibility_target_;
}

const Program& Renderer::visibility_program() {
  if (!visibility_program_) visibility_program_.emplace(context_, kVisibilityProgram, "<clraster visibility>");
  return *visibility_program_;
}

std::uint64_t Renderer::draw_pictures(std::size_t count, const Pictures& pictures, std::uint8_t* rgba,
                                      const Progress& progress,
                                      const std::function<DrawStats(Framebuffer&, std::size_t, int)>& draw_chunk) {
  const std::size_t picture_bytes = std::size_t(pictures.width) * std::size_t(pictures.height) * 4;
  // RGBA8 colour and a depth-stencil attachment of 5 bytes a pixel.
  const int chunk = layers_per_pass(pictures, 4 + 5, 5, context_.device().buffer_bytes);
  std::uint64_t dropped = 0;
  for (std::size_t first = 0; first < count; first += std::size_t(chunk)) {
    const int layers = static_cast<int>(std::min<std::size_t>(std::size_t(chunk), count - first));
    Framebuffer& framebuffer = picture_target(pictures.width, pictures.height, layers);
    framebuffer.clear({0, 0, 0, 1}, 1.0f);  // the command line's background
    dropped += draw_chunk(framebuffer, first, layers).triangles_dropped;
    copy_layers(framebuffer.color(0).read(), layers, pictures, 4, rgba + first * picture_bytes);
    if (progress) progress(first + std::size_t(layers), count);
  }
  return dropped;
}

std::uint64_t Renderer::render(const std::shared_ptr<const MeshData>& mesh, std::span<const Mat4> views,
                               const Mat4& projection, io::BuiltinShading shading, std::array<float, 2> depth_range,
                               const Pictures& pictures, std::uint8_t* rgba, const Progress& progress) {
  const std::lock_guard lock(mutex_);
  MeshBuffers& meshes = buffers(mesh);
  return draw_pictures(views.size(), pictures, rgba, progress, [&](Framebuffer& framebuffer, std::size_t first, int layers) {
    DrawCall call{&meshes.vertices, &meshes.indices};
    call.state = io::shading_state(shading, views[first], projection, depth_range);
    for (int k = 0; k < layers; ++k) call.views.push_back({views[first + std::size_t(k)], projection, nullptr});
    return framebuffer.draw(call);
  });
}

std::uint64_t Renderer::render(const std::shared_ptr<const MeshData>& mesh, std::span<const Mat4> views,
                               const Mat4& projection, const std::shared_ptr<const Program>& program,
                               const OwnValues& own, const Pictures& pictures, std::uint8_t* rgba,
                               const Progress& progress, std::vector<std::string>& warnings) {
  const std::vector<std::size_t> value_bytes = own_value_bytes(program->interface(), own, views.size());
  const std::lock_guard lock(mutex_);
  MeshBuffers& meshes = buffers(mesh);
  frontend::ClrasterModelDraws& draws = model_draws(mesh, program, warnings).draws;
  // The command line's state for programs (they read no built-in input): depth test, no culling.
  const DrawState state = io::shading_state(io::BuiltinShading::Normal, views[0], projection, {0, 1});
  return draw_pictures(views.size(), pictures, rgba, progress, [&](Framebuffer& framebuffer, std::size_t first, int layers) {
    std::vector<frontend::ProgramInputs> inputs;
    std::vector<Bindings> own_bindings;
    for (std::size_t view = first; view < first + std::size_t(layers); ++view) {
      inputs.push_back(frontend::view_inputs(views[view], projection, pictures.width, pictures.height));
      Bindings& bindings = own_bindings.emplace_back(*program);
      for (std::size_t k = 0; k < own.uniforms.size(); ++k) {
        const OwnValues::Uniform& uniform = own.uniforms[k];
        const std::size_t bytes = value_bytes[k];
        bindings.set_bytes(uniform.name, std::span(uniform.bytes).subspan(uniform.per_view ? view * bytes : 0, bytes));
      }
      for (const auto& [name, texture] : own.textures) bindings.set_texture(name, *texture, Sampler{});
    }
    draws.bind(inputs, own_bindings);
    return framebuffer.draw(draws.calls(meshes.vertices, meshes.indices, state));
  });
}

std::shared_ptr<const Program> Renderer::compile(const std::string& source, const std::string& file_name) {
  frontend::check_contract({source, file_name}, frontend::kPythonPackage);
  const std::lock_guard lock(mutex_);
  return std::make_shared<const Program>(context_, source, file_name);
}

std::shared_ptr<const Program> Renderer::material_program() {
  const std::lock_guard lock(mutex_);
  if (!material_program_) material_program_ = std::make_shared<const Program>(context_, frontend::kMaterialProgram, "<material>");
  return material_program_;
}

std::shared_ptr<const Texture> Renderer::texture(int width, int height, Format format, std::span<const std::byte> texels) {
  const std::size_t row_bytes = texels.size() / std::size_t(height);
  std::vector<std::byte> bottom_row_first(texels.size());
  for (int row = 0; row < height; ++row) {
    std::memcpy(bottom_row_first.data() + std::size_t(height - 1 - row) * row_bytes,
                texels.data() + std::size_t(row) * row_bytes, row_bytes);
  }
  const std::lock_guard lock(mutex_);
  return std::make_shared<const Texture>(context_, width, height, format, bottom_row_first, true);
}

std::uint64_t Renderer::rasterize(const std::shared_ptr<const MeshData>& mesh, std::span<const Mat4> views,
                                  const Mat4& projection, const Pictures& pictures, const VisibilityOutputs& out,
                                  const Progress& progress) {
  const std::lock_guard lock(mutex_);
  MeshBuffers& meshes = buffers(mesh);
  if (!meshes.positions) {
    std::vector<float> homogeneous;  // w = 1: the program takes clip positions as mvp times these
    for (std::size_t v = 0; v < mesh->model.vertex_count(); ++v) {
      homogeneous.insert(homogeneous.end(), &mesh->model.positions[3 * v], &mesh->model.positions[3 * v + 3]);
      homogeneous.push_back(1.0f);
    }
    meshes.positions.emplace(context_, homogeneous);
    meshes.corners.emplace(context_, mesh->indices_drawn());
  }
  const std::uint64_t dropped = draw_visibility(
      views.size(), meshes.indices, *meshes.corners, pictures, out, progress, [&](std::size_t first, int layers) {
        std::vector<VisibilityView> chunk;
        for (std::size_t view = first; view < first + std::size_t(layers); ++view) {
          DrawState camera;  // the built-in programs' product, so that the visibility buffer covers what render draws
          camera.model_view = views[view];
          camera.projection = projection;
          chunk.push_back({&*meshes.positions, pipeline::model_view_projection(camera)});
        }
        return chunk;
      });
  if (!mesh->drawn_triangles.empty()) {  // drawn triangle -> the mesh's, past those left out
    const std::size_t ids = views.size() * std::size_t(pictures.width) * std::size_t(pictures.height);
    for (std::int32_t* id = out.triangles; id != out.triangles + ids; ++id) {
      if (*id >= 0) *id = mesh->drawn_triangles[std::size_t(*id)];
    }
  }
  return dropped;
}

std::uint64_t Renderer::rasterize(std::span<const float> clip_positions, std::size_t vertex_count,
                                  std::span<const std::uint32_t> indices, const Pictures& pictures,
                                  const VisibilityOutputs& out, const Progress& progress) {
  const std::lock_guard lock(mutex_);
  const IndexBuffer index_buffer(context_, indices);
  const Buffer corners(context_, indices);
  std::vector<Buffer> uploaded;  // the chunk's views' positions, replaced chunk by chunk
  return draw_visibility(pictures.count, index_buffer, corners, pictures, out, progress, [&](std::size_t first, int layers) {
    uploaded.clear();
    uploaded.reserve(std::size_t(layers));  // the views point into it
    std::vector<VisibilityView> chunk;
    for (std::size_t view = first; view < first + std::size_t(layers); ++view) {
      chunk.push_back({&uploaded.emplace_back(context_, clip_positions.subspan(view * vertex_count * 4, vertex_count * 4)),
                       kIdentity});
    }
    return chunk;
  });
}

std::uint64_t Renderer::draw_visibility(
    std::size_t count, const IndexBuffer& indices, const Buffer& corners, const Pictures& pictures,
    const VisibilityOutputs& out, const Progress& progress,
    const std::function<std::vector<VisibilityView>(std::size_t first, int layers)>& chunk_views) {
  const Program& program = visibility_program();
  const std::size_t pixels = std::size_t(pictures.width) * std::size_t(pictures.height);
  const int chunk = layers_per_pass(pictures, VisibilityTarget::kPixelBytes, VisibilityTarget::kLargestTexelBytes,
                                    context_.device().buffer_bytes);
  std::uint64_t dropped = 0;
  for (std::size_t first = 0; first < count; first += std::size_t(chunk)) {
    const int layers = static_cast<int>(std::min<std::size_t>(std::size_t(chunk), count - first));
    VisibilityTarget& target = visibility_target(pictures.width, pictures.height, layers);
    target.framebuffer.clear_color_int(0, {-1, -1, -1, -1});
    target.framebuffer.clear_color(1, {0, 0, 0, 0});
    target.framebuffer.clear_depth(1.0f);

    // A draw per view, each in its layer's viewport and scissor, drawn as one frame: one pass over
    // the tiles, as the views of a layered framebuffer (whose attachments are RGBA8 only).
    const std::vector<VisibilityView> views = chunk_views(first, layers);
    const LayerGrid grid(layers);
    std::vector<Bindings> bindings;
    bindings.reserve(std::size_t(layers));  // the calls point into it
    std::vector<DrawCall> calls(static_cast<std::size_t>(layers));
    for (int k = 0; k < layers; ++k) {
      const VisibilityView& view = views[std::size_t(k)];
      const Rect rect = grid.layer_rect(k, pictures.width, pictures.height);
      bindings.emplace_back(program)
          .set("mvp", view.mvp)
          .set("viewport", std::array<float, 4>{float(rect.x), float(rect.y), 2.0f / float(pictures.width),
                                                2.0f / float(pictures.height)})
          .set_buffer("positions", *view.positions)
          .set_buffer("corners", corners);
      DrawCall& call = calls[std::size_t(k)];
      call.program = &program;
      call.bindings = &bindings.back();
      call.attributes = {{"position", view.positions, AttributeType::Float4}};
      call.indices = &indices;
      call.state.viewport = rect;
      call.state.scissor_test = true;
      call.state.scissor = rect;
    }
    dropped += target.framebuffer.draw(calls).triangles_dropped;

    copy_layers(target.triangles.read(), layers, pictures, 4, out.triangles + first * pixels);
    copy_layers(target.barycentrics.read(), layers, pictures, 8, out.barycentrics + first * pixels * 2);
    copy_layers(target.depths.read(), layers, pictures, 4, out.depths + first * pixels);
    if (progress) progress(first + std::size_t(layers), count);
  }
  return dropped;
}

}  // namespace clraster::python
