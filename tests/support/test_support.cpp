#include "support/test_support.hpp"

#include "api/impl.hpp"
#include "io/image_io.hpp"
#include "io/procedural.hpp"
#include "oracle/gl_renderer.hpp"
#include "program/generator.hpp"
#include "runtime/kernel_sources.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <numeric>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <type_traits>
#include <utility>

namespace clraster::test {
namespace {

// The mesh's vertices repeated in index order, for non-indexed draws.
io::Mesh without_indices(const io::Mesh& mesh) {
  io::Mesh expanded;
  for (std::uint32_t index : mesh.indices) {
    for (int axis = 0; axis < 3; ++axis) {
      expanded.positions.push_back(mesh.positions[3 * std::size_t{index} + axis]);
      expanded.normals.push_back(mesh.normals[3 * std::size_t{index} + axis]);
    }
  }
  return expanded;
}

std::vector<std::uint16_t> narrow_indices(const io::Mesh& mesh) {
  if (mesh.vertex_count() > 0x10000) {
    throw std::invalid_argument("a mesh of " + std::to_string(mesh.vertex_count()) +
                                " vertices cannot be drawn with 16-bit indices");
  }
  return {mesh.indices.begin(), mesh.indices.end()};
}

// A scene's meshes, uploaded by `upload` once per (mesh, index format).
template <typename Upload>
class UploadCache {
 public:
  using Uploaded = std::invoke_result_t<Upload, const io::Mesh&, IndexFormat>;

  explicit UploadCache(Upload upload) : upload_(std::move(upload)) {}

  const Uploaded& get(const SceneDraw& draw) {
    const auto key = std::pair{draw.mesh, draw.index_format};
    auto found = uploaded_.find(key);
    if (found == uploaded_.end()) found = uploaded_.emplace(key, upload_(*draw.mesh, draw.index_format)).first;
    return found->second;
  }

