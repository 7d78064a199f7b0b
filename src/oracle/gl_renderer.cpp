#include "oracle/gl_renderer.hpp"

#include <cmath>
#include <cstring>

#include "oracle/gl_context.hpp"
#include "oracle/gl_scene.hpp"
#include "oracle/gl_state.hpp"
#include "pipeline/draw_state.hpp"

namespace clraster::oracle {
namespace {

using gl::Context;

// ---- The built-in shading modes in GLSL -------------------------------------------------------
// One source per stage; SHADING selects the mode at compile time, so each mode is its own program
// and llvmpipe runs no per-fragment branch on the mode. Each branch is the formula documented for
// clraster::Shading in clraster.hpp.

constexpr const char* kVertexShader = R"(
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 model_view_projection;  // projection * model_view, computed on the host
uniform mat4 model_view;
uniform mat3 normal_matrix;  // inverse transpose of model_view's upper 3x3, computed on the host
out vec3 v;

void main() {
  gl_Position = model_view_projection * vec4(position, 1.0);
#if SHADING == SHADING_NORMAL
  v = normal;
#elif SHADING == SHADING_LAMBERT
  v = normal_matrix * normal;
#elif SHADING == SHADING_DEPTH
  v = vec3(-(model_view * vec4(position, 1.0)).z, 0.0, 0.0);  // view distance along -z
#elif SHADING == SHADING_CONSTANT
  v = vec3(0.0);
#endif
}
)";

constexpr const char* kFragmentShader = R"(
in vec3 v;
uniform vec4 base_color;
uniform vec2 depth_range;  // view distances drawn white and black
layout(location = 0) out vec4 color;

void main() {
#if SHADING == SHADING_NORMAL
  float len = length(v);
  color = vec4(len > 0.0 ? v / len * 0.5 + 0.5 : vec3(0.5), 1.0);
#elif SHADING == SHADING_LAMBERT
  float len = length(v);
  float k = len > 0.0 ? 0.1 + 0.9 * abs(v.z / len) : 0.1;
  color = vec4(base_color.rgb * k, base_color.a);
#elif SHADING == SHADING_DEPTH
  float g = clamp(1.0 - (v.x - depth_range.x) / (depth_range.y - depth_range.x), 0.0, 1.0);
  color = vec4(g, g, g, 1.0);
#elif SHADING == SHADING_CONSTANT
  color = base_color;
#endif
}
)";

constexpr int kShadingModes = 4;

const char* shading_define(Shading shading) {
  switch (shading) {
    case Shading::Normal: return "#define SHADING SHADING_NORMAL\n";
    case Shading::Lambert: return "#define SHADING SHADING_LAMBERT\n";
    case Shading::Depth: return "#define SHADING SHADING_DEPTH\n";
    case Shading::Constant: return "#define SHADING SHADING_CONSTANT\n";
  }
  throw InvalidArgument("unknown shading mode " + std::to_string(static_cast<int>(shading)));
}

// A linked program of one shading mode and where its uniforms are. Uniforms the mode does not use
// are inactive (location -1), and glProgramUniform* ignores location -1.
struct ShadingProgram {
  gl::Program program;
  GLint model_view_projection = -1;
  GLint model_view = -1;
  GLint normal_matrix = -1;
  GLint base_color = -1;
  GLint depth_range = -1;

  explicit ShadingProgram(Shading shading) {
    const char* prelude =
        "#version 450 core\n"
        "#define SHADING_NORMAL 0\n"
        "#define SHADING_LAMBERT 1\n"
        "#define SHADING_DEPTH 2\n"
        "#define SHADING_CONSTANT 3\n";
    const char* vertex[] = {prelude, shading_define(shading), kVertexShader};
    const char* fragment[] = {prelude, shading_define(shading), kFragmentShader};
    program = gl::build_program(vertex, fragment, "oracle shading program");
    const GLuint id = program.get();
    model_view_projection = glGetUniformLocation(id, "model_view_projection");
    model_view = glGetUniformLocation(id, "model_view");
    normal_matrix = glGetUniformLocation(id, "normal_matrix");
    base_color = glGetUniformLocation(id, "base_color");
    depth_range = glGetUniformLocation(id, "depth_range");
    gl::check("building the shading programs");
  }
};

