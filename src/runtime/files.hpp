// Reading files the library did not write itself (program sources, cache entries): regular files
// only, bounded in size, so that a FIFO, a device or a huge file named by mistake or malice is an
// error rather than a hang or a memory blow-up.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace clraster::runtime {

struct FileContents {
  std::string bytes;
  // Empty when the file was read; else why not: the system's reason ("No such file or directory"),
  // "not a regular file" or "larger than N bytes".
  std::string problem;
  bool missing = false;  // the problem is that nothing is there

  explicit operator bool() const { return problem.empty(); }
};

// The whole of the regular file at `path`, when it holds at most max_bytes. A file that is not
// regular (a directory, FIFO, socket or device) is not opened for reading.
FileContents read_regular_file(const std::filesystem::path& path, std::uintmax_t max_bytes);

}  // namespace clraster::runtime
