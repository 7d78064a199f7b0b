// The pipeline's intermediate buffers. Each grows on demand up to the capacity the memory plan gives
// it, so small scenes hold little memory and no scene holds more than the context's cap.
#pragma once

#include <CL/opencl.hpp>

#include <array>
#include <cstddef>

namespace clraster::runtime {

enum class Scratch : int {
  ShadedVertices,   // vertex stage output
  GroupCodes,       // when every vertex is shaded once: the clip codes each group of slots shares
  CulledBlocks,     // and whether each block of the draw's primitives is culled whole (block culling)
  Records,          // per primitive of a chunk: its SetupTriangle, when it needs no clipping
  BinBoxes,         // and that triangle's pixel box, what binning reads of it
  OverflowRecords,  // the SetupTriangles of the chunk's clipped primitives
  ClippedCounts,    // per primitive (+ 1): triangles clipping leaves, then their offsets in OverflowRecords
  PairCounts,       // per primitive (+ 1): tiles its triangles touch, then the offsets of its bin pairs
  TileKeys0,       // bin pairs: tile keys and triangle ids, twice for the radix sort's ping-pong
  TileKeys1,
  TriangleIds0,
  TriangleIds1,
  TileRanges,      // per tile: its run of sorted pairs
  ScanBlockSums,   // scan scratch
  RadixHistogram,  // radix sort scratch
  Count,
};
inline constexpr std::size_t kScratchCount = static_cast<std::size_t>(Scratch::Count);
using ScratchSizes = std::array<std::size_t, kScratchCount>;

class ScratchArena {
 public:
  explicit ScratchArena(cl::Context context) : context_(std::move(context)) {}

  // Releases every buffer larger than its new capacity, so that what stays held plus what may still
  // grow never exceeds the sum of the capacities.
  void set_capacities(const ScratchSizes& capacities);

  // Buffer `id` with at least `bytes` bytes (contents are lost when it grows). Grows by half again
  // as much, within its capacity, so that slowly rising demand does not reallocate every draw.
  const cl::Buffer& get(Scratch id, std::size_t bytes);

  std::size_t bytes_held() const;
  std::size_t peak_bytes() const { return peak_bytes_; }

 private:
  cl::Context context_;
  std::array<cl::Buffer, kScratchCount> buffers_{};
  ScratchSizes sizes_{};
  ScratchSizes capacities_{};
  std::size_t peak_bytes_ = 0;
};

}  // namespace clraster::runtime