 private:
  Upload upload_;
  std::map<std::pair<const io::Mesh*, IndexFormat>, Uploaded> uploaded_;
};

struct ClrasterMesh {
  VertexBuffer vertices;
  std::optional<IndexBuffer> indices;
};

}  // namespace

std::string builtin_stage_program() {
  const std::string source = runtime::sources::text("program/builtin/normal.cl");
  return program::generate_stage_program(program::parse_program(source, "normal.cl"), source, "normal.cl");
}

cl::Program build_test_program(const std::string& name, const std::string& source) {
  ContextState& state = *shared_context().impl().state;
  return state.programs.get(name, source, state.stage_build_options(state.options.tile_size));
}

Context& shared_context() {
  static Context context;
  return context;
}

Context& shared_context(WorkGroupShape shape) {
  if (shape == WorkGroupShape::Device) return shared_context();
  static Context context(ContextOptions{.work_group_shape = shape});
  return context;
}

RenderResult render_clraster(Context& context, const io::Mesh& mesh, const DrawState& state, int width, int height,
                             Topology topology) {
  const VertexBuffer vertices(context, mesh.positions, mesh.normals);
  const IndexBuffer indices(context, mesh.indices);
  Framebuffer framebuffer(context, width, height);
  framebuffer.clear({0, 0, 0, 1}, 1.0f);
  DrawCall call{&vertices, &indices};
  call.state = state;
  call.state.topology = topology;
  RenderResult result;
  result.stats = framebuffer.draw(call);
  result.image = framebuffer.read_color();
  return result;
}

Image render_gl(const io::Mesh& mesh, const DrawState& state, int width, int height, Topology topology) {
  const oracle::GlMesh gl_mesh(mesh.positions, mesh.normals, mesh.indices);
  oracle::GlRenderer gl(width, height);
  gl.clear({0, 0, 0, 1}, 1.0f);
  DrawState gl_state = state;
  gl_state.topology = topology;
  gl.draw(gl_mesh, 0, kAllElements, gl_state);
  return gl.read_color();
}

Image render_scene_clraster(Context& context, std::span<const SceneDraw> draws, int width, int height,
                            Submission submission) {
  UploadCache meshes([&](const io::Mesh& mesh, IndexFormat format) {
    switch (format) {
      case IndexFormat::Uint32:
        return ClrasterMesh{VertexBuffer(context, mesh.positions, mesh.normals), IndexBuffer(context, mesh.indices)};
      case IndexFormat::Uint16:
        return ClrasterMesh{VertexBuffer(context, mesh.positions, mesh.normals),
                            IndexBuffer(context, narrow_indices(mesh))};
      case IndexFormat::None: break;
    }
    const io::Mesh expanded = without_indices(mesh);
    return ClrasterMesh{VertexBuffer(context, expanded.positions, expanded.normals), std::nullopt};
  });
  Framebuffer framebuffer(context, width, height);
  framebuffer.clear({0, 0, 0, 1}, 1.0f);
  std::vector<DrawCall> calls;
  for (const SceneDraw& draw : draws) {
    const ClrasterMesh& mesh = meshes.get(draw);
    calls.push_back({&mesh.vertices, mesh.indices ? &*mesh.indices : nullptr, draw.first, draw.count, draw.state});
  }
  if (submission == Submission::Frame) {
    framebuffer.draw(calls);
  } else {
    for (const DrawCall& call : calls) framebuffer.draw(call);
  }
  return framebuffer.read_color();
}

Image render_scene_gl(std::span<const SceneDraw> draws, int width, int height) {
  UploadCache meshes([](const io::Mesh& mesh, IndexFormat format) {
    switch (format) {
      case IndexFormat::Uint32: return oracle::GlMesh(mesh.positions, mesh.normals, mesh.indices);
      case IndexFormat::Uint16: return oracle::GlMesh(mesh.positions, mesh.normals, narrow_indices(mesh));
      case IndexFormat::None: break;
    }
    const io::Mesh expanded = without_indices(mesh);
    return oracle::GlMesh(expanded.positions, expanded.normals);
  });
  oracle::GlRenderer gl(width, height);
  gl.clear({0, 0, 0, 1}, 1.0f);
  for (const SceneDraw& draw : draws) gl.draw(meshes.get(draw), draw.first, draw.count, draw.state);
  return gl.read_color();
}

void snap_to_grid(io::Mesh& window_mesh, double step, double offset) {
  for (std::size_t v = 0; v < window_mesh.vertex_count(); ++v) {
    for (int axis = 0; axis < 2; ++axis) {
      float& coordinate = window_mesh.positions[3 * v + axis];
      coordinate = static_cast<float>(std::round((coordinate - offset) / step) * step + offset);
    }
  }
}

io::Mesh window_to_ndc(io::Mesh window_mesh, const Rect& viewport) {
  const double origin[2] = {static_cast<double>(viewport.x), static_cast<double>(viewport.y)};
  const double half_size[2] = {viewport.width / 2.0, viewport.height / 2.0};
  for (std::size_t v = 0; v < window_mesh.vertex_count(); ++v) {
    for (int axis = 0; axis < 2; ++axis) {
      float& coordinate = window_mesh.positions[3 * v + axis];
      coordinate = static_cast<float>((coordinate - origin[axis]) / half_size[axis] - 1);
    }
  }
  return window_mesh;
}

io::Mesh random_window_triangles(int count, std::uint64_t seed, const Rect& area, float max_size, double step,
                                 double offset) {
  // Between the first and the last grid point of the area, so that snapping keeps every vertex in it.
  const auto lo = [&](int start) { return static_cast<float>(start + offset); };
  const auto hi = [&](int start, int size) { return static_cast<float>(start + size - step + offset); };
  io::Mesh mesh = io::make_random_triangles(count, seed, {lo(area.x), lo(area.y), 0},
                                            {hi(area.x, area.width), hi(area.y, area.height), 0}, max_size);
  snap_to_grid(mesh, step, offset);
  return mesh;
}

GridVertices grid_vertices(const io::Mesh& grid, const std::array<float, 3>& row_direction) {
  const auto row_key = [&](std::uint32_t v) {
    return grid.positions[3 * v] * row_direction[0] + grid.positions[3 * v + 1] * row_direction[1] +
           grid.positions[3 * v + 2] * row_direction[2];
  };
  GridVertices result;
  result.ids.resize(grid.vertex_count());
  std::iota(result.ids.begin(), result.ids.end(), 0u);
  std::sort(result.ids.begin(), result.ids.end(), [&](std::uint32_t a, std::uint32_t b) {
    return std::pair{row_key(a), grid.positions[3 * a]} < std::pair{row_key(b), grid.positions[3 * b]};
  });
  const float first_row = row_key(result.ids.front());
  while (result.columns < static_cast<int>(result.ids.size()) && row_key(result.ids[result.columns]) == first_row) {
    ++result.columns;
  }
  result.rows = static_cast<int>(result.ids.size()) / result.columns;
  return result;
}

std::vector<std::uint32_t> band_strip(const GridVertices& grid, int row) {
  std::vector<std::uint32_t> strip;
  for (int column = 0; column < grid.columns; ++column) {
    strip.insert(strip.end(), {grid.at(column, row + 1), grid.at(column, row)});
  }
  return strip;
}

std::vector<std::uint32_t> grid_strip(const GridVertices& grid) {
  std::vector<std::uint32_t> strip;
  for (int row = 0; row + 1 < grid.rows; ++row) {
    const std::vector<std::uint32_t> band = band_strip(grid, row);
    if (row > 0) strip.insert(strip.end(), {strip.back(), band.front()});
    strip.insert(strip.end(), band.begin(), band.end());
  }
  return strip;
}

DrawState overdraw_counter() {
  DrawState state;
  state.shading = Shading::Constant;
  state.base_color = {1.0f / 255, 0, 0, 0};
  state.blend[0] = kAdditiveBlend;
  state.depth_test = false;
  return state;
}

std::uint64_t covered_pixel_count(const Image& image) { return io::compare_images(image, image).covered_a; }

std::string output_directory() { return CLRASTER_TEST_OUTPUT_DIR; }

::testing::AssertionResult images_match(const Image& result, const Image& reference, const Tolerance& tolerance) {
  const io::ImageComparison c = io::compare_images(result, reference, tolerance);
  if (io::within(c, tolerance)) return ::testing::AssertionSuccess();

  const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
  std::filesystem::path dir = std::filesystem::path(output_directory()) /
                              (std::string(test->test_suite_name()) + "." + test->name());
  std::filesystem::create_directories(dir);
  io::save_png((dir / "reference.png").string(), reference);
  io::save_png((dir / "result.png").string(), result);
  io::save_png((dir / "diff.png").string(), io::diff_image(result, reference, tolerance.threshold));
  return ::testing::AssertionFailure() << "images differ: " << io::to_json(c) << "\n  pictures in " << dir.string();
}

}  // namespace clraster::test
