#include "api/impl.hpp"
#include "runtime/kernel_sources.hpp"
#include "shared/clr_limits.h"

#include <algorithm>
#include <bit>
#include <cstdlib>
#include <iostream>
#include <string>
#include <string_view>

namespace clraster {

const char* version() { return CLRASTER_VERSION; }

std::vector<DeviceInfo> list_devices() {
  std::vector<DeviceInfo> result;
  for (const runtime::Device& device : runtime::enumerate_devices()) result.push_back(device.info);
  return result;
}

namespace {

void check_options(const ContextOptions& options) {
  if (options.memory_cap < kMinMemoryCap) {
    throw InvalidArgument("memory cap of " + std::to_string(options.memory_cap) + " bytes is below the minimum of " +
                          std::to_string(kMinMemoryCap) + " bytes");
  }
  if (options.tile_size != kDeviceTileSize &&
      std::find(kTileSizes.begin(), kTileSizes.end(), options.tile_size) == kTileSizes.end()) {
    throw InvalidArgument("tile size " + std::to_string(options.tile_size) + " is not 8, 16 or 32 (or " +
                          std::to_string(kDeviceTileSize) + ", the device's choice)");
  }
}

WorkGroupShape shape_from_environment() {
  const char* text = std::getenv("CLRASTER_WORK_GROUP_SHAPE");
  if (text == nullptr || *text == '\0' || std::string_view(text) == "device") return WorkGroupShape::Device;
  if (std::string_view(text) == "wide") return WorkGroupShape::Wide;
  throw InvalidArgument(std::string("CLRASTER_WORK_GROUP_SHAPE='") + text + "' is neither 'device' nor 'wide'");
}

void print_warning(const std::string& message) { std::cerr << "clraster: warning: " << message << std::endl; }

// The largest power of two at most `limit` (which is at least 1).
std::size_t power_of_two_at_most(std::size_t limit) { return std::bit_floor(std::max<std::size_t>(limit, 1)); }

}  // namespace

ContextState::ContextState(const ContextOptions& options_in, runtime::Device device_in)
    : options(options_in),
      device(std::move(device_in)),
      context(device.device),
      queue(cl::CommandQueue(context, device.device, options.profile ? CL_QUEUE_PROFILING_ENABLE : 0), options.profile),
      programs(context, device, options.cache_dir, options.on_warning ? options.on_warning : print_warning) {
  if (!options.work_group_shape) options.work_group_shape = shape_from_environment();
  const std::size_t group_limit = device.info.work_group_items;
  // The GPU shapes take a work-item per pixel of a tile, so the tile is the largest whose pixels
  // the device's work-groups hold; the CPU shapes loop over their tile.
  tile_size_chosen = options.tile_size == kDeviceTileSize;
  if (tile_size_chosen) {
    options.tile_size = cpu_shapes() ? kCpuShapeTileSize : kGpuShapeTileSize;
    while (!cpu_shapes() && options.tile_size > kTileSizes.front() &&
           static_cast<std::size_t>(options.tile_size * options.tile_size) > group_limit) {
      options.tile_size /= 2;
    }
  }
  // The largest work-group the shapes make (clr_limits.h): a tile's, a work-item per pixel with the
  // GPU shapes; else the kernels' of one work-item per element (a scan block's adapts, scan_items).
  const int tile_items =
      cpu_shapes() ? std::max(CLR_RASTER_CPU_ITEMS, CLR_QUAD_PIXELS) : options.tile_size * options.tile_size;
  const std::size_t largest_group = std::max(static_cast<std::size_t>(tile_items), std::size_t{CLR_ITEM_GROUP_SIZE});
  if (largest_group > group_limit) {
    throw InvalidArgument("device " + device.info.name + " allows work-groups of " + std::to_string(group_limit) +
                          " work-items; the pipeline's, with tile size " + std::to_string(options.tile_size) +
                          ", need " + std::to_string(largest_group));
  }
}

bool ContextState::cpu_shapes() const { return options.work_group_shape == WorkGroupShape::Device && device.cpu(); }

std::size_t ContextState::scan_items() const {
  return cpu_shapes() ? CLR_SCAN_CPU_ITEMS
                      : std::min<std::size_t>(CLR_SCAN_GPU_ITEMS, power_of_two_at_most(device.info.work_group_items));
}

std::size_t ContextState::vertex_lanes() const { return cpu_shapes() ? CLR_CPU_VERTEX_LANES : 1; }

std::string ContextState::core_build_options() const {
  // Work-group shapes are the device's (clr_limits.h): kernels take them as constants, the host
  // reads them back from each kernel (runtime::compiled_group_size). No warnings: PoCL's compiler
  // prints them on the process's stderr ("7 warnings generated.", of its own ABI for 512-bit vectors
  // on machines without AVX-512), where nobody can act on them; errors still come in the build log.
  return "-cl-std=CL1.2 -w -DCLR_SCAN_GROUP_SIZE=" + std::to_string(scan_items());
}

std::string ContextState::stage_build_options(int tile_size) const {
  const int raster_items = cpu_shapes() ? CLR_RASTER_CPU_ITEMS : tile_size * tile_size;
  return core_build_options() + " -DCLR_TILE_SIZE=" + std::to_string(tile_size) +
         " -DCLR_RASTER_GROUP_SIZE=" + std::to_string(raster_items) +
         " -DCLR_VERTEX_LANES=" + std::to_string(vertex_lanes());
}

const cl::Program& ContextState::core_program() {
  if (!core_) {
    core_ = programs.get("core", runtime::sources::core_program(), core_build_options());
    if (const std::optional<runtime::KernelExcess> excess = runtime::kernel_beyond_limits(*core_, device)) {
      throw InvalidArgument("the pipeline's " + excess->description);
    }
  }
  return *core_;
}

pipeline::Pipeline& ContextState::get_pipeline() {
  if (!pipeline) {
    pipeline = std::make_unique<pipeline::Pipeline>(context, queue, core_program(), options.memory_cap,
                                                    device.info.buffer_bytes, device.info.constant_buffer_bytes);
  }
  return *pipeline;
}

const Program& ContextState::builtin_program(Shading shading) {
  static constexpr std::array<const char*, kShadingCount> kSources = {
      "program/builtin/normal.cl", "program/builtin/lambert.cl", "program/builtin/depth.cl",
      "program/builtin/constant.cl"};
  std::unique_ptr<Program>& builtin = builtins.at(static_cast<std::size_t>(shading));
  if (!builtin) {
    const char* const source = kSources[static_cast<std::size_t>(shading)];
    std::unique_ptr<Program::Impl> impl = compile_program(shared_from_this(), runtime::sources::text(source), source);
    // This state owns its built-in program, so the program must not own this state back (the two
    // would keep each other alive, and every context that drew with it leaked): it keeps a pointer
    // that owns nothing, which is all draws compare it with.
    impl->state = std::shared_ptr<ContextState>(std::shared_ptr<ContextState>(), this);
    builtin = std::make_unique<Program>(std::move(impl));
  }
  return *builtin;
}

Context::Context(const ContextOptions& options) : impl_(std::make_unique<Impl>()) {
  check_options(options);
  impl_->state = std::make_shared<ContextState>(options, runtime::select_device(options.device));
}
Context::~Context() = default;
Context::Context(Context&&) noexcept = default;
Context& Context::operator=(Context&&) noexcept = default;

const DeviceInfo& Context::device() const { return impl_->state->device.info; }
const ContextOptions& Context::options() const { return impl_->state->options; }
void Context::finish() { impl_->state->queue.get().finish(); }

}  // namespace clraster
