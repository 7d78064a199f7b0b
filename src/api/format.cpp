// The public face of the format table (shared/types.h), which the kernels expand too.
#include "clraster/clraster.hpp"
#include "shared/types.h"

#include <array>
#include <string>

namespace clraster {
namespace {

constexpr bool is_integer(int channel_type) {
  return channel_type == CLR_CHANNEL_SINT32 || channel_type == CLR_CHANNEL_UINT32;
}

#define CLR_FORMAT_INFO_ROW(id, name, channels, type, depth, stencil) \
  FormatInfo{(channels)*CLR_CHANNEL_BYTES(type),                      \
             channels,                                                \
             is_integer(type),                                        \
             (type) == CLR_CHANNEL_SINT32,                            \
             depth != 0,                                              \
             stencil != 0,                                            \
             name},
constexpr std::array<FormatInfo, CLR_FORMAT_COUNT> kFormats{{CLR_FORMAT_TABLE(CLR_FORMAT_INFO_ROW)}};
#undef CLR_FORMAT_INFO_ROW

// The table's rows are in the order of CLR_FORMAT_* and of clraster::Format.
#define CLR_FORMAT_ID(id, name, channels, type, depth, stencil) id,
constexpr std::array<int, CLR_FORMAT_COUNT> kFormatIds{CLR_FORMAT_TABLE(CLR_FORMAT_ID)};
#undef CLR_FORMAT_ID
constexpr bool rows_in_order() {
  for (int i = 0; i < CLR_FORMAT_COUNT; ++i) {
    if (kFormatIds[i] != i) return false;
  }
  return true;
}
static_assert(rows_in_order(), "CLR_FORMAT_TABLE rows must follow CLR_FORMAT_* order");
static_assert(static_cast<int>(Format::Depth32FStencil8) == CLR_FORMAT_DEPTH32F_STENCIL8 &&
                  static_cast<int>(Format::RGBA16F) == CLR_FORMAT_RGBA16F,
              "clraster::Format must follow CLR_FORMAT_* order");

}  // namespace

const FormatInfo& format_info(Format format) {
  const int index = static_cast<int>(format);
  if (index < 0 || index >= CLR_FORMAT_COUNT) throw InvalidArgument("unknown texture format " + std::to_string(index));
  return kFormats[index];
}

}  // namespace clraster
