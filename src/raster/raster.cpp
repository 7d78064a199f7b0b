#include "raster/raster.hpp"

#include "runtime/launch.hpp"
#include "shared/clr_limits.h"

#include <algorithm>
#include <numeric>

namespace clraster::raster {
namespace {

// The stride, coprime with `runs`, of the order in which work-groups take the runs of tiles
// (tile.cl): the first integer from runs / golden ratio, so that any range of consecutive groups
// takes runs spread evenly over the picture.
cl_uint spread_stride(std::size_t runs) {
  std::size_t stride = std::max<std::size_t>(1, static_cast<std::size_t>(static_cast<double>(runs) * 0.6180339887));
  while (std::gcd(stride, runs) != 1) ++stride;
  return static_cast<cl_uint>(stride);
}

}  // namespace

RasterStage::RasterStage(const cl::Program& program)
    : kernel_(program, "raster_tiles"), group_size_(runtime::compiled_group_size(kernel_)) {}

void RasterStage::run(runtime::Queue& queue, const RasterParams& p) {
  queue.set_stage(runtime::Stage::Raster);
  const std::size_t tiles = std::size_t{p.tiles_x} * p.tiles_y;
  const std::size_t runs = runtime::divide_round_up(tiles, std::size_t{CLR_RASTER_TILE_RUN});
  cl_uint next = runtime::set_args(kernel_, p.records, p.overflow, p.sorted_ids, p.tile_ranges, cl_uint{p.tiles_x},
                                   static_cast<cl_uint>(tiles), static_cast<cl_uint>(runs), spread_stride(runs),
                                   cl_uint{p.width}, p.uniforms, p.depth_stencil, cl_uint{p.stencil_offset},
                                   cl_uint{p.clears});
  for (const cl::Buffer& color : p.colors) kernel_.setArg(next++, color);
  geometry::set_resource_args(kernel_, next, *p.resources);
  // One work-group per tile (whole runs of them), of the shape the program was compiled for (group.cl).
  queue.get().enqueueNDRangeKernel(kernel_, cl::NullRange, cl::NDRange(runs * CLR_RASTER_TILE_RUN * group_size_),
                                   cl::NDRange(group_size_), nullptr, queue.event());
}

}  // namespace clraster::raster
