#include "stages/raster.hpp"

#include "cl/launch.hpp"

namespace clraster::stages {

void RasterStage::run(cl_host::Queue& queue, const RasterParams& p) {
  queue.set_stage(cl_host::Stage::Raster);
  cl_host::set_args(kernel_, p.records, p.overflow, p.sorted_ids, p.tile_ranges, cl_uint{p.tiles_x}, p.color, p.depth,
                    cl_uint{p.width}, p.uniforms);
  const auto side = static_cast<std::size_t>(p.tile_size);
  queue.get().enqueueNDRangeKernel(kernel_, cl::NullRange, cl::NDRange(p.tiles_x * side, p.tiles_y * side),
                                   cl::NDRange(side, side), nullptr, queue.event());
}

}  // namespace clraster::stages
