#include "runtime/program_cache.hpp"
#include "runtime/files.hpp"

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string_view>
#include <unistd.h>
#include <vector>

namespace clraster::runtime {
namespace {

// An entry: kMagic, the key's length and bytes, the binary's length and bytes (lengths as u64),
// then the FNV-1a hash of everything before it. Another version's entries start with kMagicPrefix.
constexpr std::string_view kMagicPrefix = "clraster-program-binary-";
constexpr std::string_view kMagic = "clraster-program-binary-2\n";
constexpr std::uint64_t kMaxBinaryBytes = std::uint64_t{CLR_MAX_PROGRAM_BINARY_MIB} << 20;

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

// FNV-1a: names an entry's file (collisions are harmless: the entry holds the whole key) and checks
// its contents (a damaged byte changes it but for a chance of 2^-64).
std::uint64_t fnv1a(std::string_view text) {
  std::uint64_t hash = 0xcbf29ce484222325ull;
  for (unsigned char c : text) {
    hash ^= c;
    hash *= 0x100000001b3ull;
  }
  return hash;
}

void append_u64(std::string& out, std::uint64_t value) { out.append(reinterpret_cast<const char*>(&value), sizeof value); }

// Reads a u64 at the front of `bytes` and drops it; false when there are fewer than 8 bytes.
bool take_u64(std::string_view& bytes, std::uint64_t& value) {
  if (bytes.size() < sizeof value) return false;
  std::memcpy(&value, bytes.data(), sizeof value);
  bytes.remove_prefix(sizeof value);
  return true;
}

// What an entry file's bytes hold: its key and binary, or why they cannot be used.
struct ParsedEntry {
  std::string_view key, binary;
  std::string problem;         // empty when the entry is whole
  bool other_version = false;  // another clraster's format: replaced without a word
};

ParsedEntry parse_entry(std::string_view bytes) {
  ParsedEntry entry;
  entry.other_version = bytes.starts_with(kMagicPrefix) && !bytes.starts_with(kMagic);
  if (!bytes.starts_with(kMagic)) {
    if (!entry.other_version) entry.problem = "it is not a cache entry";
    return entry;
  }
  std::uint64_t checksum = 0, key_size = 0, binary_size = 0;
  std::string_view rest = bytes.substr(kMagic.size());
  if (rest.size() < sizeof checksum) {
    entry.problem = "it is truncated";
    return entry;
  }
  std::memcpy(&checksum, bytes.data() + bytes.size() - sizeof checksum, sizeof checksum);
  rest.remove_suffix(sizeof checksum);
  if (checksum != fnv1a(bytes.substr(0, bytes.size() - sizeof checksum))) {
    entry.problem = "its checksum does not match its contents";
  } else if (!take_u64(rest, key_size) || key_size > rest.size()) {
    entry.problem = "its key length is wrong";
  } else {
    entry.key = rest.substr(0, key_size);
    rest.remove_prefix(key_size);
    if (!take_u64(rest, binary_size) || binary_size != rest.size() || binary_size == 0) {
      entry.problem = "its binary length is wrong";
    }
    entry.binary = rest;
  }
  return entry;
}

// An entry of ours, of any version (entry_path's name, kMagicPrefix first), not a file a user keeps
// in the same directory. Only a regular file is opened: a FIFO would block the read.
bool is_entry(const std::filesystem::directory_entry& file) {
  const std::string name = file.path().filename().string();
  const auto hex = [](char c) { return std::isxdigit(static_cast<unsigned char>(c)) != 0; };
  if (name.size() != 20 || !name.ends_with(".bin") || !std::all_of(name.begin(), name.begin() + 16, hex)) return false;
  std::error_code error;
  if (!file.is_regular_file(error)) return false;
  std::ifstream in(file.path(), std::ios::binary);
  std::string magic(kMagicPrefix.size(), '\0');
  return in.read(magic.data(), static_cast<std::streamsize>(magic.size())) && magic == kMagicPrefix;
}

}  // namespace

ProgramCache::ProgramCache(cl::Context context, Device device, const std::string& cache_dir, Warn warn,
                           std::uintmax_t limit_bytes)
    : context_(std::move(context)), device_(std::move(device)), warn_(std::move(warn)), limit_bytes_(limit_bytes) {
  directory_ = cache_dir.empty() ? default_cache_directory() : std::filesystem::path(cache_dir);
  if (directory_ == "off") directory_.clear();
}

std::filesystem::path ProgramCache::entry_path(const std::string& key) const {
  char name[32];
  std::snprintf(name, sizeof name, "%016llx.bin", static_cast<unsigned long long>(fnv1a(key)));
  return directory_ / name;
}

cl::Program ProgramCache::get(const std::string& name, const std::string& source, const std::string& options) {
  const std::string key = std::string("clraster ") + version() + '\n' + device_.info.platform + '\n' +
                          device_.info.name + '\n' + device_.info.driver_version + '\n' + device_.info.version +
                          '\n' + options + '\n' + source;
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

// A cached binary that is missing, of another version or for another key is simply rebuilt from
// source: the cache only ever saves time. One that is damaged (truncated, changed, not a regular
// file) or that the driver rejects is rebuilt too, with a warning (the first time only).
cl::Program ProgramCache::load_binary(const std::string& key, const std::string& options) {
  const std::filesystem::path path = entry_path(key);
  const FileContents file = read_regular_file(path, kMagic.size() + 24 + key.size() + kMaxBinaryBytes);
  if (file.missing) return {};
  if (!file) {
    unusable(path, file.problem);
    return {};
  }
  const ParsedEntry entry = parse_entry(file.bytes);
  if (entry.other_version) return {};
  if (!entry.problem.empty()) {
    unusable(path, entry.problem);
    return {};
  }
  if (entry.key != key) return {};
  try {
    const std::vector<unsigned char> binary(entry.binary.begin(), entry.binary.end());
    cl::Program program(context_, {device_.device}, cl::Program::Binaries{binary});
    program.build({device_.device}, options.c_str());
    std::error_code error;  // the entry's time says when it was last used (trim)
    std::filesystem::last_write_time(path, std::filesystem::file_time_type::clock::now(), error);
    return program;
  } catch (const cl::Error& error) {
    unusable(path, std::string("the driver rejected its binary (") + error.what() + ")");
    return {};
  }
}

void ProgramCache::unusable(const std::filesystem::path& path, const std::string& problem) {
  if (warned_) return;
  warned_ = true;
  warn_("program cache entry " + path.string() + " cannot be used: " + problem + "; it is rebuilt");
}

// Written to a temporary file and renamed, so a concurrent reader never sees half an entry.
void ProgramCache::store_binary(const std::string& key, const cl::Program& program) {
  std::vector<std::vector<unsigned char>> binaries = program.getInfo<CL_PROGRAM_BINARIES>();
  if (binaries.size() != 1 || binaries[0].empty()) return;
  std::string entry(kMagic);
  append_u64(entry, key.size());
  entry += key;
  append_u64(entry, binaries[0].size());
  entry.append(reinterpret_cast<const char*>(binaries[0].data()), binaries[0].size());
  append_u64(entry, fnv1a(entry));
  std::error_code error;
  std::filesystem::create_directories(directory_, error);
  if (error) return;
  const std::filesystem::path path = entry_path(key);
  std::filesystem::path temporary = path;
  temporary += ".tmp" + std::to_string(::getpid());
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) return;
    out.write(entry.data(), static_cast<std::streamsize>(entry.size()));
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
    if (!is_entry(*it)) continue;  // not temporary files being written, nor anyone else's
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