// The programs of every shading mode, built on first use and never destroyed (as the context).
const ShadingProgram& shading_program(Shading shading) {
  static const std::vector<ShadingProgram>* programs = [] {
    auto* built = new std::vector<ShadingProgram>();
    for (int mode = 0; mode < kShadingModes; ++mode) built->emplace_back(static_cast<Shading>(mode));
    // Meshes without normals leave attribute 1 disabled and the shaders read this current value.
    glVertexAttrib4f(1, 0.0f, 0.0f, 0.0f, 1.0f);
    return built;
  }();
  const auto index = static_cast<std::size_t>(shading);
  if (index >= programs->size()) throw InvalidArgument("unknown shading mode " + std::to_string(index));
  return (*programs)[index];
}

// Feeds attribute `location` of the vertex array from a tightly packed buffer of three floats per vertex.
void attach_vec3_attribute(GLuint vertex_array, GLuint location, const gl::Buffer& buffer) {
  glVertexArrayVertexBuffer(vertex_array, location, buffer.get(), 0, 3 * sizeof(float));
  glVertexArrayAttribFormat(vertex_array, location, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vertex_array, location, location);
  glEnableVertexArrayAttrib(vertex_array, location);
}

// The matrices are the ones clraster's pipeline computes (in double, rounded once to float), so the
// oracle and the pipeline transform the same object-space data with the same floats.
void set_uniforms(const ShadingProgram& program, const DrawState& state) {
  const GLuint id = program.program.get();
  const Mat4 mvp = pipeline::model_view_projection(state);
  glProgramUniformMatrix4fv(id, program.model_view_projection, 1, GL_FALSE, mvp.data());
  glProgramUniformMatrix4fv(id, program.model_view, 1, GL_FALSE, state.model_view.data());
  if (state.shading == Shading::Lambert) {
    const std::array<float, 9> normals = pipeline::normal_matrix(state.model_view);
    glProgramUniformMatrix3fv(id, program.normal_matrix, 1, GL_FALSE, normals.data());
  }
  glProgramUniform4fv(id, program.base_color, 1, state.base_color.data());
  glProgramUniform2fv(id, program.depth_range, 1, state.depth_shading_range.data());
}

// A level read back from t = 0 (the bottom row, as GL keeps it) as T values in rows from the top.
template <typename T>
std::vector<T> top_row_first(const std::vector<std::byte>& bottom_row_first, std::size_t row_length) {
  std::vector<T> values(bottom_row_first.size() / sizeof(T));
  const std::size_t rows = values.size() / row_length;
  const std::size_t row_bytes = row_length * sizeof(T);
  for (std::size_t row = 0; row < rows; ++row) {
    std::memcpy(values.data() + (rows - 1 - row) * row_length, bottom_row_first.data() + row * row_bytes, row_bytes);
  }
  return values;
}

}  // namespace

// ---- GlMesh ---------------------------------------------------------------------------------------

struct GlMesh::Impl {
  std::size_t vertex_count = 0;
  std::size_t index_count = 0;
  GLenum index_type = 0;  // GL_UNSIGNED_SHORT or GL_UNSIGNED_INT; 0 when not indexed
  std::size_t index_size = 0;
  gl::Buffer positions;
  gl::Buffer normals;
  gl::Buffer indices;
  gl::VertexArray vertex_array;

  template <typename Index>
  Impl(std::span<const float> position_data, std::span<const float> normal_data,
       std::span<const Index> index_data) {
    if (position_data.size() % 3 != 0) {
      throw InvalidArgument("positions hold " + std::to_string(position_data.size()) +
                            " floats, not three per vertex");
    }
    if (!normal_data.empty() && normal_data.size() != position_data.size()) {
      throw InvalidArgument(std::to_string(normal_data.size()) + " normal floats for " +
                            std::to_string(position_data.size()) + " position floats");
    }
    vertex_count = position_data.size() / 3;
    for (std::size_t i = 0; i < index_data.size(); ++i) {
      if (index_data[i] >= vertex_count) {
        throw InvalidArgument("indices[" + std::to_string(i) + "] = " + std::to_string(index_data[i]) +
                              " refers past the mesh's " + std::to_string(vertex_count) + " vertices");
      }
    }
    index_count = index_data.size();

    Context::instance().make_current();
    GLuint id = 0;
    glCreateVertexArrays(1, &id);
    vertex_array = gl::VertexArray(id);
    positions = gl::upload_buffer(std::as_bytes(position_data));
    attach_vec3_attribute(id, 0, positions);
    if (!normal_data.empty()) {
      normals = gl::upload_buffer(std::as_bytes(normal_data));
      attach_vec3_attribute(id, 1, normals);
    }
    if (!index_data.empty()) {
      indices = gl::upload_buffer(std::as_bytes(index_data));
      glVertexArrayElementBuffer(id, indices.get());
      index_type = sizeof(Index) == 2 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT;
      index_size = sizeof(Index);
    }
    gl::check("uploading a mesh");
  }

