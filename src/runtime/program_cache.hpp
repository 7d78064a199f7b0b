// Builds OpenCL programs once: an in-memory cache for the life of the context and an on-disk cache
// of program binaries between runs (a cold PoCL build takes about a second, a cached binary about a
// millisecond). Entries are keyed by the full source, the build options, the device and the driver
// version (and clraster's), so a changed kernel or driver never loads a stale binary. Each entry
// carries a checksum, verified before the driver sees the binary: a damaged entry is rebuilt. The
// directory keeps at most limit_bytes of them, dropping the entries used longest ago first.
#pragma once

#include "runtime/device.hpp"
#include "shared/clr_limits.h"

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <unordered_map>

namespace clraster::runtime {

class ProgramCache {
 public:
  using Warn = std::function<void(const std::string&)>;

  // cache_dir as in ContextOptions::cache_dir ("" picks the default location, "off" disables).
  // `warn` hears of the first unusable entry (ContextOptions::on_warning).
  ProgramCache(cl::Context context, Device device, const std::string& cache_dir, Warn warn,
               std::uintmax_t limit_bytes = std::uintmax_t{CLR_PROGRAM_CACHE_MIB} << 20);

  // The built program for this source and these options. Throws BuildError with the compiler's log.
  cl::Program get(const std::string& name, const std::string& source, const std::string& options);

 private:
  cl::Program build_from_source(const std::string& name, const std::string& source, const std::string& options);
  cl::Program load_binary(const std::string& key, const std::string& options);
  void store_binary(const std::string& key, const cl::Program& program);
  void unusable(const std::filesystem::path& path, const std::string& problem);
  std::filesystem::path entry_path(const std::string& key) const;
  void trim(const std::filesystem::path& kept) const;

  cl::Context context_;
  Device device_;
  Warn warn_;
  bool warned_ = false;
  std::filesystem::path directory_;
  std::uintmax_t limit_bytes_;
  std::unordered_map<std::string, cl::Program> programs_;
};

}  // namespace clraster::runtime
