// The on-disk cache of built programs: it keeps within its limit by removing the entries used
// longest ago, where loading an entry counts as using it; an entry that is damaged, truncated, not
// a regular file or of another version is rebuilt, with at most one warning per run.
#include "api/impl.hpp"
#include "runtime/program_cache.hpp"
#include "support/test_support.hpp"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include <sys/stat.h>
#include <unistd.h>

namespace clraster::test {
namespace {

namespace fs = std::filesystem;

std::string numbered_kernel(int n) {
  return "__kernel void number_" + std::to_string(n) + "(__global int* out) { out[0] = " + std::to_string(n) + "; }\n";
}

// Which numbered kernels the directory holds entries of (an entry stores its whole key, source included).
std::set<int> cached_kernels(const fs::path& directory) {
  std::set<int> numbers;
  for (const fs::directory_entry& entry : fs::directory_iterator(directory)) {
    std::ifstream in(entry.path(), std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    for (int n = 0; n < 10; ++n) {
      if (bytes.find("void number_" + std::to_string(n) + "(") != std::string::npos) numbers.insert(n);
    }
  }
  return numbers;
}

void ignore_warnings(const std::string&) {}

// A fresh cache directory for one test, removed at its end.
struct CacheDirectory {
  fs::path path = fs::temp_directory_path() /
                  ("clraster-program-cache-" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
                   "-" + std::to_string(::getpid()));
  CacheDirectory() { fs::remove_all(path); }
  ~CacheDirectory() { fs::remove_all(path); }

  // The entries in it (a test caches one program at a time).
  std::vector<fs::path> entries() const {
    std::vector<fs::path> found;
    for (const fs::directory_entry& entry : fs::directory_iterator(path)) found.push_back(entry.path());
    return found;
  }
};

// One run of a program that uses the cache: builds or loads numbered kernel n, runs it, and
// returns what it wrote (n when the program works) and the warnings the run gave.
struct KernelRun {
  int result = -1;
  std::vector<std::string> warnings;
};

KernelRun run_numbered_kernel(const fs::path& directory, int n) {
  ContextState& state = *shared_context().impl().state;
  KernelRun run;
  runtime::ProgramCache cache(state.context, state.device, directory.string(),
                              [&](const std::string& message) { run.warnings.push_back(message); });
  cl::Kernel kernel(cache.get("number.cl", numbered_kernel(n), ""), ("number_" + std::to_string(n)).c_str());
  cl::Buffer out(state.context, CL_MEM_WRITE_ONLY, sizeof(int));
  kernel.setArg(0, out);
  cl::CommandQueue& queue = state.queue.get();
  queue.enqueueNDRangeKernel(kernel, cl::NullRange, cl::NDRange(1), cl::NDRange(1));
  queue.enqueueReadBuffer(out, CL_TRUE, 0, sizeof(int), &run.result);
  return run;
}

std::string read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

void write_bytes(const fs::path& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

struct Damage {
  const char* name;
  std::function<std::string(std::string)> apply;  // the damaged bytes of an entry
  const char* problem;                             // what the warning says of it
};

class DamagedCacheEntry : public ::testing::TestWithParam<Damage> {};

// The run after the damage works and warns once, naming the entry; the entry is rewritten whole,
// so the run after that loads it without a word.
TEST_P(DamagedCacheEntry, IsRebuiltWithOneWarning) {
  const CacheDirectory directory;
  ASSERT_EQ(run_numbered_kernel(directory.path, 5).result, 5);
  ASSERT_EQ(directory.entries().size(), 1u);
  const fs::path entry = directory.entries().front();
  const std::string damaged_bytes = GetParam().apply(read_bytes(entry));
  write_bytes(entry, damaged_bytes);

  const KernelRun damaged = run_numbered_kernel(directory.path, 5);
  EXPECT_EQ(damaged.result, 5);
  ASSERT_EQ(damaged.warnings.size(), 1u);
  EXPECT_EQ(damaged.warnings[0],
            "program cache entry " + entry.string() + " cannot be used: " + GetParam().problem + "; it is rebuilt");
  EXPECT_TRUE(read_bytes(entry) != damaged_bytes) << "the damaged entry was not replaced";
  const KernelRun after = run_numbered_kernel(directory.path, 5);
  EXPECT_EQ(after.result, 5);
  EXPECT_TRUE(after.warnings.empty());
}

std::string flipped(std::string bytes, std::size_t at) {
  bytes.at(at) ^= 0x20;
  return bytes;
}

INSTANTIATE_TEST_SUITE_P(
    Entries, DamagedCacheEntry,
    ::testing::Values(
        Damage{"ByteOfTheBinaryFlipped", [](std::string b) { return flipped(b, b.size() * 3 / 4); },
               "its checksum does not match its contents"},
        Damage{"ByteOfTheKeyFlipped", [](std::string b) { return flipped(b, 40); },
               "its checksum does not match its contents"},
        Damage{"LastByteFlipped", [](std::string b) { return flipped(b, b.size() - 1); },
               "its checksum does not match its contents"},
        Damage{"CutInHalf", [](std::string b) { return b.substr(0, b.size() / 2); },
               "its checksum does not match its contents"},
        Damage{"CutAfterItsHeader", [](std::string b) { return b.substr(0, 30); }, "it is truncated"},
        Damage{"Emptied", [](std::string) { return std::string(); }, "it is not a cache entry"},
        Damage{"Overwritten", [](std::string b) { return std::string(b.size(), 'x'); }, "it is not a cache entry"}),
    [](const auto& info) { return std::string(info.param.name); });

TEST(ProgramCache, WarnsOnceForAllTheDamagedEntriesOfARun) {
  const CacheDirectory directory;
  ContextState& state = *shared_context().impl().state;
  const auto fill = [&](runtime::ProgramCache::Warn warn) {
    runtime::ProgramCache cache(state.context, state.device, directory.path.string(), std::move(warn));
    for (int n = 0; n < 3; ++n) cache.get("number.cl", numbered_kernel(n), "");
  };
  fill(ignore_warnings);
  ASSERT_EQ(directory.entries().size(), 3u);
  for (const fs::path& entry : directory.entries()) write_bytes(entry, flipped(read_bytes(entry), 60));
  std::vector<std::string> warnings;
  fill([&](const std::string& message) { warnings.push_back(message); });
  EXPECT_EQ(warnings.size(), 1u);
}

// A FIFO would block the reader for ever, a directory cannot be read: neither is opened, and the
// rebuilt entry takes the FIFO's place.
TEST(ProgramCache, EntryThatIsNotARegularFileIsRebuilt) {
  const CacheDirectory directory;
  ASSERT_EQ(run_numbered_kernel(directory.path, 6).result, 6);
  const fs::path entry = directory.entries().front();
  fs::remove(entry);
  ASSERT_EQ(::mkfifo(entry.c_str(), 0600), 0);
  // Another FIFO named like an entry, which trimming the directory after the rebuild passes over.
  const fs::path other = directory.path / "00000000000000ff.bin";
  ASSERT_EQ(::mkfifo(other.c_str(), 0600), 0);
  const KernelRun run = run_numbered_kernel(directory.path, 6);
  EXPECT_EQ(run.result, 6);
  ASSERT_EQ(run.warnings.size(), 1u);
  EXPECT_EQ(run.warnings[0], "program cache entry " + entry.string() + " cannot be used: not a regular file; it is rebuilt");
  EXPECT_TRUE(fs::is_regular_file(entry));
  EXPECT_TRUE(fs::is_fifo(other));
}

// An entry of another clraster version (an older format) is replaced without a word: after an upgrade
// every entry is one.
TEST(ProgramCache, EntryOfAnotherVersionIsRebuiltSilently) {
  const CacheDirectory directory;
  ASSERT_EQ(run_numbered_kernel(directory.path, 7).result, 7);
  const fs::path entry = directory.entries().front();
  std::string bytes = read_bytes(entry);
  bytes.replace(0, std::string("clraster-program-binary-2").size(), "clraster-program-binary-1");
  write_bytes(entry, bytes);
  const KernelRun run = run_numbered_kernel(directory.path, 7);
  EXPECT_EQ(run.result, 7);
  EXPECT_TRUE(run.warnings.empty());
  EXPECT_TRUE(read_bytes(entry).starts_with("clraster-program-binary-2\n"));
}

TEST(ProgramCache, RemovesTheEntriesUsedLongestAgoBeyondItsLimit) {
  const ContextState& state = *shared_context().impl().state;
  const fs::path directory = fs::temp_directory_path() / ("clraster-program-cache-test-" + std::to_string(::getpid()));
  fs::remove_all(directory);
  // Each cache object is a new run: its programs come from the directory or are built and stored.
  const auto run = [&](std::uintmax_t limit, std::initializer_list<int> kernels) {
    runtime::ProgramCache cache(state.context, state.device, directory.string(), ignore_warnings, limit);
    for (const int n : kernels) cache.get("number.cl", numbered_kernel(n), "");
  };
  run(std::uintmax_t{1} << 30, {0});
  std::uintmax_t entry_bytes = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(directory)) entry_bytes += entry.file_size();
  ASSERT_GT(entry_bytes, 0u);

  const std::uintmax_t room_for_two = entry_bytes * 5 / 2;
  run(room_for_two, {1});
  EXPECT_EQ(cached_kernels(directory), (std::set<int>{0, 1}));
  run(room_for_two, {0});  // loaded: 0 is now the one used last
  run(room_for_two, {2});  // a third entry: 1, used longest ago, goes
  EXPECT_EQ(cached_kernels(directory), (std::set<int>{0, 2}));
  // Files of someone else's in the directory are neither counted nor removed, even the oldest.
  const fs::path others = directory / "0123456789abcdef.bin";
  std::ofstream(others) << "not a program";
  fs::last_write_time(others, fs::file_time_type::clock::now() - std::chrono::hours(24 * 365));
  run(room_for_two, {3, 4});
  EXPECT_TRUE(fs::exists(others));
  fs::remove(others);
  EXPECT_EQ(cached_kernels(directory), (std::set<int>{3, 4}));
  fs::remove_all(directory);
}

}  // namespace
}  // namespace clraster::test
