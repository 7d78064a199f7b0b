// Rasterization, depth test, interpolation, shading and blending (kernel in raster.cl): one
// work-group per tile that has triangles binned to it.
#pragma once

#include "cl/queue.hpp"

#include <CL/opencl.hpp>

#include <cstdint>

namespace clraster::stages {

struct RasterParams {
  cl::Buffer records;        // SetupTriangles: per primitive ...
  cl::Buffer overflow;       // ... and of clipped primitives
  cl::Buffer sorted_ids;     // triangle ids, grouped by tile, in primitive order
  cl::Buffer tile_ranges;
  std::uint32_t tiles_x = 0;
  std::uint32_t tiles_y = 0;
  int tile_size = 0;
  cl::Buffer color;          // RGBA8 per pixel, row 0 at the bottom
  cl::Buffer depth;          // float per pixel
  std::uint32_t width = 0;
  cl::Buffer uniforms;
};

class RasterStage {
 public:
  explicit RasterStage(const cl::Program& program) : kernel_(program, "raster_tiles") {}
  void run(cl_host::Queue& queue, const RasterParams& params);

 private:
  cl::Kernel kernel_;
};

}  // namespace clraster::stages
