// A clear of a texture's level 0 that Framebuffer::clear* recorded and nothing has written yet.
//
// As llvmpipe folds a clear into its scene, the next draw into the texture writes the clear with its
// tiles: the raster pass starts every tile from the clear value instead of loading the attachment,
// and writes back every tile, those without triangles too (raster/tile.cl, `clears`). So a frame's clear
// costs no pass of its own over the framebuffer, and its tiles are not read back. Whatever else reads
// or writes the texels (a read, an upload, mipmaps, sampling in a draw) writes the clear first
// (Texture::Impl::write_pending_clear).
#pragma once

#include <array>
#include <cstdint>

namespace clraster::resources {

struct PendingClear {
  bool color = false;
  std::array<std::uint32_t, 4> color_bits{};  // the float, int or uint value, as the attachment's format takes it
  bool depth = false;
  float depth_value = 0.0f;                   // clamped to [0, 1]
  bool stencil = false;
  std::uint8_t stencil_value = 0;

  bool any() const { return color || depth || stencil; }
};

}  // namespace clraster::resources