  ~Impl() { Context::instance().make_current_for_cleanup(); }  // the members' glDelete* need the context
};

GlMesh::GlMesh(std::span<const float> positions, std::span<const float> normals,
               std::span<const std::uint32_t> indices)
    : impl_(std::make_unique<Impl>(positions, normals, indices)) {}
GlMesh::GlMesh(std::span<const float> positions, std::span<const float> normals,
               std::span<const std::uint16_t> indices)
    : impl_(std::make_unique<Impl>(positions, normals, indices)) {}
GlMesh::~GlMesh() = default;
GlMesh::GlMesh(GlMesh&&) noexcept = default;
GlMesh& GlMesh::operator=(GlMesh&&) noexcept = default;

std::size_t GlMesh::vertex_count() const { return impl_->vertex_count; }
std::size_t GlMesh::index_count() const { return impl_->index_count; }
bool GlMesh::indexed() const { return impl_->index_type != 0; }

// ---- GlRenderer -----------------------------------------------------------------------------------

struct GlRenderer::Impl {
  GlTexture color;
  GlTexture depth;
  GlFramebuffer target;

  Impl(int width, int height)
      : color(width, height, Format::RGBA8), depth(width, height, Format::Depth32F), target({&color}, &depth) {}
};

GlRenderer::GlRenderer(int width, int height) : impl_(std::make_unique<Impl>(width, height)) {}
GlRenderer::~GlRenderer() = default;
GlRenderer::GlRenderer(GlRenderer&&) noexcept = default;
GlRenderer& GlRenderer::operator=(GlRenderer&&) noexcept = default;

int GlRenderer::width() const { return impl_->target.width(); }
int GlRenderer::height() const { return impl_->target.height(); }
std::string GlRenderer::renderer() const { return Context::instance().description(); }

void GlRenderer::clear(std::array<float, 4> color, float depth) { impl_->target.clear(color, depth); }

void GlRenderer::draw(const GlMesh& mesh, std::uint32_t first, std::uint32_t count, const DrawState& state) {
  const GlMesh::Impl& data = *mesh.impl_;
  const std::uint32_t elements =
      gl::draw_range(first, count, data.index_type != 0 ? data.index_count : data.vertex_count, "the mesh");
  const auto [nearest, farthest] = state.depth_shading_range;
  if (state.shading == Shading::Depth &&
      !(std::isfinite(nearest) && std::isfinite(farthest) && nearest < farthest)) {
    throw InvalidArgument("depth shading range [" + std::to_string(nearest) + ", " +
                          std::to_string(farthest) + "] must be finite with near < far");
  }
  const GLenum mode = gl::topology(state.topology);
  Context::instance().make_current();
  const ShadingProgram& program = shading_program(state.shading);

  impl_->target.bind_for_drawing(state);
  set_uniforms(program, state);
  gl::check("setting the draw state");
  glUseProgram(program.program.get());
  glBindVertexArray(data.vertex_array.get());
  if (data.index_type != 0) {
    const auto offset = static_cast<std::uintptr_t>(first * data.index_size);
    glDrawElements(mode, GLsizei(elements), data.index_type, reinterpret_cast<const void*>(offset));
  } else {
    glDrawArrays(mode, GLint(first), GLsizei(elements));
  }
  gl::check(data.index_type != 0 ? "glDrawElements" : "glDrawArrays");
}

void GlRenderer::draw(const GlDrawCall& call) { impl_->target.draw(call); }

Image GlRenderer::read_color() const {
  return Image{width(), height(), top_row_first<std::uint8_t>(impl_->color.read(), std::size_t(width()) * 4)};
}

std::vector<float> GlRenderer::read_depth() const {
  return top_row_first<float>(impl_->depth.read(), std::size_t(width()));
}

void GlRenderer::finish() {
  Context::instance().make_current();
  glFinish();
  gl::check("glFinish");
}

}  // namespace clraster::oracle
