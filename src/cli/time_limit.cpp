#include "cli/time_limit.hpp"

#include "clraster/clraster.hpp"

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>
#include <thread>

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

// Blocks until the child calls start_clock (true) or ends without it (false).
bool wait_for_clock(int fd) {
  char byte = 0;
  for (;;) {
    const ssize_t n = ::read(fd, &byte, 1);
    if (n >= 0) return n == 1;
    if (errno != EINTR) return false;
  }
}

int exit_code(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  const int signal = WTERMSIG(status);
  throw Error("the render process was ended by signal " + std::to_string(signal) + " (" + strsignal(signal) + ")");
}

}  // namespace

int run_with_time_limit(double seconds, const std::function<int(const std::function<void()>& start_clock)>& command) {
  int clock[2];
  if (::pipe2(clock, O_CLOEXEC) != 0) throw Error(std::string("cannot start the render process: ") + std::strerror(errno));
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  const pid_t child = ::fork();
  if (child < 0) throw Error(std::string("cannot start the render process: ") + std::strerror(errno));
  if (child == 0) {
    ::close(clock[0]);
    const int write_end = clock[1];
    const int code = command([write_end] {
      const char byte = 1;
      while (::write(write_end, &byte, 1) < 0 && errno == EINTR) {
      }
      ::close(write_end);
    });
    std::cout.flush();
    std::exit(code);
  }
  ::close(clock[1]);
  g_child = child;
  std::signal(SIGINT, forward_and_die);
  std::signal(SIGTERM, forward_and_die);
  const bool timed = wait_for_clock(clock[0]);
  ::close(clock[0]);
  int status = 0;
  if (timed) {
    // Polled: a child's end cannot be waited for with a deadline otherwise, and 10 ms is nothing
    // against frames that may take seconds.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    while (::waitpid(child, &status, WNOHANG) == 0) {
      if (std::chrono::steady_clock::now() >= deadline) {
        ::kill(child, SIGKILL);
        ::waitpid(child, &status, 0);
        g_child = 0;
        char limit[32];
        std::snprintf(limit, sizeof limit, "%g", seconds);
        throw Error(std::string("the frames took longer than --time-limit ") + limit +
                    " s and were stopped (does a program loop for ever?)");
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  } else {
    while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
    }
  }
  g_child = 0;
  return exit_code(status);
}

}  // namespace clraster::cli
