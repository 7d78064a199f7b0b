// Rasterization, the fragment program and the per-fragment operations (kernel in tile.cl): one
// work-group per tile; those of tiles without triangles return at once, unless the pass writes
// pending clears.
#pragma once

#include "geometry/draw_buffers.hpp"

#include <cstdint>

namespace clraster::raster {

struct RasterParams {
  cl::Buffer records;        // SetupTriangles: per primitive ...
  cl::Buffer overflow;       // ... and of clipped primitives
  cl::Buffer sorted_ids;     // triangle ids, grouped by tile, in primitive order
  cl::Buffer tile_ranges;
  std::uint32_t tiles_x = 0;
  std::uint32_t tiles_y = 0;
  std::uint32_t width = 0;   // of the framebuffer
  cl::Buffer uniforms;
  cl::Buffer depth_stencil;  // depth floats, then stencil bytes at stencil_offset (a placeholder: none)
  std::uint32_t stencil_offset = 0;
  // Pending clears the pass writes (CLR_CLEAR_*, values in the uniforms): every tile then starts from
  // them instead of the attachments and is written back whole, with or without triangles.
  std::uint32_t clears = 0;
  std::vector<cl::Buffer> colors;  // one per program output (placeholders where no attachment is)
  const geometry::ProgramResources* resources = nullptr;
};

class RasterStage {
 public:
  explicit RasterStage(const cl::Program& program);
  void run(runtime::Queue& queue, const RasterParams& params);

 private:
  cl::Kernel kernel_;
  std::size_t group_size_;  // work-items per tile: the kernel's reqd_work_group_size
};

}  // namespace clraster::raster
