// Framebuffer::draw: resolves a DrawCall's public objects into what the pipeline reads, checking
// each against the program (attributes, bindings, outputs) before anything is rendered.
#include "api/errors.hpp"
#include "api/impl.hpp"
#include "pipeline/draw_state.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

namespace clraster {
namespace {

void check_same_context(const ContextState& framebuffer, const std::shared_ptr<ContextState>& state, const std::string& what) {
  if (state.get() != &framebuffer) throw InvalidArgument(what + " belongs to another context than the framebuffer");
}

struct AttributeFormat {
  const char* scalar;
  int components;
};

AttributeFormat attribute_format(AttributeType type) {
  const int index = static_cast<int>(type);
  if (index < 0 || index > static_cast<int>(AttributeType::UInt4)) {
    throw InvalidArgument("attribute type has the invalid value " + std::to_string(index));
  }
  static const char* const scalars[] = {"float", "int", "uint"};
  return {scalars[index / 4], index % 4 + 1};
}

void check_shading(const DrawState& s) {
  const int shading = static_cast<int>(s.shading);
  if (shading < 0 || shading > static_cast<int>(Shading::Constant)) {
    throw InvalidArgument("shading has the invalid value " + std::to_string(shading));
  }
  if (s.shading == Shading::Depth &&
      !(std::isfinite(s.depth_shading_range[0]) && std::isfinite(s.depth_shading_range[1]) &&
        s.depth_shading_range[1] > s.depth_shading_range[0])) {
    throw InvalidArgument("depth shading range [" + std::to_string(s.depth_shading_range[0]) + ", " +
                          std::to_string(s.depth_shading_range[1]) + "] must be finite with near < far");
  }
}

void check_finite(const char* name, const Mat4& matrix) {
  for (std::size_t k = 0; k < matrix.size(); ++k) {
    if (!std::isfinite(matrix[k])) {
      throw InvalidArgument(std::string(name) + " has the non-finite value " + std::to_string(matrix[k]) +
                            " at element " + std::to_string(k));
    }
  }
}

// The uniforms of the built-in program of s.shading (program/builtin/), from the state's shading
// inputs.
Bindings builtin_bindings(const Program& program, const DrawState& s) {
  check_finite("model_view", s.model_view);
  check_finite("projection", s.projection);
  Bindings b(program);
  b.set("mvp", pipeline::model_view_projection(s));
  switch (s.shading) {
    case Shading::Normal: break;
    case Shading::Lambert: {
      const std::array<float, 9> normals = pipeline::normal_matrix(s.model_view);
      Mat4 normal_matrix{};
      for (int column = 0; column < 3; ++column) {
        for (int row = 0; row < 3; ++row) normal_matrix[column * 4 + row] = normals[column * 3 + row];
      }
      b.set("normal_matrix", normal_matrix).set("base_color", s.base_color);
      break;
    }
    case Shading::Depth: b.set("model_view", s.model_view).set("depth_range", s.depth_shading_range); break;
    case Shading::Constant: b.set("base_color", s.base_color); break;
  }
  return b;
}

// Where each attribute the program declares comes from.
void resolve_attributes(const DrawCall& call, const Program::Impl& program, const ContextState& state,
                        pipeline::DrawSource& source) {
  std::vector<VertexAttribute> supplied = call.attributes;
  for (const VertexAttribute& a : supplied) {
    if (a.buffer == nullptr) throw InvalidArgument("attribute '" + a.name + "' has no buffer");
    check_same_context(state, a.buffer->impl().state, "the buffer of attribute '" + a.name + "'");
  }
  if (call.vertices != nullptr) {
    const VertexBuffer::Impl& vertices = call.vertices->impl();
    check_same_context(state, vertices.state, "vertex buffer");
    supplied.push_back({"position", &*vertices.positions, AttributeType::Float3});
    if (vertices.normals) supplied.push_back({"normal", &*vertices.normals, AttributeType::Float3});
  }
  const auto& declared = program.parsed.interface.attributes;
  for (const ProgramVariable& attribute : declared) {
    const auto found = std::find_if(supplied.begin(), supplied.end(), [&](const VertexAttribute& a) { return a.name == attribute.name; });
    AttributeDesc desc{};
    if (found == supplied.end()) {
      // A vertex buffer without normals reads zero normals, as before programs existed.
      if (call.vertices == nullptr && call.attributes.empty()) {
        throw InvalidArgument("the draw has no vertex buffer or attributes, but program " + program.file_name +
                              " reads the attribute '" + attribute.name + "'");
      }
      if (!(attribute.name == "normal" && call.vertices != nullptr)) {
        throw InvalidArgument("attribute '" + attribute.name + "' of program " + program.file_name + " (line " +
                              std::to_string(attribute.line) + ") is not supplied by the draw");
      }
      source.attribute_buffers.push_back(call.vertices->impl().positions->impl().buffer);
      source.attributes.push_back(desc);
      continue;
    }
    const AttributeFormat format = attribute_format(found->type);
    const program::VectorType wanted = program::vector_type(attribute.type);
    if (wanted.scalar != format.scalar) {
      throw InvalidArgument("attribute '" + attribute.name + "' is declared " + attribute.type + " but supplied as " +
                            format.scalar + " data");
    }
    const std::size_t element = 4 * static_cast<std::size_t>(format.components);
    const std::size_t stride = found->stride == 0 ? element : found->stride;
    const std::size_t bytes = found->buffer->impl().bytes;
    if (found->offset % 4 != 0 || stride % 4 != 0 || stride > 0xffffffffu || found->offset > 0xffffffffu) {
      throw InvalidArgument("attribute '" + attribute.name + "' needs an offset and stride that are multiples of 4 bytes (got " +
                            std::to_string(found->offset) + " and " + std::to_string(stride) + ")");
    }
    const std::uint64_t elements = found->offset + element > bytes ? 0 : (bytes - found->offset - element) / stride + 1;
    desc = {static_cast<cl_uint>(found->offset), static_cast<cl_uint>(stride), static_cast<cl_uint>(format.components),
            found->per_instance ? 1u : 0u};
    std::uint64_t& limit = found->per_instance ? source.instance_limit : source.vertex_limit;
    limit = std::min(limit, elements);
    source.attribute_buffers.push_back(found->buffer->impl().buffer);
    source.attributes.push_back(desc);
  }
  for (const VertexAttribute& a : supplied) {
    const bool known = std::any_of(declared.begin(), declared.end(), [&](const ProgramVariable& v) { return v.name == a.name; });
    if (!known && !(call.vertices != nullptr && (a.name == "position" || a.name == "normal"))) {
      throw InvalidArgument("program " + program.file_name + " declares no attribute '" + a.name + "'");
    }
  }
}

void resolve_bindings(const Bindings::Impl& bindings, const Program::Impl& program, pipeline::DrawSource& source) {
  const ProgramInterface& in = program.parsed.interface;
  for (std::size_t i = 0; i < in.uniforms.size(); ++i) {
    if (!bindings.uniform_set[i]) {
      throw InvalidArgument("uniform '" + in.uniforms[i].name + "' of program " + program.file_name + " (line " +
                            std::to_string(in.uniforms[i].line) + ") is not set");
    }
  }
  source.uniforms = bindings.uniforms;
  for (std::size_t i = 0; i < in.textures.size(); ++i) {
    const auto& bound = bindings.textures[i];
    if (bound.texture == nullptr) {
      throw InvalidArgument("texture '" + in.textures[i].name + "' of program " + program.file_name + " (line " +
                            std::to_string(in.textures[i].line) + ") is not bound");
    }
    bound.texture->write_pending_clear();  // the draw's raster pass writes only its own attachments' clears
    source.textures.push_back(bound.texture->data);
    source.texture_descs.push_back(bound.texture->describe(bound.sampler));
  }
  for (std::size_t i = 0; i < in.buffers.size(); ++i) {
    if (bindings.buffers[i] == nullptr) {
      throw InvalidArgument("buffer '" + in.buffers[i].name + "' of program " + program.file_name + " (line " +
                            std::to_string(in.buffers[i].line) + ") is not bound");
    }
    source.buffers.push_back(bindings.buffers[i]->buffer);
  }
}

// Resolves `call`'s public objects into what the pipeline reads, checking each against the program;
// for one of its views, with that view's camera or bindings.
pipeline::DrawSource resolve_draw(ContextState& state, const Framebuffer::Impl& framebuffer, const DrawCall& call,
                                  const View* view) {
  if (call.program == nullptr) check_shading(call.state);
  const Program& program = call.program != nullptr ? *call.program : state.builtin_program(call.state.shading);
  Program::Impl& compiled = program.impl();
  check_same_context(state, compiled.state, "program " + compiled.file_name);
  std::optional<Bindings> builtin;
  const Bindings* bindings = view != nullptr && view->bindings != nullptr ? view->bindings : call.bindings;
  if (call.program == nullptr) {
    if (bindings != nullptr) throw InvalidArgument("a draw with bindings needs the program they are for");
    DrawState camera = call.state;
    if (view != nullptr) {
      camera.model_view = view->model_view;
      camera.projection = view->projection;
    }
    bindings = &builtin.emplace(builtin_bindings(program, camera));
  }
  const ProgramInterface& in = compiled.parsed.interface;
  const bool declares_resources = !in.uniforms.empty() || !in.textures.empty() || !in.buffers.empty();
  if (bindings == nullptr && declares_resources) {
    throw InvalidArgument("program " + compiled.file_name + " declares uniforms, textures or buffers but the draw has no bindings");
  }
  if (bindings != nullptr && bindings->impl().program != &compiled) {
    throw InvalidArgument("the draw's bindings were made for another program than " + compiled.file_name);
  }

  pipeline::DrawSource source;
  source.program = &compiled.parsed;
  if (!compiled.stages) {
    compiled.stages = std::make_unique<pipeline::ProgramStages>(compiled.program, state.get_pipeline().sort(),
                                                               state.vertex_lanes(), compiled.tile_size);
  }
  source.stages = compiled.stages.get();
  resolve_attributes(call, compiled, state, source);
  if (bindings != nullptr) resolve_bindings(bindings->impl(), compiled, source);
  for (std::size_t k = 0; k < in.outputs.size() && k < framebuffer.colors.size(); ++k) {
    const FormatInfo& format = format_info(framebuffer.colors[k]->format());
    const std::string& type = in.outputs[k].type;
    const bool matches = type == "float4" ? !format.integer : type == "int4" ? format.integer && format.is_signed
                                                                              : format.integer && !format.is_signed;
    if (!matches) {
      throw InvalidArgument("output '" + in.outputs[k].name + "' of program " + compiled.file_name + " is " + type +
                            " but colour attachment " + std::to_string(k) + " is " + format.name);
    }
  }
  if (call.indices != nullptr) {
    IndexBuffer::Impl& indices = call.indices->impl();
    check_same_context(state, indices.state, "index buffer");
    source.indices = indices.indices;
    source.index_size = indices.index_size;
    source.index_cache = &indices.range_cache;
    source.index_count = indices.count;
  }
  source.instance_count = call.instance_count;
  return source;
}

pipeline::RenderTarget render_target(const Framebuffer::Impl& framebuffer) {
  pipeline::RenderTarget target;
  target.layer_width = framebuffer.width;
  target.layer_height = framebuffer.height;
  target.layer_columns = framebuffer.layer_columns;
  const Texture& first = framebuffer.colors.empty() ? *framebuffer.depth_stencil : *framebuffer.colors.front();
  target.width = first.width();
  target.height = first.height();
  for (Texture* color : framebuffer.colors) {
    target.colors.push_back(color->impl().data);
    target.formats.push_back(static_cast<int>(color->format()));
    target.color_clears.push_back(&color->impl().pending_clear);
  }
  if (framebuffer.depth_stencil != nullptr) {
    const Texture::Impl& depth = framebuffer.depth_stencil->impl();
    target.depth_stencil = depth.data;
    target.depth_clear = &depth.pending_clear;
    target.has_stencil = format_info(depth.format).stencil;
    target.stencil_offset = depth.describe().stencil_offset;
  }
  return target;
}

}  // namespace

DrawStats Framebuffer::draw(const DrawCall& call) { return draw(std::span<const DrawCall>(&call, 1)); }

DrawStats Framebuffer::draw(std::span<const DrawCall> calls) {
  ContextState& state = *impl_->state;
  return translate_cl_errors([&] {
    const pipeline::RenderTarget target = render_target(*impl_);
    pipeline::Pipeline& pipeline = state.get_pipeline();
    // Every draw is checked before any renders. A draw renders once into each layer, as a draw of
    // its own for each view.
    const auto layers = static_cast<std::size_t>(impl_->layers);
    std::vector<pipeline::DrawSource> sources;
    sources.reserve(calls.size() * layers);  // the frame's draws point into it
    std::vector<pipeline::FrameDraw> draws;
    draws.reserve(calls.size() * layers);
    for (const DrawCall& call : calls) {
      if (!call.views.empty() && call.views.size() != layers) {
        throw InvalidArgument("the draw has " + std::to_string(call.views.size()) + " views but the framebuffer has " +
                              std::to_string(layers) + " layers: give one view per layer, or none");
      }
      for (std::size_t view = 0; view < layers; ++view) {
        const View* v = call.views.empty() ? nullptr : &call.views[view];
        if (v != nullptr && v->bindings != nullptr && call.program == nullptr) {
          throw InvalidArgument("view " + std::to_string(view) + " has bindings but the draw has no program");
        }
        sources.push_back(resolve_draw(state, *impl_, call, v));
        draws.push_back(pipeline.prepare(target, sources.back(), call.first, call.count, call.state,
                                         static_cast<std::uint32_t>(view)));
      }
    }
    return pipeline.render(target, draws);
  });
}

}  // namespace clraster
