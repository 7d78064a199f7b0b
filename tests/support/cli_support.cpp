#include "support/cli_support.hpp"

#include "io/image_io.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <stdlib.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <thread>

extern char** environ;

namespace clraster::test {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail_system(const std::string& what) {
  throw std::runtime_error(what + ": " + std::strerror(errno));
}

// A new empty file in the scratch directory, open for writing; closed and removed on destruction.
class CaptureFile {
 public:
  explicit CaptureFile(const char* stem) : path_((scratch_directory() / (std::string(stem) + "-XXXXXX")).string()) {
    fd_ = ::mkstemp(path_.data());
    if (fd_ < 0) fail_system("mkstemp " + path_);
  }
  ~CaptureFile() {
    ::close(fd_);
    std::error_code ignored;
    fs::remove(path_, ignored);
  }
  CaptureFile(const CaptureFile&) = delete;
  CaptureFile& operator=(const CaptureFile&) = delete;

  int fd() const { return fd_; }
  std::string contents() const { return read_file(path_); }

 private:
  std::string path_;
  int fd_ = -1;
};

// The environment as "NAME=value" strings: this process's, with `overrides` replacing or adding.
std::vector<std::string> child_environment(const std::map<std::string, std::string>& overrides) {
  std::vector<std::string> result;
  for (char** entry = environ; *entry != nullptr; ++entry) {
    const std::string_view text(*entry);
    if (!overrides.contains(std::string(text.substr(0, text.find('='))))) result.emplace_back(text);
  }
  for (const auto& [name, value] : overrides) result.push_back(name + "=" + value);
  return result;
}

// argv or envp for `strings`: pointers to them, then a null pointer.
std::vector<char*> pointers(std::vector<std::string>& strings) {
  std::vector<char*> result;
  for (std::string& s : strings) result.push_back(s.data());
  result.push_back(nullptr);
  return result;
}

std::string quoted(std::string_view text) { return "'" + std::string(text) + "'"; }

// Checks what every ended-by-itself failure shares: no time-out, no signal, exit code 1..127.
::testing::AssertionResult exited_with_failure(const CliResult& result) {
  if (result.timed_out || result.signal != 0 || result.exit_code < 1 || result.exit_code > 127) {
    return ::testing::AssertionFailure() << "expected an exit code in 1..127; got " << result;
  }
  return ::testing::AssertionSuccess();
}

std::vector<std::string_view> lines_of(std::string_view text) {
  std::vector<std::string_view> lines;
  while (!text.empty()) {
    const std::size_t end = text.find('\n');
    lines.push_back(text.substr(0, end));
    text.remove_prefix(end == std::string_view::npos ? text.size() : end + 1);
  }
  return lines;
}

}  // namespace

std::ostream& operator<<(std::ostream& stream, const CliResult& result) {
  if (result.timed_out) {
    stream << "killed after the time limit";
  } else if (result.signal != 0) {
    stream << "ended by signal " << result.signal << " (" << ::strsignal(result.signal) << ")";
  } else {
    stream << "exit code " << result.exit_code;
  }
  return stream << ", stdout " << quoted(result.out) << ", stderr " << quoted(result.err);
}

CliResult run_cli(const std::vector<std::string>& args, const std::map<std::string, std::string>& env,
                  std::chrono::seconds timeout) {
  return run_executable(CLRASTER_CLI_PATH, args, env, timeout);
}

