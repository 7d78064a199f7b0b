// The command queue the pipeline enqueues into. When profiling is on, every command gets an event
// tagged with the pipeline stage it belongs to, and the stages' device times are summed per draw.
#pragma once

#include "clraster/clraster.hpp"

#include <CL/opencl.hpp>

#include <utility>
#include <vector>

namespace clraster::runtime {

enum class Stage { Vertex, Setup, Binning, Raster, Other };

class Queue {
 public:
  Queue(cl::CommandQueue queue, bool profiling) : queue_(std::move(queue)), profiling_(profiling) {}

  cl::CommandQueue& get() { return queue_; }

  // Commands enqueued from now on are counted for `stage`.
  void set_stage(Stage stage) { stage_ = stage; }

  // The event to pass to an enqueue call: null when not profiling.
  cl::Event* event() {
    if (!profiling_) return nullptr;
    events_.emplace_back(stage_, cl::Event());
    return &events_.back().second;
  }

  // Device time per stage of the commands enqueued since the last call (waits for them).
  StageTimes collect();

 private:
  cl::CommandQueue queue_;
  bool profiling_;
  Stage stage_ = Stage::Other;
  std::vector<std::pair<Stage, cl::Event>> events_;
};

}  // namespace clraster::runtime
