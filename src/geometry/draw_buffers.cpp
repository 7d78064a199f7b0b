#include "geometry/draw_buffers.hpp"

namespace clraster::geometry {

cl_uint set_resource_args(cl::Kernel& kernel, cl_uint first, const ProgramResources& resources) {
  kernel.setArg(first++, resources.uniform_block);
  kernel.setArg(first++, resources.texture_descs);
  for (const cl::Buffer& texture : resources.textures) kernel.setArg(first++, texture);
  for (const cl::Buffer& buffer : resources.buffers) kernel.setArg(first++, buffer);
  return first;
}

}  // namespace clraster::geometry
