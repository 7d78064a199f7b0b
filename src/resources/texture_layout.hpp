// Where a texture's levels live in its one device buffer (the layout TextureDesc describes to the
// kernels): level after level, each tightly packed rows from t = 0, then Depth32FStencil8's stencil
// plane.
#pragma once

#include "clraster/clraster.hpp"
#include "shared/types.h"

#include <array>
#include <cstddef>
#include <cstdint>

namespace clraster::resources {

// Levels of a full mip chain, down to 1x1: floor(log2(max(width, height))) + 1.
int full_mip_chain(int width, int height);

// Side of `level` for a level-0 side of `size`: max(1, size >> level).
int level_extent(int size, int level);

struct TextureLayout {
  std::array<std::uint32_t, CLR_MAX_TEXTURE_LEVELS> level_offset{};  // in texels from the start
  std::size_t stencil_offset = 0;                                    // in bytes; 0 without stencil
  std::size_t total_bytes = 0;
};

// For a valid size (1..CLR_MAX_TEXTURE_SIZE per side) and level count (1..full_mip_chain), which the
// caller checks. Every offset fits in 32 bits: a full chain of the largest texture has under 2^29 texels.
TextureLayout texture_layout(Format format, int width, int height, int levels);

}  // namespace clraster::resources