CliResult run_executable(const std::string& path, const std::vector<std::string>& args,
                         const std::map<std::string, std::string>& env, std::chrono::seconds timeout) {
  std::vector<std::string> argv_strings{path};
  argv_strings.insert(argv_strings.end(), args.begin(), args.end());
  std::vector<std::string> env_strings = child_environment(env);
  const std::vector<char*> argv = pointers(argv_strings);
  const std::vector<char*> envp = pointers(env_strings);

  const CaptureFile out("stdout"), err("stderr");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, out.fd(), STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&actions, err.fd(), STDERR_FILENO);
  pid_t pid = 0;
  const int spawned = ::posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  if (spawned != 0) {
    errno = spawned;
    fail_system(std::string("cannot run ") + argv[0]);
  }

  CliResult result;
  const auto deadline = std::chrono::steady_clock::now() + timeout;
  int status = 0;
  while (::waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      result.timed_out = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (!result.timed_out) {
    if (WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
    if (WIFSIGNALED(status)) result.signal = WTERMSIG(status);
  }
  result.out = out.contents();
  result.err = err.contents();
  return result;
}

::testing::AssertionResult succeeded(const CliResult& result) {
  if (result.timed_out || result.signal != 0 || result.exit_code != 0 || !result.err.empty()) {
    return ::testing::AssertionFailure() << "expected exit code 0 and nothing on stderr; got " << result;
  }
  return ::testing::AssertionSuccess();
}

::testing::AssertionResult failed_with_error(const CliResult& result, std::string_view subject) {
  if (::testing::AssertionResult exited = exited_with_failure(result); !exited) return exited;
  const std::vector<std::string_view> lines = lines_of(result.err);
  if (lines.size() != 1 || result.err.back() != '\n' || !lines[0].starts_with("clraster: error: ") ||
      lines[0].find(subject) == std::string_view::npos) {
    return ::testing::AssertionFailure() << "expected one stderr line starting 'clraster: error: ' and mentioning "
                                         << quoted(subject) << "; got " << result;
  }
  return ::testing::AssertionSuccess();
}

::testing::AssertionResult mentions(std::string_view text, std::string_view part) {
  if (text.find(part) != std::string_view::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << quoted(part) << " is not in: " << text;
}

namespace {

// Only warnings on stderr: each line starts "clraster: warning: ".
::testing::AssertionResult succeeded_with_warnings(const CliResult& result) {
  if (result.timed_out || result.signal != 0 || result.exit_code != 0) {
    return ::testing::AssertionFailure() << "expected exit code 0; got " << result;
  }
  for (const std::string_view line : lines_of(result.err)) {
    if (!line.starts_with("clraster: warning: ")) {
      return ::testing::AssertionFailure() << "expected only 'clraster: warning: ' lines on stderr; got " << result;
    }
  }
  return ::testing::AssertionSuccess();
}

Rendered run_render(const std::string& output_name, std::vector<std::string> args,
                    ::testing::AssertionResult (*check)(const CliResult&)) {
  const fs::path output = scratch_directory() / output_name;
  args.insert(args.begin(), {"render", "--output", output.string()});
  const CliResult result = run_cli(args);
  EXPECT_TRUE(check(result));
  return {output, result.exit_code == 0 ? io::load_png(output.string()) : Image{}, result.out, result.err};
}

}  // namespace

Rendered render(const std::string& output_name, std::vector<std::string> args) {
  return run_render(output_name, std::move(args), &succeeded);
}

Rendered render_with_warnings(const std::string& output_name, std::vector<std::string> args) {
  return run_render(output_name, std::move(args), &succeeded_with_warnings);
}

const fs::path& scratch_directory() {
  // Created on first use; removed by the destructor of this static at exit.
  struct Directory {
    fs::path path;
    Directory() {
      std::string pattern = (fs::temp_directory_path() / "clraster-test-XXXXXX").string();
      if (::mkdtemp(pattern.data()) == nullptr) fail_system("mkdtemp " + pattern);
      path = pattern;
    }
    ~Directory() {
      std::error_code ignored;
      fs::remove_all(path, ignored);
    }
  };
  static const Directory directory;
  return directory.path;
}

fs::path write_scratch_file(const std::string& name, std::string_view contents) {
  const fs::path path = scratch_directory() / name;
  std::ofstream file(path, std::ios::binary);
  file.write(contents.data(), static_cast<std::streamsize>(contents.size()));
  if (!file.flush()) throw std::runtime_error("cannot write " + path.string());
  return path;
}

std::string read_file(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

}  // namespace clraster::test
