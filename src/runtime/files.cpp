#include "runtime/files.hpp"

#include <cerrno>
#include <cstring>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

namespace clraster::runtime {

FileContents read_regular_file(const std::filesystem::path& path, std::uintmax_t max_bytes) {
  FileContents contents;
  const auto fail = [&](std::string problem) {
    contents.bytes.clear();
    contents.problem = std::move(problem);
    return contents;
  };
  // stat before open: opening a FIFO blocks and opening a device can act on it. O_NONBLOCK and the
  // second check cover a file swapped for such a thing in between.
  struct stat before {};
  if (::stat(path.c_str(), &before) != 0) {
    contents.missing = errno == ENOENT;
    return fail(std::strerror(errno));
  }
  if (!S_ISREG(before.st_mode)) return fail("not a regular file");
  const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) return fail(std::strerror(errno));
  struct stat opened {};
  if (::fstat(fd, &opened) != 0 || !S_ISREG(opened.st_mode) || opened.st_ino != before.st_ino ||
      opened.st_dev != before.st_dev) {
    ::close(fd);
    return fail("not a regular file");
  }
  if (static_cast<std::uintmax_t>(opened.st_size) > max_bytes) {
    ::close(fd);
    return fail("larger than " + std::to_string(max_bytes) + " bytes");
  }
  contents.bytes.resize(static_cast<std::size_t>(opened.st_size));
  std::size_t done = 0;
  while (done < contents.bytes.size()) {
    const ssize_t n = ::read(fd, contents.bytes.data() + done, contents.bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      const int error = errno;
      ::close(fd);
      return fail(std::strerror(error));
    }
    if (n == 0) break;  // shrank while being read: what is there
    done += static_cast<std::size_t>(n);
  }
  contents.bytes.resize(done);
  ::close(fd);
  return contents;
}

}  // namespace clraster::runtime
