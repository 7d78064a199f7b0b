// --time-limit: a render whose frames run too long (a program that loops for ever) is stopped.
// Neither PoCL nor Intel's CPU runtime can cancel a running kernel, so the render runs in a child
// process, which is killed when its time is up: the process the user started stays in control, and
// the picture already on disk stays as it was (outputs are replaced atomically).
#pragma once

#include <functional>

namespace clraster::cli {

// Runs `command` in a child process and returns its exit code. `command` receives `start_clock`,
// to call when the timed part begins (the frames, once programs are built); from then on the child
// has `seconds` to end, else it is killed and Error is thrown. A child ended by a signal is an Error
// too. SIGINT and SIGTERM sent to this process end the child as well.
int run_with_time_limit(double seconds, const std::function<int(const std::function<void()>& start_clock)>& command);

}  // namespace clraster::cli
