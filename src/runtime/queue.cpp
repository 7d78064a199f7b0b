#include "runtime/queue.hpp"

namespace clraster::runtime {

StageTimes Queue::collect() {
  StageTimes times;
  for (auto& [stage, event] : events_) {
    event.wait();
    const double ms = static_cast<double>(event.getProfilingInfo<CL_PROFILING_COMMAND_END>() -
                                          event.getProfilingInfo<CL_PROFILING_COMMAND_START>()) * 1e-6;
    switch (stage) {
      case Stage::Vertex: times.vertex_ms += ms; break;
      case Stage::Setup: times.setup_ms += ms; break;
      case Stage::Binning: times.binning_ms += ms; break;
      case Stage::Raster: times.raster_ms += ms; break;
      case Stage::Other: times.other_ms += ms; break;
    }
  }
  events_.clear();
  return times;
}

}  // namespace clraster::runtime
