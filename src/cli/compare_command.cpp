#include "cli/commands.hpp"
#include "io/image_compare.hpp"
#include "io/image_io.hpp"

#include <iostream>

namespace clraster::cli {

int compare(const CompareOptions& options) {
  const Image a = io::load_png(options.a);
  const Image b = io::load_png(options.b);
  const io::ImageComparison comparison = io::compare_images(a, b, options.threshold);
  if (!options.diff_output.empty()) io::save_png(options.diff_output, io::diff_image(a, b, options.threshold));
  std::cout << io::to_json(comparison) << std::endl;
  return 0;
}

int devices() {
  for (const DeviceInfo& device : list_devices()) {
    std::cout << device.index << ": " << device.name << " (" << device.type << ", " << device.compute_units
              << " compute units)\n   platform " << device.platform << ", " << device.version << ", driver "
              << device.driver_version << "\n   local memory " << (device.local_memory_bytes >> 10)
              << " KiB, work-groups of " << device.work_group_items << ", buffers of " << (device.buffer_bytes >> 20)
              << " MiB at most, " << device.address_bits << "-bit addresses\n";
  }
  return 0;
}

}  // namespace clraster::cli
