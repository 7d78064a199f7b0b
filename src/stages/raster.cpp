#include "stages/raster.hpp"

#include "cl/launch.hpp"

namespace clraster::stages {

void RasterStage::run(cl_host::Queue& queue, const RasterParams& p) {
  queue.set_stage(cl_host::Stage::Raster);
  cl_host::set_args(kernel_, p.records, p.overflow, p.sorted_ids, p.tile_ranges, cl_uint{p.tiles_x}, cl_uint{p.width},
                    p.uniforms, p.depth_stencil, cl_uint{p.stencil_offset});
  cl_uint next = 9;
  for (const cl::Buffer& color : p.colors) kernel_.setArg(next++, color);
  set_resource_args(kernel_, next, *p.resources);
  const auto side = static_cast<std::size_t>(p.tile_size);
  queue.get().enqueueNDRangeKernel(kernel_, cl::NullRange, cl::NDRange(p.tiles_x * side, p.tiles_y * side),
                                   cl::NDRange(side, side), nullptr, queue.event());
}

}  // namespace clraster::stages
