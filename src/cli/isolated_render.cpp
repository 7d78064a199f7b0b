#include "cli/isolated_render.hpp"

#include "clraster/clraster.hpp"

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <regex>
#include <string>

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

namespace clraster::cli {
namespace {

volatile pid_t g_child = 0;

// Ends the child with this process, then this process as the signal would have.
void forward_and_die(int signal) {
  if (g_child > 0) ::kill(g_child, SIGKILL);
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

[[noreturn]] void fail_system(const char* what) {
  throw Error(std::string("cannot start the render process (") + what + "): " + std::strerror(errno));
}

// Passes the child's stderr on, a line at a time, but for clang's summaries of a build's diagnostics.
class StderrRelay {
 public:
  void take(const char* bytes, std::size_t count) {
    pending_.append(bytes, count);
    for (std::size_t end; (end = pending_.find('\n')) != std::string::npos; pending_.erase(0, end + 1)) {
      pass_on(pending_.substr(0, end));
    }
  }
  void finish() {
    if (!pending_.empty()) pass_on(pending_);
    pending_.clear();
  }

 private:
  static void pass_on(const std::string& line) {
    static const std::regex summary(R"(^\d+ (warning|error)s?( and \d+ errors?)? generated\.$)");
    if (!std::regex_match(line, summary)) std::cerr << line << '\n';
  }
  std::string pending_;
};

std::string seconds_text(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", seconds);
  return text;
}

}  // namespace

int run_isolated(std::optional<double> time_limit_seconds,
                 const std::function<int(const std::function<void()>& start_clock)>& command) {
  int clock[2], errors[2];
  if (::pipe2(clock, O_CLOEXEC) != 0 || ::pipe2(errors, O_CLOEXEC) != 0) fail_system("pipe");
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  const pid_t child = ::fork();
  if (child < 0) fail_system("fork");
  if (child == 0) {
    ::close(clock[0]);
    ::close(errors[0]);
    ::dup2(errors[1], STDERR_FILENO);
    ::close(errors[1]);
    const int write_end = clock[1];
    const int code = command([write_end] {
      const char byte = 1;
      while (::write(write_end, &byte, 1) < 0 && errno == EINTR) {
      }
    });
    std::cout.flush();
    std::exit(code);
  }
  ::close(clock[1]);
  ::close(errors[1]);
  g_child = child;
  std::signal(SIGINT, forward_and_die);
  std::signal(SIGTERM, forward_and_die);

  // Until both pipes close (the child ended), relay its stderr and watch the clock; polled every
  // 10 ms at most, which is nothing against frames that may take seconds.
  StderrRelay relay;
  std::optional<std::chrono::steady_clock::time_point> deadline;
  pollfd fds[2] = {{clock[0], POLLIN, 0}, {errors[0], POLLIN, 0}};
  bool timed_out = false;
  bool frames_began = false;
  while (fds[0].fd >= 0 || fds[1].fd >= 0) {
    if (::poll(fds, 2, deadline ? 10 : -1) < 0 && errno != EINTR) break;
    for (int i = 0; i < 2; ++i) {
      if (fds[i].fd < 0 || fds[i].revents == 0) continue;
      char buffer[4096];
      const ssize_t n = ::read(fds[i].fd, buffer, sizeof buffer);
      if (n > 0 && i == 1) relay.take(buffer, static_cast<std::size_t>(n));
      frames_began |= n > 0 && i == 0;
      if (n > 0 && i == 0 && time_limit_seconds) {
        deadline = std::chrono::steady_clock::now() +
                   std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                       std::chrono::duration<double>(*time_limit_seconds));
      }
      if (n == 0 || (n < 0 && errno != EINTR)) {
        ::close(fds[i].fd);
        fds[i].fd = -1;
      }
    }
    if (deadline && std::chrono::steady_clock::now() >= *deadline) {
      ::kill(child, SIGKILL);
      timed_out = true;
      break;
    }
  }
  for (pollfd& fd : fds) {
    if (fd.fd >= 0) ::close(fd.fd);
  }
  relay.finish();
  int status = 0;
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  g_child = 0;
  if (timed_out) {
    throw Error("the frames took longer than --time-limit " + seconds_text(*time_limit_seconds) +
                " s and were stopped (does a program loop for ever?)");
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  const int signal = WTERMSIG(status);
  throw Error("the render process was ended by signal " + std::to_string(signal) + " (" + strsignal(signal) + ") " +
              (frames_began ? "during its frames: a program crashed (a write through a wild pointer?)"
                            : "before its frames began: the OpenCL compiler crashed"));
}

}  // namespace clraster::cli
