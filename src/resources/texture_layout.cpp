#include "resources/texture_layout.hpp"

#include <algorithm>
#include <bit>

namespace clraster::resources {

static_assert(std::bit_width(unsigned{CLR_MAX_TEXTURE_SIZE}) == CLR_MAX_TEXTURE_LEVELS,
              "CLR_MAX_TEXTURE_LEVELS must be the full mip chain of CLR_MAX_TEXTURE_SIZE");

int full_mip_chain(int width, int height) { return std::bit_width(static_cast<unsigned>(std::max(width, height))); }

int level_extent(int size, int level) { return std::max(1, size >> level); }

TextureLayout texture_layout(Format format, int width, int height, int levels) {
  const FormatInfo& info = format_info(format);
  TextureLayout layout;
  std::size_t texels = 0;
  for (int level = 0; level < levels; ++level) {
    layout.level_offset[level] = static_cast<std::uint32_t>(texels);
    texels +=
        static_cast<std::size_t>(level_extent(width, level)) * static_cast<std::size_t>(level_extent(height, level));
  }
  layout.total_bytes = texels * static_cast<std::size_t>(info.bytes_per_texel);
  if (info.stencil) {
    layout.stencil_offset = layout.total_bytes;
    layout.total_bytes += static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  }
  return layout;
}

}  // namespace clraster::resources
