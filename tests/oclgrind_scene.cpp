// A few small draws that between them run every kernel of the pipeline once: indexed lists (vertices
// shaded once per draw), non-indexed strips and fans (vertices shaded per chunk), clipping at the near
// plane, culling, scissor, additive blending; and mipmap generation. Run under Oclgrind by
// oclgrind_check.sh, which fails on any data race, out-of-bounds access, uninitialized read or API
// error Oclgrind reports.
#include "clraster/clraster.hpp"

#include <cstdio>
#include <vector>

int main() {
  try {
    clraster::ContextOptions options;
    options.tile_size = 8;
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

    // Mipmaps of a texture with odd sides (5x3 -> 2x1 -> 1x1), in sRGB.
    const std::vector<std::byte> texels(5 * 3 * 4, std::byte{200});
    const clraster::Texture texture(context, 5, 3, clraster::Format::SRGB8_A8, texels);
    std::printf("texture level 2: %d bytes\n", static_cast<int>(texture.read(2).size()));

    const clraster::Image image = target.read_color();
    std::printf("rendered %dx%d\n", image.width, image.height);
    return 0;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "oclgrind_scene: %s\n", error.what());
    return 1;
  }
}
