#include "runtime/program_cache.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <unistd.h>
#include <vector>

namespace clraster::runtime {
namespace {

constexpr char kMagic[] = "clraster-program-binary-1\n";

std::filesystem::path default_cache_directory() {
  if (const char* dir = std::getenv("CLRASTER_CACHE_DIR"); dir != nullptr && *dir != '\0') return dir;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && *xdg != '\0') {
    return std::filesystem::path(xdg) / "clraster";
  }
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0') {
    return std::filesystem::path(home) / ".cache" / "clraster";
  }
  return {};
}

// FNV-1a: names the cache file. Collisions are harmless because the file stores the full key.
std::uint64_t fnv1a(const std::string& text) {
  std::uint64_t hash = 0xcbf29ce484222325ull;
  for (unsigned char c : text) {
    hash ^= c;
    hash *= 0x100000001b3ull;
  }
  return hash;
}

void write_u64(std::ostream& out, std::uint64_t value) { out.write(reinterpret_cast<const char*>(&value), sizeof value); }

bool read_u64(std::istream& in, std::uint64_t& value) {
  return static_cast<bool>(in.read(reinterpret_cast<char*>(&value), sizeof value));
}

// An entry of ours (entry_path's name, kMagic first), not a file a user keeps in the same directory.
bool is_entry(const std::filesystem::path& path) {
  const std::string name = path.filename().string();
  const auto hex = [](char c) { return std::isxdigit(static_cast<unsigned char>(c)) != 0; };
  if (name.size() != 20 || !name.ends_with(".bin") || !std::all_of(name.begin(), name.begin() + 16, hex)) return false;
  std::ifstream in(path, std::ios::binary);
  std::string magic(sizeof kMagic - 1, '\0');
  return in.read(magic.data(), static_cast<std::streamsize>(magic.size())) && magic == kMagic;
}

}  // namespace

ProgramCache::ProgramCache(cl::Context context, Device device, const std::string& cache_dir,
                           std::uintmax_t limit_bytes)
    : context_(std::move(context)), device_(std::move(device)), limit_bytes_(limit_bytes) {
  directory_ = cache_dir.empty() ? default_cache_directory() : std::filesystem::path(cache_dir);
  if (directory_ == "off") directory_.clear();
}

std::filesystem::path ProgramCache::entry_path(const std::string& key) const {
  char name[32];
  std::snprintf(name, sizeof name, "%016llx.bin", static_cast<unsigned long long>(fnv1a(key)));
  return directory_ / name;
}

cl::Program ProgramCache::get(const std::string& name, const std::string& source, const std::string& options) {
  const std::string key = device_.info.platform + '\n' + device_.info.name + '\n' + device_.info.driver_version +
                          '\n' + device_.info.version + '\n' + options + '\n' + source;
  if (auto found = programs_.find(key); found != programs_.end()) return found->second;

  cl::Program program = directory_.empty() ? cl::Program() : load_binary(key, options);
  if (program() == nullptr) {
    program = build_from_source(name, source, options);
    if (!directory_.empty()) store_binary(key, program);
  }
  programs_.emplace(key, program);
  return program;
}

cl::Program ProgramCache::build_from_source(const std::string& name, const std::string& source,
                                            const std::string& options) {
  cl::Program program(context_, source);
  try {
    program.build({device_.device}, options.c_str());
  } catch (const cl::Error&) {
    std::string log = program.getBuildInfo<CL_PROGRAM_BUILD_LOG>(device_.device);
    while (!log.empty() && (log.back() == '\n' || log.back() == '\0')) log.pop_back();
    throw BuildError("OpenCL program '" + name + "' failed to build on " + device_.info.name, log);
  }
  return program;
}

// A cached binary that is missing, truncated, for another key or rejected by the driver is simply
// rebuilt from source: the cache only ever saves time.
cl::Program ProgramCache::load_binary(const std::string& key, const std::string& options) {
  const std::filesystem::path path = entry_path(key);
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  std::string magic(sizeof kMagic - 1, '\0');
  std::uint64_t key_size = 0, binary_size = 0;
  if (!in.read(magic.data(), static_cast<std::streamsize>(magic.size())) || magic != kMagic) return {};
  if (!read_u64(in, key_size) || key_size != key.size()) return {};
  std::string stored_key(key_size, '\0');
  if (!in.read(stored_key.data(), static_cast<std::streamsize>(key_size)) || stored_key != key) return {};
  if (!read_u64(in, binary_size) || binary_size == 0 || binary_size > (std::uint64_t{1} << 30)) return {};
  std::vector<unsigned char> binary(binary_size);
  if (!in.read(reinterpret_cast<char*>(binary.data()), static_cast<std::streamsize>(binary_size))) return {};
  try {
    cl::Program program(context_, {device_.device}, cl::Program::Binaries{binary});
    program.build({device_.device}, options.c_str());
    std::error_code error;  // the entry's time says when it was last used (trim)
    std::filesystem::last_write_time(path, std::filesystem::file_time_type::clock::now(), error);
    return program;
  } catch (const cl::Error&) {
    return {};
  }
}

// Written to a temporary file and renamed, so a concurrent reader never sees half an entry.
void ProgramCache::store_binary(const std::string& key, const cl::Program& program) {
  std::vector<std::vector<unsigned char>> binaries = program.getInfo<CL_PROGRAM_BINARIES>();
  if (binaries.size() != 1 || binaries[0].empty()) return;
  std::error_code error;
  std::filesystem::create_directories(directory_, error);
  if (error) return;
  const std::filesystem::path path = entry_path(key);
  std::filesystem::path temporary = path;
  temporary += ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) return;
    out.write(kMagic, sizeof kMagic - 1);
    write_u64(out, key.size());
    out.write(key.data(), static_cast<std::streamsize>(key.size()));
    write_u64(out, binaries[0].size());
    out.write(reinterpret_cast<const char*>(binaries[0].data()), static_cast<std::streamsize>(binaries[0].size()));
    if (!out) {
      out.close();
      std::filesystem::remove(temporary, error);
      return;
    }
  }
  std::filesystem::rename(temporary, path, error);
  if (error) std::filesystem::remove(temporary, error);
  else trim(path);
}

// Removes the entries used longest ago (a load refreshes an entry's time) until the directory's
// entries take at most limit_bytes_, but never `kept`, the one just written. Other processes may
// be reading or writing entries meanwhile: a removed one is rebuilt by whoever needs it next.
void ProgramCache::trim(const std::filesystem::path& kept) const {
  struct Entry {
    std::filesystem::file_time_type used;
    std::uintmax_t bytes;
    std::filesystem::path path;
  };
  std::vector<Entry> entries;
  std::uintmax_t total = 0;
  std::error_code error;
  for (std::filesystem::directory_iterator it(directory_, error), end; !error && it != end; it.increment(error)) {
    if (!is_entry(it->path())) continue;  // not temporary files being written, nor anyone else's
    std::error_code size_error, time_error;
    const std::uintmax_t bytes = it->file_size(size_error);
    const std::filesystem::file_time_type used = it->last_write_time(time_error);
    if (size_error || time_error) continue;
    total += bytes;
    entries.push_back({used, bytes, it->path()});
  }
  if (total <= limit_bytes_) return;
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.used < b.used; });
  for (const Entry& entry : entries) {
    if (total <= limit_bytes_) break;
    if (entry.path != kept && std::filesystem::remove(entry.path, error)) total -= entry.bytes;
  }
}

}  // namespace clraster::runtime
