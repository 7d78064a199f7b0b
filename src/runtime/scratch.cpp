#include "runtime/scratch.hpp"

#include "shared/clr_limits.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace clraster::runtime {

void ScratchArena::set_capacities(const ScratchSizes& capacities) {
  capacities_ = capacities;
  for (std::size_t i = 0; i < kScratchCount; ++i) {
    if (sizes_[i] > capacities_[i]) {
      buffers_[i] = cl::Buffer();
      sizes_[i] = 0;
    }
  }
}

const cl::Buffer& ScratchArena::get(Scratch id, std::size_t bytes) {
  const auto i = static_cast<std::size_t>(id);
  bytes = std::max<std::size_t>(bytes, 4);  // OpenCL rejects empty buffers
  if (bytes > capacities_[i]) throw std::logic_error("scratch request beyond the memory plan");
  if (sizes_[i] < bytes) {
    const std::size_t grown = sizes_[i] / CLR_BUFFER_GROWTH_DEN * CLR_BUFFER_GROWTH_NUM;
    const std::size_t size = std::min(std::max(bytes, grown), capacities_[i]);
    buffers_[i] = cl::Buffer();  // release first: the old and new buffer never coexist
    sizes_[i] = 0;
    buffers_[i] = cl::Buffer(context_, CL_MEM_READ_WRITE, size);
    sizes_[i] = size;
    peak_bytes_ = std::max(peak_bytes_, bytes_held());
  }
  return buffers_[i];
}

std::size_t ScratchArena::bytes_held() const { return std::accumulate(sizes_.begin(), sizes_.end(), std::size_t{0}); }

}  // namespace clraster::runtime
