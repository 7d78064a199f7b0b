// Renders that run a user's program (--program) or have a --time-limit run in a child process, so
// that nothing the program does can take the command line down with it: a compiler that crashes on
// it, frames that never end (neither PoCL nor Intel's CPU runtime can cancel a running kernel; the
// child is killed), output the OpenCL compiler prints on the process's stderr. The parent relays the
// child's stderr, says how it ended, and leaves the picture already on disk as it was (outputs are
// replaced atomically).
#pragma once

#include <functional>
#include <optional>

namespace clraster::cli {

// Runs `command` in a child process and returns its exit code. `command` receives `start_clock`, to
// call when the timed part begins (the frames, once programs are built); from then on the child has
// `time_limit_seconds` (if any) to end, else it is killed and Error is thrown. A child ended by a
// signal is an Error too. The child's stderr is relayed line by line, without the summaries
// clang prints of a build's diagnostics ("1 error generated."), which the error messages hold.
// SIGINT and SIGTERM sent to this process end the child as well.
int run_isolated(std::optional<double> time_limit_seconds,
                 const std::function<int(const std::function<void()>& start_clock)>& command);

}  // namespace clraster::cli
