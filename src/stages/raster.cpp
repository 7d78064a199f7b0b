#include "stages/raster.hpp"

#include "cl/launch.hpp"

namespace clraster::stages {

RasterStage::RasterStage(const cl::Program& program)
    : kernel_(program, "raster_tiles"), group_size_(cl_host::compiled_group_size(kernel_)) {}

void RasterStage::run(cl_host::Queue& queue, const RasterParams& p) {
  queue.set_stage(cl_host::Stage::Raster);
  cl_host::set_args(kernel_, p.records, p.overflow, p.sorted_ids, p.tile_ranges, cl_uint{p.tiles_x}, cl_uint{p.width},
                    p.uniforms, p.depth_stencil, cl_uint{p.stencil_offset}, cl_uint{p.clears});
  cl_uint next = 10;
  for (const cl::Buffer& color : p.colors) kernel_.setArg(next++, color);
  set_resource_args(kernel_, next, *p.resources);
  // One work-group per tile, of the shape the program was compiled for (raster.cl).
  const std::size_t tiles = std::size_t{p.tiles_x} * p.tiles_y;
  queue.get().enqueueNDRangeKernel(kernel_, cl::NullRange, cl::NDRange(tiles * group_size_), cl::NDRange(group_size_),
                                   nullptr, queue.event());
}

}  // namespace clraster::stages
