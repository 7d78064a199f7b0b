// A few small draws that between them run every kernel of the pipeline once: indexed lists (vertices
// shaded once per draw), non-indexed strips and fans (vertices shaded per chunk), clipping at the near
// plane, culling, scissor, additive blending; and a user program shaded in quads (derivatives and
// texture sampling exchange values between work-items) into two attachments with stencil, blending
// and framebuffer fetch, instanced, with a texture whose mipmaps are generated on the device; and
// mipmaps of a texture with odd sides; and a span program shaded in quads, sampling three textures;
// and a draw with views into a layered framebuffer.
// Run under Oclgrind by oclgrind_check.sh, which fails on any data race, out-of-bounds access or API
// error Oclgrind reports (not on uninitialized reads: that plugin of Oclgrind 21.10 crashes), and
// unless what Oclgrind drew is what the default device (PoCL) drew. With "wide", in the GPU's
// work-group shapes (many work-items per tile and per scan block, where races would show), else in
// the device's: Oclgrind calls itself a CPU too. The tile size is the device's choice: Oclgrind has
// OpenCL's minimum of 32 KiB of local memory, so the stage programs take the smaller tiles that fit.
//   oclgrind_scene [wide] OUTPUT_DIR    writes each target it read back to OUTPUT_DIR/NAME.bin, and
//                                       fails if a target holds nothing but its clear value
#include "clraster/clraster.hpp"

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace {

// Writes what a target holds to directory/name.bin, after checking that something was drawn: not
// every element equal to the first (all the targets start from a clear of one value).
template <typename T>
void keep(const std::filesystem::path& directory, const std::string& name, const std::vector<T>& values) {
  if (std::all_of(values.begin(), values.end(), [&](const T& v) { return v == values.front(); })) {
    throw std::runtime_error(name + ": nothing was drawn");
  }
  std::ofstream file(directory / (name + ".bin"), std::ios::binary);
  file.write(reinterpret_cast<const char*>(values.data()), static_cast<std::streamsize>(values.size() * sizeof(T)));
  if (!file) throw std::runtime_error("cannot write " + (directory / (name + ".bin")).string());
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const bool wide = argc == 3 && std::string_view(argv[1]) == "wide";
    if (argc != 2 && !wide) throw std::runtime_error("usage: oclgrind_scene [wide] OUTPUT_DIR");
    const std::filesystem::path output = argv[argc - 1];
    std::filesystem::create_directories(output);
    clraster::ContextOptions options;
    if (wide) options.work_group_shape = clraster::WorkGroupShape::Wide;
    options.cache_dir = "off";
    clraster::Context context(options);
    clraster::Framebuffer target(context, 37, 21);  // not a multiple of the tile
    target.clear({0, 0, 0, 1}, 1.0f);

    // An indexed list of two triangles, one crossing the near plane (z < -w at one vertex).
    const std::vector<float> positions = {-0.9f, -0.8f, 0.2f, 0.8f, -0.7f, 0.1f, 0.1f, 0.9f, -0.3f,
                                          -0.5f, 0.5f, -1.5f, 0.6f, 0.6f, 0.5f, 0.0f, -0.6f, 0.4f};
    const std::vector<float> normals(positions.size(), 0.57735f);
    const std::vector<std::uint32_t> indices = {0, 1, 2, 3, 4, 5};
    const clraster::VertexBuffer vertices(context, positions, normals);
    const clraster::IndexBuffer index_buffer(context, indices);
    clraster::DrawCall list{&vertices, &index_buffer};
    target.draw(list);

    // The same vertices as a strip and a fan, without indices, blended additively under a scissor.
    clraster::DrawCall strip{&vertices};
    strip.state.topology = clraster::Topology::TriangleStrip;
    strip.state.blend[0] = clraster::kAdditiveBlend;
    strip.state.depth_func = clraster::CompareFunc::LessEqual;
    strip.state.scissor_test = true;
    strip.state.scissor = {3, 2, 25, 15};
    target.draw(strip);
    clraster::DrawCall fan{&vertices};
    fan.state.topology = clraster::Topology::TriangleFan;
    fan.state.cull = clraster::CullMode::Back;
    fan.state.shading = clraster::Shading::Lambert;
    target.draw(fan);

    // The list again, from three cameras into the layers of a layered framebuffer, whose 13x9
    // layers share tiles.
    clraster::Framebuffer layered(context, 13, 9, 3);
    layered.clear({0, 0, 0, 1}, 1.0f);
    clraster::DrawCall views = list;
    for (int k = 0; k < 3; ++k) {
      clraster::Mat4 shifted = clraster::kIdentity;
      shifted[12] = 0.3f * static_cast<float>(k - 1);
      views.views.push_back({shifted, clraster::kIdentity, nullptr});
    }
    layered.draw(views);
    keep(output, "views", layered.color(0).read());

    // Mipmaps of a texture with odd sides (5x3 -> 2x1 -> 1x1), in sRGB.
    std::vector<std::byte> odd_texels(5 * 3 * 4);
    for (std::size_t i = 0; i < odd_texels.size(); ++i) odd_texels[i] = static_cast<std::byte>(90 + i * 11);
    const clraster::Texture texture(context, 5, 3, clraster::Format::SRGB8_A8, odd_texels);
    keep(output, "odd_level1", texture.read(1));
    if (texture.read(2).size() != 4) throw std::runtime_error("level 2 of a 5x3 texture is not one texel");

    const clraster::Image image = target.read_color();
    keep(output, "draws", image.rgba);

    const char* const source = R"(
clr_attribute(float2, corner)
clr_attribute(float2, offset)
clr_varying(float2, uv)
clr_varying_flat(uint, instance)
clr_uniform(float, scale)
clr_texture(pattern)
clr_output(float4, color)
clr_output(uint4, id)
void vertex(clr_vertex* v) {
  v->position = (float4)(v->in.corner * v->uniforms->scale + v->in.offset, 0.5f, 1.0f);
  v->out.uv = v->in.corner * 3.0f;
  v->out.instance = v->instance_id;
}
void fragment(clr_fragment* f) {
  const float4 sampled = clr_sample(f, f->textures.pattern, f->in.uv);
  f->out.color = sampled * 0.5f + clr_framebuffer_fetch(f, 0) * 0.5f + (float4)(clr_fwidth(f, f->in.uv), 0.0f, 0.0f);
  f->out.id = (uint4)(f->in.instance, f->primitive_id, 0, 0);
}
)";
    const clraster::Program program(context, source, "oclgrind_scene.cl");
    std::vector<std::uint8_t> texels(16 * 16 * 4);
    for (std::size_t i = 0; i < texels.size(); ++i) texels[i] = static_cast<std::uint8_t>(i * 37);
    const clraster::Texture pattern(context, 16, 16, clraster::Format::RGBA8, std::as_bytes(std::span(texels)));
    clraster::Bindings bindings(program);
    bindings.set("scale", 0.6f).set_texture("pattern", pattern);
    const std::vector<float> corners = {-1, -1, 1, -1, 0, 1};
    const std::vector<float> offsets = {-0.2f, 0.0f, 0.3f, 0.1f};
    const clraster::Buffer corner_buffer(context, corners), offset_buffer(context, offsets);
    clraster::Texture color(context, 29, 19, clraster::Format::RGBA16F), ids(context, 29, 19, clraster::Format::RGBA32UI),
        depth(context, 29, 19, clraster::Format::Depth32FStencil8);
    clraster::Framebuffer layers(context, {&color, &ids}, &depth);
    layers.clear({0.2f, 0.3f, 0.4f, 1});
    clraster::DrawCall overlapping;
    overlapping.program = &program;
    overlapping.bindings = &bindings;
    overlapping.attributes = {{"corner", &corner_buffer, clraster::AttributeType::Float2},
                              {"offset", &offset_buffer, clraster::AttributeType::Float2, 0, 0, true}};
    overlapping.count = 3;
    overlapping.instance_count = 2;
    overlapping.state.stencil_test = true;
    overlapping.state.stencil_front = {clraster::CompareFunc::Always, 1, 0xff, 0xff, clraster::StencilOp::Keep,
                                       clraster::StencilOp::Keep, clraster::StencilOp::IncrementWrap};
    overlapping.state.stencil_back = overlapping.state.stencil_front;
    overlapping.state.depth_func = clraster::CompareFunc::LessEqual;
    overlapping.state.blend[0] = {true, clraster::BlendEquation::Add, clraster::BlendEquation::Max,
                                  clraster::BlendFactor::SrcAlpha, clraster::BlendFactor::OneMinusSrcAlpha,
                                  clraster::BlendFactor::One, clraster::BlendFactor::One, {true, true, true, true}};
    layers.draw(overlapping);
    keep(output, "layers_color", color.read());
    keep(output, "layers_ids", ids.read());
    keep(output, "layers_stencil", layers.read_stencil());
    color.generate_mipmaps();

    // A span program shaded in quads: in the device's shapes blocks of two quads, derivatives
    // between lanes and samples in vectors, of an RGBA8 texture, of the sRGB one with odd sides,
    // mirrored (the wrap's division), and of the half-float one (texels loaded lane by lane); in the
    // wide shapes values exchanged between work-items.
    const char* const span_source = R"(
clr_attribute(float2, corner)
clr_varying(float2, uv)
clr_texture(pattern)
clr_texture(odd)
clr_texture(halves)
clr_output(float4, color)
void vertex(clr_vertex* v) {
  v->position = (float4)(v->in.corner * 0.9f, 0.3f, 1.0f);
  v->out.uv = v->in.corner * 2.5f;
}
void fragment_span(clr_span_fragment* f) {
  const clr_span_float4 a = clr_sample(f, f->textures.pattern, f->in.uv);
  const clr_span_float4 b = clr_sample(f, f->textures.odd, f->in.uv);
  const clr_span_float4 c = clr_sample(f, f->textures.halves, f->in.uv);
  const clr_span_float2 width = clr_fwidth(f, f->in.uv);
  f->out.color.x = a.x + b.x + width.x;
  f->out.color.y = a.y + c.y + clr_dfdy_fine(f, f->in.uv.y);
  f->out.color.z = b.z + c.z;
  f->out.color.w = 1.0f;
}
)";
    const clraster::Program span_program(context, span_source, "oclgrind_span.cl");
    clraster::Bindings span_bindings(span_program);
    clraster::Sampler mirrored;
    mirrored.mip_filter = clraster::MipFilter::Nearest;
    mirrored.wrap_s = mirrored.wrap_t = clraster::Wrap::MirroredRepeat;
    span_bindings.set_texture("pattern", pattern).set_texture("odd", texture, mirrored).set_texture("halves", color);
    clraster::DrawCall quads;
    quads.program = &span_program;
    quads.bindings = &span_bindings;
    quads.attributes = {{"corner", &corner_buffer, clraster::AttributeType::Float2}};
    quads.count = 3;
    target.draw(quads);
    keep(output, "span_program", target.read_color().rgba);

    // Tiles of 32x32 given explicitly are refused where the device's local memory cannot hold the
    // built-in shading's tile (oclgrind_check.sh requires this under Oclgrind, which has 32 KiB).
    if (context.device().local_memory_bytes < 40 * 1024) {
      options.tile_size = 32;
      clraster::Context large_tiles(options);
      const clraster::VertexBuffer large_tile_vertices(large_tiles, positions, normals);
      clraster::Framebuffer large_tile_target(large_tiles, 37, 21);
      try {
        large_tile_target.draw(clraster::DrawCall{&large_tile_vertices});
        throw std::runtime_error("tiles of 32x32 were not refused with " +
                                 std::to_string(context.device().local_memory_bytes) + " bytes of local memory");
      } catch (const clraster::InvalidArgument& error) {
        std::printf("oclgrind_scene: refused 32x32 tiles: %s\n", error.what());
      }
    }
    std::printf("oclgrind_scene: drew %s on %s, tiles of %d\n", output.string().c_str(), context.device().name.c_str(),
                context.options().tile_size);
    return 0;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "oclgrind_scene: %s\n", error.what());
    return 1;
  }
}
