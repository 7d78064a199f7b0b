// Running the clraster command line (or another built executable) from tests: in a child process, with
// its exit status and output captured and a time limit, so that a crash or a hang is a test
// failure instead of a lost test run. Also a scratch directory for the files the tests hand it.
#pragma once

#include "clraster/clraster.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace clraster::test {

struct CliResult {
  bool timed_out = false;  // killed after the time limit
  int exit_code = -1;      // when the process exited by itself
  int signal = 0;          // when a signal ended it
  std::string out;         // stdout
  std::string err;         // stderr
};

// "exit code 1, stdout '...', stderr '...'" (or the signal, or the time-out), for failure messages.
std::ostream& operator<<(std::ostream& stream, const CliResult& result);

// Runs CLRASTER_CLI_PATH with `args`, the test's environment plus `env` (which overrides), and
// stdin from /dev/null. A process still running after `timeout` is killed.
CliResult run_cli(const std::vector<std::string>& args, const std::map<std::string, std::string>& env = {},
                  std::chrono::seconds timeout = std::chrono::seconds(180));

// The same for any executable (the examples, for instance).
CliResult run_executable(const std::string& path, const std::vector<std::string>& args,
                         const std::map<std::string, std::string>& env = {},
                         std::chrono::seconds timeout = std::chrono::seconds(180));

// Exit code 0, not ended by a signal or the time limit, nothing on stderr.
::testing::AssertionResult succeeded(const CliResult& result);

// Failed as the command line must on bad input: exited by itself with a code in 1..127 and said
// why on exactly one stderr line that starts "clraster: error: " and mentions `subject`.
::testing::AssertionResult failed_with_error(const CliResult& result, std::string_view subject);

// "'part' is not in: text" unless `text` contains `part`.
::testing::AssertionResult mentions(std::string_view text, std::string_view part);

// What `clraster render --output scratch_directory()/output_name args...` made.
struct Rendered {
  std::filesystem::path file;
  Image picture;    // as read back from the file; empty when the render failed
  std::string out;  // stdout
  std::string err;  // stderr
};

// Runs `clraster render --output scratch_directory()/output_name args...`, which must succeed (a
// failure fails the test): exit code 0 and nothing on stderr.
Rendered render(const std::string& output_name, std::vector<std::string> args);

// The same for a render that may warn: exit code 0, and every stderr line a "clraster: warning: ".
Rendered render_with_warnings(const std::string& output_name, std::vector<std::string> args);

// A directory of this test process's own, removed when the process ends.
const std::filesystem::path& scratch_directory();

// Writes `contents` to scratch_directory() / name and returns that path.
std::filesystem::path write_scratch_file(const std::string& name, std::string_view contents);

// The bytes of a file (empty when it cannot be read).
std::string read_file(const std::filesystem::path& path);

}  // namespace clraster::test
